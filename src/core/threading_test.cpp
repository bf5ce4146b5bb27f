// thread_block: each thread's items of a per-particle pass. Every item belongs to exactly one
// thread, in ascending blocks, whichever split is used.
#include "core/threading.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace quarry {
namespace {

// The blocks of a team cover [0, n) once, in order.
void expect_cover(std::size_t n, int threads, std::span<const std::uint32_t> start) {
  std::size_t next = 0;
  for (int t = 0; t < threads; ++t) {
    const auto [first, end] = thread_block(n, t, threads, start);
    EXPECT_EQ(first, next) << "thread " << t;
    EXPECT_LE(first, end);
    next = end;
  }
  EXPECT_EQ(next, n);
}

TEST(ThreadBlock, TakesTheGivenRangesWhenTheySplitTheItemsForThisTeam) {
  const std::vector<std::uint32_t> start{0, 7, 10};  // 2 threads, 10 items: 7 and 3
  EXPECT_EQ(thread_block(10, 0, 2, start), (std::pair<std::size_t, std::size_t>{0, 7}));
  EXPECT_EQ(thread_block(10, 1, 2, start), (std::pair<std::size_t, std::size_t>{7, 10}));
  expect_cover(10, 2, start);
}

TEST(ThreadBlock, EqualBlocksWhenTheRangesAreForOtherItemsOrAnotherTeam) {
  const std::vector<std::uint32_t> start{0, 7, 10};
  // 11 items (a particle added since the ranges were drawn): blocks of 6 and 5.
  EXPECT_EQ(thread_block(11, 0, 2, start), (std::pair<std::size_t, std::size_t>{0, 6}));
  EXPECT_EQ(thread_block(11, 1, 2, start), (std::pair<std::size_t, std::size_t>{6, 11}));
  expect_cover(11, 2, start);
  expect_cover(10, 3, start);  // ranges for 2 threads, a team of 3
  expect_cover(10, 1, start);
  expect_cover(2, 4, {});      // fewer items than threads: some blocks empty
  expect_cover(0, 2, {});
  EXPECT_EQ(thread_block(10, 0, 1, {}), (std::pair<std::size_t, std::size_t>{0, 10}));
}

}  // namespace
}  // namespace quarry
