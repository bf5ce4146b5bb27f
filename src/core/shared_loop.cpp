// SharedLoop (shared_loop.h). Every access to the shared words is sequentially consistent: a
// few per loop of tens of µs, so the simplest ordering to reason about costs nothing here.
#include "core/shared_loop.h"

#include <chrono>
#include <thread>

#include "core/spin_pause.h"

namespace quarry {
namespace {

// The state word: loop number << 40 | front << 20 | back.
constexpr int kItemBits = 20;
constexpr std::uint64_t kItemMask = (std::uint64_t{1} << kItemBits) - 1;
constexpr std::uint64_t kLoopMask = (std::uint64_t{1} << (64 - 2 * kItemBits)) - 1;
constexpr std::uint64_t loop_of(std::uint64_t state) { return state >> (2 * kItemBits); }
constexpr std::uint64_t front_of(std::uint64_t state) { return (state >> kItemBits) & kItemMask; }
constexpr std::uint64_t back_of(std::uint64_t state) { return state & kItemMask; }
constexpr std::uint64_t make_state(std::uint64_t loop, std::uint64_t front, std::uint64_t back) {
  return (loop & kLoopMask) << (2 * kItemBits) | front << kItemBits | back;
}

}  // namespace

void SharedLoop::run_items(int count, Call call, const void* body) {
  if (count <= 0) return;
  if (static_cast<std::uint64_t>(count) > kItemMask) {  // more items than the word holds
    for (int i = 0; i < count; ++i) call(body, i);
    return;
  }
  // Close the loop under a new number (nothing to claim) before the call and body change: a
  // thread that read the old loop's state then fails its claim, whatever it read after.
  const std::uint64_t loop = (loop_of(state_.load()) + 1) & kLoopMask;
  state_.store(make_state(loop, 0, 0));
  call_.store(call);
  body_.store(body);
  done_.store(0);
  const std::uint64_t open = make_state(loop, 0, static_cast<std::uint64_t>(count));
  state_.store(open);
  claim_and_run(open, true);
  // Items a helper claimed may still be running (some µs each). Past kPatience the helper has
  // likely lost its core to another process: sleep, so that this core goes idle and the
  // scheduler can move the helper here to finish its item (a yield keeps the core busy).
  constexpr auto kPatience = std::chrono::microseconds(50);
  const auto since = std::chrono::steady_clock::now();
  for (unsigned turn = 1; done_.load() < count; ++turn) {
    spin_pause();
    if (turn % 64 == 0 && std::chrono::steady_clock::now() - since > kPatience)
      std::this_thread::sleep_for(kPatience);
  }
  std::exception_ptr error;
  {
    std::lock_guard lock(error_mutex_);
    std::swap(error, error_);
  }
  if (error) std::rethrow_exception(error);
}

bool SharedLoop::help() { return claim_and_run(state_.load(), false); }

bool SharedLoop::claim_and_run(std::uint64_t state, bool front) {
  const Call call = call_.load();
  const void* const body = body_.load();
  const std::uint64_t loop = loop_of(state);
  bool ran = false;
  for (;;) {
    const std::uint64_t first = front_of(state), end = back_of(state);
    if (first >= end) return ran;  // all claimed, or the loop closed
    const std::uint64_t item = front ? first : end - 1;
    const std::uint64_t claimed = front ? make_state(loop, first + 1, end)
                                        : make_state(loop, first, end - 1);
    if (!state_.compare_exchange_weak(state, claimed)) {
      if (loop_of(state) != loop) return ran;  // moved on: what was read is stale
      continue;
    }
    try {
      call(body, static_cast<int>(item));
    } catch (...) {
      std::lock_guard lock(error_mutex_);
      if (!error_) error_ = std::current_exception();
    }
    done_.fetch_add(1);
    ran = true;
    state = claimed;
  }
}

}  // namespace quarry
