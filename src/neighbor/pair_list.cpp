// Half Verlet list build: cell grid of edge 2·Rmax + skin; every particle scans the 27 cells
// around its own for partners of higher index (so each row is complete and sorted on its own,
// whatever the thread count), in chunks of rows that each list into a buffer of their own,
// then copied into the exact-size CSR arrays; contact history is carried from the previous
// build's contacts, matched by particle-id pair.
#include "neighbor/pair_list.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>

#include <omp.h>

#include "core/lanes.h"

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

template <class T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}
template <class T>
void release(ScratchArray<T>& v) {
  v.release();
}

// Sizes v to `count` elements that the caller then overwrites, in the memory v already has:
// it is mapped, so the refill takes no page faults and only the elements beyond the old size
// are zeroed first (at 200k particles a fresh 20 MB list cost 8 ms a build, serial). A fresh
// array if v is too small or more than a quarter too large (the list shrank: give the memory
// back), with room for 1/64 more: the pair count of a settled bed drifts by a fraction of a
// per cent from build to build, and an array of exactly `count` was re-made whenever it grew
// by one pair. The room is not written: it costs address space and, on huge pages, at most
// one more resident page per array.
template <class T>
void resize_for_refill(std::vector<T>& v, std::size_t count) {
  if (count > v.capacity() || v.capacity() - count > count / 4) {
    release(v);
    v.reserve(count + count / 64);
  }
  v.resize(count);
}

// Index at the last build of each current particle (kNoIndex if it is new), matched by id.
// Identity when the ids did not change (the common case: no re-sort, insertion or removal).
// Returns false for that identity case without filling old_index_of. Ids are usually compact
// (a run numbers its particles 1, 2, 3, ...): then a direct table of 4 bytes per id is used,
// else an open-addressing hash.
bool map_to_previous_indices(std::span<const ParticleId> ids, std::span<const ParticleId> previous_ids,
                             PairListWorkspace& workspace) {
  if (ids.size() == previous_ids.size() &&
      (ids.empty() || std::memcmp(ids.data(), previous_ids.data(), ids.size() * sizeof(ParticleId)) == 0))
    return false;
  const std::size_t n = ids.size();
  workspace.old_index_of.resize(n);
  std::uint32_t* const old_index_of = workspace.old_index_of.data();
  auto& values = workspace.id_table;
  ParticleId lowest = std::numeric_limits<ParticleId>::max(), highest = 0;
  for (ParticleId id : previous_ids) lowest = std::min(lowest, id), highest = std::max(highest, id);
  if (!previous_ids.empty() && highest - lowest < 2 * previous_ids.size() + 1024) {
    values.assign(highest - lowest + 1, kNoIndex);
    for (std::size_t old_index = 0; old_index < previous_ids.size(); ++old_index)
      values[previous_ids[old_index] - lowest] = static_cast<std::uint32_t>(old_index);
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles)
    for (std::size_t i = 0; i < n; ++i)
      old_index_of[i] = ids[i] >= lowest && ids[i] <= highest ? values[ids[i] - lowest] : kNoIndex;
  } else {
    std::size_t capacity = 16;
    while (capacity < 2 * previous_ids.size()) capacity *= 2;
    const std::size_t mask = capacity - 1;
    auto& keys = workspace.id_table_keys;
    keys.resize(capacity);
    values.assign(capacity, kNoIndex);
    for (std::size_t old_index = 0; old_index < previous_ids.size(); ++old_index) {
      std::size_t slot = mix_id(previous_ids[old_index]) & mask;
      while (values[slot] != kNoIndex) slot = (slot + 1) & mask;
      keys[slot] = previous_ids[old_index];
      values[slot] = static_cast<std::uint32_t>(old_index);
    }
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles)
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t slot = mix_id(ids[i]) & mask;
      while (values[slot] != kNoIndex && keys[slot] != ids[i]) slot = (slot + 1) & mask;
      old_index_of[i] = values[slot];
    }
    release(keys);
  }
  release(values);
  return true;
}

// Four candidates at a time (core/lanes.h); their indices as four 32-bit lanes.
typedef std::uint32_t Indices __attribute__((vector_size(16)));
typedef std::uint32_t UnalignedIndices __attribute__((vector_size(16), aligned(4), may_alias));
constexpr std::size_t kLanes = 4;

// The particles in the grid's cell order: positions (m), radii (m) and indices as arrays of
// their own, so that a cell row's candidates are consecutive lanes instead of a gather by
// index; kLanes entries of padding (index 0, never a partner) let a block read past a row's
// end. Transient: made for one build's distance pass (36 B a particle).
struct BinnedParticles {
  ScratchArray<double> x, y, z, radius;
  ScratchArray<std::uint32_t> index;
};

void bin_particles(const CellGrid& grid, const Vec3* position, const double* radius,
                   BinnedParticles& b) {
  const std::size_t n = grid.sorted_particles.size();
  for (auto* a : {&b.x, &b.y, &b.z, &b.radius}) a->size_for_overwrite(n + kLanes);
  b.index.size_for_overwrite(n + kLanes);
  const std::uint32_t* const sorted = grid.sorted_particles.data();
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles)
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t p = sorted[k];
    b.x[k] = position[p].x, b.y[k] = position[p].y, b.z[k] = position[p].z;
    b.radius[k] = radius[p];
    b.index[k] = p;
  }
  for (std::size_t k = n; k < n + kLanes; ++k)
    b.x[k] = b.y[k] = b.z[k] = b.radius[k] = 0.0, b.index[k] = 0;
}

// The lanes of `keep` (each all ones or all zeros) as bits: bit m is lane m.
[[gnu::always_inline]] inline unsigned lane_bits(Mask keep) {
#ifdef __AVX__
  return static_cast<unsigned>(__builtin_ia32_movmskpd256(reinterpret_cast<Lanes>(keep)));
#else
  return static_cast<unsigned>((keep[0] & 1) | (keep[1] & 2) | (keep[2] & 4) | (keep[3] & 8));
#endif
}

// For each set of kept lanes (bit m: lane m), the lanes in order, then any lane (unused).
constexpr Indices kCompaction[16] = {
    {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 2, 0, 0},
    {1, 2, 0, 0}, {0, 1, 2, 0}, {3, 0, 0, 0}, {0, 3, 0, 0}, {1, 3, 0, 0}, {0, 1, 3, 0},
    {2, 3, 0, 0}, {0, 2, 3, 0}, {1, 2, 3, 0}, {0, 1, 2, 3}};

// Appends to out[used...] every particle j > i with |xj − xi|² < ((Ri + Rj) + skin)², scanning
// the 3×3×3 cells around i's cell (the cells cx−1..cx+1 of one row are one contiguous range),
// four candidates at a time; grows `out` as needed. Each lane evaluates the expression above
// with the same operations in the same order as the scalar search (and the brute-force check
// of the tests), so the list is the same to the last pair. Branch-free: a block's partners are
// moved to its front and all four lanes written, `used` advancing by the partners' count.
// Whether j > i is a coin toss for the branch predictor (the cells hold particles in spatial,
// not index, order), so a branch on it missed half the time (issue 21: the list build is most
// of a flowing run's neighbour stage).
inline void append_partners(std::uint32_t i, const Vec3* position, const double* radius, double skin,
                            const CellGrid& grid, const BinnedParticles& binned,
                            std::vector<std::uint32_t>& out, std::size_t& used) {
  const std::uint32_t* const cell_start = grid.cell_start.data();
  const std::uint32_t nx = grid.cells_per_axis[0], ny = grid.cells_per_axis[1];
  const std::uint32_t nz = grid.cells_per_axis[2];
  const auto [cx, cy, cz] = grid.cell_coordinates(grid.particle_cell[i]);
  const std::uint32_t x_first = cx > 0 ? cx - 1 : 0, x_last = cx + 1 < nx ? cx + 1 : nx - 1;
  const std::uint32_t y_first = cy > 0 ? cy - 1 : 0, y_last = cy + 1 < ny ? cy + 1 : ny - 1;
  const std::uint32_t z_first = cz > 0 ? cz - 1 : 0, z_last = cz + 1 < nz ? cz + 1 : nz - 1;
  const Vec3 xi = position[i];
  const double ri = radius[i];
  const Lanes x = Lanes{} + xi.x, y = Lanes{} + xi.y, z = Lanes{} + xi.z;
  const Lanes r = Lanes{} + ri, s = Lanes{} + skin;
  const Mask self = Mask{} + static_cast<std::int64_t>(i);
  const Mask lane = {0, 1, 2, 3};
  for (std::uint32_t row_z = z_first; row_z <= z_last; ++row_z)
    for (std::uint32_t row_y = y_first; row_y <= y_last; ++row_y) {
      const std::uint32_t row = nx * (row_y + ny * row_z);
      const std::uint32_t begin = cell_start[row + x_first], stop = cell_start[row + x_last + 1];
      // Enough if every candidate is a partner, and for the writes of a last block's lanes
      // beyond the row.
      const std::size_t room = used + (stop - begin) + kLanes;
      if (room > out.size()) out.resize(std::max(2 * out.size(), room));
      std::uint32_t* const destination = out.data();
      for (std::uint32_t k = begin; k < stop; k += kLanes) {
        const Lanes dx = load_lanes(binned.x.data() + k) - x;
        const Lanes dy = load_lanes(binned.y.data() + k) - y;
        const Lanes dz = load_lanes(binned.z.data() + k) - z;
        const Lanes reach = (r + load_lanes(binned.radius.data() + k)) + s;  // m
        const Indices j = *reinterpret_cast<const UnalignedIndices*>(binned.index.data() + k);
        const Mask keep = ((dx * dx + dy * dy) + dz * dz < reach * reach) &
                          (__builtin_convertvector(j, Mask) > self) &
                          (lane < static_cast<std::int64_t>(stop - k));
        // The kept lanes' indices moved to the front and written as one block.
        const unsigned bits = lane_bits(keep);
        *reinterpret_cast<UnalignedIndices*>(destination + used) =
            __builtin_shuffle(j, kCompaction[bits]);
        used += static_cast<unsigned>(__builtin_popcount(bits));
      }
    }
}

// The cells along one axis that the search around cell c scans, into `cells`; returns how
// many. Non-periodic: c−1..c+1 clipped to the grid. Periodic: c−1, c, c+1 wrapped around the
// period, or every cell of the axis if it has fewer than three (each cell once: no pair twice).
inline int cells_around(const CellGrid& grid, int axis, std::uint32_t c, std::uint32_t* cells) {
  const std::uint32_t n = grid.cells_per_axis[axis];
  int count = 0;
  if (!grid.wraps[axis]) {
    for (std::uint32_t k = c > 0 ? c - 1 : 0; k <= c + 1 && k < n; ++k) cells[count++] = k;
  } else if (n < 3) {
    for (std::uint32_t k = 0; k < n; ++k) cells[count++] = k;
  } else {
    cells[count++] = c > 0 ? c - 1 : n - 1;
    cells[count++] = c;
    cells[count++] = c + 1 < n ? c + 1 : 0;
  }
  return count;
}

// The partners of append_partners across periodic faces: the cells around i's cell wrap on
// periodic axes, and the separation is the minimum image. Needed only for a particle in a cell
// at a periodic face (at_periodic_face); a separate function, so that every other search keeps
// its contiguous row ranges and plain differences.
template <class Visit>
inline void for_each_periodic_partner(std::uint32_t i, const Vec3* position, const double* radius,
                                      double skin, const CellGrid& grid, const PeriodicBox& box,
                                      Visit&& visit) {
  const std::uint32_t* const particle_of = grid.sorted_particles.data();
  const std::uint32_t* const cell_start = grid.cell_start.data();
  const std::uint32_t nx = grid.cells_per_axis[0], ny = grid.cells_per_axis[1];
  const auto [cx, cy, cz] = grid.cell_coordinates(grid.particle_cell[i]);
  std::uint32_t xs[3], ys[3], zs[3];
  const int x_count = cells_around(grid, 0, cx, xs);
  const int y_count = cells_around(grid, 1, cy, ys);
  const int z_count = cells_around(grid, 2, cz, zs);
  const Vec3 xi = position[i];
  const double ri = radius[i];
  for (int c = 0; c < z_count; ++c)
    for (int b = 0; b < y_count; ++b) {
      const std::uint32_t row = nx * (ys[b] + ny * zs[c]);
      for (int a = 0; a < x_count; ++a) {
        const std::uint32_t cell = row + xs[a];
        for (std::uint32_t k = cell_start[cell]; k < cell_start[cell + 1]; ++k) {
          const std::uint32_t j = particle_of[k];
          if (j <= i) continue;
          const Vec3 d = box.minimum_image(position[j] - xi);  // m
          const double reach = (ri + radius[j]) + skin;        // m
          if (d.x * d.x + d.y * d.y + d.z * d.z < reach * reach) visit(j);
        }
      }
    }
}

// True if the cells around `cell` wrap around a periodic axis (it is the first or last cell
// along it, or the axis has fewer than three). A particle in any other cell needs no image:
// with positions inside the period and at least three cells, a partner within reach (less than
// a cell edge away) is in an adjacent cell without wrapping, and the plain difference is its
// minimum image; one across the face is more than a whole cell away (an interior cell is at
// least one edge from both faces).
inline bool at_periodic_face(const CellGrid& grid, std::uint32_t cell) {
  const auto c = grid.cell_coordinates(cell);
  for (int a = 0; a < 3; ++a)
    if (grid.wraps[a] &&
        (grid.cells_per_axis[a] < 3 || c[a] == 0 || c[a] + 1 == grid.cells_per_axis[a]))
      return true;
  return false;
}

// Copies of the list being replaced the pairs that carry history (the contacts) into
// workspace.previous_*: about two thirds of the pairs in a settled bed. The list's own arrays
// are then refilled with the new list (resize_for_refill), so the build holds one list and
// the contacts, never two lists. Branch-free (whether a listed pair touches is a coin toss
// for the predictor): every pair is copied, to its place if it carries history, else to a
// spare slot of its thread past the kept ones.
void keep_previous_contacts(PairList& list, std::size_t previous_count) {
  PairListWorkspace& w = list.workspace;
  const bool rolling = !list.rolling_torque.empty();
  const bool jkr = !list.jkr_attached.empty();
  const Vec3* const tangential = list.tangential_displacement.data();
  const double* const normal_force = list.normal_force.data();
  const auto has_history = [&](std::uint32_t k) -> std::uint32_t {
    const Vec3& t = tangential[k];
    std::uint32_t any = (t.x != 0.0) | (t.y != 0.0) | (t.z != 0.0) | (normal_force[k] != 0.0);
    if (rolling) {
      const Vec3& r = list.rolling_torque[k];
      any |= (r.x != 0.0) | (r.y != 0.0) | (r.z != 0.0);
    }
    if (jkr) any |= list.jkr_attached[k] != 0;
    return any;
  };
  w.previous_offsets.assign(previous_count + 1, 0);
  const bool parallel = previous_count > kParallelMinParticles;
#pragma omp parallel for schedule(static) if (parallel)
  for (std::size_t i = 0; i < previous_count; ++i) {
    std::uint32_t kept = 0;
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) kept += has_history(k);
    w.previous_offsets[i + 1] = kept;
  }
  for (std::size_t i = 0; i < previous_count; ++i) w.previous_offsets[i + 1] += w.previous_offsets[i];
  const std::size_t kept = w.previous_offsets[previous_count];
  // Each thread's spare slot a cache line of every array from the kept slots and the others'
  // (written at every pair without history: shared lines would bounce between the cores).
  constexpr std::size_t kSpacing = 64;  // slots (64 B of the narrowest array)
  const std::size_t spares =
      kSpacing * (1 + (parallel ? static_cast<std::size_t>(omp_get_max_threads()) : 1));
  w.previous_partner.size_for_overwrite(kept + spares);
  w.previous_tangential_displacement.size_for_overwrite(kept + spares);
  w.previous_normal_force.size_for_overwrite(kept + spares);
  w.previous_rolling_torque.size_for_overwrite(rolling ? kept + spares : 0);
  w.previous_jkr_attached.size_for_overwrite(jkr ? kept + spares : 0);
#pragma omp parallel if (parallel)
  {
    // (A team of one, when not parallel: thread 0.)
    const std::size_t spare = kept + kSpacing * (1 + static_cast<std::size_t>(omp_get_thread_num()));
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < previous_count; ++i) {
      std::size_t out = w.previous_offsets[i];
      for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
        const std::uint32_t keep = has_history(k);
        const std::size_t to = keep ? out : spare;
        w.previous_partner[to] = list.partner[k];
        w.previous_tangential_displacement[to] = tangential[k];
        w.previous_normal_force[to] = normal_force[k];
        if (rolling) w.previous_rolling_torque[to] = list.rolling_torque[k];
        if (jkr) w.previous_jkr_attached[to] = list.jkr_attached[k];
        out += keep;
      }
    }
  }
}

// History of pair (i, j) from the previous contacts if both particles and the contact existed
// there; zero otherwise. History vectors are stored as seen from the lower index (i); both are
// antisymmetric in the pair (δt of i relative to j; rolling torque on i), so when the rebuild
// swaps which particle of the pair comes first they change sign. The JKR flag and the normal
// force (+ repulsive) are symmetric.
void carry_history(std::uint32_t old_i, std::uint32_t old_j, const PairListWorkspace& previous,
                   Vec3& tangential_displacement, double& normal_force, Vec3* rolling_torque,
                   std::uint8_t* jkr_attached) {
  tangential_displacement = Vec3{};
  normal_force = 0.0;
  if (rolling_torque) *rolling_torque = Vec3{};
  if (jkr_attached) *jkr_attached = 0;
  if (old_i == kNoIndex || old_j == kNoIndex) return;
  const std::uint32_t low = std::min(old_i, old_j), high = std::max(old_i, old_j);
  const std::uint32_t end = previous.previous_offsets[low + 1];
  for (std::uint32_t q = previous.previous_offsets[low]; q < end; ++q) {
    const std::uint32_t old_partner = previous.previous_partner[q];
    if (old_partner < high) continue;
    if (old_partner == high) {
      const double orientation = old_i < old_j ? 1.0 : -1.0;
      tangential_displacement = orientation * previous.previous_tangential_displacement[q];
      normal_force = previous.previous_normal_force[q];
      if (rolling_torque && !previous.previous_rolling_torque.empty())
        *rolling_torque = orientation * previous.previous_rolling_torque[q];
      if (jkr_attached && !previous.previous_jkr_attached.empty())
        *jkr_attached = previous.previous_jkr_attached[q];
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
  // First: a non-finite position throws here and leaves the list untouched.
  // With periodic axes the search runs on the positions moved into the period (a particle may
  // be up to skin/2 outside between the World's wraps, or anywhere for another caller).
  const bool periodic = list.periodic.any();
  if (periodic) {
    workspace.wrapped_positions.resize(n);
    Vec3* const wrapped = workspace.wrapped_positions.data();
    const PeriodicBox& box = list.periodic;
    const Vec3* const given = particles.position.data();
#pragma omp parallel for schedule(static) if (n > kParallelMinParticles)
    for (std::size_t i = 0; i < n; ++i) wrapped[i] = box.wrapped(given[i]);
  }
  const std::span<const Vec3> search_positions =
      periodic ? std::span<const Vec3>(workspace.wrapped_positions)
               : std::span<const Vec3>(particles.position);
  build_cell_grid(search_positions, cell_edge, workspace.grid, particles.id,
                  periodic ? &list.periodic : nullptr);
  const CellGrid& grid = workspace.grid;
  const Vec3* const position = search_positions.data();
  BinnedParticles binned;
  bin_particles(grid, position, radius, binned);
  // Refilled at the end; not needed meanwhile (a lower peak while the contacts are kept).
  release(list.reference_positions);

  // Where each particle was at the last build, by id. Done first, while the least memory is
  // held: the id table is freed before the previous contacts are copied.
  const bool has_previous = list.builds > 0 && list.offsets.size() == list.ids_at_build.size() + 1;
  const std::size_t previous_count = has_previous ? list.ids_at_build.size() : 0;
  std::swap(workspace.previous_ids, list.ids_at_build);
  const bool remapped = has_previous && map_to_previous_indices(particles.id, workspace.previous_ids, workspace);
  const std::uint32_t* const old_index_of = remapped ? workspace.old_index_of.data() : nullptr;
  const bool same_particles = has_previous && !remapped;
  release(workspace.previous_ids);

  // One pass over the distances: each chunk of rows lists its partners into a buffer of its
  // own (a row's size is not known before), copied into place below. Counting first and then
  // filling computed every distance twice (issue 21: the list build was 23 % of the flagship's
  // run). The buffers hold 4 B per pair while the list is built.
  constexpr std::size_t kChunkRows = 1024;
  const std::size_t chunk_count = (n + kChunkRows - 1) / kChunkRows;
  const std::size_t expected_per_row =  // partners per row, from the last build
      has_previous && previous_count > 0 ? list.partner.size() / previous_count + 1 : 8;
  std::vector<std::vector<std::uint32_t>> found(chunk_count);
  std::vector<std::uint32_t> offsets(n + 1, 0);
#pragma omp parallel for schedule(dynamic, 1) if (n > kParallelMinParticles)
  for (std::size_t c = 0; c < chunk_count; ++c) {
    std::vector<std::uint32_t>& mine = found[c];
    mine.resize(kChunkRows * expected_per_row);  // grown as needed; trimmed to `used` below
    std::size_t used = 0;
    const auto listed = [&mine, &used](std::uint32_t j) {
      if (used == mine.size()) mine.resize(2 * mine.size() + 16);
      mine[used++] = j;
    };
    for (std::size_t i = c * kChunkRows; i < std::min(n, (c + 1) * kChunkRows); ++i) {
      const std::size_t before = used;
      if (periodic && at_periodic_face(grid, grid.particle_cell[i]))
        for_each_periodic_partner(static_cast<std::uint32_t>(i), position, radius, skin, grid,
                                  list.periodic, listed);
      else
        append_partners(static_cast<std::uint32_t>(i), position, radius, skin, grid, binned, mine,
                        used);
      offsets[i + 1] = static_cast<std::uint32_t>(used - before);
    }
    mine.resize(used);
  }
  binned = {};  // freed before the previous contacts are kept: the build's peak is there
  for (std::size_t i = 0; i < n; ++i) {
    assert(std::size_t{offsets[i]} + offsets[i + 1] < kNoIndex);
    offsets[i + 1] += offsets[i];
  }
  const std::size_t pair_count = offsets[n];

  // The previous list's contacts, for their history; then the list's arrays refilled.
  keep_previous_contacts(list, previous_count);
  list.offsets = std::move(offsets);
  resize_for_refill(list.partner, pair_count);
  resize_for_refill(list.tangential_displacement, pair_count);
  resize_for_refill(list.normal_force, pair_count);
  resize_for_refill(list.rolling_torque, list.keep_rolling_history ? pair_count : 0);
  resize_for_refill(list.jkr_attached, list.keep_jkr_history ? pair_count : 0);
  const std::uint32_t* const row = list.offsets.data();
  std::uint32_t* const partner = list.partner.data();
  Vec3* const tangential = list.tangential_displacement.data();
  double* const normal_force = list.normal_force.data();
  Vec3* const rolling = list.rolling_torque.empty() ? nullptr : list.rolling_torque.data();
  std::uint8_t* const attached = list.jkr_attached.empty() ? nullptr : list.jkr_attached.data();

  // Each chunk's partners into place; each row sorted by partner, with the history of its
  // continuing contacts.
#pragma omp parallel for schedule(dynamic, 1) if (n > kParallelMinParticles)
  for (std::size_t c = 0; c < chunk_count; ++c) {
    const std::size_t first = c * kChunkRows, last = std::min(n, first + kChunkRows);
    std::copy(found[c].begin(), found[c].end(), partner + row[first]);
    release(found[c]);
    for (std::size_t i = first; i < last; ++i) {
      const std::uint32_t begin = row[i], stop = row[i + 1];
      // A handful of partners: insertion sort.
      for (std::uint32_t k = begin + 1; k < stop; ++k) {
        const std::uint32_t value = partner[k];
        std::uint32_t slot = k;
        for (; slot > begin && partner[slot - 1] > value; --slot) partner[slot] = partner[slot - 1];
        partner[slot] = value;
      }
      const std::uint32_t old_i =
          old_index_of ? old_index_of[i] : (has_previous ? static_cast<std::uint32_t>(i) : kNoIndex);
      for (std::uint32_t k = begin; k < stop; ++k) {
        const std::uint32_t j = partner[k];
        const std::uint32_t old_j = old_index_of ? old_index_of[j] : (same_particles ? j : kNoIndex);
        carry_history(old_i, old_j, workspace, tangential[k], normal_force[k],
                      rolling ? rolling + k : nullptr, attached ? attached + k : nullptr);
      }
    }
  }

  release(workspace.previous_offsets);
  release(workspace.previous_partner);
  release(workspace.previous_tangential_displacement);
  release(workspace.previous_normal_force);
  release(workspace.previous_rolling_torque);
  release(workspace.previous_jkr_attached);
  release(workspace.previous_ids);
  release(workspace.old_index_of);
  list.reference_positions.assign(particles.position.begin(), particles.position.end());
  list.ids_at_build.assign(particles.id.begin(), particles.id.end());
  list.skin = skin;
  ++list.builds;
}

void remove_from_pair_list(PairList& list, const std::vector<char>& removed) {
  const std::size_t n = removed.size();
  assert(list.built_for(n) && list.offsets.size() == n + 1);
  const std::vector<std::uint32_t> new_index = indices_after_removal(removed);  // of kept ones
  const std::size_t kept = static_cast<std::size_t>(std::count(removed.begin(), removed.end(), 0));
  const bool rolling = !list.rolling_torque.empty();
  const bool jkr = !list.jkr_attached.empty();
  // In place, front to back: an entry or row only ever moves to a lower position. Until the
  // first pair is dropped (out == k), a partner before the first removed particle keeps its
  // index and its place: a row's partners ascend, so those are the row's head, passed over.
  const auto first = static_cast<std::uint32_t>(first_removed(removed));
  std::size_t out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t begin = list.offsets[i], end = list.offsets[i + 1];
    if (removed[i]) continue;
    list.offsets[new_index[i]] = static_cast<std::uint32_t>(out);
    std::uint32_t k = begin;
    if (out == begin) {
      while (k < end && list.partner[k] < first) ++k;
      out = k;
    }
    for (; k < end; ++k) {
      const std::uint32_t j = list.partner[k];
      if (removed[j]) continue;
      list.partner[out] = new_index[j];  // ascending still: new_index keeps the order
      if (out != k) {  // up to the first pair dropped, the pairs' histories stay in place
        list.tangential_displacement[out] = list.tangential_displacement[k];
        list.normal_force[out] = list.normal_force[k];
        if (rolling) list.rolling_torque[out] = list.rolling_torque[k];
        if (jkr) list.jkr_attached[out] = list.jkr_attached[k];
      }
      ++out;
    }
    if (new_index[i] != i) {
      list.reference_positions[new_index[i]] = list.reference_positions[i];
      list.ids_at_build[new_index[i]] = list.ids_at_build[i];
    }
  }
  list.offsets.resize(kept + 1);
  list.offsets[kept] = static_cast<std::uint32_t>(out);
  list.partner.resize(out);
  list.tangential_displacement.resize(out);
  list.normal_force.resize(out);
  if (rolling) list.rolling_torque.resize(out);
  if (jkr) list.jkr_attached.resize(out);
  list.reference_positions.resize(kept);
  list.ids_at_build.resize(kept);
  ++list.builds;
}

bool pair_list_needs_rebuild(const ParticleStore& particles, const PairList& list,
                             double surface_displacement) {
  const std::size_t n = particles.size();
  if (list.builds == 0 || !list.built_for(n)) return true;
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
  if (!all_finite) return true;
  return pair_list_needs_rebuild(list, largest_displacement_squared, ids_changed, surface_displacement);
}

bool pair_list_needs_rebuild(const PairList& list, double largest_displacement_squared, bool ids_changed,
                             double surface_displacement) {
  if (list.builds == 0 || ids_changed || !std::isfinite(largest_displacement_squared)) return true;
  const double largest = std::sqrt(largest_displacement_squared);  // m
  return largest > 0.5 * list.skin || largest + surface_displacement > list.skin;
}

}  // namespace quarry
