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

// The particle side's drag is explicit in v (FluidCoupling::check_relaxation): a particle whose
// relaxation time m/β_p is shorter than the DEM step stops the run. Where even the weakest drag
// the law can give the smallest particle, m/β_min = ρ_p d²/(18 c μ), is that short, every step
// would: the deck is refused here, at its viscosity, before the run.
void check_drag_relaxation(const World& world, const FluidSpec& spec, cfd::DragLaw law,
                           double minimum_void_fraction) {
  const SimulationSpec& deck = world.spec;
  const double factor = weakest_drag_factor(law, minimum_void_fraction);
  const double mu = spec.viscosity.value;  // Pa·s
  double longest = INFINITY;               // s, the smallest particle's longest relaxation time
  std::string which;
  // A particle of type t and diameter d (m) that the deck inserts; the world's types carry
  // the densities, the fixed flags and the size samplers.
  const auto consider = [&](std::size_t t, double d) {
    const ParticleTypeInfo& type = world.types[t];
    if (type.fixed || !(type.density > 0.0)) return;  // fixed: not integrated
    const double tau = type.density * d * d / (18.0 * factor * mu);
    if (tau >= longest) return;
    longest = tau;
    which = fmt::format("'{}' (d = {:.4g} mm, ρ = {:.4g} kg/m³)", world.type_names[t], d * 1e3,
                        type.density);
  };
  const auto smallest = [&](std::size_t t) { return 2.0 * world.size_samplers[t].min_radius(); };
  for (const FactorySpec& factory : deck.factories)
    for (std::size_t t = 0; t < world.types.size(); ++t)
      if (world.type_names[t] == factory.particle_type.value) consider(t, smallest(t));
  for (const InitialParticle& p : deck.initial_particles)
    if (p.type < world.types.size())
      consider(p.type, p.radius > 0.0 ? 2.0 * p.radius : smallest(p.type));
  if (!(longest < world.dt)) return;
  throw UserError(spec.viscosity.where,
                  fmt::format("with viscosity {:.4g} Pa·s the smallest particle of type {} has a "
                              "drag relaxation time of at most m/β = {:.3g} s under the {} drag "
                              "law (at any slip and void fraction), below the DEM time step "
                              "{:.3g} s: the drag would overshoot at every step",
                              mu, which, longest, spec.drag_law.value, world.dt),
                  fmt::format("the viscosity is dynamic, in Pa·s (water 0.001, air 1.8e-5); a "
                              "DEM time step below {:.3g} s would take it",
                              longest));
}

}  // namespace

double weakest_drag_factor(cfd::DragLaw law, double minimum_void_fraction) {
  switch (law) {
    case cfd::DragLaw::stokes: return minimum_void_fraction;  // the seed's factor ε
    case cfd::DragLaw::di_felice: return 23.04 / 24.0;        // C_d → 4.8²/Re as Re → 0
    default: return 1.0;
  }
}

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
    check_drag_relaxation(world, spec, *law, options.minimum_void_fraction);
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
