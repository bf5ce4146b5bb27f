// WorkerThread: tasks run on another thread, one at a time, their exceptions reach wait().
#include "core/worker_thread.h"

#include <atomic>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

namespace quarry {
namespace {

TEST(WorkerThread, RunsEachTaskOnItsOwnThreadAndWaitsForIt) {
  WorkerThread worker;
  const std::thread::id caller = std::this_thread::get_id();
  long sum = 0;
  for (int k = 1; k <= 1000; ++k) {
    std::thread::id ran_on;
    worker.start([&sum, &ran_on, k] {
      sum += k;
      ran_on = std::this_thread::get_id();
    });
    worker.wait();
    ASSERT_NE(ran_on, caller);
  }
  EXPECT_EQ(sum, 1000L * 1001 / 2);  // every task ran, once, and was done at wait()
  worker.wait();                     // nothing under way: returns at once
}

TEST(WorkerThread, ATaskRunsWhileTheCallerWorks) {
  WorkerThread worker;
  std::atomic<bool> caller_done{false}, task_saw_caller{false};
  worker.start([&] {
    while (!caller_done.load()) std::this_thread::yield();  // ends only once the caller went on
    task_saw_caller = true;
  });
  caller_done = true;
  worker.wait();
  EXPECT_TRUE(task_saw_caller.load());
}

TEST(WorkerThread, ATasksExceptionReachesWaitAndTheWorkerGoesOn) {
  WorkerThread worker;
  worker.start([] { throw std::runtime_error("diverged"); });
  EXPECT_THROW(
      {
        try {
          worker.wait();
        } catch (const std::runtime_error& e) {
          EXPECT_STREQ(e.what(), "diverged");
          throw;
        }
      },
      std::runtime_error);
  int ran = 0;
  worker.start([&ran] { ran = 1; });
  worker.wait();
  EXPECT_EQ(ran, 1);
  std::atomic<bool> release{false};
  worker.start([&release] {
    while (!release.load()) std::this_thread::yield();  // under way until released
  });
  EXPECT_THROW(worker.start([] {}), std::logic_error);  // a second task before wait(): refused
  release = true;
  worker.wait();
}

// Both sides spin kSpin before they sleep: a task longer than that is still waited for (the
// caller sleeps and is woken), and a worker idle longer than that still takes the next task.
TEST(WorkerThread, HandsOverPastTheSpinOnBothSides) {
  WorkerThread worker;
  const auto beyond_spin = 3 * WorkerThread::kSpin;
  int ran = 0;
  worker.start([&ran, beyond_spin] {
    std::this_thread::sleep_for(beyond_spin);
    ran = 1;
  });
  worker.wait();  // spins, then sleeps until the task is done
  EXPECT_EQ(ran, 1);
  std::this_thread::sleep_for(beyond_spin);  // the worker is asleep by now
  worker.start([&ran] { ran = 2; });
  worker.wait();
  EXPECT_EQ(ran, 2);
}

// The spin statistics (SpinRecord): spins that lost their core make a side sleep at once, but
// look again every kProbe-th wait; waits too short to measure (a task found done: some µs, the
// clocks disagreeing by a third of it) are no evidence either way.
TEST(SpinRecord, ShortSpinsAreNoEvidenceOfABusyMachine) {
  SpinRecord record;
  for (int i = 0; i < 100; ++i) {
    EXPECT_TRUE(record.spin_next());
    record.add(2e-6, 1e-6);  // 2 µs of wall time, half of it on the CPU clock
  }
  EXPECT_TRUE(record.spin_next());
  EXPECT_EQ(record.slept_at_once(), 0u);
}

TEST(SpinRecord, SpinsWithoutACoreMakeItSleepButLookAgain) {
  SpinRecord record;
  EXPECT_TRUE(record.spin_next());  // nothing known yet: spin
  record.add(1e-3, 0.9e-3);         // had its core
  EXPECT_TRUE(record.spin_next());
  for (int i = 0; i < 8; ++i) record.add(3e-3, 1e-3);  // shared its core with another thread
  int spun = 0;
  for (unsigned i = 0; i < 10 * SpinRecord::kProbe; ++i) spun += record.spin_next();
  EXPECT_EQ(spun, 10);  // every kProbe-th wait only
  EXPECT_EQ(record.slept_at_once(), 10 * SpinRecord::kProbe - 10);
  for (int i = 0; i < 30; ++i) record.add(1e-3, 1e-3);  // the probes found a core again
  EXPECT_TRUE(record.spin_next());
  EXPECT_TRUE(record.spin_next());
}

TEST(WorkerThread, DestroyedWhileATaskRunsItWaitsForIt) {
  std::atomic<int> finished{0};
  {
    WorkerThread worker;
    worker.start([&finished] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      finished = 1;
    });
  }
  EXPECT_EQ(finished.load(), 1);
}

}  // namespace
}  // namespace quarry
