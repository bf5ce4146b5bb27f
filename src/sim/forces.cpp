// Contact stage (DESIGN §2 step 3). Particle–particle contacts are computed once per pair of the
// half list and added straight onto both particles ("Newton's third law" accumulation), with a
// summation order that does not depend on the thread count; then particle–surface contacts for
// the particles near a surface, their reactions gathered onto triangles and vertices in
// particle order. All of it runs in one team of threads. The sums start from the body forces
// (set_body_forces, the stage before), so no pass zeroes them.
//
// Why the order is fixed. The list holds pair (i, j) only in row i, with j > i, rows ascending.
// A serial pass (rows in order: F_i += f, F_j −= f) adds onto particle p first the pairs
// (k, p) with k < p in ascending k, then p's own row in row order — and after row p nothing
// touches p again. With T threads each owns a contiguous range of rows. A pair whose
// partner lies in a later thread's range ("crossing") is computed first — by all threads, shared
// evenly, from a list of them made once per list build — and its result kept;
// after a barrier each thread starts its particles from the crossing contributions of earlier
// ranges (ascending source row), then runs its rows exactly as the serial pass, taking the kept
// result for its own crossing pairs. Every particle thus receives the same terms in the same
// order for any T: the sums are bit-identical (checked by the determinism tests). Crossing pairs
// are few (the ranges are compact in space after the space-filling-curve sort).
//
// Why surface contacts are found in chunks. The threads' pair ranges are balanced by learning
// each thread's speed, but a core of a shared host can slow down for tens of steps, and the
// other thread then waits at the end of the pair loop (measured at 200k on 2 threads: a mean
// gap of 0.75 ms per step of 10 ms). Finding a candidate's surface contacts reads positions
// and velocities only and writes the contact's own record, so it can run as soon as a thread
// is done with its rows, in any order, by any thread, and fill the gap. A thread takes the
// chunks of its own particles first (their data is in its cache; the host may place the two
// cores on different L3 caches, and then every line one thread writes and the other reads
// costs a transfer), then helps with the others'. Each candidate's sum is added onto its
// particle after its pair sum (the same order as one thread): at once if the thread owning the
// particle's row is done with its rows, else after the next barrier. The chunks' contacts are
// gathered in chunk order (candidate order, as one thread finds them), and the reactions on the
// surfaces are added in that order too.
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <utility>

#include "contact/hertz_mindlin_batch.h"
#include "integrate/integrator.h"
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
  const Vec3* velocity_lead;          // to the force's time (set_velocity_leads)
  const Vec3* angular_velocity_lead;
  const double* radius;
  const double* inv_mass;
  const std::uint16_t* material;
  const std::uint32_t* partner;
  Vec3* tangential;
  Vec3* rolling;  // null without rolling history
  std::uint8_t* jkr_attached;  // null without JKR history
  double* normal_force;        // N, each contact's last (ContactHistory::normal_force)
  const MaterialTable* materials;
  double dt;            // s
  double lead_time;     // s, ContactKinematics::lead_time
  double overlap_limit;  // fraction of the smaller radius
  PeriodicBox periodic;  // the domain's periodic axes (read only on the kPeriodic paths)
};

// Half the relative displacement of a pair over a step at its velocities with their leads (m):
// at least the half path of its dashpot window (contact/dashpot_window.h), whose normal part it
// bounds (sum of the components' magnitudes: no square root).
[[gnu::always_inline]] inline double window_reach(const Vec3& relative_velocity, double dt) {
  return 0.5 * dt *
         (std::fabs(relative_velocity.x) + std::fabs(relative_velocity.y) +
          std::fabs(relative_velocity.z));
}

// Separation x_i − x_j of a pair (m): the minimum image across the periodic faces when
// kPeriodic. Chosen at compile time (the whole stage is instantiated for it), so the loop
// without periodic axes has no test per pair and its arithmetic is unchanged.
template <bool kPeriodic>
[[gnu::always_inline]] inline Vec3 separation(const PairView& v, const Vec3& xi, const Vec3& xj) {
  if constexpr (kPeriodic) return v.periodic.minimum_image(xi - xj);
  return xi - xj;
}

// The contact of pair k = (i, j) by the scalar law. False if the spheres do not touch (and no
// JKR adhesion holds them, and the step's dashpot window cannot reach contact): the pair's
// history is then released (the spring lets go when contact is lost). Otherwise sets
// `excessive` if the overlap passes the guard's limit (check_overlaps reports it after the step).
template <bool kPeriodic>
[[gnu::always_inline]] inline bool pair_contact(const PairView& v, std::uint32_t i, std::uint32_t j,
                                                std::uint32_t k, CrossingPair& out,
                                                int& excessive) {
  const Vec3 d = separation<kPeriodic>(v, v.position[i], v.position[j]);
  const double touch = v.radius[i] + v.radius[j];  // m
  const double distance2 = norm2(d);               // m²
  const bool attached = v.jkr_attached && v.jkr_attached[k];
  if (distance2 >= touch * touch && !attached) {
    const double reach =
        touch + window_reach((v.velocity[i] + v.velocity_lead[i]) -
                                 (v.velocity[j] + v.velocity_lead[j]),
                             v.dt);  // m
    if (!(distance2 < reach * reach)) {
      v.tangential[k] = {};
      if (v.rolling) v.rolling[k] = {};
      v.normal_force[k] = 0.0;
      return false;
    }
  }
  const double distance = std::sqrt(distance2);  // m
  ContactKinematics kin;
  kin.normal = d * (1.0 / distance);
  kin.overlap = touch - distance;
  excessive |= overlap_past_limit(kin.overlap, v.radius[i], v.radius[j], v.overlap_limit);
  kin.radius_i = v.radius[i];
  kin.radius_j = v.radius[j];
  kin.inv_mass_i = v.inv_mass[i];
  kin.inv_mass_j = v.inv_mass[j];
  kin.velocity_i = v.velocity[i];
  kin.velocity_j = v.velocity[j];
  kin.angular_velocity_i = v.angular_velocity[i];
  kin.angular_velocity_j = v.angular_velocity[j];
  kin.velocity_lead_i = v.velocity_lead[i];
  kin.velocity_lead_j = v.velocity_lead[j];
  kin.angular_velocity_lead_i = v.angular_velocity_lead[i];
  kin.angular_velocity_lead_j = v.angular_velocity_lead[j];
  kin.lead_time = v.lead_time;
  ContactHistory history{v.tangential[k], v.rolling ? v.rolling[k] : Vec3{}, attached,
                         v.normal_force[k]};
  const ContactResult r =
      evaluate_contact(v.materials->between(v.material[i], v.material[j]), kin, history, v.dt);
  v.tangential[k] = history.tangential_displacement;
  v.normal_force[k] = history.normal_force;
  if (v.rolling) v.rolling[k] = history.rolling_torque;
  if (v.jkr_attached) v.jkr_attached[k] = history.jkr_attached;
  out.force = r.force_i;
  out.torque_i = r.torque_i;
  out.torque_j = r.torque_j;
  return true;
}

// First row of each thread's range: range t gets the fraction share[t] of rows + pairs (both
// cost), ascending.
void split_rows(const std::uint32_t* offsets, std::size_t n, const std::vector<double>& share,
                std::vector<std::uint32_t>& start) {
  const int threads = static_cast<int>(share.size());
  start.assign(static_cast<std::size_t>(threads) + 1, static_cast<std::uint32_t>(n));
  const double total = static_cast<double>(offsets[n]) + static_cast<double>(n);
  start[0] = 0;
  double cumulative = 0.0;
  for (int t = 1; t < threads; ++t) {
    cumulative += share[t - 1];
    const double target = total * cumulative;
    std::size_t lo = 0, hi = n;  // first i with offsets[i] + i >= target
    while (lo < hi) {
      const std::size_t mid = (lo + hi) / 2;
      if (static_cast<double>(offsets[mid]) + static_cast<double>(mid) < target) lo = mid + 1;
      else hi = mid;
    }
    start[t] = static_cast<std::uint32_t>(std::max<std::size_t>(lo, start[t - 1]));
  }
}

// After a step on several threads: moves the shares towards equal time per thread. Thread t
// did plan.share[t] of the work in range_time[t] s; the next plan gives each thread a share
// proportional to its measured rate, blended with the current one to damp noise.
void learn_shares(ForceWorkspace& ws) {
  const std::size_t threads = ws.plan.share.size();
  if (threads < 2 || ws.range_time.size() < threads || ws.range_share.size() != threads) return;
  const auto rate = [&ws](std::size_t t) { return ws.plan.share[t] / ws.range_time[t]; };
  double sum = 0.0;
  for (std::size_t t = 0; t < threads; ++t) {
    if (!(ws.range_time[t] > 0.0)) return;
    sum += rate(t);
  }
  for (std::size_t t = 0; t < threads; ++t) {
    const double blended = 0.9 * ws.range_share[t] + 0.1 * rate(t) / sum;
    ws.range_share[t] = std::clamp(blended, 0.25 / static_cast<double>(threads), 1.0);
  }
  double norm = 0.0;
  for (double x : ws.range_share) norm += x;
  for (double& x : ws.range_share) x /= norm;
}

// True if the learnt shares have moved away from the plan's by more than 1 % of the work on
// some thread: the ranges are then drawn again before the next list build. A neighbour on a
// shared host that slows one core for some tens of steps would otherwise hold the other thread
// at the barrier until the list is rebuilt (measured at 200k on 2 threads: bursts of 10–100
// steps with one thread 20–30 % slower). A new plan costs one pass over the rows' last
// partners, about 0.5 ms at 200k; it was made about once per 15 steps there.
bool shares_moved(const ForceWorkspace& ws) {
  constexpr double kShift = 0.01;  // fraction of the step's rows + pairs
  if (ws.range_share.size() != ws.plan.share.size()) return false;
  for (std::size_t t = 0; t < ws.range_share.size(); ++t)
    if (std::abs(ws.range_share[t] - ws.plan.share[t]) > kShift) return true;
  return false;
}

// True if `plan` was made for this list of n particles (its ranges may still be for other
// threads or shares).
bool made_for_list(const ForceWorkspace::PairPlan& plan, const PairList& list, std::size_t n) {
  return plan.builds == list.builds && plan.rows == n && plan.pairs == list.size();
}

// The thread layout for this list: ranges, and the crossing pairs listed once (partners are
// ascending within a row, so a row's crossing pairs are its tail). Cost O(n + crossing), once
// per list build (or when the shares move) rather than a scan of every pair every step.
void make_plan(const PairList& list, std::size_t n, int threads, std::vector<double>& shares,
               ForceWorkspace::PairPlan& plan) {
  plan.builds = list.builds, plan.rows = n, plan.pairs = list.size(), plan.threads = threads;
  if (shares.size() != static_cast<std::size_t>(threads)) shares.assign(threads, 1.0 / threads);
  plan.share = shares;
  const std::uint32_t* const offsets = list.offsets.data();
  split_rows(offsets, n, plan.share, plan.range_start);
  plan.crossing_row.clear();
  plan.crossing_pair.clear();
  plan.crossing_begin.assign(1, 0);
  for (int t = 0; t < threads; ++t) {
    const std::uint32_t end = plan.range_start[t + 1];
    for (std::uint32_t i = plan.range_start[t]; i < end; ++i) {
      std::uint32_t k = offsets[i + 1];
      while (k > offsets[i] && list.partner[k - 1] >= end) --k;
      for (; k < offsets[i + 1]; ++k) plan.crossing_row.push_back(i), plan.crossing_pair.push_back(k);
    }
    plan.crossing_begin.push_back(static_cast<std::uint32_t>(plan.crossing_pair.size()));
  }
}

// Starts loading what the contact of particle i reads (positions and velocities).
[[gnu::always_inline]] inline void prefetch_particle(const PairView& v, std::uint32_t i) {
  __builtin_prefetch(v.position + i);
  __builtin_prefetch(v.radius + i);
  __builtin_prefetch(v.velocity + i);
  __builtin_prefetch(v.angular_velocity + i);
  __builtin_prefetch(v.velocity_lead + i);
  __builtin_prefetch(v.angular_velocity_lead + i);
}

// Particle i's data, read once per row: the compiler cannot keep it in registers across the
// batch stores itself (they might alias the particle arrays).
struct RowParticle {
  Vec3 position, velocity, angular_velocity;  // m, m/s, rad/s
  Vec3 velocity_lead, angular_velocity_lead;  // m/s, rad/s
  double radius, inv_mass;                    // m, 1/kg
};

[[gnu::always_inline]] inline RowParticle row_particle(const PairView& v, std::uint32_t i) {
  return {v.position[i],      v.velocity[i],
          v.angular_velocity[i], v.velocity_lead[i],
          v.angular_velocity_lead[i], v.radius[i],
          v.inv_mass[i]};
}

// Batched path: writes pair k = (i, j) into the batch's next lane, which is kept (count
// advances) if the spheres touch — no branch on touching, which is unpredictable. As in
// `pair_contact`, the history of a pair not touching is released (a touching pair's is rewritten
// with the kernel's result); the kernel applies the overlap guard. There is no rolling
// history on this path (compute_forces).
template <bool kPeriodic>
[[gnu::always_inline]] inline void collect_pair(const PairView& v, const RowParticle& pi,
                                                std::uint32_t j, std::uint32_t k,
                                                HertzMindlinBatch& b) {
  const Vec3 d = separation<kPeriodic>(v, pi.position, v.position[j]);
  const double rj = v.radius[j];        // m
  const Vec3 dv = pi.velocity - v.velocity[j];
  const Vec3 dl = pi.velocity_lead - v.velocity_lead[j];
  // Touching, or short of it by less than the step's dashpot window may reach (the kernel
  // decides; contact/dashpot_window.h).
  const double reach = (pi.radius + rj) + window_reach(dv + dl, v.dt);  // m
  const double distance2 = norm2(d);                                   // m²
  const bool touches = distance2 < reach * reach;
  const int m = b.count;
  b.pair[m] = k, b.slot[m] = j;
  b.dx[m] = d.x, b.dy[m] = d.y, b.dz[m] = d.z, b.distance2[m] = distance2;
  b.radius_i[m] = pi.radius, b.radius_j[m] = rj;
  b.inv_mass_i[m] = pi.inv_mass, b.inv_mass_j[m] = v.inv_mass[j];
  b.vx[m] = dv.x, b.vy[m] = dv.y, b.vz[m] = dv.z;
  const Vec3 wj = v.angular_velocity[j];
  b.wix[m] = pi.angular_velocity.x, b.wiy[m] = pi.angular_velocity.y, b.wiz[m] = pi.angular_velocity.z;
  b.wjx[m] = wj.x, b.wjy[m] = wj.y, b.wjz[m] = wj.z;
  b.lvx[m] = dl.x, b.lvy[m] = dl.y, b.lvz[m] = dl.z;
  const Vec3 lj = v.angular_velocity_lead[j];
  b.lwix[m] = pi.angular_velocity_lead.x, b.lwiy[m] = pi.angular_velocity_lead.y,
  b.lwiz[m] = pi.angular_velocity_lead.z;
  b.lwjx[m] = lj.x, b.lwjy[m] = lj.y, b.lwjz[m] = lj.z;
  const Vec3 h = v.tangential[k];
  b.hx[m] = h.x, b.hy[m] = h.y, b.hz[m] = h.z;
  v.tangential[k] = {};
  b.fn[m] = v.normal_force[k];
  v.normal_force[k] = 0.0;
  b.count = m + touches;
}

// Batched path (phase 1): appends pair k = (i, j) to the batch if the spheres touch.
template <bool kPeriodic>
[[gnu::always_inline]] inline bool add_if_touching(const PairView& v, std::uint32_t i,
                                                   std::uint32_t j, std::uint32_t k,
                                                   HertzMindlinBatch& b) {
  const int before = b.count;
  collect_pair<kPeriodic>(v, row_particle(v, i), j, k, b);
  return b.count > before;
}

// Batched path: lane m's new history (tangential spring, last normal force) stored with its pair.
[[gnu::always_inline]] inline void store_lane_history(const PairView& v, const HertzMindlinBatch& b,
                                                      int m) {
  v.tangential[b.pair[m]] = {b.hx[m], b.hy[m], b.hz[m]};
  v.normal_force[b.pair[m]] = b.fn[m];
}

// Batched path: lane m's result, and its new history stored with the pair.
[[gnu::always_inline]] inline void take_lane(const PairView& v, const HertzMindlinBatch& b, int m,
                                             CrossingPair& out) {
  store_lane_history(v, b, m);
  out.force = {b.fx[m], b.fy[m], b.fz[m]};
  out.torque_i = {b.tix[m], b.tiy[m], b.tiz[m]};
  out.torque_j = {b.tjx[m], b.tjy[m], b.tjz[m]};
}

// Pair forces, added onto p.force and p.torque (which hold the body forces). Called by every
// thread of the team (compute_contact_forces); flags excessive overlaps in `excessive`.
// kBatched: one material pair, plain Hertz–Mindlin — contacts are evaluated in batches by the
// vector kernel (contact/hertz_mindlin_batch.h), except the pairs of a row too long for a
// batch (a large particle among many small ones), which take the scalar law in every thread
// layout alike. Otherwise every contact takes the scalar law (pair_contact). kPeriodic:
// separations are minimum images (some axis of the domain is periodic).
template <bool kBatched, bool kPeriodic>
void pair_forces(World& world, int& excessive) {
  ParticleStore& p = world.particles;
  PairList& list = world.pairs;
  const std::size_t n = p.size();
  PairView v{p.position.data(),
             p.velocity.data(),
             p.angular_velocity.data(),
             world.force_workspace.velocity_lead.data(),
             world.force_workspace.angular_velocity_lead.data(),
             p.radius.data(),
             p.inv_mass.data(),
             p.material.data(),
             list.partner.data(),
             list.tangential_displacement.data(),
             list.rolling_torque.empty() ? nullptr : list.rolling_torque.data(),
             list.jkr_attached.empty() ? nullptr : list.jkr_attached.data(),
             list.normal_force.data(),
             &world.materials,
             world.dt,
             world.force_workspace.lead_time,
             world.spec.simulation.max_overlap_fraction.value,
             list.periodic};
  const std::uint32_t* const offsets = list.offsets.data();
  Vec3* const force = p.force.data();
  Vec3* const torque = p.torque.data();
  ForceWorkspace& ws = world.force_workspace;
  // The particles' one pair law (the batched path; otherwise never read).
  const InteractionParameters& only = kBatched ? *ws.batch_law : world.materials.pairs.front();
  constexpr std::uint32_t kRowLimit = HertzMindlinBatch::kCapacity;
  const auto batched_row = [offsets](std::uint32_t i) {
    return kBatched && offsets[i + 1] - offsets[i] <= kRowLimit;
  };
  ForceWorkspace::PairPlan& plan = ws.plan;
  const int threads = omp_get_num_threads(), t = omp_get_thread_num();
#pragma omp single
  {
    if (!made_for_list(plan, list, n) || plan.threads != threads ||
        shares_moved(ws))
      make_plan(list, n, threads, ws.range_share, plan);
    ws.range_time.assign(threads, 0.0);
    ws.crossing.resize(plan.crossing_pair.size());
  }
  const std::uint32_t first = plan.range_start[t], end = plan.range_start[t + 1];
  // Phase 1: the crossing pairs of all ranges (partner in a later range), shared evenly by
  // the threads; each result goes to its own slot, whichever thread computes it.
  if (threads > 1) {
    constexpr std::size_t kCrossingPrefetch = 8;  // pairs
    const std::size_t total = plan.crossing_pair.size();
    const std::size_t from = total * t / threads, to = total * (t + 1) / threads;
    HertzMindlinBatch* const batch = kBatched ? &ws.batches[t] : nullptr;
    const auto flush = [&] {
      if (!kBatched || batch->count == 0) return;
      excessive |= evaluate_hertz_mindlin_batch(only, *batch, v.dt, v.lead_time, v.overlap_limit);
      for (int m = 0; m < batch->count; ++m) take_lane(v, *batch, m, ws.crossing[batch->slot[m]]);
      batch->count = 0;
    };
    if constexpr (kBatched) batch->count = 0;
    for (std::size_t q = from; q < to; ++q) {
      // Crossing pairs lie on the ranges' borders, scattered through the arrays: nothing of
      // them is in cache. Start loading both particles a few pairs ahead.
      if (q + kCrossingPrefetch < to) {
        const std::uint32_t ahead = plan.crossing_pair[q + kCrossingPrefetch];
        prefetch_particle(v, plan.crossing_row[q + kCrossingPrefetch]);
        prefetch_particle(v, v.partner[ahead]);
        __builtin_prefetch(v.tangential + ahead, 1);
      }
      const std::uint32_t i = plan.crossing_row[q], k = plan.crossing_pair[q], j = v.partner[k];
      CrossingPair& c = ws.crossing[q];
      c.partner = j;
      if constexpr (kBatched) {
        if (batched_row(i)) {
          if (!add_if_touching<kPeriodic>(v, i, j, k, *batch)) {
            c.partner = kNotTouching;
            continue;
          }
          batch->slot[batch->count - 1] = static_cast<std::uint32_t>(q);
          if (batch->full()) flush();
          continue;
        }
      }
      if (!pair_contact<kPeriodic>(v, i, j, k, c, excessive)) c.partner = kNotTouching;
    }
    flush();
  }
#pragma omp barrier
  const double phase2_start = omp_get_wtime();  // s
  // Phase 2: the earlier ranges' crossing contributions first (ascending source row), then the
  // rows in order.
  for (std::uint32_t q = 0; q < plan.crossing_begin[t]; ++q) {
    const std::uint32_t j = v.partner[plan.crossing_pair[q]];
    if (j < first || j >= end) continue;
    const CrossingPair& c = ws.crossing[q];
    if (c.partner == kNotTouching) continue;
    force[j] -= c.force;
    torque[j] += c.torque_j;
  }
  HertzMindlinBatch* const batch = kBatched ? &ws.batches[t] : nullptr;
  std::size_t next_crossing = plan.crossing_begin[t];
  // Adds this range's crossing pair k of row i (computed in phase 1) onto particle i.
  const auto add_crossing = [&](Vec3& force_i, Vec3& torque_i) {
    const CrossingPair& c = ws.crossing[next_crossing++];
    if (c.partner == kNotTouching) return;
    force_i += c.force;
    torque_i += c.torque_i;
  };
  // Row i was the last to touch particle i: its pair sum is complete.
  const auto finish_row = [&](std::uint32_t i, const Vec3& force_i, const Vec3& torque_i) {
    force[i] = force_i;
    torque[i] = torque_i;
  };
  // Row i in list order by the scalar law.
  const auto scalar_row = [&](std::uint32_t i) {
    Vec3 force_i = force[i], torque_i = torque[i];  // N, N·m: body forces and the rows before i
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = v.partner[k];
      if (j >= end) {
        add_crossing(force_i, torque_i);
        continue;
      }
      CrossingPair c;
      if (!pair_contact<kPeriodic>(v, i, j, k, c, excessive)) continue;
      force_i += c.force;
      torque_i += c.torque_i;
      force[j] -= c.force;
      torque[j] += c.torque_j;
    }
    finish_row(i, force_i, torque_i);
  };
  if constexpr (kBatched) {
    // Rows are taken in blocks: the touching pairs of as many whole rows as fit are collected
    // into the batch (branch-free: every pair is written, the count advances if it touches),
    // evaluated together, then added row by row in list order. A row's crossing pairs are
    // its tail (partners ascend), added after its batch lanes: the pair order of one thread.
    constexpr std::uint32_t kPrefetchDistance = 16;  // pairs
    const std::uint32_t pair_end = offsets[end];
    constexpr int kRows = HertzMindlinBatch::kCapacity;  // rows per block
    std::uint16_t lanes_end[kRows];                       // per row of the block
    std::uint32_t tail[kRows];                            // first crossing pair per row
    for (std::uint32_t block = first; block < end;) {
      batch->count = 0;
      std::uint32_t stop = block;
      while (stop < end && stop - block < static_cast<std::uint32_t>(kRows)) {
        const std::uint32_t row_begin = offsets[stop], row_end = offsets[stop + 1];
        if (row_begin == row_end) {  // no partner (a particle in flight): nothing to read
          lanes_end[stop - block] = static_cast<std::uint16_t>(batch->count);
          tail[stop - block] = row_end;
          ++stop;
          continue;
        }
        if (!batched_row(stop)) {
          if (stop == block) ++stop;  // a long row alone: scalar law below
          break;
        }
        if (batch->count + static_cast<int>(row_end - row_begin) > HertzMindlinBatch::kCapacity) break;
        const RowParticle pi = row_particle(v, stop);
        std::uint32_t k = row_begin;
        for (; k < row_end; ++k) {
          // Partners a few pairs ahead: start loading what collecting and adding will read
          // (beyond a few 10^4 particles the partners' data comes from L3 or memory).
          if (k + kPrefetchDistance < pair_end) {
            const std::uint32_t ahead = v.partner[k + kPrefetchDistance];
            prefetch_particle(v, ahead);
            __builtin_prefetch(force + ahead, 1);
            __builtin_prefetch(torque + ahead, 1);
          }
          const std::uint32_t j = v.partner[k];
          if (j >= end) break;  // the crossing tail
          collect_pair<kPeriodic>(v, pi, j, k, *batch);
        }
        lanes_end[stop - block] = static_cast<std::uint16_t>(batch->count);
        tail[stop - block] = k;
        ++stop;
      }
      if (batch->count > 0) excessive |= evaluate_hertz_mindlin_batch(only, *batch, v.dt, v.lead_time, v.overlap_limit);
      int lane = 0;
      for (std::uint32_t i = block; i < stop; ++i) {
        if (offsets[i] == offsets[i + 1]) continue;  // its force and torque stay as they are
        if (!batched_row(i)) {
          scalar_row(i);
          continue;
        }
        Vec3 force_i = force[i], torque_i = torque[i];  // N, N·m: body forces and the rows before i
        for (const int lanes = lanes_end[i - block]; lane < lanes; ++lane) {
          const HertzMindlinBatch& b = *batch;
          const std::uint32_t j = b.slot[lane];
          store_lane_history(v, b, lane);
          const Vec3 f{b.fx[lane], b.fy[lane], b.fz[lane]};
          force_i += f;
          torque_i += Vec3{b.tix[lane], b.tiy[lane], b.tiz[lane]};
          force[j] -= f;
          torque[j] += Vec3{b.tjx[lane], b.tjy[lane], b.tjz[lane]};
        }
        for (std::uint32_t k = tail[i - block]; k < offsets[i + 1]; ++k) add_crossing(force_i, torque_i);
        finish_row(i, force_i, torque_i);
      }
      block = stop;
    }
  } else {
    for (std::uint32_t i = first; i < end; ++i)
      if (offsets[i] != offsets[i + 1]) scalar_row(i);  // an empty row leaves i as it is
  }
  ws.range_time[t] = omp_get_wtime() - phase2_start;
  // The sums of this range are final: others may now add surface contacts onto them.
  std::atomic_ref<int>(ws.rows_done[t]).store(1, std::memory_order_release);
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
// history taken over from i's contacts of the previous step, [previous_begin, previous_end);
// their force and torque on the particle summed into `sum`. Reads the particles, writes none.
// `kin`: the caller's kinematics record, its wall side zero (each contact sets the rest).
// Returns whether i touches a surface.
bool wall_contacts_of(const World& world, std::uint32_t i, std::size_t candidate,
                      const WallContact* previous_begin, const WallContact* previous_end,
                      std::vector<SurfaceContact>& found, std::vector<WallContact>& out,
                      ForceWorkspace::WallSum& sum, ContactKinematics& kin, int& excessive) {
  const ParticleStore& p = world.particles;
  const SurfaceCandidates& cand = world.candidates;
  const ForceWorkspace& ws = world.force_workspace;
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
    const Surface& surface = world.surfaces[s].mesh;
    const InteractionParameters& law = world.materials.between(p.material[i], surface.material);
    // A JKR contact holds down to the overlap δ_c < 0 (R* = Ri against a wall): search that
    // much farther, and keep a contact found there only if it still adheres.
    // A dashpot window may reach contact from as far as half the step's relative displacement
    // (contact/dashpot_window.h): search that much farther too.
    const double reach =
        law.surface_energy > 0.0
            ? -contact::jkr_scales(law.surface_energy, law.effective_youngs_modulus, p.radius[i])
                   .break_overlap
            : 0.5 * world.dt * (norm(p.velocity[i] + ws.velocity_lead[i]) + ws.surface_speed[s]);
    find_surface_contacts(surface, world.surfaces[s].topology, p.position[i], p.radius[i] + reach,
                          std::span<const std::uint32_t>(cand.triangle.data() + a, b - a), found);
    a = b;
    for (const SurfaceContact& c : found) {
      const double overlap = reach > 0.0 ? c.overlap - reach : c.overlap;  // m
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
      kin.normal = c.normal;
      kin.overlap = overlap;
      kin.radius_i = p.radius[i];
      kin.radius_j = 0.0;  // a wall
      kin.inv_mass_i = p.inv_mass[i];
      kin.inv_mass_j = 0.0;  // a wall
      kin.velocity_i = p.velocity[i];
      kin.velocity_j = surface_velocity(surface, c);
      kin.angular_velocity_i = p.angular_velocity[i];
      kin.velocity_lead_i = ws.velocity_lead[i];
      kin.angular_velocity_lead_i = ws.angular_velocity_lead[i];
      kin.lead_time = ws.lead_time;
      if (best >= 0) {
        used |= std::uint64_t{1} << best;
        contact.history = previous_begin[best].history;
      }
      const ContactResult r = evaluate_contact(law, kin, contact.history, world.dt);
      // Short of contact, kept only while JKR adhesion holds it or its dashpot window acts.
      if (!(overlap > 0.0) && !contact.history.jkr_attached && contact.history.normal_force == 0.0)
        continue;  // pulled off, or the window does not reach contact: released
      contact.force_on_particle = r.force_i;
      excessive |= overlap > overlap_limit * p.radius[i];
      force += r.force_i;
      torque += r.torque_i;
      out.push_back(contact);
    }
  }
  sum.particle = i;
  sum.force = force;
  sum.torque = torque;
  return out.size() > first_new;
}

// Reactions of contacts [begin, end) on the surfaces' triangles and vertices, added in order.
void add_reactions(World& world, const WallContact* begin, const WallContact* end) {
  for (const WallContact* c = begin; c < end; ++c) {
    Surface& surface = world.surfaces[c->surface].mesh;
    surface.add_contact_load(c->triangle, -c->force_on_particle, c->weights, c->point);
  }
}

// Candidates per chunk of surface-contact work: about 10 µs, fine enough to even out the threads.
constexpr std::size_t kWallChunk = 64;

// Before the team starts: the chunks laid out, the surfaces' loads of the step cleared.
void prepare_wall_contacts(World& world) {
  ForceWorkspace& ws = world.force_workspace;
  const std::size_t m = world.candidates.particles.size();
  ws.wall_chunks.resize((m + kWallChunk - 1) / kWallChunk);
  ws.chunk_found.assign(ws.wall_chunks.size(), 0);
  ws.chunk_taken.assign(ws.wall_chunks.size(), 0);
  ws.reactions_next = 0;
  ws.reactions_busy = 0;
  ws.surface_speed.assign(world.surfaces.size(), 0.0);
  for (std::size_t s = 0; s < world.surfaces.size(); ++s) {
    Surface& surface = world.surfaces[s].mesh;
    surface.clear_step_loads();
    double fastest = 0.0;  // m/s
    if (world.surfaces[s].moving())
      for (const Vec3& v : surface.vertex_velocities) fastest = std::max(fastest, norm(v));
    ws.surface_speed[s] = fastest + norm(surface.conveyor_velocity);
  }
}

// Adds the reactions of the chunks that are found, in chunk order from the first not added,
// unless another thread is adding them: then that thread takes the ones that are ready. So
// the reactions go onto the surfaces in one fixed order (chunks, then contacts) on any thread
// count, while the other chunks are still being found, instead of on one thread after the
// barrier (measured at 200k on 2 threads: 0.17 ms a step, the other thread waiting 0.13 ms).
// Why nothing is left behind: a thread marks its chunk found before it tries to take the
// adding over, and the adding thread looks at the next chunk again after it hands over; in the
// single order of these sequentially consistent operations one of the two sees the other's.
void add_ready_reactions(World& world, ForceWorkspace& ws) {
  const std::size_t chunks = ws.wall_chunks.size();
  std::atomic_ref<int> busy(ws.reactions_busy);
  const auto found = [&](std::size_t c) { return c < chunks && std::atomic_ref<int>(ws.chunk_found[c]).load() != 0; };
  for (;;) {
    if (busy.exchange(1) != 0) return;  // the thread adding will see this chunk found
    std::size_t c = ws.reactions_next;  // read and written only while busy
    for (; found(c); ++c) add_reactions(world, ws.wall_chunks[c].data(), ws.wall_chunks[c].data() + ws.wall_chunks[c].size());
    ws.reactions_next = c;
    busy.store(0);
    if (!found(c)) return;
  }
}

// A candidate's surface sum onto its particle, after its pair sum.
void add_surface_sum(ParticleStore& p, const ForceWorkspace::WallSum& sum) {
  p.force[sum.particle] += sum.force;
  p.torque[sum.particle] += sum.torque;
}

// Every thread of the team, as soon as it is done with its pair rows: takes chunks of
// candidates (its own first, below) until none is left, and finds their contacts into the
// chunk's own list. A
// particle's surface sum is added onto it at once if the thread owning its row has finished
// its rows (its pair sum is final), else kept for after the barrier (finish_contacts).
void find_wall_contacts(World& world, ForceWorkspace& ws, int& excessive) {
  const SurfaceCandidates& cand = world.candidates;
  ParticleStore& p = world.particles;
  const std::vector<std::uint32_t>& range_start = ws.plan.range_start;
  const int threads = omp_get_num_threads(), me = omp_get_thread_num();
  std::vector<ForceWorkspace::WallSum>& deferred = ws.wall_deferred[me];
  deferred.clear();
  const std::size_t m = cand.particles.size();
  // The previous step's contacts, for their history: replaced only after the team's barrier.
  const std::vector<WallContact>& previous = world.wall_contacts;
  const WallContact* const previous_end = previous.data() + previous.size();
  std::vector<SurfaceContact> found;
  // Every contact sets the same fields of it; those of a wall's side that it leaves alone stay
  // zero. One per thread and step: made per contact, its 264 bytes were zeroed each time.
  ContactKinematics kin;
  const auto find_chunk = [&](std::size_t chunk) {
    std::vector<WallContact>& out = ws.wall_chunks[chunk];
    out.clear();
    const std::size_t first = chunk * kWallChunk, end = std::min(m, first + kWallChunk);
    // Previous contacts are sorted by particle, as are the candidates: walk both together.
    const auto by_particle = [](const WallContact& c, std::uint32_t i) { return c.particle < i; };
    const WallContact* q = std::lower_bound(previous.data(), previous_end, cand.particles[first], by_particle);
    // The thread whose rows hold particle i (ranges ascend, as the candidates do).
    std::size_t owner =
        std::upper_bound(range_start.begin(), range_start.end(), cand.particles[first]) - range_start.begin() - 1;
    for (std::size_t c = first; c < end; ++c) {
      const std::uint32_t i = cand.particles[c];
      while (q < previous_end && q->particle < i) ++q;
      const WallContact* q_stop = q;
      while (q_stop < previous_end && q_stop->particle == i) ++q_stop;
      ForceWorkspace::WallSum sum;
      const bool touching = wall_contacts_of(world, i, c, q, q_stop, found, out, sum, kin, excessive);
      q = q_stop;
      if (!touching) continue;
      while (i >= range_start[owner + 1]) ++owner;
      if (std::atomic_ref<int>(ws.rows_done[owner]).load(std::memory_order_acquire) == 0)
        deferred.push_back(sum);
      else
        add_surface_sum(p, sum);
    }
    std::atomic_ref<int>(ws.chunk_found[chunk]).store(1);
    add_ready_reactions(world, ws);
  };
  // Chunk c belongs to the thread whose rows hold its first candidate: that thread's particles
  // are in its own cache (it has just summed them), and they stay there if it finds their surface contacts too. A thread takes its own chunks
  // first, in order, then helps the others from the back of theirs. Whoever takes a chunk,
  // its results are the same: only the speed depends on it.
  const auto first_chunk_of = [&](int t) -> std::size_t {  // t = threads: the end
    const auto c = std::lower_bound(cand.particles.begin(), cand.particles.end(), range_start[t]);
    return (static_cast<std::size_t>(c - cand.particles.begin()) + kWallChunk - 1) / kWallChunk;
  };
  // The taker is recorded (thread + 1): it also copies the chunk's contacts out (finish_contacts).
  const auto take = [&](std::size_t c) { return std::atomic_ref<int>(ws.chunk_taken[c]).exchange(me + 1) == 0; };
  // A thread's own chunks are taken from the front, a helper's from the back: each side takes a
  // contiguous run and stops at the first chunk the other side took, so none is left behind
  // (of several helpers, only the first to take the last chunk goes on).
  for (std::size_t c = first_chunk_of(me), own_end = first_chunk_of(me + 1); c < own_end && take(c); ++c)
    find_chunk(c);
  for (int k = 1; k < threads; ++k) {
    const int other = (me + k) % threads;
    const std::size_t other_begin = first_chunk_of(other);
    for (std::size_t c = first_chunk_of(other + 1); c-- > other_begin && take(c);) find_chunk(c);
  }
}

// Every thread of the team, after a barrier (all pair sums and all chunks done, and so all
// reactions added): the surface sums kept back added (after the pair sums: the order of one
// thread). Then the chunks' contacts are gathered into world.wall_contacts.
void finish_contacts(World& world) {
  ForceWorkspace& ws = world.force_workspace;
  ParticleStore& p = world.particles;
  for (const ForceWorkspace::WallSum& sum : ws.wall_deferred[omp_get_thread_num()]) add_surface_sum(p, sum);
  const std::size_t chunks = ws.wall_chunks.size();
#pragma omp single
  {
    ws.wall_chunk_start.resize(chunks + 1);
    ws.wall_chunk_start[0] = 0;
    for (std::size_t c = 0; c < chunks; ++c)
      ws.wall_chunk_start[c + 1] = ws.wall_chunk_start[c] + ws.wall_chunks[c].size();
    // Not cleared first: only elements past the current size are constructed, then overwritten.
    world.wall_contacts.resize(ws.wall_chunk_start[chunks]);
  }  // (its barrier: every sum is added)
  // Each chunk by the thread that found its contacts: they are in its cache.
  const int me = omp_get_thread_num() + 1;
  for (std::size_t c = 0; c < chunks; ++c)
    if (ws.chunk_taken[c] == me)
      std::copy(ws.wall_chunks[c].begin(), ws.wall_chunks[c].end(), world.wall_contacts.begin() + ws.wall_chunk_start[c]);
}

// One team for the whole stage: pair sums (phase 1, barrier, phase 2), surface contacts in
// chunks as threads come free (their reactions onto the surfaces added in chunk order as the
// chunks are found), a barrier, then finish_contacts: the kept sums added, the contacts gathered.
template <bool kBatched, bool kPeriodic>
void contact_forces(World& world) {
  const std::size_t n = world.particles.size();
  ForceWorkspace& ws = world.force_workspace;
  const int thread_count = world.threading.team(n);
  if (kBatched && ws.batches.size() < static_cast<std::size_t>(thread_count)) ws.batches.resize(thread_count);
  ws.wall_deferred.resize(std::max<std::size_t>(ws.wall_deferred.size(), thread_count));
  ws.rows_done.assign(thread_count, 0);
  prepare_wall_contacts(world);
  // Stage times as thread 0 sees them (s).
  double start = omp_get_wtime(), pairs_done = start;
  int excessive = 0;
#pragma omp parallel num_threads(thread_count) reduction(| : excessive)
  {
    pair_forces<kBatched, kPeriodic>(world, excessive);
    if (omp_get_thread_num() == 0) pairs_done = omp_get_wtime();
    find_wall_contacts(world, ws, excessive);
#pragma omp barrier
    finish_contacts(world);
  }
  const double end = omp_get_wtime();
  learn_shares(ws);
  world.excessive_overlap = excessive != 0;
  world.timers.add(world.timers.stage("pair forces"), pairs_done - start);
  world.timers.add(world.timers.stage("surface forces"), end - pairs_done);
}

}  // namespace

namespace {

// The pair law the batched kernel computes for every particle pair, or null: all particle
// types share one material (walls may have others: their contacts take the scalar law) whose
// law the kernel handles. The batched path keeps no rolling history: none if EPSD is absent.
const InteractionParameters* batch_law(const World& world) {
  if (world.types.empty() || world.pairs.keep_rolling_history) return nullptr;
  const std::uint16_t material = world.types.front().material_index;
  for (const ParticleTypeInfo& type : world.types)
    if (type.material_index != material) return nullptr;
  const InteractionParameters& law = world.materials.between(material, material);
  return batch_handles(law) ? &law : nullptr;
}

}  // namespace

void compute_contact_forces(World& world) {
  // Leads of zero unless the step set them (a caller outside the time step).
  if (world.force_workspace.velocity_lead.size() != world.particles.size()) set_velocity_leads(world, 0.0);
  world.force_workspace.batch_law = batch_law(world);
  const bool batched = world.force_workspace.batch_law != nullptr;
  const bool periodic = world.pairs.periodic.any();
  if (batched)
    periodic ? contact_forces<true, true>(world) : contact_forces<true, false>(world);
  else
    periodic ? contact_forces<false, true>(world) : contact_forces<false, false>(world);
}

}  // namespace quarry::sim
