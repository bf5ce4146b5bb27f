// The structure as a ParaView XML UnstructuredGrid (VTK "XML File Formats", ASCII data): the
// shells at their current nodal positions, VTK_QUAD and VTK_TRIANGLE cells in model order.
// Point data: displacement (m), velocity (m/s), load (N, the coupled nodal forces); cell data:
// von Mises stress at the top, middle and bottom points (Pa) and the largest effective plastic
// strain (1). Written by the deck's structures at the run's output times (structure_run.h).
#pragma once

#include <span>
#include <string>

#include "fem/shell_solver.h"

namespace quarry::fsi {

// Pre: `initial` is the model `solver` was made from; `loads` has one entry per node or is
// empty (zeros written). Cost: O(nodes + elements), about 200 bytes per node.
std::string structure_vtu(const fem::ShellSolver& solver, const fem::ShellModel& initial,
                          std::span<const fem::NodalLoad> loads);

}  // namespace quarry::fsi
