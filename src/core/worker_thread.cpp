// WorkerThread (worker_thread.h).
#include "core/worker_thread.h"

#include <ctime>
#include <stdexcept>
#include <utility>

#include "core/spin_pause.h"

namespace quarry {
namespace {

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

bool SpinRecord::spin_next() {
  ++calls_;
  if (wall_ > 0.0 && cpu_ < kOwnCore * wall_ && calls_ % kProbe != 0) {
    ++slept_at_once_;
    return false;
  }
  return true;
}

// Time spent helping is taken off both clocks by the caller (as if it had had its core):
// counted, it made spins that lost their core look as if they had it, and kept the thread
// helping, and holding items up, beside a busy process (the two-way flagship on two threads
// beside a busy loop: 1.10x the time of not helping). A spin of under kSample is no sample: the
// two clocks' few µs of disagreement would decide it. A wait that finds the task done reads
// some 2 µs of wall time to 1.5 µs of CPU time; taken as samples, runs of such waits held the
// owner asleep on a quiet machine instead of helping (2,133 of the 2,722 waits of the two-way
// flagship from 2.0 s to 2.3 s on two threads).
void SpinRecord::add(double wall, double cpu) {
  if (wall < kSample) return;
  cpu_ = 0.875 * cpu_ + 0.125 * cpu;
  wall_ = 0.875 * wall_ + 0.125 * wall;
}

// True once `done()` holds, false if WorkerThread::kSpin passed first or if this side's spins
// have lately not had a core to themselves. That is how a busy machine shows: a spinning thread
// then takes turns on its core with another runnable thread (another process, or the very thread
// it waits for), and its CPU time falls behind the wall time. It then sleeps at once (the other
// runs instead), but spins every kProbe-th time to look again. Between looks it calls help(),
// which may run some of the awaited work itself (SharedLoop::help); kSpin then counts from the
// last time it did.
template <class Done, class Help>
bool WorkerThread::Spin::until(Done done, Help help) {
  using Clock = std::chrono::steady_clock;
  if (!record.spin_next()) return false;
  const auto wall_start = Clock::now();
  auto start = wall_start, last_look = wall_start;  // kSpin counts from start
  const double cpu_start = thread_cpu_seconds();
  // s of wall time spent in help() that ran something (from the clock's last reading before
  // it: up to 64 turns of spinning more, some µs)
  double helped = 0.0;
  bool finished = false;
  for (unsigned turn = 1;; ++turn) {
    if (done()) {
      finished = true;
      break;
    }
    if (help()) {
      const auto now = Clock::now();
      helped += std::chrono::duration<double>(now - last_look).count();
      start = last_look = now;
      continue;
    }
    spin_pause();
    if (turn % 64 == 0) {
      last_look = Clock::now();
      if (last_look - start >= kSpin) break;
    }
  }
  record.add(std::chrono::duration<double>(Clock::now() - wall_start).count() - helped,
             thread_cpu_seconds() - cpu_start - helped);
  return finished;
}

WorkerThread::WorkerThread() : thread_([this] { loop(); }) {}

WorkerThread::~WorkerThread() {
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !busy_.load(); });
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void WorkerThread::start(std::function<void()> task) {
  {
    std::lock_guard lock(mutex_);
    if (busy_.load()) throw std::logic_error("WorkerThread::start: a task is under way");
    task_ = std::move(task);
    error_ = nullptr;
    busy_ = true;
  }
  changed_.notify_all();
}

void WorkerThread::wait() {
  waiter_spin_.until([this] { return !busy_.load(std::memory_order_acquire); },
                     [this] { return shared_loops_.help(); });
  std::exception_ptr error;
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !busy_.load(); });
    std::swap(error, error_);
  }
  if (error) std::rethrow_exception(error);
}

void WorkerThread::loop() {
  for (;;) {
    worker_spin_.until(
        [this] {
          return busy_.load(std::memory_order_acquire) || stopping_.load(std::memory_order_acquire);
        },
        [] { return false; });
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return busy_.load() || stopping_.load(); });
    if (!busy_.load()) return;  // stopping, nothing to do
    std::function<void()> task = std::move(task_);
    lock.unlock();
    std::exception_ptr error;
    try {
      task();
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    error_ = error;
    busy_ = false;
    lock.unlock();
    changed_.notify_all();
  }
}

}  // namespace quarry
