// The deck's structures in a run (issue #17 §5): each `structures:` entry's model read and
// adapted, its coupling surface added to the world as a coupled surface, a shell solver and a
// StructureCoupler made for it and hooked into the world's end-of-step stage, so that
// `quarry run` (sim::run) drives the two-way coupling with no loop of its own.
#pragma once

#include <iosfwd>
#include <memory>
#include <vector>

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
  // Throws UserError for a model that cannot be read or adapted, at its file and card.
  CoupledStructures(World& world, std::ostream& log);

  std::size_t size() const { return entries_.size(); }
  const fem::ShellSolver& solver(std::size_t k) const { return *entries_[k]->solver; }
  const StructureCoupler& coupler(std::size_t k) const { return *entries_[k]->coupler; }

  // One line per structure: its steps and step, added mass, largest displacement, total
  // reaction force and energies. Cost: O(nodes).
  void print_summary(std::ostream& out) const;

 private:
  struct Entry {
    std::string name;
    CoupledStructure structure;
    std::unique_ptr<fem::ShellSolver> solver;
    std::unique_ptr<StructureCoupler> coupler;
    std::size_t messages_printed = 0;
  };
  std::vector<std::unique_ptr<Entry>> entries_;
};

}  // namespace quarry::fsi
