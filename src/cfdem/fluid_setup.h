// The deck's `fluid:` section (SimulationSpec::fluid) made into a FluidCoupling attached to a
// built world: what `quarry run` does for a CFD-DEM deck (docs/deck.md "fluid").
#pragma once

#include <memory>

#include "cfdem/fluid_coupling.h"
#include "sim/world.h"

namespace quarry::cfdem {

// The weakest drag a built-in law gives a sphere of diameter d, over every slip and every void
// fraction ε ≥ minimum_void_fraction, as a multiple of Stokes' 3πμd: Di Felice's tends to 0.96
// of it as Re → 0 at ε = 1 (C_d → 4.8²/Re = 23.04/Re); the seed's Stokes law carries the factor
// ε; Schiller-Naumann, Gidaspow, Koch-Hill and Beetstra are Stokes' or more (each is Stokes at
// ε = 1 and Re → 0 and grows with Re and with the solid fraction; cfd/drag_laws.h).
double weakest_drag_factor(cfd::DragLaw law, double minimum_void_fraction);

// Options of the coupling from world.spec.fluid (which must be set). Loads the drag UDF.
// Throws UserError placed at the deck's keys: a fluid time step that is not an integer multiple
// of the DEM step (1e-9 relative), model B (not coupled yet), a drag UDF that does not load
// (cfd::load_drag_udf's errors), cells too small for the particles (FluidCoupling), blocked
// regions that block no cell, every cell or cut fluid off from the outlets (fluid_blocked.h), a
// viscosity at which even weakest_drag_factor's drag gives the deck's smallest moving particle a
// relaxation time m/β below the DEM step (the run would stop at its first step: explicit drag).
FluidCouplingOptions coupling_options_from_spec(const World& world);

// coupling_options_from_spec, then FluidCoupling::attach, FluidMonitors::attach and attach_fluid_output (fluid.pvd
// with fluid_NNNNNN.vti at the particle frames' interval); null when the deck has no fluid.
std::shared_ptr<FluidCoupling> attach_fluid_from_spec(World& world);

}  // namespace quarry::cfdem
