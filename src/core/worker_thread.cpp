// WorkerThread (worker_thread.h).
#include "core/worker_thread.h"

#include <stdexcept>
#include <utility>

namespace quarry {

WorkerThread::WorkerThread() : thread_([this] { loop(); }) {}

WorkerThread::~WorkerThread() {
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !busy_; });
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void WorkerThread::start(std::function<void()> task) {
  {
    std::lock_guard lock(mutex_);
    if (busy_) throw std::logic_error("WorkerThread::start: a task is under way");
    task_ = std::move(task);
    error_ = nullptr;
    busy_ = true;
  }
  changed_.notify_all();
}

void WorkerThread::wait() {
  std::exception_ptr error;
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !busy_; });
    std::swap(error, error_);
  }
  if (error) std::rethrow_exception(error);
}

void WorkerThread::loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return busy_ || stopping_; });
    if (!busy_) return;  // stopping, nothing to do
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
    changed_.notify_all();
  }
}

}  // namespace quarry
