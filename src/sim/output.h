// Output: what a run writes while it goes — ParaView frames of the particles and surfaces,
// monitor rows and plots, the FEM load export, checkpoints — each on its own schedule counted
// in steps, so that a restarted run keeps the same schedule. Attached to a World
// (World::output) it is the last stage of every step; without one a step writes nothing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "geometry/surface_pressure.h"
#include "io/csv_table.h"
#include "io/pvd_series.h"
#include "sim/world.h"

namespace quarry::fem_export {
class LoadExporter;
}

namespace quarry::sim {

struct OutputOptions {
  std::filesystem::path directory;  // where the files go
  double end_time = 0.0;            // s: the run's end (sets the default monitor interval)
  std::ostream* log = nullptr;      // notes (files written, warnings); null: std::cerr
  // Restart: the checkpoint's time (s) and frame number. Files written up to that time are
  // kept and continued; later records are dropped.
  std::optional<double> resume_time;
  std::uint64_t frame_index = 0;
  // A fresh run into a folder that holds an earlier run's output: false refuses (UserError),
  // true removes what that run wrote first (the files its manifest lists, nothing else).
  bool overwrite = false;
};

// The output folder's manifest: the files a run wrote there, one relative path a line, so that
// a later run can tell the folder is taken and --overwrite can remove exactly those files.
inline constexpr const char* kOutputManifest = ".quarry_outputs";

// Makes `directory` ready for a run's output: creates it, removes the temporary files a killed
// run left (NAME.tmp.PID.N), and for a fresh run (not `resume`) refuses a folder holding an
// earlier run's output unless `overwrite`, which removes the files that run's manifest lists
// (and, for a folder of a Quarry without manifests, its checkpoint, monitors and series).
// Throws UserError naming the folder and what is there, FileError when it cannot remove them.
void prepare_output_folder(const std::filesystem::path& directory, bool resume, bool overwrite);

class Output {
 public:
  // Creates the folder and sizes the surfaces' output windows. Throws std::runtime_error (or
  // filesystem_error) when the folder or a file cannot be created.
  Output(World& world, const OutputOptions& options);
  ~Output();
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;

  // A fresh run's first monitor row and frame (sim::initialize calls it); nothing on a restart.
  void start(World& world);
  // After a step: the load export, then a monitor row, a frame and a checkpoint when due.
  void after_step(World& world);
  // The run is over at world.time: the last frame (unless `interrupted`, or one was just
  // written), the export's last record and CalculiX decks, the monitor file and its plots.
  void finish(World& world, bool interrupted);
  // The run stopped on a physics error: keep the monitors so far, a last frame to look at, the
  // export up to here.
  void stopped_by_error(World& world);
  // Writes the checkpoint now (a stop signal); returns its path.
  std::string write_checkpoint_now(World& world);

  const std::filesystem::path& directory() const { return directory_; }
  const std::string& checkpoint_path() const { return checkpoint_path_; }
  std::uint64_t frame_index() const { return frame_index_; }
  bool checkpoint_written() const { return checkpoint_written_; }
  // Steps between monitor rows (≥ 1): what other monitors of the run (fluid, structures) follow.
  std::uint64_t monitor_every() const { return monitor_every_; }
  // Adds a file (relative to the folder) to the manifest, which is rewritten atomically; what
  // hooks write into the folder goes there too, so --overwrite removes it.
  void wrote(const std::string& relative);

 private:
  void write_frame(World& world);
  void record_monitors(World& world);
  // The monitor file and the velocity-profile files to disk.
  void flush_tables();

  std::ostream& log_;
  std::filesystem::path directory_;
  double end_time_ = 0.0;
  std::uint64_t output_every_ = 0, monitor_every_ = 0, checkpoint_every_ = 0;  // steps (0: never)
  std::uint64_t frame_index_ = 0;
  std::size_t surface_count_ = 0;  // surfaces when the output began: its columns and series
  CsvTable monitors_;
  // velocity_profile monitors: their index in spec.monitors and file (profile_NAME.csv).
  std::vector<std::size_t> profile_monitors_;
  std::vector<CsvTable> profiles_;
  PvdSeries particle_series_;
  std::optional<PvdSeries> contact_series_;  // output.contacts: contacts.pvd
  std::vector<PvdSeries> surface_series_;
  std::vector<PressureSmoother> smoothers_;  // per surface: its frames' coarse-grained pressure
  std::string checkpoint_path_;
  bool checkpoint_written_ = false;
  bool frame_pending_ = false;     // a step was taken since the last frame
  std::unique_ptr<fem_export::LoadExporter> exporter_;
  std::set<std::string> manifest_;  // the files of this folder the run wrote (relative)
};

}  // namespace quarry::sim
