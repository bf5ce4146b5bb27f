// Fluid monitors of a CFD-DEM run (issue #18 §5): the pressure drop between two planes (a bed's
// pressure drop against Ergun or its weight), the flow rate through a plane (superficial
// velocity), the particles' mean slip velocity; a row in fluid_monitors.csv with each monitor row
// of the run, plots at the end. docs/deck.md "fluid", docs/cfd.md "Monitors".
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "cfdem/fluid_coupling.h"
#include "core/fluid_spec.h"
#include "io/csv_table.h"

namespace quarry::cfdem {

// Mean pressure (Pa) over the plane x_axis = coordinate (m) across the whole grid: per column of
// cells along the axis, linear in the two cell centres that bracket the plane (extrapolated
// linearly from the first or last two in the half cells at the grid's ends, exact for a
// hydrostatic field), then the mean over the columns (equal cells: equal areas) whose two cells
// are fluid (not blocked); NaN when the plane has no such column.
double plane_pressure(const cfd::FluidSolver& fluid, int axis, double coordinate);

// Volumetric flow rate of fluid (m³/s) through the face layer nearest to x_axis = coordinate:
// Σ ε_f u_n A over its faces, ε_f the mean of the two cells' void fraction (one cell on the
// grid's border), u_n the interstitial face velocity: positive along +axis. Divided by the
// plane's area it is the superficial velocity.
double flow_rate(const cfd::FluidSolver& fluid, const std::vector<double>& void_fraction, int axis,
                 double coordinate);

// The area of a plane normal to `axis` across the grid (m²).
double plane_area(const cfd::FluidGrid& grid, int axis);

// Mean over the particles of u_p − v_p (m/s): u_p the fluid velocity the coupling froze at the
// particle at its last exchange, v_p the particle's velocity now. Particles the coupling has not
// seen yet (added since the exchange) are left out; none → zero.
Vec3 mean_slip_velocity(const FluidCoupling& coupling, const World& world);

class FluidMonitors {
 public:
  // The table's columns for these monitors: time_s, then per monitor
  //   pressure_drop: NAME_dp_Pa (p_from − p_to), NAME_dp_dynamic_Pa (less the hydrostatic
  //                  head ρ_f g·(x_from − x_to): what drag and the particles' weight hold up);
  //   flow_rate:     NAME_Q_m3_s, NAME_U_m_s (superficial velocity Q / A);
  //   slip_velocity: NAME_slip_x_m_s, NAME_slip_y_m_s, NAME_slip_z_m_s.
  static std::vector<std::string> columns(const std::vector<FluidMonitorSpec>& monitors);

  // The values of one row at the world's time (the same order as columns()).
  static std::vector<double> row(const std::vector<FluidMonitorSpec>& monitors, const FluidCoupling& coupling,
                                 const World& world);

  // Adds an end_of_step hook writing a row every Output::monitor_every() steps (and at the
  // first step) to OUTPUT/fluid_monitors.csv, and an end_of_run hook calling finish(); null
  // when `monitors` is empty. Nothing is written while the world has no output. The checkpoint
  // section "fluid monitors" holds how many rows the table had (a checkpoint also writes them
  // to the file): a restart keeps those rows of the file and appends, as monitors.csv does.
  static std::shared_ptr<FluidMonitors> attach(World& world, std::shared_ptr<FluidCoupling> coupling,
                                               std::vector<FluidMonitorSpec> monitors);

  // A last row at the world's time, flushes the table and draws fluid_pressure_drop.png, fluid_flow_rate.png and
  // fluid_slip_velocity.png for the monitors of each kind (when the run wrote rows).
  void finish(World& world);

 private:
  void record(World& world);
  // After a restart, before the first row: the table as the checkpoint left it.
  void resume_table(World& world);

  // Restored from a checkpoint taken at `time` (s), when the table held `rows` rows (none: no
  // table yet).
  struct Resume {
    double time = 0.0;
    std::optional<std::uint64_t> rows;
  };

  std::shared_ptr<FluidCoupling> coupling_;
  std::vector<FluidMonitorSpec> monitors_;
  std::optional<CsvTable> table_;
  std::optional<Resume> resume_;
};

}  // namespace quarry::cfdem
