// SharedLoop: every item of every loop runs exactly once, on the owner or on a helper; the owner
// takes items from the front and a helper from the back; an item's exception reaches run().
#include "core/shared_loop.h"

#include <array>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace quarry {
namespace {

// A thread calling help() until stopped.
class Helper {
 public:
  explicit Helper(SharedLoop& loop)
      : thread_([this, &loop] {
          while (!stop_.load()) loop.help();
        }) {}
  ~Helper() {
    stop_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// Waits (up to 30 s, a bound against a hung test) until `ready` holds.
template <class Ready>
bool wait_for(Ready ready) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!ready()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::yield();
  }
  return true;
}

TEST(SharedLoop, AloneRunsEveryItemInOrderOnItsThread) {
  SharedLoop loop;
  std::vector<int> order;
  loop.run(5, [&](int i) { order.push_back(i); });
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
  loop.run(0, [&](int) { ADD_FAILURE() << "an item of an empty loop ran"; });
  EXPECT_FALSE(loop.help());  // nothing under way
}

TEST(SharedLoop, EveryItemOfEveryLoopRunsOnceWithAHelper) {
  SharedLoop loop;
  const std::thread::id owner = std::this_thread::get_id();
  Helper helper(loop);
  long helped = 0;
  for (int round = 0; round < 300; ++round) {
    const int count = 1 + round % 37;
    std::vector<std::atomic<int>> runs(static_cast<std::size_t>(count));
    std::vector<std::thread::id> by(static_cast<std::size_t>(count));
    loop.run(count, [&](int i) {
      runs[static_cast<std::size_t>(i)] += 1;
      by[static_cast<std::size_t>(i)] = std::this_thread::get_id();
      std::this_thread::sleep_for(std::chrono::microseconds(20));  // so that the helper gets some
    });
    for (int i = 0; i < count; ++i) {
      ASSERT_EQ(runs[static_cast<std::size_t>(i)].load(), 1) << "round " << round << " item " << i;
      helped += by[static_cast<std::size_t>(i)] != owner ? 1 : 0;
    }
  }
  std::printf("the helper ran %ld items\n", helped);
}

TEST(SharedLoop, TheOwnerTakesTheFrontAndAHelperTheBack) {
  SharedLoop loop;
  const std::thread::id owner = std::this_thread::get_id();
  constexpr int kOwner = 1, kHelper = 2;
  std::array<std::atomic<int>, 8> by{};  // who ran item i
  Helper helper(loop);
  loop.run(8, [&](int i) {
    const bool mine = std::this_thread::get_id() == owner;
    by[static_cast<std::size_t>(i)] = mine ? kOwner : kHelper;
    const auto helper_ran = [&] {
      for (const std::atomic<int>& b : by)
        if (b.load() == kHelper) return true;
      return false;
    };
    // The owner's first item waits until the helper has taken one, and that one until the
    // owner has had its first: both then run items, whatever the timing.
    if (mine && i == 0) {
      ASSERT_TRUE(wait_for(helper_ran));
    }
    if (!mine) {
      ASSERT_TRUE(wait_for([&] { return by[0].load() != 0; }));
    }
  });
  EXPECT_EQ(by[0].load(), kOwner);
  EXPECT_EQ(by[7].load(), kHelper);  // the helper's first claim is the last item
}

TEST(SharedLoop, AnItemsExceptionReachesRunAndTheOtherItemsStillRun) {
  SharedLoop loop;
  const std::thread::id owner = std::this_thread::get_id();
  std::atomic<int> ran{0};
  std::atomic<bool> helper_threw{false};
  Helper helper(loop);
  EXPECT_THROW(loop.run(6,
                        [&](int i) {
                          ran += 1;
                          if (std::this_thread::get_id() != owner) {
                            helper_threw = true;
                            throw std::runtime_error("helper's item");
                          }
                          // The owner's items wait for the helper's throw (bounded).
                          if (i == 0) {
                            ASSERT_TRUE(wait_for([&] { return helper_threw.load(); }));
                          }
                        }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 6);
  std::atomic<int> after{0};
  loop.run(4, [&](int) { after += 1; });  // the next loop is not disturbed
  EXPECT_EQ(after.load(), 4);
}

}  // namespace
}  // namespace quarry
