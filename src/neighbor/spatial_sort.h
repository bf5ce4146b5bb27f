// Spatial sort: a permutation that orders particles along a Hilbert curve of grid cells, so
// that particles close in space are close in memory (Hilbert 1891; Skilling 2004 for the index).
// Applied now and then between steps (ParticleStore::permute), followed by a list rebuild.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/particle_store.h"

namespace quarry {

// Returns `order` such that new index k should hold old index order[k]: particles sorted by the
// Hilbert index of their cell (cubic cells of edge ≥ cell_size (m) over the bounding box, at most
// 2^21 per axis), ties broken by ParticleStore::id — deterministic for any thread count.
// Pre: cell_size > 0; ids unique. Throws PhysicsError for a non-finite position.
// Cost: O(n log n) (one std::sort of n keys); key computation parallel.
std::vector<std::size_t> spatial_order(const ParticleStore& particles, double cell_size);

// Index of cell `cell` along the 3-D Hilbert curve through the 2^bits cells per axis (1 ≤ bits
// ≤ 21, every coordinate < 2^bits): consecutive indices are face-neighbouring cells.
std::uint64_t hilbert_index(std::array<std::uint32_t, 3> cell, int bits);

}  // namespace quarry
