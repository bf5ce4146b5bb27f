// The deck's structures in a run (issue #17 §5): each `structures:` entry's model read and
// adapted, its coupling surface added to the world as a coupled surface, a shell solver and a
// StructureCoupler made for it and hooked into the world's end-of-step stage, so that
// `quarry run` (sim::run) drives the two-way coupling with no loop of its own. Their state is
// the checkpoint section "structures" (structure_checkpoint.cpp), so that `quarry restart` and
// the C ABI continue such a run to the bit.
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
#include "sim/binary_stream.h"
#include "sim/world.h"

namespace quarry::fsi {

class CoupledStructures {
 public:
  // Pre: `world` is built (sim::build_world) and not yet initialised, or restored from a
  // checkpoint of a run with the same structures (sim::read_checkpoint): its coupling surfaces
  // are then the world's already (the checkpoint's deck lists them) and keep their state, and
  // sim::restore_sections gives the structures theirs. `world` must not move while this object
  // lives (the hooks hold it). PERIOD: the deck's, else the EDEM card's, else TTERM/100;
  // FILTER: the deck's, else the EDEM card's when PERIOD is the card's, else PERIOD.
  // Coupling messages (the cycle-2 reset, the PERIOD warning) go to `log` as they arise, and
  // finish()'s lines at the end of the run (an end_of_run hook).
  // Frames (structure_vtu.h) go to the run's output folder (World::output; none without one) as
  // structure_<name>_NNNN.vtu with a structure_<name>.pvd series, every output.interval of the
  // deck (0: only the final one, written by finish()); monitors to structure_<name>.csv every
  // output.monitor_interval (0: at the frames): time, largest displacement, total reaction,
  // total coupled load, energies. Throws UserError for a model that cannot be read or adapted,
  // at its file and card, or a structure whose name a surface of a new run's world has.
  CoupledStructures(World& world, std::ostream& log);

  std::size_t size() const { return entries_.size(); }
  const std::string& name(std::size_t k) const { return entries_[k]->name; }
  const fem::ShellSolver& solver(std::size_t k) const { return *entries_[k]->solver; }
  const StructureCoupler& coupler(std::size_t k) const { return *entries_[k]->coupler; }

  // At the end of the run (the end_of_run hook calls it; the C ABI at quarry_close): each
  // structure's final frame and monitor row (when the run has an output folder; and with
  // output.plots, structure_NAME_{displacement,reactions,energies}.png), and one line
  // per structure with its steps and step, largest displacement, total reaction force and
  // energies. Cost: O(nodes).
  void finish(std::ostream& out);

  // The checkpoint section "structures" (structure_checkpoint.cpp): every structure's solver
  // and coupler state and the output's (frame numbers, next output times, the series' entries,
  // the monitor rows). load_state checks the whole section against the structures of this deck
  // and the restored world first and throws std::runtime_error or std::invalid_argument saying
  // what is wrong, leaving every structure as it was.
  void save_state(BinaryWriter& out) const;
  void load_state(BinaryReader& in, const World& world);

 private:
  struct Entry {
    std::string name;
    CoupledStructure structure;
    std::unique_ptr<fem::ShellSolver> solver;
    std::unique_ptr<StructureCoupler> coupler;
    std::size_t messages_printed = 0;
    std::vector<std::vector<std::int32_t>> supports;  // fem::support_groups of the model
    // Output: the series and the table are made in the output folder at their first use,
    // starting with `listed` and `rows`, which then empty: a checkpoint's entries and rows (a
    // restart carries them, so its folder may be another one and still gets the whole series
    // and table).
    std::optional<PvdSeries> series;
    std::optional<CsvTable> monitors;
    std::vector<PvdEntry> listed;
    std::vector<std::vector<double>> rows;
    std::int64_t frames = 0;
    double last_frame_time = -1.0;  // s
  };
  // The monitor table's columns: the totals, then each support's reaction.
  static std::vector<std::string> monitor_columns(const Entry& entry);
  std::vector<double> monitor_row(const Entry& entry) const;
  void open_output(Entry& entry);
  void add_monitor_row(Entry& entry);
  void write_frame(Entry& entry);
  void write_plots(const Entry& entry);
  World& world_;
  std::ostream& log_;
  std::filesystem::path output_directory_;  // the run's output folder, once a step has seen it
  double interval_ = 0.0, next_output_ = 0.0;  // s
  double monitor_interval_ = 0.0, next_monitor_ = 0.0;  // s
  std::vector<std::unique_ptr<Entry>> entries_;
};

}  // namespace quarry::fsi
