// Output stage: schedules in steps (so a restart keeps them), ParaView frames of particles and
// surfaces with the surfaces' window-mean loads, monitor rows, the FEM load export (issue 4) and
// checkpoints; every file written atomically.
#include "sim/output.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <iostream>
#include <sstream>

#include "export/load_exporter.h"
#include "geometry/surface_pressure.h"
#include "io/atomic_file.h"
#include "io/paraview_script.h"
#include "io/vtu_writer.h"
#include "sim/frame_contacts.h"
#include "sim/monitor_sensors.h"
#include "sim/monitors.h"
#include "sim/run.h"

namespace quarry::sim {

namespace {

// A restart's table: the rows the interrupted run wrote up to the checkpoint time when the
// folder holds them; a restart into another folder starts the table afresh (the earlier rows
// stay in the first run's folder), as its PVD series do.
void resume_table(CsvTable& table, const std::filesystem::path& path, double resume_time) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) return;
  table = CsvTable::load(path);
  table.truncate_after(resume_time);
}

// Steps between events for an interval in seconds (0 → never).
std::uint64_t every_steps(double interval, double dt) {
  if (interval <= 0.0) return 0;
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(interval / dt)));
}

// A temporary file of write_file_atomically (NAME.tmp.PID.N) that a killed run left.
bool is_stale_temporary(const std::string& name) { return name.find(".tmp.") != std::string::npos; }

std::vector<const Surface*> meshes_of(const World& world) {
  std::vector<const Surface*> meshes;
  for (const WorldSurface& s : world.surfaces) meshes.push_back(&s.mesh);
  return meshes;
}

// A particle monitor whose id no row ever saw (every value NaN) is most likely a wrong id.
void warn_of_unseen_particles(const World& world, const CsvTable& monitors, std::ostream& log) {
  for (const MonitorSpec& m : world.spec.monitors) {
    if (m.kind.value != MonitorKind::particle) continue;
    const std::string column = m.name.value + "_x_m";
    std::size_t k = 0;
    while (k < monitors.columns().size() && monitors.columns()[k] != column) ++k;
    if (k == monitors.columns().size()) continue;
    bool seen = false;
    for (const auto& row : monitors.rows()) seen = seen || std::isfinite(row[k]);
    if (!seen)
      log << fmt::format("quarry: warning: {}:{}:{}: monitor '{}': no particle had id {} at any monitor row (its "
                         "columns are empty); ids are given from 1 in creation order\n",
                         m.particle_id.where.file, m.particle_id.where.line, m.particle_id.where.column,
                         m.name.value, m.particle_id.value);
  }
}

}  // namespace

void prepare_output_folder(const std::filesystem::path& directory, bool resume, bool overwrite) {
  namespace fs = std::filesystem;
  fs::create_directories(directory);
  std::error_code error;
  std::vector<std::string> earlier;  // what an earlier run left (for the message)
  for (const auto& entry : fs::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file(error) && is_stale_temporary(name)) {
      fs::remove(entry.path(), error);
      continue;
    }
    if (name == kOutputManifest || name == "checkpoint.qck" || name == "monitors.csv" || name == "particles.pvd")
      earlier.push_back(name);
  }
  if (resume || earlier.empty()) return;
  if (!overwrite)
    throw UserError(SourceLocation{directory.string(), 0, 0},
                    fmt::format("the output folder holds an earlier run's output ({}); a new run would mix "
                                "its files with that run's",
                                fmt::join(earlier, ", ")),
                    "add --overwrite to replace that run's files (only those), or choose another folder "
                    "with --output-dir; 'quarry restart' continues a run in its own folder");
  // Remove what the earlier run wrote: its manifest's files, else (a folder of a Quarry without
  // manifests) its checkpoint, monitors, plots and series.
  std::vector<fs::path> remove;
  if (const std::optional<std::string> listed = read_file(directory / kOutputManifest)) {
    std::istringstream lines(*listed);
    for (std::string line; std::getline(lines, line);) {
      const fs::path relative(line);
      if (line.empty() || relative.is_absolute() || line.find("..") != std::string::npos) continue;  // not ours
      remove.push_back(directory / relative);
    }
    remove.push_back(directory / kOutputManifest);
  } else {
    for (const auto& entry : fs::directory_iterator(directory)) {
      const std::string name = entry.path().filename().string();
      const std::string extension = entry.path().extension().string();
      if (name == "checkpoint.qck" || name == "monitors.csv" || extension == ".pvd" ||
          (extension == ".vtu" && name.size() > 11 && name[name.size() - 11] == '_') ||
          (extension == ".png" && entry.is_regular_file()))
        remove.push_back(entry.path());
    }
  }
  for (const fs::path& path : remove) {
    fs::remove_all(path, error);
    if (error) throw FileError(fmt::format("cannot remove '{}' of the earlier run: {}", path.string(), error.message()));
  }
}

void Output::wrote(const std::string& relative) {
  if (!manifest_.insert(relative).second) return;
  std::string text;
  for (const std::string& name : manifest_) text += name + "\n";
  write_file_atomically(directory_ / kOutputManifest, text);
}

Output::Output(World& world, const OutputOptions& options)
    : log_(options.log ? *options.log : std::cerr),
      directory_(options.directory),
      end_time_(options.end_time),
      frame_index_(options.frame_index),
      surface_count_(world.surfaces.size()),
      monitors_(directory_ / "monitors.csv", monitor_columns(world, world.surfaces.size())),
      particle_series_(directory_ / "particles.pvd"),
      checkpoint_path_((directory_ / "checkpoint.qck").string()) {
  prepare_output_folder(directory_, options.resume_time.has_value(), options.overwrite);
  if (const std::optional<std::string> listed = read_file(directory_ / kOutputManifest)) {
    std::istringstream lines(*listed);  // a restart keeps the run's list and goes on with it
    for (std::string line; std::getline(lines, line);)
      if (!line.empty()) manifest_.insert(line);
  }
  const auto& out = world.spec.output;
  output_every_ = every_steps(out.interval.value, world.dt);
  monitor_every_ = every_steps(out.monitor_interval.value > 0 ? out.monitor_interval.value : out.interval.value, world.dt);
  if (monitor_every_ == 0)  // neither given: about 200 rows over the run
    monitor_every_ = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(end_time_ / world.dt / 200));
  checkpoint_every_ = every_steps(out.checkpoint_interval.value, world.dt);
  for (WorldSurface& s : world.surfaces) {
    surface_series_.emplace_back(directory_ / (s.mesh.name + ".pvd"));
    smoothers_.emplace_back();
    // Frames show triangles: the window is per triangle whatever the input's elements.
    if (!s.output_window.sized()) s.output_window = LoadWindow(s.mesh);
  }
  if (options.resume_time) {
    // Keep what the interrupted run wrote up to the checkpoint time, drop anything later.
    resume_table(monitors_, directory_ / "monitors.csv", *options.resume_time);
    particle_series_.load_existing(*options.resume_time);
    for (auto& series : surface_series_) series.load_existing(*options.resume_time);
  }
  for (std::size_t k = 0; k < world.spec.monitors.size(); ++k) {
    const MonitorSpec& m = world.spec.monitors[k];
    if (m.kind.value != MonitorKind::velocity_profile || !m.region) continue;  // the deck requires the box
    const std::string file = "profile_" + m.name.value + ".csv";
    profile_monitors_.push_back(k);
    profiles_.emplace_back(directory_ / file, velocity_profile_columns());
    if (options.resume_time) resume_table(profiles_.back(), directory_ / file, *options.resume_time);
    wrote(file);
  }
  if (out.contacts.value) {
    contact_series_.emplace(directory_ / "contacts.pvd");
    if (options.resume_time) contact_series_->load_existing(*options.resume_time);
    wrote("contacts.pvd");
  }
  // A fresh run's mass-flow monitors start with no sides seen; a restart has the checkpoint's.
  if (!options.resume_time) world.plane_crossings.clear();
  exporter_ = std::make_unique<fem_export::LoadExporter>(world.spec.fem_export, meshes_of(world), directory_,
                                                         world.dt, end_time_, options.resume_time);
  exporter_->set_pressure_smoothing_width(world.max_radius);
  if (exporter_->active()) wrote(std::filesystem::relative(exporter_->directory(), directory_).string());
  wrote("monitors.csv");
  wrote("particles.pvd");
  for (const WorldSurface& s : world.surfaces) wrote(s.mesh.name + ".pvd");
  // The ParaView script that opens these series (README "Seeing the results").
  std::vector<std::string> surface_names;
  for (const WorldSurface& s : world.surfaces) surface_names.push_back(s.mesh.name);
  wrote(kParaviewScript);
  write_file_atomically(directory_ / kParaviewScript, paraview_script(surface_names));
  for (const auto& note : exporter_->notes()) log_ << "quarry: " << note << "\n";
}

Output::~Output() = default;

void Output::start(World& world) {
  record_monitors(world);
  write_frame(world);
}

void Output::after_step(World& world) {
  exporter_->after_step(meshes_of(world), world.time, world.step_count, world.dt);
  const std::uint64_t n = world.step_count;
  const auto due = [n](std::uint64_t every) { return every != 0 && n % every == 0; };
  frame_pending_ = true;
  count_flow_windows(world);
  if (due(monitor_every_)) record_monitors(world);
  if (due(output_every_)) write_frame(world);
  if (due(checkpoint_every_)) write_checkpoint_now(world);
}

void Output::finish(World& world, bool interrupted) {
  if (frame_pending_ && !interrupted) write_frame(world);
  const std::size_t notes_before = exporter_->notes().size();
  exporter_->finish(meshes_of(world), world.time, interrupted);
  for (std::size_t k = notes_before; k < exporter_->notes().size(); ++k) log_ << "quarry: " << exporter_->notes()[k] << "\n";
  flush_tables();
  warn_of_unseen_particles(world, monitors_, log_);
  if (world.spec.output.plots.value && !monitors_.rows().empty())
    for (const std::string& plot : write_monitor_plots(directory_.string(), monitors_.columns(), monitors_.rows(),
                                                       norm(world.spec.simulation.gravity.value)))
      wrote(plot);
}

void Output::stopped_by_error(World& world) {
  flush_tables();
  write_frame(world);
  exporter_->finish(meshes_of(world), world.time, true);
}

std::string Output::write_checkpoint_now(World& world) {
  flush_tables();
  wrote("checkpoint.qck");
  write_checkpoint(world, checkpoint_path_, frame_index_);
  checkpoint_written_ = true;
  return checkpoint_path_;
}

void Output::write_frame(World& world) {
  const std::string tag = fmt::format("{:06}", frame_index_);
  const std::string particle_file = "particles_" + tag + ".vtu";
  const std::vector<FrameContact> contacts = frame_contacts(world);
  const ParticleContactFields fields = particle_contact_fields(world, contacts);
  wrote(particle_file);
  write_file_atomically(directory_ / particle_file, particles_vtu(world.particles, world.type_names, &fields));
  particle_series_.add(world.time, particle_file);
  if (contact_series_) {
    std::vector<ContactLine> lines;
    lines.reserve(contacts.size());
    for (const FrameContact& c : contacts) lines.push_back(c.line);
    const std::string contact_file = "contacts_" + tag + ".vtu";
    wrote(contact_file);
    write_file_atomically(directory_ / contact_file, contacts_vtu(lines));
    contact_series_->add(world.time, contact_file);
  }
  LoadFrame means;
  for (std::size_t s = 0; s < surface_count_; ++s) {
    WorldSurface& surface = world.surfaces[s];
    surface.output_window.take_means(surface.mesh, world.time, means);
    const std::string file = surface.mesh.name + "_" + tag + ".vtu";
    wrote(file);
    // Vertex pressures: nodal (load-conserving) and coarse-grained over a Gaussian of standard
    // deviation = the largest particle radius (converges to the mean load; issue #20).
    const std::vector<double> nodal = nodal_pressure(surface.mesh, means.nodal_force);
    const std::vector<double> smoothed = world.max_radius > 0.0
                                             ? smoothers_[s].smooth(surface.mesh, nodal, world.max_radius)
                                             : std::vector<double>{};
    write_file_atomically(directory_ / file, surface_vtu(surface.mesh, means.pressure, means.shear_stress,
                                                         means.force, means.nodal_force, nodal, smoothed));
    surface_series_[s].add(world.time, file);
  }
  flush_tables();
  frame_pending_ = false;
  ++frame_index_;
}

void Output::record_monitors(World& world) {
  monitors_.add_row(monitor_row(world, surface_count_));
  for (std::size_t k = 0; k < profile_monitors_.size(); ++k) {
    const std::vector<VelocityBin> bins = velocity_profile(world, world.spec.monitors[profile_monitors_[k]]);
    for (std::size_t b = 0; b < bins.size(); ++b) {
      const VelocityBin& bin = bins[b];
      const std::vector<double> row = {world.time, static_cast<double>(b), bin.centre,
                                       static_cast<double>(bin.particles), bin.mass, bin.mean_velocity.x,
                                       bin.mean_velocity.y, bin.mean_velocity.z};
      profiles_[k].add_row(row);
    }
  }
}

void Output::flush_tables() {
  monitors_.flush();
  for (CsvTable& profile : profiles_) profile.flush();
}

}  // namespace quarry::sim
