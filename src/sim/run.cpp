// Run loop: schedule of frames, monitor rows and checkpoints (in steps, so that a restarted run
// keeps the same schedule), progress with ETA, signal handling, end-of-run report.
#include "sim/run.h"

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>

#include "export/load_exporter.h"
#include "io/atomic_file.h"
#include "io/csv_table.h"
#include "io/deck.h"
#include "io/pvd_series.h"
#include "io/vtu_writer.h"
#include "sim/monitors.h"
#include "sim/step.h"

namespace quarry::sim {

namespace {

namespace fs = std::filesystem;

std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int signal_number) { g_stop_signal.store(signal_number); }

// Steps between events for an interval in seconds (0 → never).
std::uint64_t every_steps(double interval, double dt) {
  if (interval <= 0.0) return 0;
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(interval / dt)));
}

std::string duration_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const auto s = static_cast<long long>(seconds + 0.5);
  if (s >= 3600) return fmt::format("{}h{:02}m", s / 3600, (s % 3600) / 60);
  if (s >= 60) return fmt::format("{}m{:02}s", s / 60, s % 60);
  return fmt::format("{}s", s);
}

struct Session {
  World& world;
  RunOptions options;
  std::ostream& log;
  fs::path directory;
  double end_time = 0.0;
  std::uint64_t output_every = 0, monitor_every = 0, checkpoint_every = 0;
  std::uint64_t frame_index = 0;
  CsvTable monitors;
  PvdSeries particle_series;
  std::vector<PvdSeries> surface_series;
  std::string checkpoint_path;

  Session(World& w, const RunOptions& o)
      : world(w), options(o), log(o.log ? *o.log : std::cerr),
        directory(o.output_directory.empty() ? w.spec.output.directory.value : o.output_directory),
        monitors(directory / "monitors.csv", monitor_columns(w)),
        particle_series(directory / "particles.pvd") {
    fs::create_directories(directory);
    end_time = o.end_time ? *o.end_time : w.spec.simulation.end_time.value;
    const auto& out = w.spec.output;
    output_every = every_steps(out.interval.value, w.dt);
    monitor_every = every_steps(out.monitor_interval.value > 0 ? out.monitor_interval.value
                                                               : out.interval.value, w.dt);
    if (monitor_every == 0)  // neither given: about 200 rows over the run
      monitor_every = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(end_time / w.dt / 200));
    checkpoint_every = every_steps(out.checkpoint_interval.value, w.dt);
    for (const auto& s : w.surfaces) surface_series.emplace_back(directory / (s.name + ".pvd"));
    checkpoint_path = (directory / "checkpoint.qck").string();
  }

  void write_frame() {
    complete_step(world);  // the velocities written must be the step's final ones
    const std::string tag = fmt::format("{:06}", frame_index);
    const std::string particle_file = "particles_" + tag + ".vtu";
    write_file_atomically(directory / particle_file, particles_vtu(world.particles, world.type_names));
    particle_series.add(world.time, particle_file);
    std::vector<double> pressure;
    std::vector<Vec3> shear, force;
    for (std::size_t s = 0; s < world.surfaces.size(); ++s) {
      Surface& surface = world.surfaces[s];
      surface.window_means(pressure, shear, force);
      const std::string file = surface.name + "_" + tag + ".vtu";
      write_file_atomically(directory / file, surface_vtu(surface, pressure, shear, force));
      surface_series[s].add(world.time, file);
      surface.clear_window();
    }
    monitors.flush();
    ++frame_index;
  }

  // How the next step is to end. If something looks at the state after it (a monitor row, a
  // frame, a checkpoint, a stop signal, the end of the run), with its closing half kick left
  // pending: they complete the step first. Otherwise its force stage also does the opening
  // pass of the step after it, one pass over the particles less (sim/step.h).
  StepEnd step_end() const {
    const std::uint64_t n = world.step_count + 1;
    const auto due = [n](std::uint64_t every) { return every != 0 && n % every == 0; };
    const double time_after = world.time + world.dt;  // s: as step() advances it
    const bool last = !(time_after < end_time - 0.5 * world.dt);
    if (last || due(monitor_every) || due(output_every) || due(checkpoint_every) || g_stop_signal.load() != 0)
      return StepEnd::kick_pending;
    return StepEnd::next_opened;
  }

  void record_monitors() {
    complete_step(world);
    const std::vector<double> row = monitor_row(world);
    monitors.add_row(row);
  }
};

}  // namespace

static RunSummary run_session(Session& session, bool fresh) {
  World& world = session.world;
  std::ostream& log = session.log;
  RunSummary summary;
  g_stop_signal.store(0);
  auto previous_int = std::signal(SIGINT, on_stop_signal);
  auto previous_term = std::signal(SIGTERM, on_stop_signal);

  for (const auto& w : world.warnings) log << "quarry: warning: " << w << "\n";
  if (fresh) {
    insert_and_remove(world);
    update_neighbors(world, true);
    compute_forces(world);
    session.record_monitors();
    session.write_frame();
  }
  // FEM load export (issue 4); a restart keeps the records up to the checkpoint and appends.
  fem_export::LoadExporter exporter(world.spec.fem_export, world.surfaces, session.directory,
                                    world.dt, fresh ? std::nullopt : std::optional(world.time));
  for (const auto& note : exporter.notes()) log << "quarry: " << note << "\n";
  log << fmt::format("quarry: dt = {:.4g} s, {} steps to t = {:.4g} s, output in {}\n", world.dt,
                     static_cast<std::uint64_t>(std::max(0.0, (session.end_time - world.time) / world.dt) + 0.5),
                     session.end_time, session.directory.string());

  const auto start = std::chrono::steady_clock::now();
  auto last_progress = start;
  double last_progress_time = world.time;  // s, simulated time at the last progress line
  const double progress_every = world.spec.output.progress_interval.value;
  bool frame_pending = false;
  std::vector<char> reported_shortfall(world.factories.size(), 0);

  while (world.time < session.end_time - 0.5 * world.dt) {
    const StepEnd ending = session.step_end();
    try {
      step(world, ending);
    } catch (const PhysicsError&) {
      // Keep what was computed: the monitors so far and a last frame to look at in ParaView.
      session.monitors.flush();
      session.write_frame();
      exporter.finish(world.surfaces, world.time, true);
      std::signal(SIGINT, previous_int);
      std::signal(SIGTERM, previous_term);
      throw;
    }
    summary.steps += 1;
    summary.steps_opened_ahead += ending == StepEnd::next_opened;
    for (auto& surface : world.surfaces) surface.accumulate_window(world.dt);
    exporter.after_step(world.surfaces, world.time, world.step_count, world.dt);
    const std::uint64_t n = world.step_count;
    frame_pending = true;
    if (session.monitor_every && n % session.monitor_every == 0) session.record_monitors();
    if (session.output_every && n % session.output_every == 0) {
      session.write_frame();
      frame_pending = false;
    }
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
    // A step that opened the next one cannot be checkpointed: a stop signal is taken after
    // the next step, which sees it and ends complete.
    const int signal_number = world.next_opened ? 0 : g_stop_signal.load();
    if ((session.checkpoint_every && n % session.checkpoint_every == 0) || signal_number) {
      session.monitors.flush();
      complete_step(world);
      write_checkpoint(world, session.checkpoint_path, session.frame_index);
      summary.checkpoint = session.checkpoint_path;
    }
    if (signal_number) {
      summary.interrupted = true;
      log << fmt::format("\nquarry: stopped by signal {} at step {} (t = {:.6g} s); checkpoint "
                         "written to {}; continue with: quarry restart {}\n",
                         signal_number, n, world.time, session.checkpoint_path, session.checkpoint_path);
      break;
    }
    const auto now = std::chrono::steady_clock::now();
    if (!session.options.quiet && std::chrono::duration<double>(now - last_progress).count() >= progress_every) {
      // ETA from the pace since the last line: the cost per step grows as particles are added.
      const double recent_wall = std::chrono::duration<double>(now - last_progress).count();
      const double recent_simulated = world.time - last_progress_time;
      const double eta = recent_simulated > 0 ? recent_wall * (session.end_time - world.time) / recent_simulated : NAN;
      const double wall = std::chrono::duration<double>(now - start).count();
      last_progress = now;
      last_progress_time = world.time;
      log << fmt::format("t = {:.4f} / {:.4g} s ({:5.1f} %)  step {}  {} particles  {:.0f} steps/s  "
                         "ETA {}\n", world.time, session.end_time,
                         100.0 * world.time / session.end_time, n, world.particles.size(),
                         summary.steps / std::max(wall, 1e-9), duration_text(eta));
    }
  }
  complete_step(world);
  if (frame_pending && !summary.interrupted) session.write_frame();
  const std::size_t notes_before_finish = exporter.notes().size();
  exporter.finish(world.surfaces, world.time, summary.interrupted);
  for (std::size_t k = notes_before_finish; k < exporter.notes().size(); ++k)
    log << "quarry: " << exporter.notes()[k] << "\n";
  session.monitors.flush();
  if (world.spec.output.plots.value && !session.monitors.rows().empty())
    write_monitor_plots(session.directory.string(), session.monitors.columns(), session.monitors.rows());

  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.simulated_time = world.time;
  summary.particles = world.particles.size();
  summary.final_state_hash = state_hash(world);
  if (!summary.interrupted) {
    for (const Factory& factory : world.factories)
      if (!factory.finished())
        log << fmt::format("quarry: note: factory '{}' had not finished at the end time\n",
                           factory.spec().name.value);
  }
  log << fmt::format("quarry: {} steps in {:.2f} s ({:.0f} steps/s, {:.3g} particle-steps/s), {} "
                     "particles, {} removed (left the domain), {} list rebuilds\n",
                     summary.steps, summary.wall_seconds, summary.steps / std::max(summary.wall_seconds, 1e-9),
                     static_cast<double>(summary.steps) * static_cast<double>(world.particles.size()) /
                         std::max(summary.wall_seconds, 1e-9),
                     world.particles.size(), world.removed_outside, world.rebuilds);
  if (!session.options.quiet) log << world.timers.table();
  std::signal(SIGINT, previous_int);
  std::signal(SIGTERM, previous_term);
  return summary;
}

RunSummary run(World& world, const RunOptions& options) {
  Session session(world, options);
  return run_session(session, true);
}

RunSummary restart(const std::string& checkpoint_path, const RunOptions& options) {
  const std::string deck = checkpoint_deck_path(checkpoint_path);
  World world = build_world(parse_deck(deck));
  const std::uint64_t frame_index = read_checkpoint(world, checkpoint_path);
  RunOptions o = options;
  if (o.output_directory.empty())
    o.output_directory = fs::path(checkpoint_path).parent_path().string();
  Session session(world, o);
  session.frame_index = frame_index;
  // Keep what the interrupted run wrote up to the checkpoint time, drop anything later.
  session.monitors = CsvTable::load(session.directory / "monitors.csv");
  session.monitors.truncate_after(world.time);
  session.particle_series.load_existing(world.time);
  for (auto& series : session.surface_series) series.load_existing(world.time);
  return run_session(session, false);
}

}  // namespace quarry::sim
