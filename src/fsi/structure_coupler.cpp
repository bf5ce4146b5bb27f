// The two-way DEM ↔ shell coupling loop (structure_coupler.h).
#include "fsi/structure_coupler.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "sim/step.h"

namespace quarry::fsi {

StructureCoupler::StructureCoupler(World& world, std::size_t surface, fem::ShellSolver& solver,
                                   std::vector<std::int32_t> node_of_vertex, CouplerOptions options)
    : world_(world),
      surface_(surface),
      side_(solver, std::move(node_of_vertex), options.structure_step_fraction, options.schedule) {
  WorldSurface& s = world_.surfaces.at(surface_);
  if (s.driver.kind != SurfaceDriverKind::coupled)
    throw std::invalid_argument("surface '" + s.mesh.name + "' is not coupled");
  if (side_.node_of_vertex().size() != s.mesh.vertex_count())
    throw std::invalid_argument(fmt::format("surface '{}' has {} vertices, the coupling names {} nodes",
                                            s.mesh.name, s.mesh.vertex_count(), side_.node_of_vertex().size()));
  if (options.resume) return;  // the surface as the checkpoint left it; set_state follows
  // The sync at t = 0: the surface where the structure is; its window starts empty.
  std::vector<Vec3> x, v;
  side_.surface_nodes(world_.time, x, v);
  sim::set_surface_vertices(world_, surface_, x, v);
  s.coupling_window = LoadWindow(s.mesh, s.element_of_triangle, s.element_count);
  side_.begin_period(world_.dt);
}

void StructureCoupler::advance_period() {
  do {
    sim::step(world_);
  } while (!after_dem_step());
}

void StructureCoupler::advance_to(double time) {
  while (world_.time < time - 1e-6 * world_.dt) advance_period();
}

bool StructureCoupler::after_dem_step() {
  // 1. The structure up to the DEM's time, not past its sync point.
  side_.keep_up(world_.time, world_.dt);
  // 2. The DEM at its sync point: the structure finishes its period, then 3. the exchange.
  if (!side_.schedule().reached(world_.time, world_.dt)) return false;
  side_.finish_period(world_.dt);
  exchange();
  check_period_stability();
  side_.begin_period(world_.dt);
  return true;
}

StepHook StructureCoupler::step_hook() {
  return {HookStage::end_of_step, "structure coupling", [this](World&) { after_dem_step(); }};
}

// 3. Exchange at the sync point, in the terms of the C ABI (structure_side.h).
void StructureCoupler::exchange() {
  WorldSurface& s = world_.surfaces[surface_];
  // DEM → structure: this period's window means (impulse / duration, and the duration), as
  // quarry_get_surface_loads hands them to a partner; the window restarts.
  s.coupling_window.take_means(s.mesh, world_.time, means_);
  side_.receive(means_.nodal_force, means_.duration);
  // Structure → DEM: nodal positions at the DEM's time, and velocities.
  std::vector<Vec3> x, v;
  side_.surface_nodes(world_.time, x, v);
  sim::set_surface_vertices(world_, surface_, x, v);
  side_.synchronised();
}

// Research notes §1.3: a force held for a period P on a particle–node pair (a two-mass spring
// of Hertz tangent stiffness S_n) is stable only for P < 2/ω, ω = √(S_n / m*), 1/m* = 1/m_p +
// 1/m_node. S_n = 2E*√(R δ) (DESIGN §4) at the Hertz impact overlap for the deck's impact speed V
// (1 m/s if not given): δ = (15 m* V² / (16 E* √R))^(2/5) (Johnson, Contact Mechanics, §11.4).
// The smallest particle and the lightest coupled node give the largest ω. Warned once, with the
// research note's margin P ≤ 0.2 · 2/ω.
void StructureCoupler::check_period_stability() {
  if (stability_checked_ || world_.particles.size() == 0) return;
  stability_checked_ = true;
  const ParticleStore& p = world_.particles;
  std::size_t smallest = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (p.radius[i] < p.radius[smallest]) smallest = i;
  double node_mass = 1e300;  // kg
  for (std::int32_t n : side_.node_of_vertex())
    node_mass = std::min(node_mass, side_.solver().nodal_masses()[static_cast<std::size_t>(n)]);
  const MaterialSpec& particle_material = world_.spec.materials.at(p.material[smallest]);
  const MaterialSpec& wall_material = world_.spec.materials.at(world_.surfaces[surface_].mesh.material);
  const auto compliance = [](const MaterialSpec& m) {
    return (1.0 - m.poisson_ratio.value * m.poisson_ratio.value) / m.youngs_modulus.value;
  };
  const double effective_modulus = 1.0 / (compliance(particle_material) + compliance(wall_material));  // Pa
  const double radius = p.radius[smallest];                                                          // m
  const double effective_mass = 1.0 / (p.inv_mass[smallest] + 1.0 / node_mass);                     // kg
  const double speed = world_.spec.simulation.impact_speed ? world_.spec.simulation.impact_speed->value : 1.0;
  const double overlap = std::pow(15.0 * effective_mass * speed * speed / (16.0 * effective_modulus * std::sqrt(radius)), 0.4);
  const double stiffness = 2.0 * effective_modulus * std::sqrt(radius * overlap);  // N/m
  const double limit = 2.0 / std::sqrt(stiffness / effective_mass);                 // s
  const CouplingSchedule& schedule = side_.schedule();
  if (schedule.period() > 0.2 * limit)
    side_.add_message(fmt::format(
        "warning: coupling PERIOD {:.4g} s is long for the contact stiffness: a particle of radius {:.4g} m on "
        "a node of {:.4g} kg (S_n {:.4g} N/m at {:.3g} m/s) is stable only for PERIOD < 2/ω = {:.4g} s; "
        "use PERIOD ≤ {:.4g} s (research notes §1.3)",
        schedule.period(), radius, node_mass, stiffness, speed, limit, 0.2 * limit));
}

CouplerState StructureCoupler::state() const {
  CouplerState s = side_.state();
  s.stability_checked = stability_checked_;
  return s;
}

void StructureCoupler::check_state(const CouplerState& s) const { side_.check_state(s); }

void StructureCoupler::set_state(CouplerState s) {
  const bool checked = s.stability_checked;
  side_.set_state(std::move(s));
  stability_checked_ = checked;
}

Vec3 StructureCoupler::impulse_in_transit() const {
  Vec3 sum = side_.pending_impulse();  // N·s
  for (const Vec3& j : world_.surfaces[surface_].coupling_window.nodal_impulse) sum += j;
  return sum;
}

}  // namespace quarry::fsi
