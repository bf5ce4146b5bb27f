// quarry_settled_bed: the peer-comparison reference problem in Quarry (issue 3). Settles the
// jittered lattice, or re-settles the peers' LAMMPS-settled bed (--from-data, a write_data file),
// or loads a settled bed (--bed); times warm-up + timed steps (sim::advance), and prints one
// machine-readable line "QUARRY_BENCH key=value ..." plus the per-stage time table.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>

#include "core/allocator.h"
#include "bench/lammps_data.h"
#include "bench/settled_bed_scene.h"
#include "core/diagnostics.h"
#include "sim/run.h"
#include "sim/step.h"

namespace {

using quarry::World;
namespace bench = quarry::bench;

struct Options {
  bench::SettledBedParameters bed;
  long settle_steps = 25000;        // the peers' lattice settling for 10k (bench/peers)
  double settle_energy = 0.0;       // J per particle; > 0: stop settling once below it
  std::string data_file;            // LAMMPS data file: start from its particles, not the lattice
  std::string bed_file;             // load if it exists, else settle and save here
  int threads = 1;
  long warmup_steps = 200;          // the peers' NWARM
  long timed_steps = 2000;          // the peers' timed phase
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Steps until `steps` are done or the kinetic energy per particle falls below the target
// (checked every 500 steps, as often as the peers print it); logs progress to stderr.
void settle(World& world, const Options& options) {
  const auto start = std::chrono::steady_clock::now();
  for (long s = 1; s <= options.settle_steps; ++s) {
    quarry::sim::step(world);
    if (s % 500 == 0 || s == options.settle_steps) {
      const double energy = bench::kinetic_energy_per_particle(world);  // J
      if (s % 2500 == 0 || s == options.settle_steps)
        std::cerr << fmt::format("settle: step {} ke/particle {:.3e} J zmax {:.5f} m ({:.0f} s)\n", s,
                                 energy, bench::measure_bed(world).max_height, seconds_since(start));
      if (options.settle_energy > 0.0 && energy < options.settle_energy) {
        std::cerr << fmt::format("settle: below {:.1e} J per particle after {} steps\n",
                                 options.settle_energy, s);
        break;
      }
    }
  }
}

int run_bench(const Options& options) {
  const bool have_bed = !options.bed_file.empty() && std::filesystem::exists(options.bed_file);
  // The lattice only when it is to be settled: kept alive while a saved bed is read, it would
  // add its particles to the process's peak memory that the harness reports
  // (docs/performance.md, "The settled bed at 200k on the Zen 5 host").
  World world = have_bed ? std::move(quarry::sim::read_checkpoint(options.bed_file).world)
                         : bench::make_lattice_world(options.bed);
  world.threading.threads = options.threads;
  const std::size_t n = static_cast<std::size_t>(options.bed.cells_x) *
                        static_cast<std::size_t>(options.bed.cells_y) *
                        static_cast<std::size_t>(options.bed.cells_z);  // the lattice's sites
  if (have_bed) {
    if (world.particles.size() != n)
      throw std::runtime_error(fmt::format("{} holds {} particles, the lattice {}: other --nx/--ny/--nz?",
                                           options.bed_file, world.particles.size(), n));
    std::cerr << fmt::format("bed: loaded {} ({} particles, t = {:.4f} s)\n", options.bed_file, n, world.time);
  } else {
    if (!options.data_file.empty()) {
      // The peers' bed (LAMMPS write_data): same particles, no tangential contact history (a
      // data file has none), so it is re-settled briefly as LIGGGHTS does (in.lig.settle).
      const bench::LammpsData data = bench::read_lammps_data(options.data_file);
      bench::replace_particles(world, options.bed, data);
      std::cerr << fmt::format("bed: {} particles from {} ({})\n", data.atoms.size(), options.data_file,
                               data.title);
    }
    bench::prepare_first_step(world);
    if (!options.data_file.empty())
      std::cerr << fmt::format("bed: ke/particle {:.3e} J before settling\n",
                               bench::kinetic_energy_per_particle(world));
    settle(world, options);
    if (!options.bed_file.empty()) {
      quarry::sim::write_checkpoint(world, options.bed_file, 0);
      std::cerr << fmt::format("bed: saved {}\n", options.bed_file);
    }
  }
  std::cerr << fmt::format("bed: ke/particle {:.3e} J\n", bench::kinetic_energy_per_particle(world));
  if (options.timed_steps <= 0) return 0;

  quarry::sim::advance(world, static_cast<std::uint64_t>(std::max(0L, options.warmup_steps)));
  world.timers.reset();
  const std::uint64_t rebuilds_before = world.rebuilds;
  const auto start = std::chrono::steady_clock::now();
  quarry::sim::advance(world, static_cast<std::uint64_t>(options.timed_steps));
  const double loop_seconds = seconds_since(start);  // s
  const std::uint64_t rebuilds = world.rebuilds - rebuilds_before;

  std::cerr << "per-stage time of the timed steps:\n" << world.timers.table();
  std::cout << bench::bench_result_line(world, options.threads, options.timed_steps, loop_seconds, rebuilds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  quarry::use_mapped_large_allocations();
  Options options;
  CLI::App app{"Quarry settled-bed benchmark (the LIGGGHTS/LAMMPS reference problem of issue 3)"};
  app.add_option("--nx", options.bed.cells_x, "lattice sites along x")->check(CLI::PositiveNumber);
  app.add_option("--ny", options.bed.cells_y, "lattice sites along y")->check(CLI::PositiveNumber);
  app.add_option("--nz", options.bed.cells_z, "lattice sites along z")->check(CLI::PositiveNumber);
  app.add_option("--seed", options.bed.seed, "jitter random seed");
  app.add_option("--from-data", options.data_file,
                 "start from the particles of this LAMMPS data file (write_data, atom_style sphere, "
                 "units si; the peers' settled bed) instead of the lattice");
  app.add_option("--settle-steps", options.settle_steps,
                 "most settling steps from the lattice or the --from-data bed");
  app.add_option("--settle-energy", options.settle_energy,
                 "stop settling when kinetic energy per particle (J) is below this (0: never)");
  app.add_option("--bed", options.bed_file, "settled bed file: loaded if it exists, else written");
  app.add_option("--threads", options.threads, "OpenMP threads")->check(CLI::PositiveNumber);
  app.add_option("--warmup", options.warmup_steps, "untimed steps before the timed ones");
  app.add_option("--steps", options.timed_steps, "timed steps (0: only settle/save)");
  CLI11_PARSE(app, argc, argv);
  try {
    return run_bench(options);
  } catch (const quarry::UserError& e) {
    std::cerr << e.diagnostics().format();  // file:line:col: error: …, the line, a hint
    return 2;
  } catch (const quarry::PhysicsError& e) {
    std::cerr << "quarry_settled_bed: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "quarry_settled_bed: " << e.what() << "\n";
    return 4;
  }
}
