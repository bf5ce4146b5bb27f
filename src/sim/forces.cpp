// Force stage (DESIGN §2 step 3). Particle–particle contacts are computed once per pair of the
// half list and added straight onto both particles ("Newton's third law" accumulation), with a
// summation order that does not depend on the thread count; body forces are added as soon as a
// particle's pair sum is complete; then particle–surface contacts for the particles near a
// surface, their reactions gathered onto triangles and vertices in particle order.
//
// Why the order is fixed. The list holds pair (i, j) only in row i, with j > i, rows ascending.
// A serial pass (zero all, then rows in order: F_i += f, F_j −= f) adds onto particle p first
// the pairs (k, p) with k < p in ascending k, then p's own row in row order — and after row p
// nothing touches p again. With T threads each owns a contiguous range of rows. A pair whose
// partner lies in a later thread's range ("crossing") is computed first and its result kept;
// after a barrier each thread starts its particles from the crossing contributions of earlier
// ranges (ascending source row), then runs its rows exactly as the serial pass, taking the kept
// result for its own crossing pairs. Every particle thus receives the same terms in the same
// order for any T: the sums are bit-identical (checked by the determinism tests). Crossing pairs
// are few (the ranges are compact in space after the space-filling-curve sort).
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "contact/hertz_mindlin_batch.h"
#include "sim/step.h"

namespace quarry::sim {

namespace {

using CrossingPair = ForceWorkspace::CrossingPair;
// CrossingPair::partner of a crossing pair that does not touch (nothing to add).
constexpr std::uint32_t kNotTouching = 0xffffffffu;

// Raw views of the arrays the pair loop reads; through the vectors the compiler would have to
// reload particle data after every store (possible aliasing of Vec3 arrays).
struct PairView {
  const Vec3* position;
  const Vec3* velocity;
  const Vec3* angular_velocity;
  const double* radius;
  const double* inv_mass;
  const std::uint16_t* material;
  const std::uint32_t* partner;
  Vec3* tangential;
  Vec3* rolling;  // null without rolling history
  const MaterialTable* materials;
  double dt;            // s
  double overlap_limit;  // fraction of the smaller radius
};

// Head of both paths for pair k = (i, j): x_i − x_j and its square. False if the spheres do not
// touch; the pair's history is then reset (the spring is released when contact is lost).
// Otherwise sets `excessive` if the overlap passes the guard's limit (check_overlaps reports
// it after the step): δ > limit·min(Ri, Rj) ⇔ |d| < touch − limit·min(Ri, Rj).
[[gnu::always_inline]] inline bool touching(const PairView& v, std::uint32_t i, std::uint32_t j,
                                            std::uint32_t k, Vec3& d, double& distance2, int& excessive) {
  d = v.position[i] - v.position[j];
  const double touch = v.radius[i] + v.radius[j];  // m
  distance2 = norm2(d);                            // m²
  if (distance2 >= touch * touch) {
    v.tangential[k] = {};
    if (v.rolling) v.rolling[k] = {};
    return false;
  }
  const double inner = touch - v.overlap_limit * std::min(v.radius[i], v.radius[j]);  // m
  excessive |= !(inner > 0.0) || distance2 < inner * inner;
  return true;
}

// The contact of pair k = (i, j) by the scalar law: false if they do not touch (see touching).
[[gnu::always_inline]] inline bool pair_contact(const PairView& v, std::uint32_t i, std::uint32_t j,
                                                std::uint32_t k, CrossingPair& out, int& excessive) {
  Vec3 d;
  double distance2;  // m²
  if (!touching(v, i, j, k, d, distance2, excessive)) return false;
  const double distance = std::sqrt(distance2);  // m
  ContactKinematics kin;
  kin.normal = d * (1.0 / distance);
  kin.overlap = (v.radius[i] + v.radius[j]) - distance;
  kin.radius_i = v.radius[i];
  kin.radius_j = v.radius[j];
  kin.inv_mass_i = v.inv_mass[i];
  kin.inv_mass_j = v.inv_mass[j];
  kin.velocity_i = v.velocity[i];
  kin.velocity_j = v.velocity[j];
  kin.angular_velocity_i = v.angular_velocity[i];
  kin.angular_velocity_j = v.angular_velocity[j];
  ContactHistory history{v.tangential[k], v.rolling ? v.rolling[k] : Vec3{}};
  const ContactResult r =
      evaluate_contact(v.materials->between(v.material[i], v.material[j]), kin, history, v.dt);
  v.tangential[k] = history.tangential_displacement;
  if (v.rolling) v.rolling[k] = history.rolling_torque;
  out.force = r.force_i;
  out.torque_i = r.torque_i;
  out.torque_j = r.torque_j;
  return true;
}

// First row of each thread's range: balances rows + pairs (both cost), ascending.
void split_rows(const std::uint32_t* offsets, std::size_t n, int threads, std::vector<std::uint32_t>& start) {
  start.assign(static_cast<std::size_t>(threads) + 1, static_cast<std::uint32_t>(n));
  const double total = static_cast<double>(offsets[n]) + static_cast<double>(n);
  start[0] = 0;
  for (int t = 1; t < threads; ++t) {
    const double target = total * t / threads;
    std::size_t lo = 0, hi = n;  // first i with offsets[i] + i >= target
    while (lo < hi) {
      const std::size_t mid = (lo + hi) / 2;
      if (static_cast<double>(offsets[mid]) + static_cast<double>(mid) < target) lo = mid + 1;
      else hi = mid;
    }
    start[t] = static_cast<std::uint32_t>(std::max<std::size_t>(lo, start[t - 1]));
  }
}

// Batched path: appends pair k = (i, j) to the batch if the spheres touch (see touching).
[[gnu::always_inline]] inline bool add_if_touching(const PairView& v, std::uint32_t i, std::uint32_t j,
                                                   std::uint32_t k, HertzMindlinBatch& b, int& excessive) {
  Vec3 d;
  double distance2;  // m²
  if (!touching(v, i, j, k, d, distance2, excessive)) return false;
  const int m = b.count++;
  b.pair[m] = k;
  b.dx[m] = d.x, b.dy[m] = d.y, b.dz[m] = d.z, b.distance2[m] = distance2;
  b.radius_i[m] = v.radius[i], b.radius_j[m] = v.radius[j];
  b.inv_mass_i[m] = v.inv_mass[i], b.inv_mass_j[m] = v.inv_mass[j];
  const Vec3 dv = v.velocity[i] - v.velocity[j];
  b.vx[m] = dv.x, b.vy[m] = dv.y, b.vz[m] = dv.z;
  const Vec3 wi = v.angular_velocity[i], wj = v.angular_velocity[j];
  b.wix[m] = wi.x, b.wiy[m] = wi.y, b.wiz[m] = wi.z;
  b.wjx[m] = wj.x, b.wjy[m] = wj.y, b.wjz[m] = wj.z;
  const Vec3 h = v.tangential[k];
  b.hx[m] = h.x, b.hy[m] = h.y, b.hz[m] = h.z;
  return true;
}

// Batched path: lane m's result, and its new history stored with the pair.
[[gnu::always_inline]] inline void take_lane(const PairView& v, const HertzMindlinBatch& b, int m,
                                             CrossingPair& out) {
  v.tangential[b.pair[m]] = {b.hx[m], b.hy[m], b.hz[m]};
  out.force = {b.fx[m], b.fy[m], b.fz[m]};
  out.torque_i = {b.tix[m], b.tiy[m], b.tiz[m]};
  out.torque_j = {b.tjx[m], b.tjy[m], b.tjz[m]};
}

// Pair forces and body forces (gravity, coupling loads): sets p.force and p.torque.
// kBatched: one material pair, plain Hertz–Mindlin — contacts are evaluated in batches by the
// vector kernel (contact/hertz_mindlin_batch.h), except the pairs of a row too long for a
// batch (a large particle among many small ones), which take the scalar law in every thread
// layout alike. Otherwise every contact takes the scalar law (pair_contact).
template <bool kBatched>
void pair_and_body_forces(World& world) {
  ParticleStore& p = world.particles;
  PairList& list = world.pairs;
  const std::size_t n = p.size();
  PairView v{p.position.data(), p.velocity.data(), p.angular_velocity.data(), p.radius.data(),
             p.inv_mass.data(), p.material.data(), list.partner.data(),
             list.tangential_displacement.data(),
             list.rolling_torque.empty() ? nullptr : list.rolling_torque.data(), &world.materials,
             world.dt, world.spec.simulation.max_overlap_fraction.value};
  const std::uint32_t* const offsets = list.offsets.data();
  Vec3* const force = p.force.data();
  Vec3* const torque = p.torque.data();
  const double* const inv_mass = p.inv_mass.data();
  const Vec3 gravity = world.spec.simulation.gravity.value;  // m/s²
  const Vec3* const external_force = p.has_external_loads() ? p.external_force.data() : nullptr;
  const Vec3* const external_torque = p.has_external_loads() ? p.external_torque.data() : nullptr;
  ForceWorkspace& ws = world.force_workspace;
  const int thread_count = n > parallel_threshold ? std::max(1, omp_get_max_threads()) : 1;
  if (ws.crossing.size() < static_cast<std::size_t>(thread_count)) ws.crossing.resize(thread_count);
  if (kBatched && ws.batches.size() < static_cast<std::size_t>(thread_count)) ws.batches.resize(thread_count);
  const InteractionParameters& only = world.materials.between(0, 0);
  constexpr std::uint32_t kRowLimit = HertzMindlinBatch::kCapacity;
  const auto batched_row = [offsets](std::uint32_t i) {
    return kBatched && offsets[i + 1] - offsets[i] <= kRowLimit;
  };
  std::vector<std::uint32_t>& start = ws.range_start;
  int excessive = 0;
#pragma omp parallel num_threads(thread_count) reduction(| : excessive)
  {
    const int threads = omp_get_num_threads(), t = omp_get_thread_num();
#pragma omp single
    split_rows(offsets, n, threads, start);
    const std::uint32_t first = start[t], end = start[t + 1];
    std::vector<CrossingPair>& mine = ws.crossing[t];
    HertzMindlinBatch* const batch = kBatched ? &ws.batches[t] : nullptr;
    const auto flush_crossing = [&] {
      if (!kBatched || batch->count == 0) return;
      evaluate_hertz_mindlin_batch(only, *batch, v.dt);
      for (int m = 0; m < batch->count; ++m) take_lane(v, *batch, m, mine[batch->slot[m]]);
      batch->count = 0;
    };
    mine.clear();
    // Phase 1: this range's crossing pairs (partner in a later range).
    if (threads > 1) {
      if constexpr (kBatched) batch->count = 0;
      for (std::uint32_t i = first; i < end; ++i)
        for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
          const std::uint32_t j = v.partner[k];
          if (j < end) continue;
          mine.push_back(CrossingPair{});
          CrossingPair& c = mine.back();
          c.partner = j;
          if constexpr (kBatched) {
            if (batched_row(i)) {
              if (!add_if_touching(v, i, j, k, *batch, excessive)) {
                c.partner = kNotTouching;
                continue;
              }
              batch->slot[batch->count - 1] = static_cast<std::uint32_t>(mine.size() - 1);
              if (batch->full()) flush_crossing();
              continue;
            }
          }
          if (!pair_contact(v, i, j, k, c, excessive)) c.partner = kNotTouching;
        }
      flush_crossing();
    }
#pragma omp barrier
    // Phase 2: start from the earlier ranges' crossing contributions, then the rows in order.
    for (std::uint32_t i = first; i < end; ++i) force[i] = torque[i] = Vec3{};
    for (int u = 0; u < t; ++u)
      for (const CrossingPair& c : ws.crossing[u])
        if (c.partner >= first && c.partner < end) {
          force[c.partner] -= c.force;
          torque[c.partner] += c.torque_j;
        }
    std::size_t next_crossing = 0;
    int lane = 0;  // batched path: next lane of the current batch
    // Row i in list order; contact(i, j, k, c) gives pair k's result, false if not touching.
    const auto add_row = [&](std::uint32_t i, auto&& contact) {
      Vec3 force_i = force[i], torque_i = torque[i];  // N, N·m: the rows before i are done
      for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
        const std::uint32_t j = v.partner[k];
        if (j >= end) {
          const CrossingPair& c = mine[next_crossing++];
          if (c.partner == kNotTouching) continue;
          force_i += c.force;
          torque_i += c.torque_i;
          continue;
        }
        CrossingPair c;
        if (!contact(i, j, k, c)) continue;
        force_i += c.force;
        torque_i += c.torque_i;
        force[j] -= c.force;
        torque[j] += c.torque_j;
      }
      // Row i was the last to touch particle i: its pair sum is complete.
      force_i += gravity / inv_mass[i];
      if (external_force) {
        force_i += external_force[i];
        torque_i += external_torque[i];
      }
      force[i] = force_i;
      torque[i] = torque_i;
    };
    const auto scalar = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, CrossingPair& c) {
      return pair_contact(v, i, j, k, c, excessive);
    };
    if constexpr (kBatched) {
      constexpr std::uint32_t kPrefetchDistance = 16;  // pairs
      const std::uint32_t pair_end = offsets[end];
      const auto from_batch = [&](std::uint32_t, std::uint32_t, std::uint32_t k, CrossingPair& c) {
        if (lane >= batch->count || batch->pair[lane] != k) return false;
        take_lane(v, *batch, lane++, c);
        return true;
      };
      for (std::uint32_t block = first; block < end;) {
        // Collect the touching pairs of as many whole rows as fit, evaluate, then add in order.
        batch->count = 0;
        std::uint32_t stop = block;
        while (stop < end) {
          const std::uint32_t row_pairs = offsets[stop + 1] - offsets[stop];
          if (!batched_row(stop)) {
            if (stop == block) ++stop;  // a long row alone: scalar law below
            break;
          }
          if (batch->count + static_cast<int>(row_pairs) > HertzMindlinBatch::kCapacity) break;
          for (std::uint32_t k = offsets[stop]; k < offsets[stop + 1]; ++k) {
            // Partners a few pairs ahead: start loading what collecting and adding will read
            // (beyond a few 10^4 particles the partners' data comes from L3 or memory).
            if (k + kPrefetchDistance < pair_end) {
              const std::uint32_t ahead = v.partner[k + kPrefetchDistance];
              __builtin_prefetch(v.position + ahead);
              __builtin_prefetch(v.velocity + ahead);
              __builtin_prefetch(v.angular_velocity + ahead);
              __builtin_prefetch(force + ahead, 1);
              __builtin_prefetch(torque + ahead, 1);
            }
            if (v.partner[k] < end) add_if_touching(v, stop, v.partner[k], k, *batch, excessive);
          }
          ++stop;
        }
        if (batch->count > 0) evaluate_hertz_mindlin_batch(only, *batch, v.dt);
        lane = 0;
        for (std::uint32_t i = block; i < stop; ++i) {
          if (batched_row(i)) add_row(i, from_batch);
          else add_row(i, scalar);
        }
        block = stop;
      }
    } else {
      for (std::uint32_t i = first; i < end; ++i) add_row(i, scalar);
    }
  }
  world.excessive_overlap = excessive != 0;
}

// Velocity of the surface material at a contact point: the vertices' velocities interpolated
// with the barycentric weights, plus the conveyor velocity's tangential part (m/s).
Vec3 surface_velocity(const Surface& surface, const SurfaceContact& c) {
  const auto& tri = surface.triangles[c.triangle];
  Vec3 v = surface.vertex_velocities[tri[0]] * c.weights[0] +
           surface.vertex_velocities[tri[1]] * c.weights[1] +
           surface.vertex_velocities[tri[2]] * c.weights[2];
  const Vec3& belt = surface.conveyor_velocity;
  return v + belt - c.normal * dot(belt, c.normal);
}

// Contacts of candidate particle i with the surfaces: appended to `out` (detection order),
// history taken over from i's contacts of the previous step, [previous_begin, previous_end).
void wall_contacts_of(World& world, std::uint32_t i, std::size_t candidate,
                      const WallContact* previous_begin, const WallContact* previous_end,
                      std::vector<SurfaceContact>& found, std::vector<WallContact>& out, int& excessive) {
  ParticleStore& p = world.particles;
  const SurfaceCandidates& cand = world.candidates;
  const double overlap_limit = world.spec.simulation.max_overlap_fraction.value;  // of radius
  const std::size_t first_new = out.size();
  std::uint64_t used = 0;  // bit q: previous contact q was taken over
  Vec3 force, torque;
  const std::uint32_t begin = cand.offsets[candidate], end = cand.offsets[candidate + 1];
  // Candidates are grouped by surface: detect contacts one surface at a time.
  for (std::uint32_t a = begin; a < end;) {
    std::uint32_t b = a;
    while (b < end && cand.surface[b] == cand.surface[a]) ++b;
    const std::uint16_t s = cand.surface[a];
    const Surface& surface = world.surfaces[s];
    find_surface_contacts(surface, world.topologies[s], p.position[i], p.radius[i],
                          std::span<const std::uint32_t>(cand.triangle.data() + a, b - a), found);
    a = b;
    for (const SurfaceContact& c : found) {
      WallContact contact;
      contact.particle = i;
      contact.surface = s;
      contact.triangle = c.triangle;
      contact.normal = c.normal;
      contact.weights = c.weights;
      contact.point = c.point;
      // Keep tangential history for a contact that continues: same surface, similar normal.
      int best = -1;
      double best_alignment = 0.5;  // cos 60°
      for (const WallContact* q = previous_begin; q < previous_end && q - previous_begin < 64; ++q) {
        const int slot = static_cast<int>(q - previous_begin);
        if ((used >> slot & 1u) || q->surface != s) continue;
        const double alignment = dot(q->normal, c.normal);
        if (alignment > best_alignment) best_alignment = alignment, best = slot;
      }
      if (best >= 0) {
        used |= std::uint64_t{1} << best;
        contact.history = previous_begin[best].history;
      }
      ContactKinematics kin;
      kin.normal = c.normal;
      kin.overlap = c.overlap;
      kin.radius_i = p.radius[i];
      kin.radius_j = 0.0;  // a wall
      kin.inv_mass_i = p.inv_mass[i];
      kin.inv_mass_j = 0.0;  // a wall
      kin.velocity_i = p.velocity[i];
      kin.velocity_j = surface_velocity(surface, c);
      kin.angular_velocity_i = p.angular_velocity[i];
      const ContactResult r = evaluate_contact(
          world.materials.between(p.material[i], surface.material), kin, contact.history, world.dt);
      contact.force_on_particle = r.force_i;
      excessive |= c.overlap > overlap_limit * p.radius[i];
      force += r.force_i;
      torque += r.torque_i;
      out.push_back(contact);
    }
  }
  if (out.size() > first_new) {
    p.force[i] += force;
    p.torque[i] += torque;
  }
}

void wall_forces(World& world) {
  const SurfaceCandidates& cand = world.candidates;
  const std::size_t m = cand.particles.size();
  ForceWorkspace& ws = world.force_workspace;
  std::swap(ws.previous_wall_contacts, world.wall_contacts);
  world.wall_contacts.clear();
  const std::vector<WallContact>& previous = ws.previous_wall_contacts;
  const int thread_count = m > parallel_threshold ? std::max(1, omp_get_max_threads()) : 1;
  if (ws.wall_found.size() < static_cast<std::size_t>(thread_count)) ws.wall_found.resize(thread_count);
  int excessive = 0;
  int team = 1;  // threads that ran
#pragma omp parallel num_threads(thread_count) reduction(| : excessive)
  {
    const int threads = omp_get_num_threads(), t = omp_get_thread_num();
    const std::size_t first = m * t / threads, end = m * (t + 1) / threads;
    // Per-thread buffers, concatenated in thread order below; one thread needs no third copy.
    std::vector<WallContact>& out = threads == 1 ? world.wall_contacts : ws.wall_found[t];
    out.clear();
    if (t == 0) team = threads;
    std::vector<SurfaceContact> found;
    // Previous contacts are sorted by particle, as are the candidates: walk both together.
    const auto by_particle = [](const WallContact& c, std::uint32_t i) { return c.particle < i; };
    const WallContact* q = previous.data();
    if (first < end)
      q = std::lower_bound(previous.data(), previous.data() + previous.size(), cand.particles[first], by_particle);
    const WallContact* const q_end = previous.data() + previous.size();
    for (std::size_t c = first; c < end; ++c) {
      const std::uint32_t i = cand.particles[c];
      while (q < q_end && q->particle < i) ++q;
      const WallContact* q_stop = q;
      while (q_stop < q_end && q_stop->particle == i) ++q_stop;
      wall_contacts_of(world, i, c, q, q_stop, found, out, excessive);
      q = q_stop;
    }
  }
  if (team > 1)  // one thread wrote straight into world.wall_contacts
    for (int t = 0; t < team; ++t)
      world.wall_contacts.insert(world.wall_contacts.end(), ws.wall_found[t].begin(), ws.wall_found[t].end());
  world.excessive_overlap = world.excessive_overlap || excessive != 0;
  // Reactions on the surfaces, gathered in particle order (deterministic).
  for (auto& surface : world.surfaces) surface.clear_step_loads();
  for (const WallContact& c : world.wall_contacts) {
    Surface& surface = world.surfaces[c.surface];
    const Vec3 reaction = -c.force_on_particle;
    surface.triangle_force[c.triangle] += reaction;
    const auto& tri = surface.triangles[c.triangle];
    for (int k = 0; k < 3; ++k) surface.vertex_force[tri[k]] += reaction * c.weights[k];
    surface.total_force += reaction;
    surface.total_torque += cross(c.point, reaction);
  }
}

}  // namespace

void compute_forces(World& world) {
  {
    ScopedStage timer(world.timers, world.timers.stage("pair forces"));
    const auto& pairs = world.materials.pairs;
    if (pairs.size() == 1 && is_plain_hertz_mindlin(pairs[0]))
      pair_and_body_forces<true>(world);
    else
      pair_and_body_forces<false>(world);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("surface forces"));
    wall_forces(world);
  }
}

}  // namespace quarry::sim
