// The structure's half of the EDEM card's exchange (structure_coupler.h): the shell solver's
// periods between sync points, FILTER over the nodal forces the DEM hands over, and the nodal
// positions and velocities that go back. No DEM in here: the built-in coupler
// (StructureCoupler) drives it with a World, an external partner with the C ABI
// (tests/fsi_partner/shell_partner.cpp, docs/fem.md "Coupling an external FEM code"). Both give
// it the same numbers, the window-mean nodal forces and the window's length that
// quarry_get_surface_loads returns, so the two paths take the same steps to the bit.
#pragma once

#include <cmath>
#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "fem/shell_solver.h"
#include "fsi/coupling_schedule.h"
#include "fsi/force_filter.h"

namespace quarry::fsi {

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
  bool stability_checked = false;  // StructureCoupler's; StructureSide passes it through
  std::vector<std::string> messages;
};

class StructureSide {
 public:
  // `solver` must outlive this; coupling-surface vertex k is solver node node_of_vertex[k]
  // (fsi::coupling_mesh). `step_fraction`: the structure's step as a fraction of its stable
  // estimate. Throws std::invalid_argument for a node that is not the solver's.
  StructureSide(fem::ShellSolver& solver, std::vector<std::int32_t> node_of_vertex, double step_fraction,
                ScheduleSettings schedule);

  // Structure → DEM: the coupled nodes' positions (m) at the DEM's time `dem_time` (s) — the
  // structure's own, advanced by v·(dem_time − t_structure), the motion the DEM surface follows
  // anyway — and velocities (m/s), per surface vertex: what quarry_set_surface_nodes takes.
  void surface_nodes(double dem_time, std::vector<Vec3>& positions, std::vector<Vec3>& velocities) const;

  // A structure period at a constant step, loaded by the last exchange's impulse J spread evenly
  // over it: loads = J / (n·dt) for its n steps, Σ = J. `dem_dt`: the DEM's step (s), for the
  // cycle-2 reset.
  void begin_period(double dem_dt);
  bool at_sync() const { return period_steps_done_ == period_steps_; }
  // The structure's share of its period for the DEM step that ends at `dem_time` (s), of
  // `dem_dt` (the built-in coupler at each DEM step): the steps left to its sync point spread
  // evenly over the DEM steps left to the DEM's, this one included; at the DEM's sync step, all.
  // Called again for the same DEM time (the end-of-step hook after the alongside one): nothing.
  void keep_up(double dem_time, double dem_dt);
  // Steps the structure to its sync point.
  void finish_period(double dem_dt);

  // DEM → structure at the exchange: the window-mean nodal forces (N, per surface vertex) over
  // `window` (s), as quarry_get_surface_loads gives them. Their impulses F·window go through
  // FILTER; the next period applies the filtered mean force × window (= the impulse when
  // FILTER = PERIOD). Throws std::invalid_argument for a size that is not the vertex count.
  void receive(std::span<const Vec3> mean_force, double window);
  // Both solvers are at the sync point and have exchanged: the next request is set.
  void synchronised() { schedule_.synchronised(); }

  // The solver's team from now on (the world's, which the thread governor may change).
  void set_threading(const Threading& threading) { solver_.set_threading(threading); }
  const CouplingSchedule& schedule() const { return schedule_; }
  const std::vector<fem::NodalLoad>& loads() const { return loads_; }  // N per node, this period
  double structure_step() const { return structure_dt_; }             // s, of this period
  std::int64_t structure_steps() const { return structure_steps_; }
  const std::vector<std::int32_t>& node_of_vertex() const { return node_of_vertex_; }
  const fem::ShellSolver& solver() const { return solver_; }
  // Lines to print (the cycle-2 reset; the built-in coupler adds its PERIOD warning).
  const std::vector<std::string>& messages() const { return messages_; }
  void add_message(std::string line) { messages_.push_back(std::move(line)); }
  // The impulse (N·s, summed over nodes) received but not yet applied to the structure.
  Vec3 pending_impulse() const;

  // The state (stability_checked false); check_state throws std::invalid_argument naming what
  // does not fit this structure or is not finite; set_state checks, then takes it.
  CouplerState state() const;
  void check_state(const CouplerState& state) const;
  void set_state(CouplerState state);

 private:
  void step(double dem_dt);

  fem::ShellSolver& solver_;
  std::vector<std::int32_t> node_of_vertex_;
  double step_fraction_;
  CouplingSchedule schedule_;
  ForceFilter filter_;
  // N·s per vertex, for the structure's next period; zero once that period has applied it.
  std::vector<Vec3> pending_impulse_;
  std::vector<Vec3> impulse_, filtered_force_;  // N·s and N per vertex, scratch
  std::vector<fem::NodalLoad> loads_;           // per solver node
  double structure_dt_ = 0.0;                   // s
  std::int64_t period_steps_ = 0, period_steps_done_ = 0;  // this period's
  std::int64_t structure_steps_ = 0;
  std::vector<std::string> messages_;
  // s, the DEM time keep_up last stepped for; no part of the state (set_state clears it): the
  // first call after a restart is for a later DEM time in either case.
  double paced_to_ = -INFINITY;
};

}  // namespace quarry::fsi
