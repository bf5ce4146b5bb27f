// Tests of the stable counting sort: equal to std::stable_sort by key, serial and parallel.
#include "core/counting_sort.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace quarry {
namespace {

void expect_matches_stable_sort(const std::vector<std::uint32_t>& keys, std::uint32_t key_count) {
  std::vector<std::uint32_t> bucket_start, sorted_items;
  CountingSortWorkspace workspace;
  stable_counting_sort(keys, key_count, bucket_start, sorted_items, workspace);

  std::vector<std::uint32_t> expected(keys.size());
  std::iota(expected.begin(), expected.end(), 0u);
  std::stable_sort(expected.begin(), expected.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  EXPECT_EQ(sorted_items, expected);
  ASSERT_EQ(bucket_start.size(), std::size_t{key_count} + 1);
  EXPECT_EQ(bucket_start.front(), 0u);
  EXPECT_EQ(bucket_start.back(), keys.size());
  for (std::uint32_t c = 0; c < key_count; ++c)
    for (std::uint32_t k = bucket_start[c]; k < bucket_start[c + 1]; ++k)
      ASSERT_EQ(keys[sorted_items[k]], c);
}

std::vector<std::uint32_t> random_keys(std::size_t count, std::uint32_t key_count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::uint32_t> key(0, key_count - 1);
  std::vector<std::uint32_t> keys(count);
  for (auto& k : keys) k = key(random);
  return keys;
}

TEST(CountingSort, EmptyInputGivesZeroBuckets) {
  expect_matches_stable_sort({}, 5);
}

TEST(CountingSort, SmallInputMatchesStableSort) {
  expect_matches_stable_sort({3, 1, 3, 0, 1, 1, 4, 0}, 6);
}

TEST(CountingSort, LargeInputMatchesStableSortForOneAndTwoThreads) {
  // Large enough for the per-thread-histogram path.
  const auto keys = random_keys(100000, 20000, 7);
  const int threads_before = omp_get_max_threads();
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    SCOPED_TRACE(threads);
    expect_matches_stable_sort(keys, 20000);
  }
  omp_set_num_threads(threads_before);
}

TEST(CountingSort, AllItemsInOneBucketKeepTheirOrder) {
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(2);
  expect_matches_stable_sort(std::vector<std::uint32_t>(70000, 2), 3);
  omp_set_num_threads(threads_before);
}

}  // namespace
}  // namespace quarry
