// Monitors: one CSV row of global quantities per monitor interval (time, particle count,
// kinetic energy, mean velocity, contact count, force and torque on each surface, then the
// deck's monitors: region mass, particle, mass flow, region stress), and the PNG plots.
#pragma once

#include <string>
#include <vector>

#include "sim/world.h"

namespace quarry::sim {

// Columns and one row of the monitors; the first `surface_count` surfaces (those that existed
// when the output began) have columns, then every monitor of the deck its own (sensor_columns).
// A row advances the mass-flow monitors' state (world.plane_crossings): take one per monitor
// interval. Cost: O(particles + contacts).
std::vector<std::string> monitor_columns(const World& world, std::size_t surface_count);
std::vector<double> monitor_row(World& world, std::size_t surface_count);
// PNG plots next to the CSV: force on each surface, mean particle speed, particle count and
// kinetic energy against time.
// Returns the files written (names in `directory`).
std::vector<std::string> write_monitor_plots(const std::string& directory, const std::vector<std::string>& columns,
                                             const std::vector<std::vector<double>>& rows);

}  // namespace quarry::sim
