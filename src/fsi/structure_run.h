// The deck's structures in a run (issue #17 §5): each `structures:` entry's model read and
// adapted, its coupling surface added to the world as a coupled surface, a shell solver and a
// StructureCoupler made for it and hooked into the world's end-of-step stage, so that
// `quarry run` (sim::run) drives the two-way coupling with no loop of its own.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <vector>

#include "io/csv_table.h"
#include "io/pvd_series.h"
#include "fem/shell_solver.h"
#include "fsi/structure_adapter.h"
#include "fsi/structure_coupler.h"
#include "sim/world.h"

namespace quarry::fsi {

class CoupledStructures {
 public:
  // Pre: `world` is built (sim::build_world) and not yet initialised; it must not move while
  // this object lives (the hooks hold it). PERIOD: the deck's, else the EDEM card's, else
  // TTERM/100; FILTER: the deck's, else the EDEM card's when PERIOD is the card's, else PERIOD.
  // Coupling messages (the cycle-2 reset, the PERIOD warning) go to `log` as they arise.
  // Frames (structure_vtu.h) go to `output_directory` as structure_<name>_NNNN.vtu with a
  // structure_<name>.pvd series, every output.interval of the deck (0: only the final one,
  // written by finish()); monitors to structure_<name>.csv every output.monitor_interval (0: at
  // the frames): time, largest displacement, total reaction, total coupled load, energies. Throws UserError for a model that cannot be read or adapted, at its
  // file and card.
  CoupledStructures(World& world, std::ostream& log, std::filesystem::path output_directory);

  std::size_t size() const { return entries_.size(); }
  const fem::ShellSolver& solver(std::size_t k) const { return *entries_[k]->solver; }
  const StructureCoupler& coupler(std::size_t k) const { return *entries_[k]->coupler; }

  // At the end of the run: each structure's final frame, and one line per structure with its
  // steps and step, largest displacement, total reaction force and energies. Cost: O(nodes).
  void finish(std::ostream& out);

 private:
  struct Entry {
    std::string name;
    CoupledStructure structure;
    std::unique_ptr<fem::ShellSolver> solver;
    std::unique_ptr<StructureCoupler> coupler;
    std::size_t messages_printed = 0;
    std::optional<PvdSeries> series;
    std::optional<CsvTable> monitors;
    int frames = 0;
    double last_frame_time = -1.0;  // s
  };
  void write_frame(Entry& entry);
  void add_monitor_row(Entry& entry);
  std::filesystem::path output_directory_;
  double interval_ = 0.0, next_output_ = 0.0;  // s
  double monitor_interval_ = 0.0, next_monitor_ = 0.0;  // s
  std::vector<std::unique_ptr<Entry>> entries_;
};

}  // namespace quarry::fsi
