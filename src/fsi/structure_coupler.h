// Two-way coupling of a DEM world and the built-in shell solver (issue #17 §3), with the EDEM
// card's schedule (coupling_schedule.h). Each solver keeps its own step: the structure steps at
// a fraction of its stable estimate, the DEM at its own dt. One coupling period:
//   1. the structure steps towards its sync point (its first step at or after the request),
//      loaded by the nodal forces of the previous exchange, keeping up with the DEM's time;
//   2. the DEM steps to its sync point; its coupled surface moves on from the last nodal
//      positions with the nodal velocities (no jumps) and collects the impulses of its loads;
//   3. exchange, once both are at their sync points: the structure's nodal positions (advanced
//      by v·(t_dem − t_fem) to the DEM's time) and velocities go to the DEM surface; the DEM's
//      per-node impulses, filtered over FILTER, go back as the load of the next period.
// Between syncs neither solver sees the other, so the structure may run after each DEM step
// (after_dem_step: the run loop's end-of-step hook) or a period at a time (advance_period):
// the results are the same.
// Nodal forces are the DEM load window's consistent nodal forces: each contact force split to
// its triangle's three vertices by the barycentric weights of the contact point, which keeps the
// force and its moment about any point (Σ λ_i F = F, Σ x_i × λ_i F = p × F); a quad's two
// triangles share its four nodes. Moments at the nodes are not sent (the contact torques and the
// shell offset of the contact point are ignored).
// With FILTER = PERIOD the structure receives each period's impulse exactly: the loads are the
// impulse divided by the length of the structure's next period (a whole number of its steps).
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "fem/shell_solver.h"
#include "fsi/coupling_schedule.h"
#include "fsi/force_filter.h"
#include "sim/world.h"

namespace quarry::fsi {

struct CouplerOptions {
  ScheduleSettings schedule;
  // The structure's step as a fraction of its stable estimate (fem::ShellSolver: 0.9 on regular
  // meshes as LS-DYNA and Radioss, 0.8 on irregular ones).
  double structure_step_fraction = 0.9;
  // The world comes from a checkpoint: its surface and load window hold the coupled state the
  // run left, which the constructor then leaves alone (no sync at t = 0); set_state gives the
  // coupler its own state next.
  bool resume = false;
};

// What a coupler holds between steps (checkpoints: structure_checkpoint.cpp), besides the
// solver's state and the world's surface.
struct CouplerState {
  ScheduleState schedule;
  double filter_window = 0.0;  // s
  std::deque<ForceFilter::Period> filter_periods;
  std::vector<Vec3> pending_impulse;  // N·s per surface vertex
  std::vector<fem::NodalLoad> loads;  // per solver node
  double structure_dt = 0.0;          // s
  std::int64_t period_steps = 0, period_steps_done = 0, structure_steps = 0;
  bool stability_checked = false;
  std::vector<std::string> messages;
};

class StructureCoupler {
 public:
  // `world`: built and initialised; `surface` its coupled surface whose vertex k is solver node
  // node_of_vertex[k] (fsi::coupling_mesh). Sets the surface to the structure's state now
  // (the sync at t = 0) and starts its load window. The world and solver must outlive the
  // coupler. Throws std::invalid_argument if the surface is not coupled or sizes differ.
  StructureCoupler(World& world, std::size_t surface, fem::ShellSolver& solver,
                   std::vector<std::int32_t> node_of_vertex, CouplerOptions options);

  // One coupling period: both solvers to their next sync point, then the exchange.
  void advance_period();
  // To run after every DEM step (sim::step's end-of-step hooks): the structure keeps up with
  // the DEM's time, never past its own sync point; at the DEM's sync point the structure
  // finishes its period and they exchange. Returns whether an exchange took place.
  bool after_dem_step();
  // The hook that calls after_dem_step, for World::hooks (the coupler must outlive the world's
  // use of it).
  StepHook step_hook();
  // Periods until the DEM's time reaches `time` (s).
  void advance_to(double time);

  const CouplingSchedule& schedule() const { return schedule_; }
  // Lines to print: the cycle-2 reset, the PERIOD stability warning (each once).
  const std::vector<std::string>& messages() const { return messages_; }
  // The impulse (N·s, summed over nodes) the exchange holds: given by the particles but not yet
  // applied to the structure. Particles + structure + this is conserved (gravity off, free
  // structure) with FILTER = PERIOD.
  Vec3 impulse_in_transit() const;
  // The nodal loads (N) of the structure's current period (set at the last exchange).
  const std::vector<fem::NodalLoad>& loads() const { return loads_; }
  double structure_step() const { return structure_dt_; }  // s, of the last period
  std::int64_t structure_steps() const { return structure_steps_; }

  CouplerState state() const;
  // Checks every size against the surface and the solver and every value, then takes the
  // state; throws std::invalid_argument naming what is wrong before it changes anything.
  void set_state(CouplerState state);
  void check_state(const CouplerState& state) const;  // set_state's checks alone
  std::size_t surface() const { return surface_; }  // the world's coupled surface

 private:
  void begin_structure_period();
  void step_structure();
  bool structure_at_sync() const { return period_steps_done_ == period_steps_; }
  void exchange();
  void check_period_stability();

  World& world_;
  std::size_t surface_;
  fem::ShellSolver& solver_;
  std::vector<std::int32_t> node_of_vertex_;
  CouplerOptions options_;
  CouplingSchedule schedule_;
  ForceFilter filter_;
  // N·s per vertex, for the structure's next period; zero once that period has applied it.
  std::vector<Vec3> pending_impulse_;
  std::vector<Vec3> filtered_force_;      // N per vertex, scratch
  std::vector<fem::NodalLoad> loads_;     // per solver node
  double structure_dt_ = 0.0;
  std::int64_t period_steps_ = 0, period_steps_done_ = 0;  // the structure's, this period
  std::int64_t structure_steps_ = 0;
  bool stability_checked_ = false;
  std::vector<std::string> messages_;
};

}  // namespace quarry::fsi
