// Spatial sort: a permutation that orders particles along a Morton (Z-order) curve of grid
// cells, so that particles close in space are close in memory (Morton, IBM report 1966).
// Applied now and then between steps (ParticleStore::permute), followed by a list rebuild.
#pragma once

#include <cstddef>
#include <vector>

#include "core/particle_store.h"

namespace quarry {

// Returns `order` such that new index k should hold old index order[k]: particles sorted by the
// Morton code of their cell (cubic cells of edge ≥ cell_size (m) over the bounding box, at most
// 2^21 per axis), ties broken by ParticleStore::id — deterministic for any thread count.
// Pre: cell_size > 0; ids unique. Throws PhysicsError for a non-finite position.
// Cost: O(n log n) (one std::sort of n keys); key computation parallel.
std::vector<std::size_t> spatial_order(const ParticleStore& particles, double cell_size);

}  // namespace quarry
