// quarry_fluidised_bed: the CFD-DEM benchmark of issue #18 ("Performance"). Glass beads of 1 mm
// in water, periodic across (beads and fluid), on a distributor plate at the inlet, fed at
// 3 times Wen & Yu's minimum fluidisation velocity (24 mm/s), Gidaspow drag, a fluid step of
// --coupling-steps (default 10) DEM steps of 25 µs: the bed of src/cfdem/fluidised_bed_test.cpp, wider. The beads start on a
// loose lattice resting on the plate; the first coupled steps (untimed) lift the bed, the next
// ones are timed. Prints one line "QUARRY_FLUID_BENCH key=value ..." with the time per coupled
// step split into the coupling's parts (void fraction, drag, fluid step, fluid values, particle
// forces) and the DEM (everything else), the particles' state hash (the same bits for any thread
// count), the fluid's step and the least stable step it had over the timed steps
// (stable_time_step, with the drag: docs/cfd.md "Time step"; looked at between the timed
// steps, outside the time), plus the run's stage table.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <map>
#include <string>

#include "bench/settled_bed_scene.h"
#include "cfdem/fluid_coupling.h"
#include "core/allocator.h"
#include "io/deck.h"
#include "sim/exchange.h"
#include "sim/run.h"
#include "sim/step.h"

namespace {

using namespace quarry;
namespace bench = quarry::bench;

constexpr double kDiameter = 1e-3;          // m
constexpr double kCell = 2.1e-3;            // m: 9.3 bead volumes per cell
constexpr double kSuperficial = 0.0239;     // m/s: 3 x 7.97 mm/s (Wen & Yu 1966)

struct Options {
  long particles = 10000;
  int cells_across = 16;
  int cells_up = 200;
  int threads = 1;
  int warmup = 50;          // coupled steps, untimed
  int coupled_steps = 100;  // timed
  int coupling_steps = 10;  // DEM steps per fluid step
  cfd::Advection advection = cfd::Advection::central;
};

World bed_world(const Options& o) {
  const double width = o.cells_across * kCell, height = o.cells_up * kCell;  // m
  const std::string deck = fmt::format(R"(
simulation:
  end_time: 100
  time_step: 2.5e-5
  impact_speed: 0.1
  gravity: [0, 0, -9.81]
  domain: {{min: [0, 0, -0.001], max: [{w}, {w}, {h}], periodic: [x, y]}}
materials:
  - {{name: glass, density: 2500, youngs_modulus: 1.0e6, poisson_ratio: 0.3}}
interactions:
  - {{materials: [glass, glass], restitution: 0.5, static_friction: 0.3}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: {r}}}}}
surfaces:
  - {{name: plate, type: plane, point: [{c}, {c}, 0], normal: [0, 0, 1], size: {ws}, material: glass}}
output:
  directory: out_fluidised_bed_bench
  interval: 0
  plots: false
)",
                                       fmt::arg("w", width), fmt::arg("h", height), fmt::arg("c", 0.5 * width),
                                       fmt::arg("ws", 3.0 * width), fmt::arg("r", 0.5 * kDiameter));
  World world = build_world(parse_deck_string(deck, "fluidised_bed_bench.yaml"));
  world.threading = Threading{o.threads, 0};
  // A loose lattice (spacing ≥ 1.2 d, a whole number per period) from the plate up.
  const int across = static_cast<int>(std::floor(width / (1.2 * kDiameter)));
  const double spacing = width / across;  // m
  std::vector<sim::NewParticle> beads;
  for (long n = 0; n < o.particles; ++n) {
    const long layer = n / (across * across), in_layer = n % (across * across);
    sim::NewParticle p;
    p.position = {(static_cast<double>(in_layer % across) + 0.5) * spacing,
                  (static_cast<double>(in_layer / across) + 0.5) * spacing,
                  0.5 * kDiameter + 1e-5 + static_cast<double>(layer) * 1.2 * kDiameter};
    p.radius = 0.5 * kDiameter;
    beads.push_back(p);
  }
  if (beads.back().position.z > 0.5 * height)
    throw std::invalid_argument(fmt::format("{} beads stack {:.3g} m high, more than half the column ({:.3g} m): "
                                            "more cells up",
                                            o.particles, beads.back().position.z, height));
  sim::add_particles(world, beads);
  return world;
}

std::shared_ptr<cfdem::FluidCoupling> attach_fluid(World& world, const Options& o) {
  cfdem::FluidCouplingOptions options;
  options.grid.cell_size = {kCell, kCell, kCell};
  options.grid.cells = {o.cells_across, o.cells_across, o.cells_up};
  options.properties = {1000.0, 1e-3};
  options.boundaries.set_periodic(0);
  options.boundaries.set_periodic(1);
  options.boundaries.face(2, 0).kind = cfd::BoundaryKind::velocity_inlet;
  options.boundaries.face(2, 0).velocity = {0.0, 0.0, kSuperficial};
  options.boundaries.face(2, 1).kind = cfd::BoundaryKind::pressure_outlet;
  options.boundaries.face(2, 1).reference_point = {0.0, 0.0, o.cells_up * kCell};
  options.drag_law = cfd::DragLaw::gidaspow;
  options.coupling_steps = o.coupling_steps;
  options.solver.advection = o.advection;
  return cfdem::FluidCoupling::attach(world, std::move(options));
}

std::vector<double> coupling_seconds(const cfdem::FluidCoupling& coupling) {
  std::vector<double> s;
  for (std::size_t k = 0; k < coupling.timers().names().size(); ++k)
    s.push_back(coupling.timers().seconds(static_cast<int>(k)));
  return s;
}

int run(const Options& o) {
  World world = bed_world(o);
  const auto coupling = attach_fluid(world, o);
  sim::initialize(world);
  sim::advance(world, static_cast<std::uint64_t>(o.warmup) * static_cast<std::uint64_t>(o.coupling_steps));
  const std::vector<double> before = coupling_seconds(*coupling);
  world.timers.reset();
  int iterations = 0, momentum_iterations = 0;
  double stable_dt = coupling->fluid().stable_time_step();  // s: the least over the timed steps
  double wall = 0.0;  // s: the coupled steps alone, not the look at the stable step between them
  for (int n = 0; n < o.coupled_steps; ++n) {
    const auto start = std::chrono::steady_clock::now();
    sim::advance(world, static_cast<std::uint64_t>(o.coupling_steps));
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stable_dt = std::min(stable_dt, coupling->fluid().stable_time_step());
    iterations += coupling->fluid().last_report().pressure.iterations;
    for (const cfd::SolveReport& m : coupling->fluid().last_report().momentum) momentum_iterations += m.iterations;
  }
  const std::vector<double> after = coupling_seconds(*coupling);
  const double per_step = 1e3 / o.coupled_steps;  // ms per coupled step per second of total
  std::string parts;
  double fluid_side = 0.0;
  for (std::size_t k = 0; k < after.size(); ++k) {
    const double seconds = after[k] - before[k];
    fluid_side += seconds;
    std::string key = coupling->timers().names()[k];
    std::replace(key.begin(), key.end(), ' ', '_');
    parts += fmt::format(" {}_ms={:.4f}", key, seconds * per_step);
  }
  const double dem = wall - fluid_side;
  std::cout << fmt::format(
      "QUARRY_FLUID_BENCH particles={} cells={} threads={} advection={} coupling_steps={} coupled_steps={} wall_s={:.4f} "
      "step_ms={:.4f}{} dem_ms={:.4f} fluid_over_dem={:.4f} pressure_iterations={:.2f} momentum_iterations={:.2f} "
      "fluid_dt_ms={:.4f} fluid_stable_dt_ms={:.4f} rss_mb={:.1f} state_hash={:016x}\n",
      world.particles.size(), coupling->options().grid.cell_count(), o.threads,
      o.advection == cfd::Advection::hybrid ? "hybrid" : "central", o.coupling_steps, o.coupled_steps, wall,
      wall * per_step, parts, dem * per_step, fluid_side / dem,
      static_cast<double>(iterations) / o.coupled_steps, static_cast<double>(momentum_iterations) / o.coupled_steps,
      o.coupling_steps * world.dt * 1e3, stable_dt * 1e3, bench::peak_rss_bytes() / 1048576.0, sim::state_hash(world));
  std::cerr << world.timers.table(wall);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  quarry::use_mapped_large_allocations();
  CLI::App app{"quarry_fluidised_bed: the CFD-DEM benchmark (issue #18)"};
  Options o;
  app.add_option("--particles", o.particles, "beads")->check(CLI::PositiveNumber);
  app.add_option("--cells-across", o.cells_across, "fluid cells along x and y (2.1 mm each)")->check(CLI::PositiveNumber);
  app.add_option("--cells-up", o.cells_up, "fluid cells along z")->check(CLI::PositiveNumber);
  app.add_option("--threads", o.threads, "threads")->check(CLI::PositiveNumber);
  app.add_option("--warmup", o.warmup, "coupled steps before the timed ones")->check(CLI::NonNegativeNumber);
  app.add_option("--coupled-steps", o.coupled_steps, "timed coupled steps")->check(CLI::PositiveNumber);
  app.add_option("--coupling-steps", o.coupling_steps, "DEM steps per fluid step (default 10)")
      ->check(CLI::PositiveNumber);
  const std::map<std::string, cfd::Advection> schemes{{"central", cfd::Advection::central},
                                                      {"hybrid", cfd::Advection::hybrid}};
  app.add_option("--advection", o.advection, "the fluid's advection scheme: central (default) or hybrid")
      ->transform(CLI::CheckedTransformer(schemes));
  CLI11_PARSE(app, argc, argv);
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::cerr << "quarry_fluidised_bed: " << e.what() << "\n";
    return 2;
  }
}
