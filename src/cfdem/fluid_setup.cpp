// SimulationSpec::fluid → FluidCouplingOptions (grid, properties, faces, blocked cells, drag,
// coupling steps), with the deck's locations on every error.
#include "cfdem/fluid_setup.h"

#include <fmt/format.h>

#include <cmath>

#include "cfdem/fluid_blocked.h"
#include "cfdem/fluid_monitors.h"
#include "cfdem/fluid_output.h"
#include "core/diagnostics.h"

namespace quarry::cfdem {

namespace {

cfd::BoundaryKind boundary_kind(FluidBoundaryType type) {
  switch (type) {
    case FluidBoundaryType::wall: return cfd::BoundaryKind::wall;
    case FluidBoundaryType::velocity_inlet: return cfd::BoundaryKind::velocity_inlet;
    case FluidBoundaryType::pressure_outlet: return cfd::BoundaryKind::pressure_outlet;
    case FluidBoundaryType::periodic: return cfd::BoundaryKind::periodic;
  }
  return cfd::BoundaryKind::wall;
}

}  // namespace

FluidCouplingOptions coupling_options_from_spec(const World& world) {
  const FluidSpec& spec = *world.spec.fluid;
  FluidCouplingOptions options;
  options.grid.origin = spec.origin.value;
  options.grid.cell_size = {spec.cell_size.value, spec.cell_size.value, spec.cell_size.value};
  for (int axis = 0; axis < 3; ++axis)
    options.grid.cells[static_cast<std::size_t>(axis)] = static_cast<int>(spec.cells.value[axis]);
  options.grid_where = spec.cell_size.where;
  options.properties = {spec.density.value, spec.viscosity.value};
  for (std::size_t face = 0; face < 6; ++face) {
    const FluidFaceSpec& f = spec.faces[face];
    cfd::FaceBoundary& b = options.boundaries.faces[face];
    b.kind = boundary_kind(f.type.value);
    b.velocity = f.velocity.value;
    b.reference_pressure = f.reference_pressure.value;
    b.reference_point = f.reference_point.value;
  }
  options.blocked = blocked_cells_from_spec(world, options.grid);
  check_blocked_cells(spec, options.grid, options.boundaries, options.blocked);
  options.solver.model = spec.model.value == FluidModel::b ? cfd::VolumeAveragedModel::b : cfd::VolumeAveragedModel::a;
  options.solver.advection =
      spec.advection.value == FluidAdvection::hybrid ? cfd::Advection::hybrid : cfd::Advection::central;
  // Δt_f = n Δt_DEM with n a whole number (the seed's rule: physical times must match). A DEM
  // step the deck fixed must divide the fluid's; an automatic one (a Rayleigh fraction, which
  // moves with the materials and sizes) takes the whole number of its steps at or below the
  // fluid's (at least one), so the two stay commensurate whichever the deck changes.
  const double ratio = spec.time_step.value / world.dt;
  const bool automatic = !world.spec.simulation.fixed_time_step.has_value();
  const double steps = automatic ? std::max(1.0, std::floor(ratio * (1.0 + 1e-9))) : std::round(ratio);
  if (!automatic && (steps < 1.0 || std::abs(ratio - steps) > 1e-9 * steps))
    throw UserError(spec.time_step.where,
                    fmt::format("the fluid time step {:.6g} s is not a whole multiple of the DEM time "
                                "step {:.6g} s (ratio {:.9g})",
                                spec.time_step.value, world.dt, ratio),
                    fmt::format("use {:.6g} s ({} DEM steps)", std::max(1.0, steps) * world.dt,
                                std::max(1.0, steps)));
  options.coupling_steps = static_cast<int>(steps);
  if (spec.drag_udf) {
    options.drag_udf = cfd::load_drag_udf(spec.drag_udf->library.value, spec.drag_udf->function.value,
                                          spec.drag_udf->library.where, spec.drag_udf->function.where);
  } else {
    const std::optional<cfd::DragLaw> law = cfd::drag_law_from_name(spec.drag_law.value);
    if (!law) throw UserError(spec.drag_law.where, "unknown drag law \"" + spec.drag_law.value + "\"");
    options.drag_law = *law;
  }
  return options;
}

std::shared_ptr<FluidCoupling> attach_fluid_from_spec(World& world) {
  if (!world.spec.fluid) return nullptr;
  FluidCouplingOptions options = coupling_options_from_spec(world);
  try {
    std::shared_ptr<FluidCoupling> coupling = FluidCoupling::attach(world, std::move(options));
    attach_fluid_output(world, coupling);
    FluidMonitors::attach(world, coupling, world.spec.fluid->monitors);  // kept alive by its hooks
    return coupling;
  } catch (const std::invalid_argument& e) {
    throw UserError(world.spec.fluid->where, e.what());
  }
}

}  // namespace quarry::cfdem
