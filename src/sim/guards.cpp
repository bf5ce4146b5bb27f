// Run-time physics guards (DESIGN, STYLE "errors"): stop with the step, the particle, the
// values and what to change when the state stops being physical — NaN/inf, or an overlap
// beyond a fraction of the radius (the time step is too large or the material too soft).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/surface_contact.h"
#include "integrate/integrator.h"
#include "integrate/timestep.h"
#include "sim/opening_lanes.h"
#include "sim/step.h"
#include "sim/time_step_choice.h"

namespace quarry::sim {

namespace {
bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite_state(const ParticleStore& p, std::size_t i) {
  return finite(p.position[i]) && finite(p.velocity[i]) && finite(p.angular_velocity[i]);
}
std::string show(const Vec3& v) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z);
}

// Whether an excessive overlap is physics or a blow-up (issue 19). An elastic contact keeps
// ½ m* v_n² + U(δ) constant, U = 8/15 E* sqrt(R*) δ^(5/2) (Hertz, Johnson 1985 eq. 11.23) or
// ½ k δ² (linear): the pair holds the energy of an impact at v_eq = sqrt(v_n² + 2U/m*). At
// or below the deck's expected impact speed the overlap is what theory predicts for the
// material and the speed; far above it, energy was created (the time step is too large) —
// unless a heavier particle of the deck, landing at that speed, brings at least that energy:
// a 7 cm particle on a 3 cm one lying on the floor, or a dense stream behind it, presses the
// pair further than its own impact could, and both readings are given.
struct OverlapDiagnosis {
  std::string what, hint;
};

OverlapDiagnosis diagnose_overlap(const World& world, const InteractionParameters& p,
                                  double effective_mass, double effective_radius,
                                  double reference_radius, double overlap, double normal_speed) {
  const double elastic = p.normal_model == NormalModel::linear
                             ? 0.5 * p.linear_normal_stiffness * overlap * overlap
                             : 8.0 / 15.0 * p.effective_youngs_modulus *
                                   std::sqrt(effective_radius) * std::pow(overlap, 2.5);  // J
  const double equivalent =
      std::sqrt(normal_speed * normal_speed + 2.0 * elastic / effective_mass);  // m/s
  const TimeStepChoice choice = choose_time_step(world.spec, world.fastest_surface);
  const double expected = choice.impact_speed;  // m/s
  const double guard = world.spec.simulation.max_overlap_fraction.value;
  // The stiffening that keeps this pair's peak overlap, all of its energy stored elastically,
  // at 80 % of the guard: the Hertz peak overlap goes as E^(-2/5), so E scales as
  // (delta_peak / target)^(5/2); linear delta_peak = v sqrt(m*/k), so k as (delta_peak / target)^2.
  const double target = 0.8 * guard * reference_radius;  // m
  const double stiffening =
      p.normal_model == NormalModel::linear
          ? equivalent * equivalent * effective_mass / p.linear_normal_stiffness / (target * target)
          : std::pow(hertz_peak_overlap(effective_mass, effective_radius, p.effective_youngs_modulus,
                                        equivalent) / target,
                     2.5);
  const std::string stiffen = fmt::format(
      "a {:.2g}-fold {} keeps this pair's peak overlap at 80 % of the limit", stiffening,
      p.normal_model == NormalModel::linear ? "normal stiffness" : "Young's modulus");
  if (equivalent <= 1.25 * expected)
    return {
        fmt::format(
            "the pair holds the energy of an impact at {:.3g} m/s, within the expected {:.3g} m/s: "
            "this overlap is what contact theory predicts for this material at this speed, not "
            "an instability",
            equivalent, expected),
        fmt::format("stiffen the material ({}), raise simulation.max_overlap_fraction (now {:.3g}), "
                    "or lower the impact speed; `quarry check` compares the Hertz peak overlap "
                    "with the guard",
                    stiffen, guard)};
  const double brought = 0.5 * choice.heaviest_mass * expected * expected;  // J
  if (elastic <= brought && choice.heaviest_mass > 4.0 * effective_mass)
    return {fmt::format("the pair holds the energy of an impact at {:.3g} m/s, above the "
                        "expected {:.3g} m/s, but a '{}' particle ({:.3g} kg) landing at that "
                        "speed brings {:.3g} J, more than the {:.3g} J stored here: a heavier "
                        "particle or a dense stream pressing the pair against its neighbours or "
                        "a wall (physics), or energy created numerically (an instability)",
                        equivalent, expected, choice.heaviest_type, choice.heaviest_mass, brought,
                        elastic),
            fmt::format("if heavy particles land on light ones, stiffen the material ({}) or "
                        "raise simulation.max_overlap_fraction (now {:.3g}); reducing "
                        "simulation.time_step (now {:.4g} s) helps only against an instability",
                        stiffen, guard, world.dt)};
  return {fmt::format("the pair holds the energy of an impact at {:.3g} m/s, far above the "
                      "expected {:.3g} m/s: "
                      "energy was created numerically (the run is going unstable)",
                      equivalent, expected),
          fmt::format(
              "reduce simulation.time_step (now {:.4g} s); if impacts really are that fast, say so "
              "with simulation.impact_speed so that the time step is chosen for them",
              world.dt)};
}

// The opening pass over particles [first, end) of one thread: kick, drift, and the scan of what
// the drift did (into `tally`), four particles at a time (sim/opening_lanes.h), the rest one by
// one; the same values either way. kApart: the kick adds the one-step loads kept apart from the
// forces; kCompare: the list was built for these particles (`reference`, `id_at_build`). Each
// combination is an instance of its own, so a plain step reads nothing it does not need.
// `domain`: null when the deck has none.
template <bool kApart, bool kCompare>
void open_range(ParticleStore& p, std::size_t first, std::size_t end, double h, double dt,
                const ParticleStore::ApartLoads& apart, const Aabb* domain, const Vec3* reference,
                const ParticleId* id_at_build, OpeningTally& tally) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const Aabb box = domain ? *domain : Aabb{{-inf, -inf, -inf}, {inf, inf, inf}};
  const Packed lo = packed_corner(box.lo), hi = packed_corner(box.hi);
  LaneTally lanes;
  std::size_t i = first;
  for (; i + 4 <= end; i += 4)
    open_four<kApart, kCompare>(p, i, h, dt, apart, lo, hi, reference, id_at_build, lanes);
  lanes.add_to(tally, domain != nullptr);
  for (; i < end; ++i) {
    if constexpr (kApart)
      integrate::kick_drift_particle(p, i, h, dt, apart);
    else
      integrate::kick_drift_particle(p, i, h, dt);
    const Vec3 x = p.position[i], v = p.velocity[i], w = p.angular_velocity[i];
    // x·0 is 0 for a finite x and NaN for ±inf or NaN, so one sum tells whether all nine
    // components are finite (the first offender is searched only if one is not).
    const double zero = (x.x * 0.0 + x.y * 0.0 + x.z * 0.0) + (v.x * 0.0 + v.y * 0.0 + v.z * 0.0) +
                        (w.x * 0.0 + w.y * 0.0 + w.z * 0.0);
    tally.non_finite |= !(zero == 0.0);
    if (domain) tally.any_outside |= !domain->contains(x);
    // Moved more than half its radius (|v| dt > R/2): check_tunnelling looks closer.
    tally.fast |= (v.x * v.x + v.y * v.y + v.z * v.z) * (dt * dt) > 0.25 * p.radius[i] * p.radius[i];
    if constexpr (kCompare) {
      // NaN compares false: a non-finite particle is reported through `non_finite`, not here.
      const double d2 = norm2(x - reference[i]);  // m²
      tally.largest_displacement_squared =
          d2 > tally.largest_displacement_squared ? d2 : tally.largest_displacement_squared;
      tally.ids_changed |= p.id[i] != id_at_build[i];
    }
  }
}

}  // namespace

// Per-thread tallies of the parallel opening pass, merged (exact: flags and a maximum, so any
// merge order gives the same result).
#pragma omp declare reduction(merge:OpeningTally \
                              : omp_out.merge(omp_in)) initializer(omp_priv = OpeningTally{})

DriftScan kick_drift_scan(World& world, double h, double dt) {
  ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  // Periodic axes are unbounded here: a particle leaving through a periodic face is wrapped
  // at the next list build (rebuild_lists), not removed.
  const Aabb& deck_box = world.spec.simulation.domain.value;
  const Aabb box = world.pairs.periodic.removal_bounds(deck_box);
  const Aabb* const domain = deck_box.empty() ? nullptr : &box;
  const PairList& list = world.pairs;
  const bool compare = list.built_for(n);
  const Vec3* const reference = compare ? list.reference_positions.data() : nullptr;  // m
  const ParticleId* const id_at_build = compare ? list.ids_at_build.data() : nullptr;
  OpeningTally tally;
  const std::span<const std::uint32_t> ranges = particle_ranges(world);
  const ParticleStore::ApartLoads apart = p.apart_once_loads();  // a partner's one-step loads
#pragma omp parallel num_threads(world.threading.team(n)) reduction(merge : tally)
  {
    const auto [first, end] = thread_block(n, omp_get_thread_num(), omp_get_num_threads(), ranges);
    const auto open = [&]<bool kApart, bool kCompare>() {
      open_range<kApart, kCompare>(p, first, end, h, dt, apart, domain, reference, id_at_build, tally);
    };
    if (apart.any())
      compare ? open.template operator()<true, true>() : open.template operator()<true, false>();
    else
      compare ? open.template operator()<false, true>() : open.template operator()<false, false>();
  }
  std::size_t first_bad = n;
  if (tally.non_finite)
    for (std::size_t i = 0; i < n && first_bad == n; ++i)
      if (!finite_state(p, i)) first_bad = i;
  DriftScan scan;
  static_cast<OpeningTally&>(scan) = tally;
  scan.particles = n;
  scan.first_non_finite = first_bad;
  scan.list_compared = compare;
  return scan;
}

void check_finite(const World& world) {
  const ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  // The first offending index (the same for any thread count), or n: a parallel min-reduction.
  std::size_t first_bad = n;
#pragma omp parallel for schedule(static) num_threads(world.threading.team(n)) \
    reduction(min                                                              \
              : first_bad)
  for (std::size_t i = 0; i < n; ++i)
    if (!finite_state(p, i)) first_bad = std::min(first_bad, i);
  DriftScan scan;
  scan.particles = n;
  scan.first_non_finite = first_bad;
  check_finite(world, scan);
}

void check_finite(const World& world, const DriftScan& scan) {
  const ParticleStore& p = world.particles;
  if (scan.first_non_finite < scan.particles) {
    const std::size_t i = scan.first_non_finite;
    throw PhysicsError(fmt::format(
        "step {} (t = {:.6g} s): particle id {} has a non-finite state: position {} m, "
        "velocity {} m/s, angular velocity {} rad/s, force {} N\n"
        "  hint: the run went unstable; reduce simulation.time_step (now {:.4g} s) or check the "
        "material stiffness, restitution and external forces",
        world.step_count, world.time, p.id[i], show(p.position[i]), show(p.velocity[i]),
        show(p.angular_velocity[i]), show(integrate::kick_force(p, i, p.apart_once_loads())), world.dt));
  }
}

void check_tunnelling(const World& world, const DriftScan& scan, double dt) {
  if (!scan.fast || world.surfaces.empty()) return;
  const ParticleStore& p = world.particles;
  std::vector<std::uint32_t> candidates;
  std::vector<SurfaceContact> contacts;
  for (std::size_t i = 0; i < p.size();
       ++i) {                              // in index order: the same message for any thread count
    const double r = p.radius[i];          // m
    const Vec3 step = p.velocity[i] * dt;  // m, this drift (x_new = x_old + v dt)
    const double length = norm(step);
    if (!(length > 0.5 * r)) continue;
    // The swept segment, sampled every R/2 (at most 1000 samples): a sphere of radius R at each
    // sample covers the whole sweep. The grids were built for the vertices at the last list
    // build; the skin covers what a surface moved since.
    const int samples = static_cast<int>(std::min(1000.0, std::ceil(length / (0.5 * r))));
    const double reach = r + world.skin;
    for (int k = 0; k <= samples; ++k) {
      const Vec3 at = p.position[i] - step * (1.0 - static_cast<double>(k) / samples);
      for (const WorldSurface& s : world.surfaces) {
        s.grid.query(Aabb{at - Vec3{reach, reach, reach}, at + Vec3{reach, reach, reach}},
                     candidates);
        if (candidates.empty()) continue;
        find_surface_contacts(s.mesh, s.topology, at, r, candidates, contacts);
        if (contacts.empty()) continue;
        // The suggested step moves the particle a tenth of its radius (the default overlap guard).
        throw PhysicsError(fmt::format(
            "step {} (t = {:.6g} s): particle id {} moved {:.4g} m in one step ({:.0f} % of its "
            "radius "
            "{:.4g} m) at {:.4g} m/s past surface '{}' (element {}): its contact cannot be "
            "resolved and it "
            "can pass through the surface unseen (tunnelling)\n"
            "  hint: reduce simulation.time_step (now {:.4g} s) to at most {:.3g} s for this "
            "speed, or give "
            "simulation.impact_speed ≥ {:.3g} m/s so that check sizes the time step for it",
            world.step_count, world.time, p.id[i], length, 100.0 * length / r, r, length / dt,
            s.mesh.name, contacts.front().triangle, dt, 0.1 * r / (length / dt), length / dt));
      }
    }
  }
}

void check_overlaps(const World& world) {
  // The force stage flags excessive overlaps as it computes them; only then is it worth
  // searching for the first offender (in a fixed order, so the message is deterministic).
  if (!world.excessive_overlap) return;
  const ParticleStore& p = world.particles;
  const double limit = world.spec.simulation.max_overlap_fraction.value;
  const PairList& list = world.pairs;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
      // Positions are those of the force stage (the closing half kick changes velocities only).
      const std::uint32_t j = list.partner[k];
      const Vec3 d = list.periodic.minimum_image(p.position[i] - p.position[j]);  // m
      const double overlap = (p.radius[i] + p.radius[j]) - norm(d);               // m
      if (overlap <= 0.0) continue;
      const double smaller = std::min(p.radius[i], p.radius[j]);
      if (overlap <= limit * smaller) continue;
      const Vec3 n = normalized(d);
      const OverlapDiagnosis why =
          diagnose_overlap(world, world.materials.between(p.material[i], p.material[j]),
                           1.0 / (p.inv_mass[i] + p.inv_mass[j]),
                           p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]), smaller,
                           overlap, dot(p.velocity[i] - p.velocity[j], n));
      throw PhysicsError(fmt::format(
          "step {} (t = {:.6g} s): particles id {} and id {} overlap by {:.4g} m = {:.1f} % of the "
          "smaller radius {:.4g} m (limit {:.3g} %); relative speed {:.4g} m/s; {}\n  hint: {}",
          world.step_count, world.time, p.id[i], p.id[j], overlap, 100.0 * overlap / smaller,
          smaller, 100.0 * limit, norm(p.velocity[i] - p.velocity[j]), why.what, why.hint));
    }
  }
  for (const WallContact& contact : world.wall_contacts) {
    const std::size_t i = contact.particle;
    const double overlap = p.radius[i] - norm(p.position[i] - contact.point);
    if (overlap <= limit * p.radius[i]) continue;
    const Surface& mesh = world.surfaces[contact.surface].mesh;
    Vec3 wall_velocity;  // m/s, the triangle's mean vertex velocity
    if (!mesh.vertex_velocities.empty())
      for (int k = 0; k < 3; ++k)
        wall_velocity += mesh.vertex_velocities[mesh.triangles[contact.triangle][k]] / 3.0;
    const OverlapDiagnosis why = diagnose_overlap(
        world, world.materials.between(p.material[i], mesh.material), 1.0 / p.inv_mass[i],
        p.radius[i], p.radius[i], overlap, dot(p.velocity[i] - wall_velocity, contact.normal));
    throw PhysicsError(fmt::format(
        "step {} (t = {:.6g} s): particle id {} penetrates surface '{}' (element {}) by {:.4g} m "
        "= {:.1f} % of its radius {:.4g} m (limit {:.3g} %); speed {:.4g} m/s; {}\n  hint: {}{}",
        world.step_count, world.time, p.id[i], mesh.name, contact.triangle, overlap,
        100.0 * overlap / p.radius[i], p.radius[i], 100.0 * limit, norm(p.velocity[i]), why.what,
        why.hint,
        mesh.vertex_velocities.empty()
            ? ""
            : "; a surface moving faster than particles can follow also causes this"));
  }
}

}  // namespace quarry::sim
