// WorkerThread (worker_thread.h).
#include "core/worker_thread.h"

#include <stdexcept>
#include <utility>

namespace quarry {
namespace {

// True once `done()` holds, false if WorkerThread::kSpin passed first. Reads the clock every
// 64 turns; each turn tells the core it is spinning (a pause on x86).
template <class Done>
bool spin_until(Done done) {
  const auto deadline = std::chrono::steady_clock::now() + WorkerThread::kSpin;
  for (unsigned turn = 1;; ++turn) {
    if (done()) return true;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
    if (turn % 64 == 0 && std::chrono::steady_clock::now() >= deadline) return false;
  }
}

}  // namespace

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
  spin_until([this] { return !busy_.load(std::memory_order_acquire); });
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
    spin_until([this] { return busy_.load(std::memory_order_acquire) || stopping_.load(std::memory_order_acquire); });
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
