// WorkerThread: one thread that runs one task at a time for its owner, who hands a task over
// (start) and later waits for it (wait). The thread sleeps on a condition variable between tasks,
// so it costs nothing while idle, even on a busy machine, and is reused from task to task (a new
// std::thread per task costs tens of µs to start).
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace quarry {

class WorkerThread {
 public:
  WorkerThread();
  ~WorkerThread();  // waits for a task under way, then ends the thread
  WorkerThread(const WorkerThread&) = delete;
  WorkerThread& operator=(const WorkerThread&) = delete;

  // Runs `task` on the worker. Pre: no task under way (wait() returned since the last start).
  void start(std::function<void()> task);
  // Blocks until the task has returned; rethrows what it threw. No task under way: returns.
  void wait();

 private:
  void loop();

  std::mutex mutex_;
  std::condition_variable changed_;
  std::function<void()> task_;
  bool busy_ = false, stopping_ = false;
  std::exception_ptr error_;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace quarry
