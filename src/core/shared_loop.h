// SharedLoop: loops that one thread (the owner) runs and that another thread may join while it
// would otherwise only wait. On two threads the structure's steps run beside the DEM's stages on
// a worker thread (WorkerThread), and the DEM's thread then waits for them at the step's end:
// waiting, it takes items of the structure's element and node loops instead (World::alongside).
//
// The owner claims items from the front, helpers from the back, so that from one loop to the
// next each thread mostly gets the same items again and finds their data in its own cache (the
// shell histories: claimed from one counter, the items changed threads at random and the
// kernel's time grew by a quarter). Who runs which item still depends on timing: a loop whose
// items each write only their own results (the shell solver's element blocks, node blocks and
// per-block sums) gives the same bits whoever runs them.
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>

namespace quarry {

class SharedLoop {
 public:
  // body(i) for every i in [0, count), on this thread and on any thread in help() meanwhile;
  // returns when all have returned, rethrowing the first exception one threw (the others still
  // run). One owner: run() is not called from two threads at once, nor from within a body.
  template <class Body>
  void run(int count, const Body& body) {
    run_items(count, [](const void* b, int i) { (*static_cast<const Body*>(b))(i); }, &body);
  }

  // Runs items of the owner's loop under way, if one is, until none is left to claim. True if it
  // ran any. Any thread but the owner's, at any time.
  bool help();

 private:
  using Call = void (*)(const void* body, int item);
  void run_items(int count, Call call, const void* body);
  // Claims items of the loop whose counters read `state`, from the front or from the back, and
  // runs them until none is left; true if it ran any.
  bool claim_and_run(std::uint64_t state, bool front);

  // The loop under way: its number (24 bits), the first unclaimed item and one past the last
  // (20 bits each). A claim is a compare-and-swap of the whole word, so a thread that read the
  // loop's call and body before the owner moved on to its next loop cannot claim an item of
  // that next one.
  std::atomic<std::uint64_t> state_{0};
  std::atomic<Call> call_{nullptr};
  std::atomic<const void*> body_{nullptr};
  std::atomic<int> done_{0};  // items of the loop under way that have returned
  std::mutex error_mutex_;
  std::exception_ptr error_;  // under error_mutex_
};

}  // namespace quarry
