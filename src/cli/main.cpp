// quarry: the command-line front end. A thin layer over io (deck), sim (world, run loop) and api
// (the coupling server):
//   quarry run deck.yaml | check deck.yaml | estimate deck.yaml | restart checkpoint.qck
//   quarry serve [deck.yaml] --endpoint ipc://PATH | tcp://HOST:PORT
//   quarry udf build SOURCE.c [-o OUTPUT.so] [--cflags FLAGS]
// Exit codes: 0 success (and `serve` stopped by SIGINT/SIGTERM: that is how it ends), 2 user
// error (deck, mesh, command line, an endpoint it cannot listen at), 3 physics failure at run
// time, 4 internal error, 130 a run stopped by a signal (after writing a checkpoint).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <csignal>
#include <iostream>

#include "api/built_in_solvers.h"
#include "api/server.h"
#include "cfdem/fluid_setup.h"
#include "cli/udf_build.h"
#include "core/allocator.h"
#include "fsi/structure_run.h"
#include "io/deck.h"
#include "quarry_version.h"
#include "sim/estimate.h"
#include "sim/memory_estimate.h"
#include "sim/run.h"
#include "sim/time_step_choice.h"
#include "sim/world.h"

namespace {

using namespace quarry;

// The signal that asked the run to stop (0: none). A signal handler can only write to a
// variable of the process; the library takes it as RunOptions::stop and has no globals itself.
std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int signal_number) { g_stop_signal.store(signal_number); }

struct Common {
  int threads = 0;
  std::string output_dir;
  double end_time = -1.0;
  bool quiet = false;
  bool overwrite = false;
  bool fixed_threads = false;
};

void apply_threads(int threads) {
  if (threads > 0) omp_set_num_threads(threads);
}

sim::RunOptions run_options(const Common& c) {
  sim::RunOptions o;
  o.output_directory = c.output_dir;
  if (c.end_time > 0) o.end_time = c.end_time;
  o.quiet = c.quiet;
  o.stop = &g_stop_signal;
  o.threads = c.threads;
  o.overwrite = c.overwrite;
  o.adapt_threads = !c.fixed_threads;
  return o;
}

int exit_code(const sim::RunSummary& s) { return s.interrupted() ? 130 : 0; }

// What `run` attaches to a deck's world beyond build_world: the fluid of a fluid: section (with
// its frames, monitors and checkpoint sections), then the structures of a structures: section
// (two-way shell coupling as end-of-step hooks, their frames and monitors, their checkpoint
// section; their summary lines at the end of the run). `estimate` calibrates with them;
// `restart` makes them again on the restored world and gives them their state from the
// checkpoint.
std::shared_ptr<void> attach_to_world(World& world) {
  return std::make_shared<api::BuiltInSolvers>(api::attach_built_in_solvers(world, std::cerr));
}

int command_run(const std::string& deck, const Common& c) {
  World world = build_world(parse_deck(deck));
  const auto attached = attach_to_world(world);
  return exit_code(sim::run(world, run_options(c)));
}

int command_check(const std::string& deck) {
  SimulationSpec spec = parse_deck(deck);
  // The time step's errors before anything else of the deck; its warnings once the surfaces
  // are built (a moving wall raises the expected impact speed), at the same deck locations.
  throw_time_step_errors(choose_time_step(spec));
  World world = build_world(spec);
  const TimeStepChoice choice = choose_time_step(spec, world.fastest_surface);
  std::cerr << problems_of(choice, Severity::warning).format();
  // The fluid: section's checks (grid, time step, UDF, blocked cells) and the structures' (their
  // models read and adapted, their line each, then the exchange's stability at the PERIOD the
  // run will hold, for the particles the deck's types can be).
  const api::BuiltInSolvers attached = api::attach_built_in_solvers(world, std::cerr);
  const auto& fluid = attached.fluid;
  if (attached.structures)
    for (std::size_t k = 0; k < attached.structures->size(); ++k) {
      const fsi::StructureCoupler& coupler = attached.structures->coupler(k);
      for (const std::string& line : coupler.stability_warnings(coupler.period_after_reset()))
        std::cerr << "structure \"" << attached.structures->name(k) << "\": " << line << "\n";
    }
  // The world's own notes (e.g. facets an STL reader removed); the time step's are printed above.
  for (const std::string& note : world.warnings)
    if (std::none_of(choice.problems.begin(), choice.problems.end(), [&](const Diagnostic& p) { return p.message == note; }))
      std::cerr << "quarry: warning: " << note << "\n";
  std::size_t triangles = 0;
  for (const auto& s : world.surfaces) triangles += s.mesh.triangle_count();
  const sim::MemoryEstimate memory = sim::estimate_memory(spec);
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
  };
  const auto steps = static_cast<std::size_t>(spec.simulation.end_time.value / world.dt + 0.5);
  std::cout << fmt::format(
      "{}: ok — {}, {}, {} ({}), {}; dt = {:.4g} s ({} to {:.4g} s); memory about {} of {}\n", deck,
      count(spec.materials.size(), "material", "materials"),
      count(spec.particle_types.size(), "particle type", "particle types"),
      count(world.surfaces.size(), "surface", "surfaces"), count(triangles, "triangle", "triangles"),
      count(spec.factories.size(), "factory", "factories"), world.dt, count(steps, "step", "steps"),
      spec.simulation.end_time.value, sim::format_bytes(memory.bytes),
      sim::format_bytes(static_cast<double>(sim::machine_memory_bytes())));
  if (fluid) {
    const cfd::FluidGrid& g = fluid->options().grid;
    const std::size_t blocked = fluid->blocked_cells().count;
    const double fluid_step = fluid->options().coupling_steps * world.dt;  // s
    const double asked = spec.fluid->time_step.value;                       // s, the deck's
    const std::string rounded =
        std::abs(fluid_step - asked) > 1e-9 * asked
            ? fmt::format("; the deck's {:.4g} s rounded down to whole steps of the automatic DEM step", asked)
            : "";
    std::cout << fmt::format("{}: fluid grid {} x {} x {} = {}, {} blocked ({:.1f} %), "
                             "fluid step {:.4g} s ({} DEM steps{})\n",
                             deck, g.cells[0], g.cells[1], g.cells[2], count(g.cell_count(), "cell", "cells"), blocked,
                             100.0 * static_cast<double>(blocked) / static_cast<double>(g.cell_count()),
                             fluid_step, fluid->options().coupling_steps, rounded);
  }
  return 0;
}

int command_estimate(const std::string& deck) {
  const SimulationSpec spec = parse_deck(deck);
  // The calibration runs the deck's own world with what `run` attaches to it (a fluid).
  std::cout << sim::format_estimate(sim::estimate_run(spec, attach_to_world));
  return 0;
}

// Serves until SIGINT or SIGTERM; one line on stdout per event ("listening on ENDPOINT" first,
// which is what scripts wait for).
int command_serve(const std::string& deck, const std::string& endpoint, const Common& c) {
  const auto say = [](const std::string& line) { std::cout << "quarry serve: " << line << std::endl; };
  api::ServerOptions options;
  options.endpoint = endpoint;
  options.deck_path = deck;
  options.output_directory = c.output_dir;
  options.threads = c.threads;
  options.stop = &g_stop_signal;
  options.log = say;
  try {
    api::serve(options, [&](const std::string& bound) {
      say(fmt::format("listening on {} ({}; one client at a time; SIGINT or SIGTERM stops it)", bound,
                      deck.empty() ? "each client opens its simulation" : "the deck " + deck));
    });
  } catch (const UserError&) {
    throw;
  } catch (const PhysicsError&) {
    throw;
  } catch (const std::runtime_error& e) {  // cannot listen there; the deck's open refused
    std::cerr << "quarry serve: error: " << e.what() << "\n";
    return 2;
  }
  say(fmt::format("stopped (signal {})", g_stop_signal.load()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // First of all, so that a stop asked for at any time is taken (and a checkpoint written once
  // the run is under way) rather than killing the process.
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  quarry::use_mapped_large_allocations();
  CLI::App app{"Quarry — discrete element method engine for bulk materials"};
  app.set_version_flag("--version", std::string("quarry ") + QUARRY_VERSION);
  app.require_subcommand(1);
  Common common;
  std::string deck, checkpoint;

  // Values the run cannot use are refused here (exit 2), not ignored.
  const auto positive_finite_seconds = [](const std::string& text) -> std::string {
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !std::isfinite(value) || !(value > 0.0))
      return fmt::format("'{}' is not a time: give a finite number of seconds > 0, e.g. --end-time 2.5", text);
    return {};
  };
  auto add_common = [&](CLI::App* sub, bool with_run_options) {
    sub->add_option("--threads", common.threads, "OpenMP threads (default: all cores or the deck's)")
        ->check(CLI::Range(0, 4096).description("0 (the default) or a number of threads up to 4096"));
    if (with_run_options) {
      sub->add_option("--output-dir", common.output_dir, "output folder (overrides output.directory)");
      sub->add_option("--end-time", common.end_time, "end time in s (overrides simulation.end_time)")
          ->check(CLI::Validator(positive_finite_seconds, "SECONDS > 0"));
      sub->add_flag("--quiet", common.quiet, "no progress lines or stage table");
      sub->add_flag("--overwrite", common.overwrite,
                    "replace an earlier run's output in the output folder (only the files it wrote)");
      sub->add_flag("--fixed-threads", common.fixed_threads,
                    "use every thread at every step, even when one is measured faster (benchmarks)");
    }
  };
  CLI::App* run = app.add_subcommand("run", "run a simulation from a YAML deck");
  run->add_option("deck", deck, "the YAML deck")->required();
  add_common(run, true);
  CLI::App* check = app.add_subcommand("check", "check a deck: report every error, print a summary");
  check->add_option("deck", deck, "the YAML deck")->required();
  add_common(check, false);
  CLI::App* estimate = app.add_subcommand("estimate", "time step, steps and wall-time estimate for a deck");
  estimate->add_option("deck", deck, "the YAML deck")->required();
  add_common(estimate, false);
  CLI::App* restart = app.add_subcommand("restart", "continue a run from its checkpoint");
  restart->add_option("checkpoint", checkpoint, "checkpoint.qck written by 'quarry run'")->required();
  add_common(restart, true);
  std::string endpoint;
  CLI::App* serve = app.add_subcommand("serve", "run a simulation as a coupling server for a partner process "
                                                "(quarry_open with an endpoint; docs/coupling.md)");
  serve->add_option("deck", deck, "a YAML deck opened at start (without one, each client's quarry_open decides)");
  serve->add_option("--endpoint", endpoint, "ipc://PATH (same host: arrays in shared memory) or tcp://HOST:PORT "
                                            "(port 0: a free one, printed)")
      ->required();
  serve->add_option("--output-dir", common.output_dir, "output folder of the simulations served");
  add_common(serve, false);
  CLI::App* udf = app.add_subcommand("udf", "user-defined functions: drag laws written in C (docs/cfd.md)");
  udf->require_subcommand(1);
  cli::UdfBuildOptions udf_options;
  CLI::App* udf_build = udf->add_subcommand(
      "build", "compile a drag UDF's C source into a shared library beside it (SOURCE.c -> SOURCE.so) "
               "and check that it loads");
  udf_build->add_option("source", udf_options.source, "the C source, which includes <quarry/drag_udf.h>")
      ->required();
  udf_build->add_option("-o,--output", udf_options.output, "the library to write (default: the source's name with .so)");
  udf_build->add_option("--cflags", udf_options.cflags,
                        "more compiler arguments, split at spaces, e.g. --cflags=\"-O3 -DFAST -lgsl\" (repeatable)")
      ->allow_extra_args(false);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  apply_threads(common.threads);
  try {
    if (run->parsed()) return command_run(deck, common);
    if (check->parsed()) return command_check(deck);
    if (estimate->parsed()) return command_estimate(deck);
    if (restart->parsed()) return exit_code(sim::restart(checkpoint, run_options(common), attach_to_world));
    if (serve->parsed()) return command_serve(deck, endpoint, common);
    if (udf_build->parsed()) return cli::udf_build(udf_options, std::cout, std::cerr);
  } catch (const UserError& e) {
    std::cerr << e.diagnostics().format();
    return 2;
  } catch (const PhysicsError& e) {
    std::cerr << "quarry: error: " << e.what() << "\n";
    return 3;
  } catch (const FileError& e) {
    std::cerr << "quarry: error: " << e.what()
              << "\n  hint: check that the folder exists, is writable, and that the disk has space\n";
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "quarry: error: " << e.what()
              << "\n  hint: check that the path exists and is a folder where a folder is meant\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "quarry: internal error: " << e.what() << "\n";
    return 4;
  }
  return 0;
}
