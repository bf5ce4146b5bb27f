// Run loop: the output stage attached, steps to the end time, progress with ETA, a clean stop
// with a checkpoint when asked, the end-of-run report.
#include "sim/run.h"

#include <fmt/format.h>

#include <omp.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "core/progress_eta.h"
#include "sim/output.h"
#include "sim/thread_governor.h"
#include "sim/step.h"

namespace quarry::sim {

namespace {

namespace fs = std::filesystem;

std::string duration_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const auto s = static_cast<long long>(seconds + 0.5);
  if (s >= 3600) return fmt::format("{}h{:02}m", s / 3600, (s % 3600) / 60);
  if (s >= 60) return fmt::format("{}m{:02}s", s / 60, s % 60);
  return fmt::format("{}s", s);
}

int stop_requested(const RunOptions& options) { return options.stop ? options.stop->load() : 0; }

using Clock = std::chrono::steady_clock;

std::string plural(std::uint64_t n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

// Steps the world (its output attached) to `end_time`. `start`: when the run began (before
// initialize, whose forces and first frame the stage table counts).
RunSummary run_loop(World& world, const RunOptions& options, double end_time, Clock::time_point start) {
  std::ostream& log = options.log ? *options.log : std::cerr;
  Output& output = *world.output;
  RunSummary summary;
  for (const auto& w : world.warnings) log << "quarry: warning: " << w << "\n";
  log << fmt::format("quarry: dt = {:.4g} s, {} steps to t = {:.4g} s, output in {}\n", world.dt,
                     static_cast<std::uint64_t>(std::max(0.0, (end_time - world.time) / world.dt) + 0.5),
                     end_time, output.directory().string());

  auto last_progress = Clock::now();
  ProgressEta eta_pace;  // smoothed over about 30 s of wall time (core/progress_eta.h)
  double last_progress_time = world.time;  // s, simulated time at the last progress line
  std::uint64_t last_progress_step = world.step_count;
  const double progress_every = world.spec.output.progress_interval.value;  // wall s; 0: none
  std::vector<char> reported_shortfall(world.factories.size(), 0);
  // The team of each step: all requested threads, or one while that is measured to be faster
  // (another process busy on the cores; thread_governor.h). Results do not depend on it.
  const int configured = world.threading.threads;  // 0: the OpenMP default
  const int requested = configured > 0 ? configured : omp_get_max_threads();
  ThreadGovernor::Options adapt;
  adapt.enabled = options.adapt_threads;
  ThreadGovernor governor(requested, adapt);

  while (world.time < end_time - 0.5 * world.dt) {
    if (const int signal_number = stop_requested(options)) {
      summary.stop_signal = signal_number;
      {
        ScopedStage timer(world.timers, world.timers.stage("output"));
        summary.checkpoint = output.write_checkpoint_now(world);
      }
      log << fmt::format("\nquarry: stopped by signal {} at step {} (t = {:.6g} s); checkpoint "
                         "written to {}; continue with: quarry restart {}\n",
                         signal_number, world.step_count, world.time, summary.checkpoint, summary.checkpoint);
      break;
    }
    const auto step_start = Clock::now();
    try {
      world.threading.threads = governor.threads();
      step(world);
    } catch (const PhysicsError&) {
      world.threading.threads = configured;
      output.stopped_by_error(world);  // the monitors so far and a last frame to look at
      throw;
    }
    governor.step_took(std::chrono::duration<double>(Clock::now() - step_start).count());
    summary.steps += 1;
    if (output.checkpoint_written()) summary.checkpoint = output.checkpoint_path();
    for (std::size_t f = 0; f < world.factories.size(); ++f) {
      const Factory& factory = world.factories[f];
      if (reported_shortfall[f] || !factory.finished() || factory.shortfall() <= 0) continue;
      reported_shortfall[f] = 1;
      const std::string text = fmt::format(
          "factory '{}' could not place {} of its particles by t = {:.4g} s (region full or "
          "blocked); enlarge the region, lower the rate, or extend stop_time",
          factory.spec().name.value, factory.shortfall(), world.time);
      world.warnings.push_back(text);
      log << "quarry: warning: " << text << "\n";
    }
    const auto now = std::chrono::steady_clock::now();
    const double since_progress = std::chrono::duration<double>(now - last_progress).count();  // s
    if (!options.quiet && progress_every > 0.0 && since_progress >= progress_every) {
      // ETA from the recent pace (the cost per step grows as particles are added), smoothed so
      // that an interval holding a frame or a checkpoint does not swing it.
      eta_pace.add(world.time - last_progress_time, since_progress);
      const double eta = eta_pace.seconds_left(end_time - world.time);
      // The pace since the last line, not since the start: a pour slows as it fills (the
      // full-scale truck bed showed 42 steps/s from the start while it ran at 20).
      const double pace = static_cast<double>(world.step_count - last_progress_step) / since_progress;
      last_progress = now;
      last_progress_time = world.time;
      last_progress_step = world.step_count;
      log << fmt::format("t = {:.4f} / {:.4g} s ({:5.1f} %)  step {}  {} particles  {:.0f} steps/s  "
                         "ETA {}\n", world.time, end_time, 100.0 * world.time / end_time, world.step_count,
                         world.particles.size(), pace, duration_text(eta));
    }
  }
  world.threading.threads = configured;
  summary.steps_on_one_thread = requested > 1 && options.adapt_threads ? governor.steps_with_one() : 0;
  run_hooks(world, HookStage::end_of_run);  // timed under each hook's name
  {
    ScopedStage timer(world.timers, world.timers.stage("output"));
    output.finish(world, summary.interrupted());  // last frame, export records and decks, plots
  }

  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  summary.simulated_time = world.time;
  summary.particles = world.particles.size();
  summary.final_state_hash = state_hash(world);
  if (!summary.interrupted()) {
    for (const Factory& factory : world.factories)
      if (!factory.finished())
        log << fmt::format("quarry: note: factory '{}' had not finished at the end time\n",
                           factory.spec().name.value);
  }
  // The listed pairs per particle at the end (the half list with its skin): LIGGGHTS' "Total #
  // of neighbors" / atoms, for the benchmarks' side-by-side tables.
  const std::string listed =
      world.particles.size() > 0
          ? fmt::format(" ({:.2f} listed pairs per particle at the end)",
                        static_cast<double>(world.pairs.size()) /
                            static_cast<double>(world.particles.size()))
          : std::string();
  log << fmt::format("quarry: {} in {:.2f} s ({:.0f} steps/s, {:.3g} particle-steps/s), {}, {} removed "
                     "(left the domain), {}{}\n",
                     plural(summary.steps, "step", "steps"), summary.wall_seconds,
                     summary.steps / std::max(summary.wall_seconds, 1e-9),
                     static_cast<double>(summary.steps) * static_cast<double>(world.particles.size()) /
                         std::max(summary.wall_seconds, 1e-9),
                     plural(world.particles.size(), "particle", "particles"), world.removed_outside,
                     plural(world.rebuilds, "list rebuild", "list rebuilds"), listed);
  // The table's stages and its "untimed" line add up to the wall time above (issue 20: the
  // output at the end was missing, the table summed 63 s of a 71 s run).
  if (requested > 1 && options.adapt_threads && governor.steps_with_one() > 0)
    log << fmt::format("quarry: {} of the {} steps ran on 1 thread instead of {}, measured faster then "
                       "(too few particles to share, or the cores busy with another process; results are the same)\n",
                       governor.steps_with_one(), summary.steps, requested);
  if (!options.quiet) {
    log << world.timers.table(summary.wall_seconds);
    // Hooks that ran on their own thread while the stages ran: their time overlaps the table's.
    const StageTimers& alongside = world.alongside_timers;
    for (std::size_t k = 0; k < alongside.names().size(); ++k)
      log << fmt::format("{:<24} {:>12.3f}  (on its own thread, alongside the stages)\n", alongside.names()[k],
                         alongside.seconds(static_cast<int>(k)));
  }
  return summary;
}

OutputOptions output_options(const World& world, const RunOptions& options, double end_time) {
  OutputOptions o;
  o.directory = options.output_directory.empty() ? fs::path(world.spec.output.directory.value)
                                                 : fs::path(options.output_directory);
  o.end_time = end_time;
  o.log = options.log;
  o.overwrite = options.overwrite;
  return o;
}

}  // namespace

RunSummary run(World& world, const RunOptions& options) {
  const double end_time = options.end_time ? *options.end_time : world.spec.simulation.end_time.value;
  if (options.threads > 0) world.threading.threads = options.threads;
  world.stop_request = options.stop;
  world.output = std::make_unique<Output>(world, output_options(world, options, end_time));
  const Clock::time_point start = Clock::now();
  initialize(world);  // also the first monitor row and frame
  RunSummary summary = run_loop(world, options, end_time, start);
  world.output.reset();
  return summary;
}

RunSummary restart(const std::string& checkpoint_path, const RunOptions& options, const AttachToWorld& attach) {
  RestoredWorld restored = read_checkpoint(checkpoint_path);
  World& world = restored.world;
  // What the run attached beyond the deck's world (a fluid, structures), made again from the
  // checkpoint's deck, then given the state it had; kept alive while the world runs.
  const std::shared_ptr<void> attached = attach ? attach(world) : nullptr;
  restore_sections(world, restored.sections, checkpoint_path);
  const double end_time = options.end_time ? *options.end_time : world.spec.simulation.end_time.value;
  if (options.threads > 0) world.threading.threads = options.threads;
  RunOptions o = options;
  if (o.output_directory.empty()) {
    const fs::path folder = fs::path(checkpoint_path).parent_path();
    o.output_directory = folder.empty() ? std::string(".") : folder.string();
  }
  OutputOptions output = output_options(world, o, end_time);
  output.resume_time = world.time;
  output.frame_index = restored.frame_index;
  world.output = std::make_unique<Output>(world, output);
  world.stop_request = options.stop;
  RunSummary summary = run_loop(world, o, end_time, Clock::now());
  world.output.reset();
  return summary;
}

}  // namespace quarry::sim
