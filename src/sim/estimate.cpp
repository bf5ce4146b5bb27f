// Run-time estimate: expected particle count N(t) from the factories' schedules, and a cost per
// step a + N (b + r c) measured on this machine, plus the output (docs/performance.md, "What
// quarry estimate measures"). From the deck's own first steps, timed stage by stage: a (the
// stages that are not the particles': hooks such as a fluid or a structure, moving geometry,
// factories) and r (the fraction of steps that rebuild the lists). b (the particle stages of a
// step, per particle) is the dearer of the deck's own and a dense bed's at rest: the smallest
// particle type packed in a box under gravity with the deck's contact law, which is what most
// bulk material becomes however it starts (the hopper's fill falling apart cost 118 ns per
// particle-step, the packed hopper 266-280 ns, its bed 237-301); where the deck's fluid will
// carry the particles (fluid_carries_particles), the bed is held apart instead: a fluidised
// bed's weight rests on the fluid, not on contacts. c (a rebuild per particle) is the dearer of
// the two. Issue 20.
#include "sim/estimate.h"

#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <sstream>
#include <cmath>
#include <numbers>
#include <optional>

#include "insert/size_distribution.h"
#include "io/vtu_writer.h"
#include "sim/output.h"
#include "sim/step.h"
#include "sim/time_step_choice.h"
#include "sim/world.h"

namespace quarry::sim {

namespace {

// The median wall time (s) of `count` rebuilds of the world's lists: a rebuild takes a few
// milliseconds, about a time slice of a loaded machine, so a single timing (or a mean) moved
// by 2x between calls where the median of 11 does not.
double median_rebuild_seconds(World& world, int count = 11) {
  std::vector<double> seconds;
  for (int k = 0; k < count; ++k) {
    const auto start = std::chrono::steady_clock::now();
    rebuild_lists(world);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::nth_element(seconds.begin(), seconds.begin() + count / 2, seconds.end());
  return seconds[count / 2];
}

// Wall time (s) each calibration runs for: long enough that the timer and one neighbour-list
// rebuild do not dominate the figure, short enough that `estimate` answers in a few seconds.
constexpr double kBedBudget = 1.0;
constexpr double kDeckBudget = 1.5;

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

// Seconds per particle-step on a cubic lattice bed of `count` particles of the given type at
// rest, lightly compressed so that each particle has its six neighbours in contact. (It was
// stirred at half the impact speed while rebuilds were priced from it; the deck's own rebuild
// rate prices them now, and stirring made the flagship's bed cheaper than its packed load, 215
// against 270 ns per particle-step, as the stirred lattice loosened.)
struct BedCalibration {
  double seconds_per_particle_step = 0;     // s: a step without its neighbour stage
  double rebuild_seconds_per_particle = 0;  // s: one rebuild of the pair and surface lists
  double frame_seconds_per_particle = 0;    // s: a frame's VTU text, per particle
};
// held_apart: the lattice spaced by a gap of 2 % of a diameter (inside the neighbour skin of
// 10 %: the same pairs listed), without gravity: the bed a fluid carries, whose beads' weight
// rests on the fluid and whose listed pairs mostly do not touch (the fluidised bed example,
// 2.7 listed pairs per bead, cost 103 ns per particle-step against 188 ns packed).
BedCalibration calibrate_bed(const SimulationSpec& deck, std::size_t type_index, int count, double budget,
                             bool held_apart) {
  SimulationSpec spec;
  spec.deck_path = deck.deck_path;
  spec.materials = deck.materials;
  spec.interactions = deck.interactions;
  spec.particle_types = {deck.particle_types[type_index]};
  spec.simulation = deck.simulation;
  spec.simulation.sort_interval = 0;
  spec.simulation.impact_speed = Located<double>(0.1);
  // The calibration measures cost, not physics: the packed lattice must not stop on the deck's
  // overlap guard (issue 19: `estimate` exited 3 on decks `check` accepts). An overlap of a whole
  // radius still stops it (the neighbour search is sized for less).
  spec.simulation.max_overlap_fraction = 1.0;
  const std::string material = spec.particle_types[0].material.value;
  const SizeSampler sampler(spec.particle_types[0].size);
  // One size, the smallest: a lattice of the deck's mix spaced by its largest leaves the small
  // ones out of contact (tried on the flagship: 3.2-3.8e-7 s per particle-step, this bed
  // 5.5-6e-7, the flagship's settled bed restored from its checkpoint 7.5e-7).
  const double radius = sampler.min_radius();
  const int side = std::max(2, static_cast<int>(std::lround(std::cbrt(static_cast<double>(count)))));
  const double gap = held_apart ? 0.02 * 2.0 * radius : 0.0;  // m, between neighbours and walls
  const double spacing = held_apart ? 2.0 * radius + gap : 2.0 * radius * 0.999;  // m (packed: slight overlap)
  Aabb domain;
  domain.lo = Vec3{-1, -1, -1} * (side * spacing);
  domain.hi = Vec3{2, 2, 2} * (side * spacing);
  spec.simulation.domain = domain;
  // Confined under the deck's gravity by a box of the deck's first surface material, the walls
  // touching the outer layer: the bed stays dense (a free stirred lattice flew apart, and the
  // longer the calibration the cheaper it got: 14x between calls, issue 20), and a third of
  // its particles (the outer layer of 16^3) touch a wall, about as many as rest on the
  // surfaces of a filled hopper or truck bed.
  if (!deck.surfaces.empty()) {
    SurfaceSpec box;
    box.name = Located<std::string>("calibration_box");
    box.kind = Located<SurfaceKind>(SurfaceKind::box);
    box.min = Located<Vec3>(Vec3{-1, -1, -1} * (radius + gap));
    box.max = Located<Vec3>(Vec3{1, 1, 1} * ((side - 1) * spacing + radius + gap));
    box.material = deck.surfaces.front().material;
    spec.surfaces = {box};
  }
  if (deck.surfaces.empty() || held_apart) spec.simulation.gravity = Vec3{};
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
  initialize(world);
  for (int k = 0; k < 3; ++k) step(world);  // warm-up: first-touch of the lists and scratch
  // Timed in five blocks of a fifth of the budget, the median block taken: a block that met a
  // busy moment of the machine does not move the figure (one timing of the whole moved the
  // flagship's estimate by 12 % between calls).
  const int neighbor_stage = world.timers.stage("neighbor");
  const double n = static_cast<double>(world.particles.size());
  std::vector<double> block_seconds;  // s per particle-step, without the neighbour stage
  for (int block = 0; block < 5; ++block) {
    const double neighbor_before = world.timers.seconds(neighbor_stage);
    const auto start = std::chrono::steady_clock::now();
    int steps = 0;
    double elapsed = 0.0;
    while (steps < 4 || (elapsed < budget / 5 && steps < 1000)) {
      step(world);
      ++steps;
      elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    // Without the neighbour stage (rebuilds are priced per rebuild: their rate is the deck's).
    const double neighbor = world.timers.seconds(neighbor_stage) - neighbor_before;
    block_seconds.push_back(std::max(0.0, elapsed - neighbor) / (static_cast<double>(steps) * n));
  }
  std::nth_element(block_seconds.begin(), block_seconds.begin() + 2, block_seconds.end());
  BedCalibration c;
  c.seconds_per_particle_step = block_seconds[2];
  c.rebuild_seconds_per_particle = median_rebuild_seconds(world) / n;
  const auto frame_start = std::chrono::steady_clock::now();
  const std::string text = particles_vtu(world.particles, world.type_names);
  c.frame_seconds_per_particle =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - frame_start).count() / n;
  if (text.empty()) c.frame_seconds_per_particle = 0;  // (keeps the call from being dropped)
  return c;
}

// A scratch output folder beside where the run would write (same file system: a frame's
// fsyncs cost there what the run's will), removed afterwards: the nearest existing folder of
// the deck's output directory, in a hidden subfolder of this process.
std::filesystem::path scratch_folder(const SimulationSpec& spec) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::path folder = fs::absolute(fs::path(spec.output.directory.value), error);
  while (!folder.empty() && !fs::is_directory(folder, error) && folder != folder.parent_path())
    folder = folder.parent_path();
  if (folder.empty() || !fs::is_directory(folder, error)) folder = fs::temp_directory_path();
  return folder / fmt::format(".quarry_estimate.{}", static_cast<long>(::getpid()));
}

// The deck's own world for about `budget` s of wall time (or to its end), with its output into a
// scratch folder: steps taken, their particle-steps and seconds (without the output), the cost
// of a frame (the mean of those written, with their monitor rows) and of the end of the run (a
// last frame, the export's last records and decks, the plots). A physics error ends the
// calibration there, with the costs of the steps before it (`check` accepted the deck). The first
// steps (initialize, a few warm-up steps) are not timed: they fill the lists and scratch memory.
struct DeckCalibration {
  double steps = 0, particle_steps = 0, seconds = 0, particles_at_start = 0;
  // Of `seconds`: the particle stages (kicks and drift, forces, guards, loads) and the
  // neighbour stage; the rest is what a step costs beyond its particles. The particle stages
  // have a part that does not grow with the particles (the surfaces' loads cleared and summed:
  // 17 us a step on the two-way truck bed's 2,520 triangles; the loops' set-up), split off by
  // particle_stage_fit when the count moved enough during the calibration.
  double particle_seconds = 0, neighbor_seconds = 0;
  double particle_fixed_seconds = 0;  // of particle_seconds: the part per step, × steps
  // Of `seconds`: the factories' insertions, and the particles they inserted meanwhile (an
  // insertion is priced per particle: the drum's factory cost 200 us a step while it filled).
  double insert_seconds = 0, inserted = 0;
  double rebuild_seconds = 0, particles_at_end = 0;  // one rebuild of the lists at the end
  double rebuild_particle_steps = 0;  // sum of the particle count over the steps that rebuilt
  double frame_seconds = 0, finish_seconds = 0;  // s: a frame (and the monitor rows before it), the end
  FastestSurface fastest_surface;  // of the deck's world: it adds to the expected impact speed
};
DeckCalibration calibrate_deck(const SimulationSpec& spec, const AttachToWorld& attach, double budget) {
  namespace fs = std::filesystem;
  using Clock = std::chrono::steady_clock;
  DeckCalibration c;
  const fs::path scratch = scratch_folder(spec);
  World world = build_world(spec);
  c.fastest_surface = world.fastest_surface;
  const std::shared_ptr<void> attached = attach ? attach(world) : nullptr;
  const double end = spec.simulation.end_time.value;
  const auto running = [&] { return world.time < end - 0.5 * world.dt; };
  const auto seconds_since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  std::ostringstream notes;  // the output's notes are the run's, not the estimate's
  try {
    OutputOptions options;
    options.directory = scratch;
    options.end_time = end;
    options.log = &notes;
    options.overwrite = true;
    world.output = std::make_unique<Output>(world, options);
    const int output_stage = world.timers.stage("output");
    const int neighbor_stage = world.timers.stage("neighbor");
    const int insert_stage = world.timers.stage("insert/remove");
    std::vector<int> particle_stages;
    for (const char* name : {"integrate", "body forces", "pair forces", "surface forces", "guards", "loads"})
      particle_stages.push_back(world.timers.stage(name));
    const auto particle_stage_seconds = [&] {
      double sum = 0.0;
      for (const int s : particle_stages) sum += world.timers.seconds(s);
      return sum;
    };
    initialize(world);  // the first frame: timed into the output stage
    c.frame_seconds = world.timers.seconds(output_stage);
    c.particles_at_start = static_cast<double>(world.particles.size());
    for (int k = 0; k < 3 && running(); ++k) step(world);
    const double output_before = world.timers.seconds(output_stage);
    const double particle_before = particle_stage_seconds();
    const double neighbor_before = world.timers.seconds(neighbor_stage);
    const double insert_before = world.timers.seconds(insert_stage);
    const double count_before = static_cast<double>(world.particles.size() + world.removed_outside);
    const auto start = Clock::now();
    double elapsed = 0.0;
    std::vector<double> step_counts, step_particle_seconds;  // per step: particles, their stages' s
    while (running() && (c.steps < 20 || elapsed < budget)) {
      const std::uint64_t rebuilds = world.rebuilds;
      const double particle_stages_before = particle_stage_seconds();
      step(world);
      step_counts.push_back(static_cast<double>(world.particles.size()));
      step_particle_seconds.push_back(particle_stage_seconds() - particle_stages_before);
      c.steps += 1;
      c.particle_steps += static_cast<double>(world.particles.size());
      if (world.rebuilds != rebuilds) c.rebuild_particle_steps += static_cast<double>(world.particles.size());
      elapsed = seconds_since(start);
      // The steps' own cost: without the monitor rows and frames that fell in the calibration
      // (those are priced per frame below). Kept up to date: a physics error may end the loop.
      c.seconds = std::max(0.0, elapsed - (world.timers.seconds(output_stage) - output_before));
      c.particle_seconds = particle_stage_seconds() - particle_before;
      c.neighbor_seconds = world.timers.seconds(neighbor_stage) - neighbor_before;
      c.insert_seconds = world.timers.seconds(insert_stage) - insert_before;
      c.inserted = static_cast<double>(world.particles.size() + world.removed_outside) - count_before;
    }
    c.particle_fixed_seconds = particle_stage_fit(step_counts, step_particle_seconds) * c.steps;
    // A frame's cost: the mean over the frames written so far (with the monitor rows between).
    c.frame_seconds = world.timers.seconds(output_stage) / static_cast<double>(std::max<std::uint64_t>(1, world.output->frame_index()));
    c.rebuild_seconds = median_rebuild_seconds(world);
    c.particles_at_end = static_cast<double>(world.particles.size());
    const auto finish_start = Clock::now();
    world.output->finish(world, false);
    c.finish_seconds = seconds_since(finish_start);
  } catch (const PhysicsError&) {
    // The costs are those of the steps before the one that failed (the run would stop there
    // too, with the same message; `estimate` prices the deck as written).
  } catch (const std::exception&) {
    // The scratch folder could not be written (read-only place): priced without the output.
  }
  world.output.reset();
  std::error_code error;
  fs::remove_all(scratch, error);
  return c;
}

}  // namespace

// particle_stage_fit (estimate.h): a deck's first steps are often a pour beginning; the two-way
// truck bed's first 712 steps had 36 particles on average and 48 us a step of surface
// bookkeeping in its particle stages, which priced at 1.1 us per particle-step against the 0.25
// its particles cost in the run (the estimate 1.78 times the run; 1.04 with the fit).
double particle_stage_fit(const std::vector<double>& counts, const std::vector<double>& seconds) {
  const std::size_t m = counts.size();
  if (m < 20) return 0.0;
  double mean_n = 0, mean_t = 0, largest = 0, smallest = counts.front();
  for (std::size_t k = 0; k < m; ++k) {
    mean_n += counts[k] / static_cast<double>(m);
    mean_t += seconds[k] / static_cast<double>(m);
    largest = std::max(largest, counts[k]);
    smallest = std::min(smallest, counts[k]);
  }
  if (!(largest - smallest >= 0.25 * largest)) return 0.0;
  double covariance = 0, variance = 0;
  for (std::size_t k = 0; k < m; ++k) {
    covariance += (counts[k] - mean_n) * (seconds[k] - mean_t);
    variance += (counts[k] - mean_n) * (counts[k] - mean_n);
  }
  const double slope = covariance / variance;  // s per particle-step
  const double intercept = mean_t - slope * mean_n;
  return slope >= 0.0 && intercept >= 0.0 ? intercept : 0.0;
}

double minimum_fluidisation_velocity(double fluid_density, double viscosity, double particle_density,
                                     double diameter, double gravity) {
  if (!(particle_density > fluid_density) || !(diameter > 0) || !(viscosity > 0) || !(fluid_density > 0))
    return 0.0;
  const double archimedes = fluid_density * (particle_density - fluid_density) * gravity * diameter * diameter *
                            diameter / (viscosity * viscosity);
  const double reynolds = std::sqrt(33.7 * 33.7 + 0.0408 * archimedes) - 33.7;
  return reynolds * viscosity / (fluid_density * diameter);
}

bool fluid_carries_particles(const SimulationSpec& spec, double& inlet, double& minimum) {
  inlet = minimum = 0.0;
  const double g = norm(spec.simulation.gravity.value);
  if (!spec.fluid || !(g > 0) || spec.particle_types.empty()) return false;
  const Vec3 up = spec.simulation.gravity.value * (-1.0 / g);
  for (const FluidFaceSpec& face : spec.fluid->faces)
    if (face.type.value == FluidBoundaryType::velocity_inlet) inlet = std::max(inlet, dot(face.velocity.value, up));
  for (const ParticleTypeInfo& t : particle_type_infos(spec)) {
    const double diameter = 2.0 * SizeSampler(t.size).max_radius();
    minimum = std::max(minimum, minimum_fluidisation_velocity(spec.fluid->density.value, spec.fluid->viscosity.value,
                                                              t.density, diameter, g));
  }
  return inlet > minimum && minimum > 0.0;
}

Estimate estimate_run(const SimulationSpec& spec, const AttachToWorld& attach) {
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
    for (std::size_t f = 0; f < spec.factories.size(); ++f) {
      n += factory_count_at(spec.factories[f], particle_mass[f], t);
    }
    e.peak_particles = std::max(e.peak_particles, n);
    e.particle_steps += n * e.steps / samples;
  }
  e.threads = spec.simulation.threads.value > 0 ? spec.simulation.threads.value : omp_get_max_threads();
  const DeckCalibration deck = e.dt > 0 && e.steps > 0 ? calibrate_deck(spec, attach, kDeckBudget) : DeckCalibration{};
  BedCalibration bed;
  if (!types.empty() && e.dt > 0) {
    // A deck that never has more particles than a loop's threading threshold runs each loop
    // on one thread (core/threading.h), so its bed must too: 12^3 below it, 16^3 above (the
    // drum's 2,000 beads cost 1.7x per particle what the 4,096 of the bed did on two threads).
    e.calibration_particles = e.peak_particles > static_cast<double>(Threading{}.threshold) ? 4096 : 1728;
    e.fluidised = fluid_carries_particles(spec, e.inlet_velocity, e.fluidisation_velocity);
    bed = calibrate_bed(spec, types[smallest_type].type_index, e.calibration_particles, kBedBudget, e.fluidised);
    e.seconds_per_particle_step = bed.seconds_per_particle_step;
  }
  if (deck.fastest_surface.speed > 0.0) {  // the contact time at the impacts moving walls add
    const TimeStepChoice moving = choose_time_step(spec, deck.fastest_surface);
    e.hertz_time = moving.hertz_time;
    e.hertz_limiter = moving.hertz_limiter;
    e.impact_speed = moving.impact_speed;
  }
  if (e.dt > 0 && e.steps > 0) {
    e.deck_steps = deck.steps;
    e.deck_particles = deck.steps > 0 ? deck.particle_steps / deck.steps : 0.0;
    e.deck_seconds = deck.seconds;
    // Rebuilds: the deck's own rate (set by its speeds and skin: a pour rebuilds every few
    // steps), each priced per particle as the dearer of the bed's and the deck's own (its
    // surfaces' candidate lists, its domain's grid), timed at the end of its calibration.
    e.rebuild_fraction = deck.particle_steps > 0 ? deck.rebuild_particle_steps / deck.particle_steps : 0.0;
    const double rebuild = std::max(bed.rebuild_seconds_per_particle,
                                    deck.particles_at_end > 0 ? deck.rebuild_seconds / deck.particles_at_end : 0.0);
    // The particle stages: the dearer of the bed (dense, or held apart where a fluid carries
    // the particles) and the deck's own first steps. A deck
    // starts loose (a fill falling, a bed not yet settled: the hopper's first steps cost 118 ns
    // per particle, its packed bulk 266-280 ns, the fluidised bed's 41 then 107 ns), and its
    // particles end dense; impacts and many surface contacts can make the deck's own dearer.
    const double deck_particle =
        deck.particle_steps > 0 ? (deck.particle_seconds - deck.particle_fixed_seconds) / deck.particle_steps : 0.0;
    e.seconds_per_particle_step =
        std::max(bed.seconds_per_particle_step, deck_particle) + e.rebuild_fraction * rebuild;
    // What the deck's steps cost beyond their particles and rebuilds (a fluid, a structure,
    // moving geometry, factories, the loop itself), measured directly: the fluidised bed's
    // fluid is 217 us a step, whatever its beads do.
    if (deck.steps > 0)
      e.seconds_per_step = std::max(0.0, deck.seconds - (deck.particle_seconds - deck.particle_fixed_seconds) -
                                             deck.neighbor_seconds - deck.insert_seconds) /
                           deck.steps;
    // The insertions still to come after the calibration's start, at its cost per particle.
    if (deck.inserted > 0)
      e.insert_seconds = deck.insert_seconds / deck.inserted * std::max(0.0, e.peak_particles - deck.particles_at_start);
    // Frames: one at the start, one per output interval, priced as those of the calibration
    // (their fsyncs and files, the monitor rows between) plus the VTU text of the particles
    // expected then.
    const double interval = spec.output.interval.value;
    const double fixed_frame = std::max(0.0, deck.frame_seconds - e.deck_particles * bed.frame_seconds_per_particle);
    if (interval > 0)
      for (double t = interval; t < end + 0.5 * interval; t += interval) {
        double n = 0.0;
        for (std::size_t f = 0; f < spec.factories.size(); ++f) n += factory_count_at(spec.factories[f], particle_mass[f], t);
        e.frames += 1;
        e.output_seconds += fixed_frame + n * bed.frame_seconds_per_particle;
      }
    e.output_seconds += fixed_frame + deck.particles_at_start * bed.frame_seconds_per_particle + deck.finish_seconds;
  }
  e.wall_seconds =
      e.steps * e.seconds_per_step + e.particle_steps * e.seconds_per_particle_step + e.insert_seconds + e.output_seconds;
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
  s += fmt::format("cost on this machine     {:.3g} s per step + {:.3g} s per particle-step on {} thread{}\n",
                   e.seconds_per_step, e.seconds_per_particle_step, e.threads, e.threads == 1 ? "" : "s");
  s += fmt::format("  measured on              the deck's first {:.0f} steps ({:.2f} s, {:.0f} particle{} on average, "
                   "lists rebuilt at {:.0f} % of the steps) and {} particles at rest in a box\n",
                   e.deck_steps, e.deck_seconds, e.deck_particles, std::lround(e.deck_particles) == 1 ? "" : "s",
                   100.0 * e.rebuild_fraction, e.calibration_particles);
  if (e.fluidised)
    s += fmt::format("  the bed held apart:      the fluid carries the particles (inlet {:.3g} m/s, above the minimum "
                     "fluidisation velocity {:.3g} m/s, Wen & Yu)\n",
                     e.inlet_velocity, e.fluidisation_velocity);
  if (e.insert_seconds > 0)
    s += fmt::format("insertions               {:.3g} s (the factories' particles still to come)\n", e.insert_seconds);
  s += fmt::format("output                   {:.0f} frame{} and the end of the run: {:.3g} s\n", e.frames + 1,
                   e.frames + 1 == 1 ? "" : "s", e.output_seconds);
  const double w = e.wall_seconds;
  s += fmt::format("estimated wall time      {:.{}f} s ({:.2f} h)\n", w, w < 100 ? 1 : 0, w / 3600.0);
  return s;
}

}  // namespace quarry::sim
