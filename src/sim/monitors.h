// Monitors: one CSV row of global quantities per monitor interval (time, particle count,
// kinetic energy, mean velocity, contact count, force and torque on each surface, then the
// deck's monitors: region mass, particle, mass flow, region stress), and the PNG plots.
#pragma once

#include <string>
#include <vector>

#include "io/png_plot.h"
#include "sim/world.h"

namespace quarry::sim {

// The component along the rotation axis (through `axis_point`, along `axis_direction`) of the
// torque of a load whose torque about the origin is `torque_about_origin` (N m) and whose
// resultant is `force` (N): (T_O - p x F) . a / |a|. A surface turning about that axis (a drum)
// has a column NAME_T_axis_Nm of it: the torque its drive must supply (with the opposite sign).
double torque_about_axis(const Vec3& torque_about_origin, const Vec3& force, const Vec3& axis_point,
                         const Vec3& axis_direction);

// Columns and one row of the monitors (Tx/Ty/Tz_Nm: about the origin of the deck's frame); the
// first `surface_count` surfaces (those that existed when the output began) have columns, then
// each rotating surface its torque about its axis, then every monitor of the deck its own
// (sensor_columns). A row advances the mass-flow monitors' state (world.plane_crossings): take
// one per monitor interval. Cost: O(particles + contacts).
std::vector<std::string> monitor_columns(const World& world, std::size_t surface_count);
std::vector<double> monitor_row(World& world, std::size_t surface_count);
// After every step: the mass-flow monitors with a window (`region`) count the step's crossings
// (count_window_crossings). Cost: O(particles) per such monitor, nothing without one.
void count_flow_windows(World& world);

// Column k of a monitor table against its first column (time), labelled `label`: a series of
// the plots below, or of another monitor table's (the fluid's).
PlotSeries column_series(const std::vector<std::vector<double>>& rows, std::size_t k, const std::string& label);

// PNG plots next to the CSV: force on each surface with the weight m g of the material in each
// monitor region as a reference (`gravity`: |g|, m/s²), the torque on each rotating surface
// about its axis, mean particle speed, particle count, kinetic energy, the mass in each monitor
// region and its rate of change (the discharge rate of a hopper).
// Returns the files written (names in `directory`).
std::vector<std::string> write_monitor_plots(const std::string& directory, const std::vector<std::string>& columns,
                                             const std::vector<std::vector<double>>& rows, double gravity);

// Net outflow -dm/dt (kg/s) of a mass series m(t): central differences over +-`half_window`
// rows (one-sided at the ends), so that the particle-sized steps of m are averaged over a few
// monitor intervals. Returns one value per row (NaN where t does not advance).
std::vector<double> outflow_rate(const std::vector<double>& t, const std::vector<double>& m, std::size_t half_window);

}  // namespace quarry::sim
