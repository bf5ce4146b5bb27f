// Threading: how many OpenMP threads one world's loops use. A setting of the world, not of the
// process, so that several worlds in one process (coupling partners, tests) each keep their own.
#pragma once

#include <omp.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>

namespace quarry {

class SharedLoop;

struct Threading {
  int threads = 0;  // 0: the caller's OpenMP default (OMP_NUM_THREADS, or the cores)
  // Loops over fewer items than this run on one thread: below it, starting a team costs more
  // than the work. Results are bit-identical either way; the determinism tests set it to 0 so
  // that small scenes do run on several threads.
  std::size_t threshold = 2048;
  // Where a loop that would run on one thread may be shared with a thread that waits for it
  // (SharedLoop; the structure's steps beside the DEM's): null, nowhere. Only loops whose items
  // write their own results use it, so results do not depend on it either.
  SharedLoop* shared = nullptr;

  // Threads for a loop over n items.
  int team(std::size_t n) const {
    if (n <= threshold) return 1;
    const int available = threads > 0 ? threads : omp_get_max_threads();
    return available > 1 ? available : 1;
  }
};

// The items [first, end) of thread t of a team of `threads` over n items: range t of `start`
// (threads + 1 ascending starts ending at n) when it is a split of n for this team, else the
// t-th of equal blocks. The step's per-particle passes take the force stage's ranges so that
// each particle is updated on the thread that sums its forces: on two vCPUs a line written by
// the other core is fetched from it and a line it has read is invalidated there first (the
// drum on 2 threads: the drift's stores to the thread-1 half took 3.4x thread 0's when the
// passes split at n/2 and the force ranges at 0.49-0.53 n; docs/performance.md).
inline std::pair<std::size_t, std::size_t> thread_block(std::size_t n, int t, int threads,
                                                        std::span<const std::uint32_t> start) {
  if (start.size() == static_cast<std::size_t>(threads) + 1 && start.back() == n)
    return {start[t], start[t + 1]};
  const std::size_t base = n / threads, extra = n % threads, ut = static_cast<std::size_t>(t);
  const std::size_t first = ut * base + (ut < extra ? ut : extra);
  return {first, first + base + (ut < extra ? 1 : 0)};
}

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
