// PVD series: the ParaView collection file that lists the VTU files of one output stream with
// their simulation times, rewritten atomically after each output (end of an output step).
// On restart the entries up to the restart time are reloaded so the series continues.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace quarry {

struct PvdEntry {
  double time = 0.0;  // s, simulation time of the data set
  std::string file;   // path relative to the .pvd's folder, as ParaView resolves it
};

class PvdSeries {
 public:
  // Starts an empty series for `pvd_path`; nothing is written until add().
  explicit PvdSeries(std::filesystem::path pvd_path);

  // Restart: a series for `pvd_path` holding the entries of the existing file with
  // time ≤ `restart_time` (s); an absent file gives an empty series. Throws like load_existing.
  static PvdSeries resume(std::filesystem::path pvd_path, double restart_time);

  // Appends one data set at `time` (s) and rewrites the whole .pvd atomically.
  // `relative_file` is relative to the .pvd's folder. Cost: O(entries) formatting and one
  // atomic file write. Throws std::runtime_error if the file cannot be written.
  void add(double time, const std::string& relative_file);

  // Replaces the in-memory entries by those of the file on disk with time ≤ `up_to_time` (s),
  // in file order; later entries (written after the checkpoint we restart from) are dropped
  // and vanish from the file at the next add(). An absent file leaves the series empty.
  // Throws std::runtime_error naming the file if it exists but cannot be read or parsed.
  void load_existing(double up_to_time);

  // Replaces the in-memory entries (a restart that carries them in its checkpoint); the file
  // changes at the next add().
  void set_entries(std::vector<PvdEntry> entries) { entries_ = std::move(entries); }

  const std::vector<PvdEntry>& entries() const { return entries_; }
  const std::filesystem::path& path() const { return pvd_path_; }

  // The .pvd text for the current entries (what add() writes).
  std::string to_xml() const;

 private:
  std::filesystem::path pvd_path_;
  std::vector<PvdEntry> entries_;
};

}  // namespace quarry
