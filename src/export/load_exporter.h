// LoadExporter: the FEM load export of a run (issue 4). Called by the run loop after the force
// stage of every step; every export interval it writes, per surface flagged `export: true`, the
// interval means to MED, a VTU series, a CSV and a nodal-force history on disk; at the end it
// writes the CalculiX deck. Memory does not grow with the number of intervals.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/simulation_spec.h"
#include "geometry/surface.h"

namespace quarry::fem_export {

class LoadExporter {
 public:
  // Starts the export into <output_directory>/<spec.directory>/ for every surface with
  // export_loads set, meshes taken from `surfaces` now (reference positions). Does nothing when
  // !spec.enabled (then notes() says so if some surface is flagged).
  // Fresh run (resume_time empty): files are created anew. Restart (resume_time = the
  // checkpoint time, s): the existing files are kept up to that time and later records dropped;
  // the interval running at the checkpoint restarts at it, so its mean covers only the part
  // after the restart. `dt` (s) fixes the interval in steps: max(1, round(interval / dt)).
  // `end_time` (s, the run's end; ≤ 0: unknown) lets the last interval absorb a remainder
  // shorter than half an interval (no sliver records, see after_step).
  // Throws std::runtime_error when a file cannot be created or does not match the mesh.
  LoadExporter(const ExportSpec& spec, std::span<const Surface* const> surfaces,
               const std::filesystem::path& output_directory, double dt, double end_time,
               std::optional<double> resume_time);
  ~LoadExporter();
  LoadExporter(const LoadExporter&) = delete;
  LoadExporter& operator=(const LoadExporter&) = delete;

  bool active() const { return !outputs_.empty(); }

  // After the force stage of the step that ended at `time` (s), number `step_count`, length
  // `dt` (s): accumulates the surfaces' loads and, when the step ends an export interval, writes
  // one record to every format — except when the run's end is less than half an interval away:
  // then that interval goes on to the end and finish() writes it as one record of its true
  // length (≤ 1.5 intervals), instead of a full record and a sliver of a few steps whose mean
  // is dominated by noise (a 0.4 ms record after 3 s of 0.1 s intervals had a negative pressure).
  // Pre: `surfaces` is the same list as at construction.
  // Cost: O(triangles + vertices) per exported surface; a record costs a few file writes.
  void after_step(std::span<const Surface* const> surfaces, double time, std::uint64_t step_count,
                  double dt);

  // End of the run at `time` (s): writes the unfinished interval as a last record (unless
  // `interrupted`: then the restart continues it) — a partial interval (≥ half an interval, or
  // any length when the end was not foreseen) is noted in notes() with its length; then the
  // CalculiX deck of each surface
  // from its whole history. Safe to call once; later calls do nothing.
  void finish(std::span<const Surface* const> surfaces, double time, bool interrupted);

  // Width (m, the Gaussian's standard deviation) of the coarse-grained pressure in the VTU
  // records (geometry/surface_pressure.h); ≤ 0 (the default): the VTU has no smoothed pressure.
  void set_pressure_smoothing_width(double width) { smoothing_width_ = width; }

  // Lines for the run's log (files written, warnings such as supports that hold no node).
  const std::vector<std::string>& notes() const { return notes_; }
  std::filesystem::path directory() const { return directory_; }

 private:
  struct SurfaceOutput;
  void write_record(const Surface& surface, SurfaceOutput& output, double time);

  ExportSpec spec_;
  std::filesystem::path directory_;
  std::uint64_t every_steps_ = 1;
  double interval_ = 0.0;  // s, every_steps_ × dt
  double end_time_ = 0.0;  // s, ≤ 0: unknown
  double smoothing_width_ = 0.0;  // m
  std::vector<std::unique_ptr<SurfaceOutput>> outputs_;
  std::vector<std::string> notes_;
  bool finished_ = false;
};

// The CSV of one surface: header and row format (one row per element and record).
inline constexpr const char* kLoadsCsvHeader =
    "time_s,element_id,pressure_Pa,shear_x_Pa,shear_y_Pa,shear_z_Pa,force_x_N,force_y_N,"
    "force_z_N";

}  // namespace quarry::fem_export
