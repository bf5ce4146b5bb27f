// Threading: how many OpenMP threads one world's loops use. A setting of the world, not of the
// process, so that several worlds in one process (coupling partners, tests) each keep their own.
#pragma once

#include <omp.h>

#include <cstddef>

namespace quarry {

struct Threading {
  int threads = 0;  // 0: the caller's OpenMP default (OMP_NUM_THREADS, or the cores)
  // Loops over fewer items than this run on one thread: below it, starting a team costs more
  // than the work. Results are bit-identical either way; the determinism tests set it to 0 so
  // that small scenes do run on several threads.
  std::size_t threshold = 2048;

  // Threads for a loop over n items.
  int team(std::size_t n) const {
    if (n <= threshold) return 1;
    const int available = threads > 0 ? threads : omp_get_max_threads();
    return available > 1 ? available : 1;
  }
};

// Makes `threading.threads` the calling thread's OpenMP default for a scope (the neighbour
// module's loops use the default team), and restores the previous default on exit. OpenMP's
// default is per calling thread, so worlds stepped on different threads do not interfere.
class ThreadScope {
 public:
  explicit ThreadScope(const Threading& threading) : previous_(omp_get_max_threads()) {
    if (threading.threads > 0) omp_set_num_threads(threading.threads);
  }
  ~ThreadScope() { omp_set_num_threads(previous_); }
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;

 private:
  int previous_;
};

}  // namespace quarry
