// Time-step choice: Rayleigh limit per particle type, Hertz contact-time check per material pair.
#include "sim/time_step_choice.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "contact/contact_law.h"
#include "core/sphere.h"
#include "insert/size_distribution.h"
#include "integrate/timestep.h"

namespace quarry {

namespace {

const MaterialSpec* find_material(const SimulationSpec& spec, const std::string& name) {
  for (const auto& m : spec.materials)
    if (m.name.value == name) return &m;
  return nullptr;
}

MaterialProperties properties_of(const MaterialSpec& m) {
  return {m.density.value, m.youngs_modulus.value, m.poisson_ratio.value, m.rigid.value};
}

// The fastest factory launch speed (m/s) and its factory.
std::pair<double, const FactorySpec*> fastest_launch(const SimulationSpec& spec) {
  std::pair<double, const FactorySpec*> fastest{0.0, nullptr};
  for (const auto& f : spec.factories)
    if (norm(f.initial_velocity.value) > fastest.first)
      fastest = {norm(f.initial_velocity.value), &f};
  return fastest;
}

// Impact speed estimated from the deck (m/s): the fastest factory velocity or initial particle
// (`particles:`) plus free fall over the domain's diagonal, v = |v0| + sqrt(2 g H), plus the
// fastest prescribed wall's speed V (a particle moving at v meets a wall coming at it at v + V).
double estimated_impact_speed(const SimulationSpec& spec, const FastestSurface& fastest) {
  const Aabb& box = spec.simulation.domain.value;
  const double height = box.empty() ? 0.0 : norm(box.hi - box.lo);
  double launch = fastest_launch(spec).first;  // m/s
  for (const InitialParticle& p : spec.initial_particles) launch = std::max(launch, norm(p.velocity));
  return launch + std::sqrt(2.0 * norm(spec.simulation.gravity.value) * height) + fastest.speed;
}

// Expected impact speed (m/s): the deck's value, else the estimate.
double expected_impact_speed(const SimulationSpec& spec, const FastestSurface& fastest) {
  return spec.simulation.impact_speed ? spec.simulation.impact_speed->value
                                      : estimated_impact_speed(spec, fastest);
}

}  // namespace

TimeStepChoice choose_time_step(const SimulationSpec& spec, const FastestSurface& fastest) {
  TimeStepChoice choice;
  choice.rayleigh_time = std::numeric_limits<double>::infinity();
  choice.hertz_time = std::numeric_limits<double>::infinity();
  choice.impact_speed = expected_impact_speed(spec, fastest);

  // Surface materials that particles can hit (walls and coupled structures).
  std::vector<const MaterialSpec*> wall_materials;
  for (const auto& s : spec.surfaces)
    if (const MaterialSpec* m = find_material(spec, s.material.value)) wall_materials.push_back(m);
  for (const auto& s : spec.structures)
    if (const MaterialSpec* m = find_material(spec, s.material.value)) wall_materials.push_back(m);
  const Vec3& g = spec.simulation.gravity.value;
  const double gravity = std::hypot(g.x, g.y, g.z);  // m/s²; without overflow for 1e308

  for (const auto& type : spec.particle_types) {
    const MaterialSpec* material = find_material(spec, type.material.value);
    if (!material) continue;
    const SizeSampler sizes(type.size);
    const double radius = sizes.min_radius();  // m, the smallest one limits
    const double largest_mass = sphere_mass(material->density, sizes.max_radius());  // kg
    if (!type.fixed.value && largest_mass > choice.heaviest_mass) {
      choice.heaviest_mass = largest_mass;
      choice.heaviest_type = type.name.value;
    }
    const double shear = shear_modulus(material->youngs_modulus, material->poisson_ratio);
    const double rayleigh =
        rayleigh_time_step(radius, material->density, shear, material->poisson_ratio);
    if (rayleigh < choice.rayleigh_time) {
      choice.rayleigh_time = rayleigh;
      choice.rayleigh_limiter = fmt::format("particle type '{}' (material '{}', R = {:.4g} mm)",
                                            type.name.value, material->name.value, radius * 1e3);
    }
    // Hertz contact time: smallest particle against its own kind and against each wall.
    const MaterialProperties own = properties_of(*material);
    const double mass = sphere_mass(material->density, radius);
    // E* (Pa) of this type against `other` (a surface's material or its own).
    const auto effective_youngs = [&own](const MaterialProperties& other) {
      InteractionSpec neutral;
      return make_interaction(own, other, neutral).effective_youngs_modulus;
    };
    auto consider = [&](const MaterialProperties& other, double effective_mass,
                        double effective_radius, const std::string& what) {
      const double youngs = effective_youngs(other);  // Pa
      const double t = hertz_contact_time(effective_mass, effective_radius, youngs,
                                          choice.impact_speed);
      if (t < choice.hertz_time) {
        choice.hertz_time = t;
        choice.hertz_limiter = what;
      }
      const double overlap = hertz_peak_overlap(effective_mass, effective_radius, youngs,
                                                choice.impact_speed);
      if (overlap / radius > choice.peak_overlap_fraction) {
        choice.peak_overlap_fraction = overlap / radius;
        choice.peak_overlap_limiter = what;
      }
    };
    // At rest under its own weight: the largest particle of the type on each wall and on one
    // of its own kind, both of the wall's and its own stiffness (resting_overlap below).
    if (!type.fixed.value && !wall_materials.empty() && gravity > 0.0) {
      const double largest = sizes.max_radius();  // m: δ/R grows as R^(2/3)
      const double weight = largest_mass * gravity;  // N
      auto rest_on = [&](const MaterialProperties& other, double effective_radius,
                         const std::string& what) {
        // Hertz F = 4/3 E* √R* δ^(3/2) (Johnson 1985 eq. 4.22) at F = m g.
        const double overlap = std::pow(
            3.0 * weight / (4.0 * effective_youngs(other) * std::sqrt(effective_radius)),
            2.0 / 3.0);  // m
        if (overlap / largest > choice.resting_overlap_fraction) {
          choice.resting_overlap_fraction = overlap / largest;
          choice.resting_overlap_limiter = what;
        }
      };
      rest_on(own, 0.5 * largest,
              fmt::format("a '{}' particle of R = {:.4g} mm on another", type.name.value,
                          largest * 1e3));
      for (const MaterialSpec* wall : wall_materials)
        rest_on(properties_of(*wall), largest,
                fmt::format("a '{}' particle of R = {:.4g} mm on a '{}' surface", type.name.value,
                            largest * 1e3, wall->name.value));
    }
    if (choice.impact_speed > 0.0) {
      consider(own, 0.5 * mass, 0.5 * radius,
               fmt::format("two '{}' particles, R = {:.4g} mm", type.name.value, radius * 1e3));
      for (const MaterialSpec* wall : wall_materials)
        consider(properties_of(*wall), mass, radius,
                 fmt::format("'{}' particle on a '{}' surface, R = {:.4g} mm", type.name.value,
                             wall->name.value, radius * 1e3));
    }
  }

  if (spec.simulation.fixed_time_step) {
    choice.dt = spec.simulation.fixed_time_step->value;
    choice.fixed = true;
  } else if (std::isfinite(choice.rayleigh_time)) {
    choice.dt = spec.simulation.rayleigh_fraction.value * choice.rayleigh_time;
  }

  const SourceLocation where = spec.simulation.fixed_time_step
                                   ? spec.simulation.fixed_time_step->where
                                   : spec.simulation.rayleigh_fraction.where;
  if (choice.dt <= 0.0 || !std::isfinite(choice.dt)) {
    choice.problems.push_back({Severity::error, where, "no time step could be chosen",
                               "give simulation.time_step or define a particle type"});
    return choice;
  }
  // The run counts its steps in 64 bits and its time in doubles: beyond 1e15 steps the time no
  // longer advances by dt exactly enough to schedule outputs (and no run would end).
  constexpr double kMostSteps = 1e15;
  const double steps = spec.simulation.end_time.value / choice.dt;
  if (steps > kMostSteps)
    choice.problems.push_back(
        {Severity::error, spec.simulation.end_time.where,
         fmt::format("end time {:.4g} s is {:.3g} steps of {:.4g} s (at most {:.0e})",
                     spec.simulation.end_time.value, steps, choice.dt, kMostSteps),
         "shorten simulation.end_time or use a larger time step"});
  if (std::isfinite(choice.hertz_time)) {
    choice.steps_per_contact = choice.hertz_time / choice.dt;
    const std::string what = fmt::format(
        "time step {:.4g} s resolves the Hertz contact time {:.4g} s ({}, impact speed {:.3g} m/s) "
        "with only {:.1f} steps",
        choice.dt, choice.hertz_time, choice.hertz_limiter, choice.impact_speed,
        choice.steps_per_contact);
    const std::string hint = fmt::format(
        "use a time step ≤ {:.3g} s (10 steps per contact), or lower the Young's modulus",
        choice.hertz_time / 10.0);
    if (choice.steps_per_contact < 6.0)
      choice.problems.push_back({Severity::error, where, what + " (at least 6 are needed)", hint});
    else if (choice.steps_per_contact < 10.0)
      choice.problems.push_back({Severity::warning, where, what + " (10 are recommended)", hint});
  }
  // An impact_speed below a factory's launch speed checks the time step for impacts slower than
  // the deck makes (issue 19: 0.1 m/s given, particles launched at 100 m/s passed through a plate).
  if (const auto [launch, factory] = fastest_launch(spec);
      spec.simulation.impact_speed && launch > choice.impact_speed)
    choice.problems.push_back({Severity::warning, spec.simulation.impact_speed->where,
                               fmt::format("impact_speed {:.3g} m/s is below the launch speed "
                                           "{:.3g} m/s of factory '{}': the time step "
                                           "is checked for slower impacts than the deck makes",
                                           choice.impact_speed, launch, factory->name.value),
                               fmt::format("give impact_speed ≥ {:.3g} m/s (the launch speed; with "
                                           "free fall over the domain {:.3g} "
                                           "m/s), or remove it to use that estimate",
                                           launch, estimated_impact_speed(spec, fastest))});
  // The same for a wall moving faster than the deck's impact_speed (a mixer's blade, a drum).
  if (spec.simulation.impact_speed && fastest.speed > choice.impact_speed)
    choice.problems.push_back({Severity::warning, spec.simulation.impact_speed->where,
                               fmt::format("impact_speed {:.3g} m/s is below the speed {:.3g} m/s "
                                           "of surface '{}': the time step is checked for slower "
                                           "impacts than the deck makes",
                                           choice.impact_speed, fastest.speed, fastest.name),
                               fmt::format("give impact_speed ≥ {:.3g} m/s (the surface's speed; "
                                           "with the particles' own estimate {:.3g} m/s), or "
                                           "remove it to use that estimate",
                                           fastest.speed, estimated_impact_speed(spec, fastest))});
  // A sound impact must not trip the overlap guard (issue 19: a pour of 5 MPa, 4 mm spheres at
  // 1.5 m/s stopped on the 10 % guard where Hertz predicts 12.5 %). δ ∝ E*^(−2/5) (Johnson 1985
  // eq. 11.23), so E × (δ/δ_guard)^(5/2) brings the peak down to the guard.
  const double guard = spec.simulation.max_overlap_fraction.value;
  if (guard > 0.0 && choice.peak_overlap_fraction > guard) {
    const double stiffer = std::pow(choice.peak_overlap_fraction / guard, 2.5);
    choice.problems.push_back(
        {Severity::warning, spec.simulation.max_overlap_fraction.where,
         fmt::format(
             "at the impact speed {:.3g} m/s Hertz theory predicts a peak overlap of {:.1f} % of "
             "the "
             "radius ({}), above the overlap guard {:.0f} %: a sound impact would stop the run",
             choice.impact_speed, 100.0 * choice.peak_overlap_fraction, choice.peak_overlap_limiter,
             100.0 * guard),
         fmt::format(
             "raise the Young's modulus {:.3g}-fold (the peak then meets the guard), or set "
             "simulation.max_overlap_fraction above {:.3g}; if the impacts are slower, say so with "
             "simulation.impact_speed",
             stiffer, choice.peak_overlap_fraction)});
  }
  // Gravity the contacts cannot carry (a gravity of 1e308 m/s² passed check, and its run
  // stopped at its first contact): a particle at rest on a surface, or on another resting
  // there, presses in by the Hertz static overlap of its weight. Beyond the guard every
  // particle that comes to rest stops the run. δ ∝ E*^(−2/3), so E × (δ/δ_guard)^(3/2) brings
  // it to the guard.
  if (guard > 0.0 && !(choice.resting_overlap_fraction <= guard) &&
      !choice.resting_overlap_limiter.empty()) {
    const double stiffer = std::pow(choice.resting_overlap_fraction / guard, 1.5);
    choice.problems.push_back(
        {Severity::error, spec.simulation.gravity.where,
         fmt::format("gravity {:.4g} m/s² presses {} in by {:.3g} % of its radius at rest "
                     "(Hertz), beyond the overlap guard {:.0f} %: every particle that comes to "
                     "rest would stop the run",
                     gravity, choice.resting_overlap_limiter,
                     100.0 * choice.resting_overlap_fraction, 100.0 * guard),
         fmt::format("gravity is in m/s² (9.81 on Earth); a gravity this strong needs the "
                     "Young's modulus {:.3g}-fold, or simulation.max_overlap_fraction above {:.3g}",
                     stiffer, choice.resting_overlap_fraction)});
  }
  return choice;
}

Diagnostics problems_of(const TimeStepChoice& choice, Severity severity) {
  Diagnostics out;
  for (const Diagnostic& p : choice.problems) {
    if (p.severity != severity) continue;
    if (severity == Severity::error) out.error(p.where, p.message, p.hint);
    else out.warning(p.where, p.message, p.hint);
  }
  return out;
}

void throw_time_step_errors(const TimeStepChoice& choice) {
  const Diagnostics errors = problems_of(choice, Severity::error);
  if (errors.has_errors()) throw UserError(errors);
}

}  // namespace quarry
