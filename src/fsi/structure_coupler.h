// Two-way coupling of a DEM world and the built-in shell solver (issue #17 §3), with the EDEM
// card's schedule (coupling_schedule.h). Each solver keeps its own step: the structure steps at
// a fraction of its stable estimate, the DEM at its own dt. One coupling period reads top to
// bottom in advance_period():
//   1. the structure steps to its sync point (its first step at or after the request), loaded
//      by the nodal forces of the previous exchange;
//   2. the DEM steps to its sync point; its coupled surface moves on from the last nodal
//      positions with the nodal velocities (no jumps) and collects the impulses of its loads;
//   3. exchange: the structure's nodal positions (advanced by v·(t_dem − t_fem) to the DEM's
//      time) and velocities go to the DEM surface; the DEM's per-node impulses, filtered over
//      FILTER, go back as the load of the next period.
// Nodal forces are the DEM load window's consistent nodal forces: each contact force split to
// its triangle's three vertices by the barycentric weights of the contact point, which keeps the
// force and its moment about any point (Σ λ_i F = F, Σ x_i × λ_i F = p × F); a quad's two
// triangles share its four nodes. Moments at the nodes are not sent (the contact torques and the
// shell offset of the contact point are ignored).
// With FILTER = PERIOD the structure receives each period's impulse exactly: the loads are the
// impulse divided by the length of the structure's next period (a whole number of its steps).
#pragma once

#include <cstdint>
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
  // Periods until the DEM's time reaches `time` (s).
  void advance_to(double time);

  const CouplingSchedule& schedule() const { return schedule_; }
  // Lines to print: the cycle-2 reset, the PERIOD stability warning (each once).
  const std::vector<std::string>& messages() const { return messages_; }
  // The impulse (N·s, summed over nodes) the exchange holds: given by the particles but not yet
  // applied to the structure. Particles + structure + this is conserved (gravity off, free
  // structure) with FILTER = PERIOD.
  Vec3 impulse_in_transit() const;
  // The nodal loads (N) the structure carries in the current period.
  const std::vector<fem::NodalLoad>& loads() const { return loads_; }
  double structure_step() const { return structure_dt_; }  // s, of the last period
  std::int64_t structure_steps() const { return structure_steps_; }

 private:
  void advance_structure();
  void advance_dem();
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
  std::int64_t structure_steps_ = 0;
  bool stability_checked_ = false;
  std::vector<std::string> messages_;
};

}  // namespace quarry::fsi
