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
// (after_dem_step: the run loop's end-of-step hook), during it on a thread of its own
// (keep_up: an alongside hook) or a period at a time (advance_period): the results are the
// same.
// Nodal forces are the DEM load window's consistent nodal forces: each contact force split to
// its triangle's three vertices by the barycentric weights of the contact point, which keeps the
// force and its moment about any point (Σ λ_i F = F, Σ x_i × λ_i F = p × F); a quad's two
// triangles share its four nodes. Moments at the nodes are not sent (the contact torques and the
// shell offset of the contact point are ignored).
// With FILTER = PERIOD the structure receives each period's impulse: the loads are the impulse
// divided by the length of the structure's next period (a whole number of its steps).
// The structure's half (its periods, FILTER, the nodes it sends) is StructureSide, which an
// external partner drives through the C ABI: the DEM's load window goes to it as the window
// mean and length quarry_get_surface_loads returns (impulse J/d, then ×d again: J to within
// an ulp), so that the built-in path and such a partner take the same steps to the bit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fem/shell_solver.h"
#include "fsi/coupling_schedule.h"
#include "fsi/structure_side.h"
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
  // The structure's part of a DEM step that needs nothing from it: up to the DEM's time (the
  // step's end), not past its sync point, on `threading`'s team. A HookStage::alongside hook
  // calls it, so that the structure runs on its own thread while the DEM steps
  // (sim/step.cpp); after_dem_step then finds it there. The same steps either way.
  void keep_up(double dem_time, double dem_dt, const Threading& threading);
  // Periods until the DEM's time reaches `time` (s).
  void advance_to(double time);

  const CouplingSchedule& schedule() const { return side_.schedule(); }
  // The PERIOD (s) the schedule holds after the cycle-2 reset (now, or as it will be made with
  // the solvers' present steps): max(DT_user, 2·dt_structure, 2·dt_dem).
  double period_after_reset() const;
  // The stability checks of the exchange at `period` (s) (period_stability.h; docs/fem.md
  // "Stability of PERIOD", "Damping the structure"), for the particles each of the deck's types
  // can be: the warning lines, none when both pass. The coupler gives them once, after its
  // first period with particles; `quarry check` before a run.
  std::vector<std::string> stability_warnings(double period) const;
  // Lines to print: the cycle-2 reset, the PERIOD stability warning (each once).
  const std::vector<std::string>& messages() const { return side_.messages(); }
  // The impulse (N·s, summed over nodes) the exchange holds: given by the particles but not yet
  // applied to the structure. Particles + structure + this is conserved (gravity off, free
  // structure) with FILTER = PERIOD.
  Vec3 impulse_in_transit() const;
  // The nodal loads (N) of the structure's current period (set at the last exchange).
  const std::vector<fem::NodalLoad>& loads() const { return side_.loads(); }
  double structure_step() const { return side_.structure_step(); }  // s, of the last period
  std::int64_t structure_steps() const { return side_.structure_steps(); }

  CouplerState state() const;
  // Checks every size against the surface and the solver and every value, then takes the
  // state; throws std::invalid_argument naming what is wrong before it changes anything.
  void set_state(CouplerState state);
  void check_state(const CouplerState& state) const;  // set_state's checks alone
  std::size_t surface() const { return surface_; }  // the world's coupled surface

 private:
  void exchange();
  void check_period_stability();

  World& world_;
  std::size_t surface_;
  StructureSide side_;
  LoadFrame means_;  // scratch: the window's means at the exchange
  bool stability_checked_ = false;
};

}  // namespace quarry::fsi
