// Run-time estimate: expected particle count from the factories' schedules, and the cost per
// particle-step measured on a lattice bed of the smallest particle type with the deck's contact
// law (so contact count and stiffness are representative).
#include "sim/estimate.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "insert/size_distribution.h"
#include "sim/step.h"
#include "sim/time_step_choice.h"
#include "sim/world.h"

namespace quarry::sim {

namespace {

// Expected number of particles a factory has inserted by time t (linear ramp at its rate).
double factory_count_at(const FactorySpec& f, double particle_mass, double t) {
  double target = 0.0;
  if (f.target_count) target = static_cast<double>(f.target_count->value);
  else if (f.target_mass && particle_mass > 0) target = f.target_mass->value / particle_mass;
  if (t < f.start_time.value) return 0.0;
  if (!f.mass_rate || f.mass_rate->value <= 0) return target;
  const double rate = f.mass_rate->value / particle_mass;  // particles/s
  const double by_rate = rate * (std::min(t, f.stop_time.value) - f.start_time.value);
  return std::min(target, by_rate);
}

// Seconds per particle-step on a cubic lattice bed of `count` particles of the given type,
// lightly compressed so that each particle has its six neighbours in contact, and stirred with
// random velocities of half the impact speed so that neighbour lists are rebuilt about as often
// as in a pour (a bed at rest would hide the rebuild cost and under-estimate a filling run).
double calibrate(const SimulationSpec& deck, std::size_t type_index, int count, double speed) {
  SimulationSpec spec;
  spec.deck_path = deck.deck_path;
  spec.materials = deck.materials;
  spec.interactions = deck.interactions;
  spec.particle_types = {deck.particle_types[type_index]};
  spec.simulation = deck.simulation;
  spec.simulation.sort_interval = 0;
  spec.simulation.impact_speed = Located<double>(0.1);
  // The calibration measures cost, not physics: the stirred lattice must not stop on the deck's
  // overlap guard (issue 19: `estimate` exited 3 on decks `check` accepts). An overlap of a whole
  // radius still stops it (the neighbour search is sized for less).
  spec.simulation.max_overlap_fraction = 1.0;
  const std::string material = spec.particle_types[0].material.value;
  const SizeSampler sampler(spec.particle_types[0].size);
  const double radius = sampler.min_radius();
  const int side = std::max(2, static_cast<int>(std::cbrt(static_cast<double>(count))));
  const double spacing = 2.0 * radius * 0.999;  // m, slight overlap
  Aabb domain;
  domain.lo = Vec3{-1, -1, -1} * (side * spacing);
  domain.hi = Vec3{2, 2, 2} * (side * spacing);
  spec.simulation.domain = domain;
  spec.simulation.gravity = Vec3{};
  World world = build_world(spec);
  std::size_t m = 0;
  while (m < world.materials.count() && world.materials.names[m] != material) ++m;
  const double density = world.materials.properties[m].density;
  ParticleId id = 1;
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b)
      for (int c = 0; c < side; ++c)
        world.particles.add(id++, 0, static_cast<std::uint16_t>(m), Vec3{double(a), double(b), double(c)} * spacing,
                            Vec3{}, radius, density, 0.0);
  // Deterministic pseudo-random directions (golden-angle spiral), magnitude `speed` (m/s).
  for (std::size_t i = 0; i < world.particles.size(); ++i) {
    const double z = 1.0 - 2.0 * (static_cast<double>(i) + 0.5) / static_cast<double>(world.particles.size());
    const double phi = 2.39996322972865332 * static_cast<double>(i);  // rad, golden angle
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    world.particles.velocity[i] = Vec3{r * std::cos(phi), r * std::sin(phi), z} * speed;
  }
  initialize(world);
  const auto start = std::chrono::steady_clock::now();
  int steps = 0;
  double elapsed = 0.0;
  while (steps < 20 || (elapsed < 1.0 && steps < 2000)) {  // at least 20 steps, about 1 s
    step(world);
    ++steps;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return elapsed / (static_cast<double>(steps) * static_cast<double>(world.particles.size()));
}

}  // namespace

Estimate estimate_run(const SimulationSpec& spec) {
  Estimate e;
  const TimeStepChoice choice = choose_time_step(spec);
  e.rayleigh_time = choice.rayleigh_time;
  e.rayleigh_limiter = choice.rayleigh_limiter;
  e.hertz_time = choice.hertz_time;
  e.hertz_limiter = choice.hertz_limiter;
  e.impact_speed = choice.impact_speed;
  e.dt = choice.dt;
  const double end = spec.simulation.end_time.value;
  e.steps = e.dt > 0 ? std::ceil(end / e.dt - 0.5) : 0;
  // Particle count against time, integrated over the run with 1000 samples.
  const std::vector<ParticleTypeInfo> types = particle_type_infos(spec);
  std::vector<double> particle_mass(spec.factories.size(), 0.0);
  std::size_t smallest_type = 0;
  double smallest = 1e300;
  for (std::size_t t = 0; t < types.size(); ++t) {
    const SizeSampler s(types[t].size);
    if (s.min_radius() < smallest) smallest = s.min_radius(), smallest_type = t;
  }
  for (std::size_t f = 0; f < spec.factories.size(); ++f)
    for (const auto& t : types)
      if (spec.particle_types[t.type_index].name.value == spec.factories[f].particle_type.value)
        particle_mass[f] = SizeSampler(t.size).mean_particle_mass(t.density);
  const int samples = 1000;
  for (int k = 0; k < samples; ++k) {
    const double t = (k + 0.5) / samples * end;
    double n = 0.0;
    for (std::size_t f = 0; f < spec.factories.size(); ++f)
      n += factory_count_at(spec.factories[f], particle_mass[f], t);
    e.peak_particles = std::max(e.peak_particles, n);
    e.particle_steps += n * e.steps / samples;
  }
  if (!types.empty() && e.dt > 0) {
    e.calibration_particles = 4096;
    e.seconds_per_particle_step =
        calibrate(spec, smallest_type, e.calibration_particles, 0.5 * e.impact_speed);
  }
  e.wall_seconds = e.particle_steps * e.seconds_per_particle_step;
  return e;
}

std::string format_estimate(const Estimate& e) {
  std::string s;
  s += fmt::format("Rayleigh time step T_R   {:.4g} s   limited by {}\n", e.rayleigh_time, e.rayleigh_limiter);
  s += fmt::format("Hertz contact time T_h   {:.4g} s   at impact speed {:.3g} m/s, {}\n", e.hertz_time,
                   e.impact_speed, e.hertz_limiter);
  s += fmt::format("time step dt             {:.4g} s   ({:.1f} % of T_R, {:.1f} steps per contact)\n",
                   e.dt, 100.0 * e.dt / e.rayleigh_time, e.hertz_time / e.dt);
  s += fmt::format("steps                    {:.0f}\n", e.steps);
  s += fmt::format("particles (expected)     {:.0f} at most, {:.3g} particle-steps\n", e.peak_particles,
                   e.particle_steps);
  s += fmt::format("cost on this machine     {:.3g} s per particle-step (measured on {} stirred particles)\n",
                   e.seconds_per_particle_step, e.calibration_particles);
  const double w = e.wall_seconds;
  s += fmt::format("estimated wall time      {:.0f} s ({:.2f} h)\n", w, w / 3600.0);
  return s;
}

}  // namespace quarry::sim
