// Monitors: one CSV row of global quantities per monitor interval (time, particle count,
// kinetic energy, mean velocity, contact count, force and torque on each surface, mass inside
// each monitor region), and the PNG plots drawn from them.
#pragma once

#include <string>
#include <vector>

#include "sim/world.h"

namespace quarry::sim {

std::vector<std::string> monitor_columns(const World& world);
std::vector<double> monitor_row(const World& world);
// PNG plots next to the CSV: force on each surface, mean particle speed, particle count and
// kinetic energy against time.
void write_monitor_plots(const std::string& directory, const std::vector<std::string>& columns,
                         const std::vector<std::vector<double>>& rows);

}  // namespace quarry::sim
