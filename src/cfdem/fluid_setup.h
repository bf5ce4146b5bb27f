// The deck's `fluid:` section (SimulationSpec::fluid) made into a FluidCoupling attached to a
// built world: what `quarry run` does for a CFD-DEM deck (docs/deck.md "fluid").
#pragma once

#include <memory>

#include "cfdem/fluid_coupling.h"
#include "sim/world.h"

namespace quarry::cfdem {

// Options of the coupling from world.spec.fluid (which must be set). Loads the drag UDF.
// Throws UserError placed at the deck's keys: a fluid time step that is not an integer multiple
// of the DEM step (1e-9 relative), model B (not coupled yet), a drag UDF that does not load
// (cfd::load_drag_udf's errors), cells too small for the particles (FluidCoupling), blocked
// regions that block no cell, every cell or cut fluid off from the outlets (fluid_blocked.h).
FluidCouplingOptions coupling_options_from_spec(const World& world);

// coupling_options_from_spec, then FluidCoupling::attach, FluidMonitors::attach and attach_fluid_output (fluid.pvd
// with fluid_NNNNNN.vti at the particle frames' interval); null when the deck has no fluid.
std::shared_ptr<FluidCoupling> attach_fluid_from_spec(World& world);

}  // namespace quarry::cfdem
