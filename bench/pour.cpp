// quarry_pour: the flowing-material benchmark of issue 21 (a): a jittered lattice of spheres
// lifted above the floor of a closed box falls and piles up, with the material of the settled
// bed (bench/peers: Hertz-Mindlin with history, e = 0.5, mu = 0.5, E = 5 MPa). The lattice
// is written once as a LAMMPS data file (--write-data) that every code then reads
// (--from-data here, read_data in bench/peers/in.lig.pour and in.lmp.pour), so all start from
// the same particles. Times the steps from rest (sim::advance) and prints one line
// "QUARRY_BENCH key=value ..." (the keys of quarry_settled_bed) plus the per-stage table.
#include <CLI/CLI.hpp>
#include <chrono>
#include <fmt/format.h>
#include <iostream>

#include "bench/lammps_data.h"
#include "bench/settled_bed_scene.h"
#include "core/allocator.h"
#include "core/diagnostics.h"
#include "io/atomic_file.h"
#include "sim/step.h"

namespace {

namespace bench = quarry::bench;

struct Options {
  bench::SettledBedParameters pour;
  std::string write_data;  // write the lattice here and stop
  std::string from_data;   // start from this data file's particles (the lattice written before)
  int threads = 1;
  long steps = 20000;
};

// The pour's defaults: 30 000 spheres of 4 mm on a 5 mm lattice (1 mm gaps), lifted 5 cm: the
// bottom layer lands at 1.0 m/s after 0.10 s, the top one after about 0.15 s, so 20 000 steps
// of 10 µs cover the fall, the impact and the first spreading of the pile. The Hertz peak
// overlap of a bead hitting the floor at 1.0 m/s is 8 % of its radius, delta/R =
// (5 pi rho v^2 / (4 E*))^(2/5) (Johnson, Contact Mechanics, eq. 11.24), and the layers landing
// on it push pairs past 10 %: physics of this soft material, so the guard stands at 20 % (the
// peers have none).
bench::SettledBedParameters pour_defaults() {
  bench::SettledBedParameters p;
  p.cells_x = 30;
  p.cells_y = 40;
  p.cells_z = 25;
  p.particle_radius = 2.0e-3;  // m
  p.lattice_spacing = 5.0e-3;  // m
  p.jitter = 1.0e-4;           // m
  p.lift = 0.05;               // m
  p.skin = 4.0e-4;             // m (0.1 d, as the settled bed)
  p.time_step = 1.0e-5;        // s
  p.max_overlap_fraction = 0.2;
  return p;
}

int run_pour(const Options& options) {
  quarry::World world = bench::make_lattice_world(options.pour);
  if (!options.write_data.empty()) {
    quarry::write_file_atomically(options.write_data,
                                  bench::lammps_data_text(bench::to_lammps_data(world, options.pour)));
    std::cerr << fmt::format("pour: wrote {} particles to {}\n", world.particles.size(), options.write_data);
    return 0;
  }
  if (!options.from_data.empty())
    bench::replace_particles(world, options.pour, bench::read_lammps_data(options.from_data));
  world.threading.threads = options.threads;
  bench::prepare_first_step(world);
  world.timers.reset();
  const std::uint64_t rebuilds_before = world.rebuilds;
  const auto start = std::chrono::steady_clock::now();
  quarry::sim::advance(world, static_cast<std::uint64_t>(options.steps));
  const double loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::uint64_t rebuilds = world.rebuilds - rebuilds_before;

  std::cerr << "per-stage time of the timed steps:\n" << world.timers.table(loop_seconds);
  std::cout << bench::bench_result_line(world, options.threads, options.steps, loop_seconds, rebuilds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  quarry::use_mapped_large_allocations();
  Options options;
  options.pour = pour_defaults();
  bench::SettledBedParameters& p = options.pour;
  CLI::App app{"Quarry pour benchmark (issue 21: a lifted lattice falls onto the floor of a box)"};
  app.add_option("--nx", p.cells_x, "lattice sites along x")->check(CLI::PositiveNumber);
  app.add_option("--ny", p.cells_y, "lattice sites along y")->check(CLI::PositiveNumber);
  app.add_option("--nz", p.cells_z, "lattice sites along z")->check(CLI::PositiveNumber);
  app.add_option("--seed", p.seed, "jitter random seed");
  app.add_option("--write-data", options.write_data,
                 "write the lattice as a LAMMPS data file (atom_style sphere, SI) and stop");
  app.add_option("--from-data", options.from_data, "start from this data file's particles (--write-data)");
  app.add_option("--skin", p.skin, "neighbour skin (m)")->check(CLI::PositiveNumber);
  app.add_option("--threads", options.threads, "OpenMP threads")->check(CLI::PositiveNumber);
  app.add_option("--steps", options.steps, "timed steps from rest")->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    return run_pour(options);
  } catch (const quarry::UserError& e) {
    std::cerr << e.diagnostics().format();  // file:line:col: error: …, the line, a hint
    return 2;
  } catch (const quarry::PhysicsError& e) {
    std::cerr << "quarry_pour: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "quarry_pour: " << e.what() << "\n";
    return 4;
  }
}
