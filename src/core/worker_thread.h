// WorkerThread: one thread that runs one task at a time for its owner, who hands a task over
// (start) and later waits for it (wait). Both sides spin a while (up to kSpin) before sleeping
// on a condition variable: on a virtual machine, waking sleeping threads cost the structure
// alongside the DEM some 0.15 ms per step (the vCPU halts; bench/micro/worker_thread_bench.cpp).
// A side whose recent spins did not have a core to themselves (a busy machine) sleeps at once,
// so that the thread it waits for, or another process, gets the core. A longer wait sleeps, so an
// idle worker costs nothing. While the owner spins in wait() it runs items of the task's shared
// loops (shared_loops()). The thread is reused from task to task (a new std::thread per task
// costs tens of µs to start).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "core/shared_loop.h"

namespace quarry {

// One side's recent spins (WorkerThread): whether they had a core to themselves, judged by the
// thread's CPU time against the wall time, each spin weighing 1/8 (an exponential mean).
class SpinRecord {
 public:
  static constexpr double kOwnCore = 0.75;   // CPU / wall time of recent spins to go on spinning
  static constexpr unsigned kProbe = 16;     // while not: spin every kProbe-th wait, to look again
  static constexpr double kSample = 100e-6;  // s: a spin shorter than this is no sample

  // At a wait: whether to spin (else sleep at once).
  bool spin_next();
  // A spin of `wall` s of wall time and `cpu` s of CPU time, both without the time it helped.
  void add(double wall, double cpu);
  // Waits that slept at once.
  std::uint64_t slept_at_once() const { return slept_at_once_; }

 private:
  double cpu_ = 0.0, wall_ = 0.0;  // s, the means
  unsigned calls_ = 0;
  std::uint64_t slept_at_once_ = 0;
};

class WorkerThread {
 public:
  // How long either side spins before it sleeps: longer than the gaps of a DEM step's handover
  // (the serial hooks between two steps, a structure finishing a little after the DEM), short
  // against anything worth sleeping through.
  static constexpr std::chrono::microseconds kSpin{3000};

  WorkerThread();
  ~WorkerThread();  // waits for a task under way, then ends the thread
  WorkerThread(const WorkerThread&) = delete;
  WorkerThread& operator=(const WorkerThread&) = delete;

  // Runs `task` on the worker. Pre: no task under way (wait() returned since the last start).
  void start(std::function<void()> task);
  // Blocks until the task has returned; rethrows what it threw. No task under way: returns.
  // While it spins it runs items of the task's shared loops (shared_loops()).
  void wait();
  // Loops the task may run through (SharedLoop::run) so that its owner, waiting in wait(),
  // takes items of them instead of only spinning.
  SharedLoop& shared_loops() { return shared_loops_; }

 private:
  void loop();

  // One side's spinning (worker_thread.cpp).
  struct Spin {
    SpinRecord record;
    template <class Done, class Help>
    bool until(Done done, Help help);
  };
  Spin waiter_spin_;  // the owner's, in wait()
  Spin worker_spin_;  // the worker's, between tasks
  SharedLoop shared_loops_;

  std::mutex mutex_;
  std::condition_variable changed_;
  std::function<void()> task_;          // under mutex_
  std::exception_ptr error_;            // under mutex_
  std::atomic<bool> busy_{false};       // written under mutex_, read by the spinning side too
  std::atomic<bool> stopping_{false};   // likewise
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace quarry
