// Stable counting sort: serial for small inputs; otherwise each thread histograms a contiguous
// block of items, and block t's items of key c go after those of blocks < t — the same
// placement the serial sort gives, whatever the number of threads.
#include "core/counting_sort.h"

#include <algorithm>
#include <cassert>
#include <cstddef>

#include <omp.h>

namespace quarry {

namespace {

// Below this many items the parallel bookkeeping costs more than it saves.
constexpr std::size_t kParallelMinItems = 1u << 15;
// Per-thread histograms cost threads × keys memory and time; stay serial when the keys
// outnumber the items this many times (a sparse grid).
constexpr std::size_t kMaxKeysPerItemForParallel = 4;

// value_of(item) is what gets written for an item: its index or a payload.
template <class ValueOf>
void serial_sort(std::span<const std::uint32_t> keys, std::uint32_t key_count, ValueOf value_of,
                 std::vector<std::uint32_t>& bucket_start, std::vector<std::uint32_t>& sorted_items) {
  std::fill(bucket_start.begin(), bucket_start.end(), 0u);
  for (const std::uint32_t key : keys) ++bucket_start[key + 1];
  for (std::uint32_t c = 0; c < key_count; ++c) bucket_start[c + 1] += bucket_start[c];
  // bucket_start[c] is used as the write cursor of bucket c, then restored from the next one.
  for (std::size_t item = 0; item < keys.size(); ++item)
    sorted_items[bucket_start[keys[item]]++] = value_of(item);
  for (std::uint32_t c = key_count; c > 0; --c) bucket_start[c] = bucket_start[c - 1];
  bucket_start[0] = 0;
}

template <class ValueOf>
void sort_by_key(std::span<const std::uint32_t> keys, std::uint32_t key_count, ValueOf value_of,
                 std::vector<std::uint32_t>& bucket_start, std::vector<std::uint32_t>& sorted_items,
                 CountingSortWorkspace& workspace) {
  const std::size_t item_count = keys.size();
  bucket_start.resize(std::size_t{key_count} + 1);
  sorted_items.resize(item_count);
  const int max_threads = omp_in_parallel() ? 1 : omp_get_max_threads();
  if (max_threads <= 1 || item_count < kParallelMinItems ||
      key_count > kMaxKeysPerItemForParallel * item_count) {
    serial_sort(keys, key_count, value_of, bucket_start, sorted_items);
    return;
  }

  const std::size_t keys_per_thread = key_count;
  workspace.per_thread_counts.resize(static_cast<std::size_t>(max_threads) * keys_per_thread);
  std::uint32_t* const counts = workspace.per_thread_counts.data();
  std::uint32_t* const starts = bucket_start.data();
  std::uint32_t* const output = sorted_items.data();
  const std::uint32_t* const key_of = keys.data();

#pragma omp parallel num_threads(max_threads)
  {
    const std::size_t thread_count = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t thread = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t begin = item_count * thread / thread_count;
    const std::size_t end = item_count * (thread + 1) / thread_count;
    std::uint32_t* const my_counts = counts + thread * keys_per_thread;
    std::fill(my_counts, my_counts + keys_per_thread, 0u);
    for (std::size_t item = begin; item < end; ++item) ++my_counts[key_of[item]];
#pragma omp barrier
    // Bucket totals, then an exclusive prefix over buckets (serial: one add per key).
#pragma omp for schedule(static)
    for (std::size_t c = 0; c < key_count; ++c) {
      std::uint32_t total = 0;
      for (std::size_t t = 0; t < thread_count; ++t) total += counts[t * keys_per_thread + c];
      starts[c + 1] = total;
    }
#pragma omp single
    {
      starts[0] = 0;
      for (std::size_t c = 0; c < key_count; ++c) starts[c + 1] += starts[c];
    }
    // Turn each thread's count into its first write position inside the bucket.
#pragma omp for schedule(static)
    for (std::size_t c = 0; c < key_count; ++c) {
      std::uint32_t cursor = starts[c];
      for (std::size_t t = 0; t < thread_count; ++t) {
        const std::uint32_t count = counts[t * keys_per_thread + c];
        counts[t * keys_per_thread + c] = cursor;
        cursor += count;
      }
    }
    for (std::size_t item = begin; item < end; ++item)
      output[my_counts[key_of[item]]++] = value_of(item);
  }
}

}  // namespace

void stable_counting_sort(std::span<const std::uint32_t> keys, std::uint32_t key_count,
                          std::vector<std::uint32_t>& bucket_start,
                          std::vector<std::uint32_t>& sorted_items,
                          CountingSortWorkspace& workspace) {
  sort_by_key(
      keys, key_count, [](std::size_t item) { return static_cast<std::uint32_t>(item); },
      bucket_start, sorted_items, workspace);
}

void stable_counting_sort_payload(std::span<const std::uint32_t> keys, std::uint32_t key_count,
                                  std::span<const std::uint32_t> payload,
                                  std::vector<std::uint32_t>& bucket_start,
                                  std::vector<std::uint32_t>& sorted_payload,
                                  CountingSortWorkspace& workspace) {
  assert(payload.size() == keys.size());
  const std::uint32_t* const value = payload.data();
  sort_by_key(
      keys, key_count, [value](std::size_t item) { return value[item]; }, bucket_start,
      sorted_payload, workspace);
}

}  // namespace quarry
