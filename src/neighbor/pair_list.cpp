// Half Verlet list build: cell grid of edge 2·Rmax + skin; each adjacent cell pair visited
// once (half stencil) into per-thread buffers; pairs grouped by lower index with a stable
// counting sort and sorted by partner, so the list does not depend on the thread count;
// contact history matched by id pair; reverse index by a second counting sort.
#include "neighbor/pair_list.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>

#include <omp.h>

namespace quarry {

namespace {

constexpr std::uint32_t kNoIndex = std::numeric_limits<std::uint32_t>::max();
// Below this many particles a parallel region costs more than it saves.
constexpr std::size_t kParallelMinParticles = 4096;

// splitmix64 finaliser (Steele, Lea & Flood, OOPSLA 2014): spreads sequential ids over the table.
std::uint64_t mix_id(std::uint64_t x) {
  x ^= x >> 30; x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27; x *= 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Index at the last build of each current particle (kNoIndex if it is new), matched by id.
// Identity when the ids did not change (the common case: no re-sort, insertion or removal).
// Returns false for that identity case without filling old_index_of.
bool map_to_previous_indices(std::span<const ParticleId> ids, std::span<const ParticleId> previous_ids,
                             PairListWorkspace& workspace) {
  if (ids.size() == previous_ids.size() &&
      (ids.empty() || std::memcmp(ids.data(), previous_ids.data(), ids.size() * sizeof(ParticleId)) == 0))
    return false;
  std::size_t capacity = 16;
  while (capacity < 2 * previous_ids.size()) capacity *= 2;
  const std::size_t mask = capacity - 1;
  auto& keys = workspace.id_table_keys;
  auto& values = workspace.id_table_values;
  keys.resize(capacity);
  values.assign(capacity, kNoIndex);
  for (std::size_t old_index = 0; old_index < previous_ids.size(); ++old_index) {
    std::size_t slot = mix_id(previous_ids[old_index]) & mask;
    while (values[slot] != kNoIndex) slot = (slot + 1) & mask;
    keys[slot] = previous_ids[old_index];
    values[slot] = static_cast<std::uint32_t>(old_index);
  }
  const std::size_t n = ids.size();
  workspace.old_index_of.resize(n);
  std::uint32_t* const old_index_of = workspace.old_index_of.data();
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles)
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t slot = mix_id(ids[i]) & mask;
    while (values[slot] != kNoIndex && keys[slot] != ids[i]) slot = (slot + 1) & mask;
    old_index_of[i] = values[slot];
  }
  return true;
}

// Appends every pair found among the particles at grid positions [first, end) and their
// forward half stencil (the rest of their own cell, the next cell in x, the next row in y,
// the nine cells of the next layer in z — each unordered pair of adjacent cells once) to
// buffer as (lower index << 32 | higher index). Returns the number of pairs.
std::size_t collect_half_stencil_pairs(std::uint32_t first, std::uint32_t end, double skin,
                                       const CellGrid& grid, const PackedSphere* spheres,
                                       std::vector<std::uint64_t>& buffer) {
  const std::uint32_t* const particle_of = grid.sorted_particles.data();
  const std::uint32_t* const cell_start = grid.cell_start.data();
  const std::uint32_t nx = grid.cells_per_axis[0], ny = grid.cells_per_axis[1];
  const std::uint32_t nz = grid.cells_per_axis[2];
  std::size_t used = 0;
  std::uint32_t position = first;
  while (position < end) {
    // One cell at a time: its stencil rows are shared by all of its particles.
    const std::uint32_t cell = grid.particle_cell[particle_of[position]];
    const std::uint32_t cell_end = std::min(cell_start[cell + 1], end);
    const auto [cx, cy, cz] = grid.cell_coordinates(cell);
    const std::uint32_t x_first = cx > 0 ? cx - 1 : 0, x_last = cx + 1 < nx ? cx + 1 : nx - 1;
    // Ranges of grid positions: [begin, end) of the forward rows (at most four).
    std::uint32_t row_begin[4], row_end[4];
    int row_count = 0;
    if (cy + 1 < ny) {
      const std::uint32_t row = nx * (cy + 1 + ny * cz);
      row_begin[row_count] = cell_start[row + x_first];
      row_end[row_count++] = cell_start[row + x_last + 1];
    }
    if (cz + 1 < nz) {
      const std::uint32_t y_first = cy > 0 ? cy - 1 : 0, y_last = cy + 1 < ny ? cy + 1 : ny - 1;
      for (std::uint32_t y = y_first; y <= y_last; ++y) {
        const std::uint32_t row = nx * (y + ny * (cz + 1));
        row_begin[row_count] = cell_start[row + x_first];
        row_end[row_count++] = cell_start[row + x_last + 1];
      }
    }
    // Later particles of the own cell and the next cell in x are one contiguous range.
    const std::uint32_t own_end = cell_start[cx + 1 < nx ? cell + 2 : cell + 1];
    std::size_t stencil_size = own_end - position;
    for (int r = 0; r < row_count; ++r) stencil_size += row_end[r] - row_begin[r];
    const std::size_t needed = used + stencil_size * (cell_end - position);
    if (buffer.size() < needed) buffer.resize(std::max(2 * buffer.size(), needed + 4096));
    std::uint64_t* const out = buffer.data();

    for (; position < cell_end; ++position) {
      const PackedSphere self = spheres[position];
      const std::uint64_t i = particle_of[position];
      auto scan = [&](std::uint32_t begin, std::uint32_t stop) {
        for (std::uint32_t k = begin; k < stop; ++k) {
          const std::uint64_t j = particle_of[k];
          const double dx = spheres[k].x - self.x;
          const double dy = spheres[k].y - self.y;
          const double dz = spheres[k].z - self.z;
          const double reach = (self.radius + spheres[k].radius) + skin;  // m
          // Branch-free: write always, advance only for a pair (the test is unpredictable).
          out[used] = i < j ? (i << 32 | j) : (j << 32 | i);
          used += static_cast<std::size_t>(dx * dx + dy * dy + dz * dz < reach * reach);
        }
      };
      scan(position + 1, own_end);
      for (int r = 0; r < row_count; ++r) scan(row_begin[r], row_end[r]);
    }
  }
  return used;
}

// Copies the history of pair (i, j) from the previous list if both particles and the pair
// existed there; zero otherwise. History vectors are stored as seen from the lower index (i);
// both are antisymmetric in the pair (δt of i relative to j; rolling torque on i), so when the
// rebuild swaps which particle of the pair comes first they change sign.
void carry_history(std::uint32_t old_i, std::uint32_t old_j, const PairListWorkspace& previous,
                   Vec3& tangential_displacement, Vec3& rolling_torque) {
  tangential_displacement = Vec3{};
  rolling_torque = Vec3{};
  if (old_i == kNoIndex || old_j == kNoIndex) return;
  const std::uint32_t low = std::min(old_i, old_j), high = std::max(old_i, old_j);
  const std::uint32_t end = previous.previous_offsets[low + 1];
  for (std::uint32_t q = previous.previous_offsets[low]; q < end; ++q) {
    const std::uint32_t old_partner = previous.previous_partner[q];
    if (old_partner < high) continue;
    if (old_partner == high) {
      const double orientation = old_i < old_j ? 1.0 : -1.0;
      tangential_displacement = orientation * previous.previous_tangential_displacement[q];
      rolling_torque = orientation * previous.previous_rolling_torque[q];
    }
    return;
  }
}

}  // namespace

void build_pair_list(const ParticleStore& particles, double skin, PairList& list) {
  assert(skin >= 0.0);
  const std::size_t n = particles.size();
  assert(n < kNoIndex);
  PairListWorkspace& workspace = list.workspace;

  double largest_radius = 0.0;  // m
  const double* const radius = particles.radius.data();
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles) reduction(max : largest_radius)
  for (std::size_t i = 0; i < n; ++i) largest_radius = std::max(largest_radius, radius[i]);
  // Any pair within reach is closer than 2·Rmax + skin; a positive edge is needed even if that is 0.
  const double cell_edge = std::max(2.0 * largest_radius + skin, std::numeric_limits<double>::min());
  build_cell_grid(particles.position, cell_edge, workspace.grid, particles.id);
  const CellGrid& grid = workspace.grid;

  // Keep the previous list (for its history) while the new one is built into the old buffers.
  // Only after the grid: a non-finite position throws there and leaves the list untouched.
  const bool has_previous = list.builds > 0 && list.offsets.size() == list.ids_at_build.size() + 1;
  std::swap(list.offsets, workspace.previous_offsets);
  std::swap(list.partner, workspace.previous_partner);
  std::swap(list.tangential_displacement, workspace.previous_tangential_displacement);
  std::swap(list.rolling_torque, workspace.previous_rolling_torque);
  std::swap(list.ids_at_build, workspace.previous_ids);
  if (!has_previous) {
    workspace.previous_offsets.assign(1, 0);
    workspace.previous_partner.clear();
    workspace.previous_ids.clear();
  }
  const bool remapped = map_to_previous_indices(particles.id, workspace.previous_ids, workspace);
  const std::uint32_t* const old_index_of = remapped ? workspace.old_index_of.data() : nullptr;

  workspace.spheres_by_cell.resize(n);
  PackedSphere* const spheres = workspace.spheres_by_cell.data();
  const Vec3* const position = particles.position.data();
  const std::uint32_t* const sorted = grid.sorted_particles.data();
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles)
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = sorted[k];
    spheres[k] = {position[i].x, position[i].y, position[i].z, radius[i]};
  }

  // Pass 1: each thread finds the pairs of a contiguous block of grid positions.
  const int max_threads = n > kParallelMinParticles ? omp_get_max_threads() : 1;
  if (workspace.thread_pairs.size() < static_cast<std::size_t>(max_threads))
    workspace.thread_pairs.resize(static_cast<std::size_t>(max_threads));
  std::vector<std::size_t> block_start(static_cast<std::size_t>(max_threads) + 1, 0);
#pragma omp parallel num_threads(max_threads)
  {
    const std::size_t thread_count = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t thread = static_cast<std::size_t>(omp_get_thread_num());
    const auto first = static_cast<std::uint32_t>(n * thread / thread_count);
    const auto end = static_cast<std::uint32_t>(n * (thread + 1) / thread_count);
    std::vector<std::uint64_t>& buffer = workspace.thread_pairs[thread];
    const std::size_t used = collect_half_stencil_pairs(first, end, skin, grid, spheres, buffer);
    block_start[thread + 1] = used;
#pragma omp barrier
#pragma omp single
    {
      for (std::size_t t = 0; t < thread_count; ++t) block_start[t + 1] += block_start[t];
      assert(block_start[thread_count] < kNoIndex);
      workspace.pair_lower.resize(block_start[thread_count]);
      workspace.pair_higher.resize(block_start[thread_count]);
    }
    std::uint32_t* const lower = workspace.pair_lower.data() + block_start[thread];
    std::uint32_t* const higher = workspace.pair_higher.data() + block_start[thread];
    for (std::size_t p = 0; p < used; ++p) {
      lower[p] = static_cast<std::uint32_t>(buffer[p] >> 32);
      higher[p] = static_cast<std::uint32_t>(buffer[p]);
    }
  }
  const std::size_t pair_count = workspace.pair_lower.size();

  // Pass 2: group by lower index (CSR), then partners ascending within each i. The found order
  // depends on the thread blocks; the sorted result does not.
  stable_counting_sort_payload(workspace.pair_lower, static_cast<std::uint32_t>(n),
                               workspace.pair_higher, list.offsets, list.partner,
                               workspace.pair_sort);
  list.tangential_displacement.resize(pair_count);
  list.rolling_torque.resize(pair_count);
  const std::uint32_t* const offsets = list.offsets.data();
  std::uint32_t* const partner = list.partner.data();
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles)
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t begin = offsets[i], stop = offsets[i + 1];
    // A handful of partners: insertion sort.
    for (std::uint32_t k = begin + 1; k < stop; ++k) {
      const std::uint32_t value = partner[k];
      std::uint32_t slot = k;
      for (; slot > begin && partner[slot - 1] > value; --slot) partner[slot] = partner[slot - 1];
      partner[slot] = value;
    }
    const std::uint32_t old_i = old_index_of ? old_index_of[i] : static_cast<std::uint32_t>(i);
    for (std::uint32_t k = begin; k < stop; ++k) {
      const std::uint32_t j = partner[k];
      const std::uint32_t old_j = old_index_of ? old_index_of[j] : j;
      carry_history(old_i, old_j, workspace, list.tangential_displacement[k], list.rolling_torque[k]);
    }
  }

  stable_counting_sort(list.partner, static_cast<std::uint32_t>(n), list.reverse_offsets,
                       list.reverse_pairs, workspace.reverse_sort);
  list.reference_positions.assign(particles.position.begin(), particles.position.end());
  list.ids_at_build.assign(particles.id.begin(), particles.id.end());
  list.skin = skin;
  ++list.builds;
}

bool pair_list_needs_rebuild(const ParticleStore& particles, const PairList& list,
                             double extra_displacement) {
  const std::size_t n = particles.size();
  if (list.builds == 0 || list.reference_positions.size() != n || list.ids_at_build.size() != n)
    return true;
  const Vec3* const position = particles.position.data();
  const Vec3* const reference = list.reference_positions.data();
  const ParticleId* const id = particles.id.data();
  const ParticleId* const id_at_build = list.ids_at_build.data();
  double largest_displacement_squared = 0.0;  // m²
  bool ids_changed = false;
  bool all_finite = true;  // std::max would silently drop a NaN displacement
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles) \
    reduction(max : largest_displacement_squared) reduction(|| : ids_changed) reduction(&& : all_finite)
  for (std::size_t i = 0; i < n; ++i) {
    const double displacement_squared = norm2(position[i] - reference[i]);  // m²
    largest_displacement_squared = std::max(largest_displacement_squared, displacement_squared);
    all_finite = all_finite && std::isfinite(displacement_squared);
    ids_changed = ids_changed || id[i] != id_at_build[i];
  }
  // A diverged particle forces a rebuild, which reports it (build_cell_grid throws).
  if (ids_changed || !all_finite) return true;
  return std::sqrt(largest_displacement_squared) + extra_displacement > 0.5 * list.skin;
}

}  // namespace quarry
