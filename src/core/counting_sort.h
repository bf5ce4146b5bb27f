// Stable counting sort of item indices by small integer keys (cell of a particle, partner of a
// pair, cell of a surface grid's triangle). Used when the neighbour lists and a moving
// surface's grid are rebuilt (time-step stage 2). O(n + keys); the OpenMP path gives exactly
// the serial result, so the output never depends on the thread count.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace quarry {

// Scratch memory reused between sorts so that a rebuild allocates nothing once warmed up.
struct CountingSortWorkspace {
  std::vector<std::uint32_t> per_thread_counts;  // threads × keys histograms of the parallel path
};

// Sorts the item indices 0..keys.size()-1 by keys[item] (each < key_count).
// Post: bucket_start has key_count+1 entries; the items with key c are
//   sorted_items[bucket_start[c] .. bucket_start[c+1]), in ascending item order (stable).
// Cost: O(keys.size() + key_count) work; parallel over items when that pays off.
// Pre: keys.size() < 2^32 and every key < key_count (checked by debug asserts only).
void stable_counting_sort(std::span<const std::uint32_t> keys, std::uint32_t key_count,
                          std::vector<std::uint32_t>& bucket_start,
                          std::vector<std::uint32_t>& sorted_items,
                          CountingSortWorkspace& workspace);

// The same grouping, but writes payload[item] instead of the item index: sorted_payload holds
// the payloads of the items with key c at [bucket_start[c], bucket_start[c+1]), in item order.
// Pre: payload.size() == keys.size().
void stable_counting_sort_payload(std::span<const std::uint32_t> keys, std::uint32_t key_count,
                                  std::span<const std::uint32_t> payload,
                                  std::vector<std::uint32_t>& bucket_start,
                                  std::vector<std::uint32_t>& sorted_payload,
                                  CountingSortWorkspace& workspace);

}  // namespace quarry
