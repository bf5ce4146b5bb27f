// FEM load export driver (load_exporter.h): the schedule of export intervals in steps, the
// per-surface writers, restart handling, and the CalculiX deck at the end of the run.
#include "export/load_exporter.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "export/aster_comm.h"
#include "export/calculix_deck.h"
#include "geometry/load_window.h"
#include "geometry/surface_pressure.h"
#include "export/med_file.h"
#include "export/nodal_history.h"
#include "io/atomic_file.h"
#include "io/pvd_series.h"
#include "io/vtu_writer.h"

namespace quarry::fem_export {

namespace fs = std::filesystem;

struct LoadExporter::SurfaceOutput {
  std::size_t surface_index = 0;
  std::string name;
  LoadWindow window;
  LoadFrame frame;                       // reused for every record
  std::vector<Vec3> mesh_vertices;       // m, as at the start of the export
  // A moving surface (surface.moving): ∫ (x − x_ref) dt per vertex over the running interval
  // (m·s), with the loads' rectangle rule, and its mean at the last record (m).
  std::vector<Vec3> displacement_integral, displacement;
  std::unique_ptr<NodalHistoryWriter> history;
  std::unique_ptr<MedLoadWriter> med;
  std::vector<std::string> med_groups;   // node group names in the MED file
  std::unique_ptr<PvdSeries> vtu_series;
  PressureSmoother smoother;             // the VTU records' coarse-grained pressure
  std::ofstream csv;

  SurfaceOutput(std::size_t index, const Surface& surface)
      : surface_index(index), name(surface.name), window(surface) {}
};

namespace {

bool wants(const ExportSpec& spec, ExportFormat format) {
  return spec.formats.empty() ||
         std::any_of(spec.formats.begin(), spec.formats.end(),
                     [&](const Located<ExportFormat>& f) { return f.value == format; });
}

// Cuts a CSV written by an interrupted run after its last row with time ≤ resume_time (s).
void truncate_csv(const fs::path& path, double resume_time) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return;
  std::string line;
  std::uintmax_t keep = 0;
  bool header = true;
  while (std::getline(in, line)) {
    if (!header) {
      const double time = std::strtod(line.c_str(), nullptr);
      if (in.eof() || time > resume_time) break;  // a last line without '\n' is incomplete
    }
    header = false;
    keep = static_cast<std::uintmax_t>(in.tellg());
  }
  in.close();
  fs::resize_file(path, keep);
}

}  // namespace

LoadExporter::LoadExporter(const ExportSpec& spec, std::span<const Surface* const> surfaces,
                           const fs::path& output_directory, double dt, double end_time,
                           std::optional<double> resume_time)
    : spec_(spec), directory_(output_directory / spec.directory.value), end_time_(end_time) {
  if (!spec.enabled) {
    for (const Surface* surface : surfaces)
      if (surface->export_loads)
        notes_.push_back(fmt::format("warning: surface '{}' has export: true but the deck has no "
                                     "export: section; nothing is exported (docs/deck.md)",
                                     surface->name));
    return;
  }
  every_steps_ = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::llround(spec.interval.value / dt)));
  interval_ = static_cast<double>(every_steps_) * dt;
  fs::create_directories(directory_);
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const Surface& surface = *surfaces[s];
    if (!surface.export_loads) continue;
    auto output = std::make_unique<SurfaceOutput>(s, surface);
    output->mesh_vertices =
        surface.reference_vertices.size() == surface.vertex_count() ? surface.reference_vertices
                                                                    : surface.vertices;
    if (surface.moving) output->displacement_integral.assign(surface.vertex_count(), Vec3{});
    const fs::path base = directory_ / surface.name;
    output->history = std::make_unique<NodalHistoryWriter>(
        fs::path(base.string() + "_nodal_forces.bin"), surface.vertex_count(), resume_time);
    if (wants(spec, ExportFormat::med)) {
      // The CalculiX supports also become MED node groups, so code_aster can fix them by name.
      std::vector<MedNodeGroup> groups;
      if (spec.calculix)
        for (const SupportSpec& support : spec.calculix->supports)
          groups.push_back({support.name.value, nodes_in_box(output->mesh_vertices,
                                                             support.min.value, support.max.value)});
      output->med = std::make_unique<MedLoadWriter>(base.string() + ".med", surface.name,
                                                    output->mesh_vertices, surface.triangles,
                                                    resume_time.has_value(), groups, surface.moving);
      for (const MedNodeGroup& group : groups) output->med_groups.push_back(group.name);
    }
    if (wants(spec, ExportFormat::vtu)) {
      const fs::path pvd = base.string() + "_loads.pvd";
      output->vtu_series = std::make_unique<PvdSeries>(
          resume_time ? PvdSeries::resume(pvd, *resume_time) : PvdSeries(pvd));
    }
    if (wants(spec, ExportFormat::csv)) {
      const fs::path csv = base.string() + "_loads.csv";
      std::error_code ignored;
      const bool append = resume_time && fs::exists(csv, ignored);
      if (append) truncate_csv(csv, *resume_time);
      output->csv.open(csv, std::ios::binary | (append ? std::ios::app : std::ios::trunc));
      if (!output->csv) throw FileError("cannot write '" + csv.string() + "'");
      if (!append) output->csv << kLoadsCsvHeader << '\n';
    }
    outputs_.push_back(std::move(output));
  }
  notes_.push_back(fmt::format("exporting loads of {} surface{} every {} steps ({:.4g} s) to {}",
                               outputs_.size(), outputs_.size() == 1 ? "" : "s", every_steps_, every_steps_ * dt,
                               directory_.string()));
}

LoadExporter::~LoadExporter() = default;

void LoadExporter::write_record(const Surface& surface, SurfaceOutput& output, double time) {
  if (!output.displacement_integral.empty()) {
    // The mean over the same steps as the loads' (before take_means restarts the window).
    const double duration = output.window.duration;  // s
    output.displacement.resize(output.displacement_integral.size());
    for (std::size_t v = 0; v < output.displacement.size(); ++v) {
      output.displacement[v] = duration > 0.0 ? output.displacement_integral[v] / duration : Vec3{};
      output.displacement_integral[v] = Vec3{};
    }
  }
  output.window.take_means(surface, time, output.frame);
  const LoadFrame& frame = output.frame;
  output.history->append(time, frame.nodal_force);
  output.history->flush();
  const std::size_t record = output.history->frame_count();  // 1-based number of this record
  if (output.med) output.med->write(static_cast<int>(record), frame, output.displacement);
  if (output.csv.is_open()) {
    fmt::memory_buffer rows;  // one buffer for the record's rows, not a string per row
    for (std::size_t e = 0; e < frame.pressure.size(); ++e) {
      const Vec3& s = frame.shear_stress[e];
      const Vec3& f = frame.force[e];
      fmt::format_to(std::back_inserter(rows), "{:.9g},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
                     time, e, frame.pressure[e], s.x, s.y, s.z, f.x, f.y, f.z);
    }
    output.csv.write(rows.data(), static_cast<std::streamsize>(rows.size()));
    output.csv.flush();
    if (!output.csv) throw FileError("cannot write the loads CSV of surface '" + output.name + "' (disk full?)");
  }
  if (output.vtu_series) {
    const std::string file = fmt::format("{}_loads_{:06}.vtu", output.name, record - 1);
    const std::vector<double> nodal = nodal_pressure(surface, frame.nodal_force);
    const std::vector<double> smoothed = smoothing_width_ > 0.0
                                             ? output.smoother.smooth(surface, nodal, smoothing_width_)
                                             : std::vector<double>{};
    write_file_atomically(directory_ / file,
                          surface_vtu(surface, frame.pressure, frame.shear_stress, frame.force, frame.nodal_force,
                                      nodal, smoothed, output.displacement));
    output.vtu_series->add(time, file);
  }
}

void LoadExporter::after_step(std::span<const Surface* const> surfaces, double time,
                              std::uint64_t step_count, double dt) {
  if (finished_) return;
  // Steps left until the run loop stops (it steps while time < end − dt/2). A remainder of
  // fewer than half an interval's steps joins this interval rather than making its own record.
  const long long steps_left = end_time_ > 0.0 ? std::llround((end_time_ - time) / dt) : 0;
  const bool absorb_remainder =
      steps_left > 0 && 2 * static_cast<std::uint64_t>(steps_left) < every_steps_;
  for (auto& output : outputs_) {
    const Surface& surface = *surfaces[output->surface_index];
    output->window.accumulate(surface, dt);
    // The vertices the step's loads were found on, up to a coupling partner's correction at
    // its synchronisation (the extrapolated surface then moves to where the partner says).
    for (std::size_t v = 0; v < output->displacement_integral.size(); ++v)
      output->displacement_integral[v] += (surface.vertices[v] - output->mesh_vertices[v]) * dt;
    if (step_count % every_steps_ == 0 && !absorb_remainder) write_record(surface, *output, time);
  }
}

void LoadExporter::finish(std::span<const Surface* const> surfaces, double time, bool interrupted) {
  if (finished_) return;
  finished_ = true;
  for (auto& output : outputs_) {
    const Surface& surface = *surfaces[output->surface_index];
    if (!interrupted && output->window.duration > 0.0) {
      const double length = output->window.duration;  // s
      const double interval = interval_;                // s
      // Flag a record shorter than an interval (a remainder of ≥ half an interval, or an end
      // that was not foreseen); a merged one (up to 1.5 intervals) is noted too.
      if (std::abs(length - interval) > 1e-9 * interval)
        notes_.push_back(fmt::format("surface '{}': the last export record (t = {:.6g} s) is the mean "
                                     "over {:.6g} s, not one interval of {:.6g} s ({})",
                                     output->name, time, length, interval,
                                     length < interval ? "the run ended inside it"
                                                       : "the remainder up to the end joined it"));
      write_record(surface, *output, time);
    }
    output->history->flush();
    if (output->csv.is_open()) output->csv.close();
    if (output->med) {
      // The code_aster template beside the MED file, naming its mesh, fields and instants.
      NodalHistoryReader history(output->history->path());
      const AsterCommInput comm{output->name, output->name + ".med", output->med->mesh_name(),
                                history.times(), output->med_groups, output->med->has_displacement()};
      write_file_atomically(directory_ / (output->name + ".comm"), aster_comm_text(comm));
    }
    if (!wants(spec_, ExportFormat::calculix) || !spec_.calculix) continue;
    if (output->history->frame_count() == 0) {
      notes_.push_back(fmt::format("warning: no export interval of surface '{}' has ended; no "
                                   "CalculiX deck written", output->name));
      continue;
    }
    NodalHistoryReader history(output->history->path());
    const ShellMesh mesh = quadratic_shell_mesh(output->mesh_vertices, surface.triangles);
    const fs::path inp = directory_ / (output->name + ".inp");
    const CalculixDeckSummary summary =
        write_calculix_deck(inp, output->name, mesh, *spec_.calculix, history);
    for (std::size_t s = 0; s < summary.support_node_counts.size(); ++s)
      if (summary.support_node_counts[s] == 0)
        notes_.push_back(fmt::format(
            "warning: support '{}' holds no node of surface '{}'; check its box",
            spec_.calculix->supports[s].name.value, output->name));
    notes_.push_back(fmt::format("CalculiX deck {} ({} interval{}); run: cd {} && ccx {}",
                                 inp.string(), summary.frames, summary.frames == 1 ? "" : "s", directory_.string(),
                                 output->name));
  }
}

}  // namespace quarry::fem_export
