// The two-way DEM ↔ shell coupling loop (structure_coupler.h).
#include "fsi/structure_coupler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "contact/normal_hertz.h"
#include "core/sphere.h"
#include "fsi/period_stability.h"
#include "integrate/timestep.h"
#include "insert/size_distribution.h"
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
  side_.set_threading(world_.threading);  // for the next period: the governor's team now
  side_.finish_period(world_.dt);
  exchange();
  check_period_stability();
  side_.begin_period(world_.dt);
  return true;
}

void StructureCoupler::keep_up(double dem_time, double dem_dt, const Threading& threading) {
  side_.set_threading(threading);
  side_.keep_up(dem_time, dem_dt);
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

// The exchange lags the node's force by a period (the mean over period k acts during k + 1) and
// the surface's velocity by up to one: a particle on a node is a two-mass oscillator, ω =
// √(S_n/m*), 1/m* = 1/m_p + 1/m_node, whose lag acts as a negative damping of about
// S_n·P·m_p/(m_p + m_node) against the contact's dashpot. The per-period map's stability
// (period_stability.h; docs/fem.md "Stability of PERIOD") gives the limit ω·P_crit(ζ, m_node/m_p).
// S_n: Hertz tangent stiffness 2E*√(R δ) (DESIGN §4) at the impact overlap for the deck's impact
// speed V (1 m/s if not given), δ = (15 m* V² / (16 E* √R))^(2/5) (Johnson, Contact Mechanics,
// §11.4); the linear law's k. ζ: the DEM's dashpot against a wall, c/(2√(S_n m_p)) = √(5/6)|β|
// for Hertz–Mindlin (c = −2√(5/6) β √(S_n m_p)), |β| for the linear law. The smallest particle
// and the lightest coupled node that can move give the largest ω, the largest particle the
// smallest m_node/m_p: the shorter of their limits counts. The particles: the smallest and the
// largest each particle type can have (those a factory inserts later too). The ratio is taken
// at most 1: a node heavier than one particle is, under a bed, loaded by the column above it
// through several contacts, and a bed of 1.8–2.2 mm beads on a clamped plate
// (tests/fsi/plate_bed.yaml without mass scaling, ratio 7 for one bead, where the model is
// stable at any PERIOD) grew at ω·P ≈ 1.1 (at ratio 1 and e = 0.3 the limit is 0.94).
// Warned once, above half the limit: S_n, the overlap and the ratio are estimates (ω·P_crit
// 0.70 at m_node/m_p = 0.48, 0.60 at 0.23, 0.49 at 0.1 for e = 0.4).
void StructureCoupler::check_period_stability() {
  // After the cycle-2 reset: a PERIOD below twice a solver's step is raised there.
  if (stability_checked_ || world_.particles.size() == 0 || !side_.schedule().reset_done()) return;
  stability_checked_ = true;
  for (std::string& line : stability_warnings(side_.schedule().period())) side_.add_message(std::move(line));
}

double StructureCoupler::period_after_reset() const {
  return side_.schedule().period_after_reset(side_.structure_step(), world_.dt);
}

std::vector<std::string> StructureCoupler::stability_warnings(double period) const {
  std::vector<std::string> lines;
  struct Particle {
    double radius = 0.0, mass = 0.0;  // m, kg
    std::size_t material = 0;
  };
  std::vector<Particle> particles;
  for (const ParticleTypeInfo& type : particle_type_infos(world_.spec)) {
    if (type.fixed) continue;
    const SizeSampler sizes(type.size);
    for (const double radius : {sizes.min_radius(), sizes.max_radius()})
      particles.push_back({radius, sphere_mass(type.density, radius),
                           type.material_index});
  }
  if (particles.empty()) return lines;
  // The coupled nodes that can move along some axis: a node whose translations are all
  // prescribed (a clamped edge) takes any force without moving, an infinite mass here.
  const fem::ShellSolver& solver = side_.solver();
  std::vector<double> masses;  // kg
  for (std::int32_t n : side_.node_of_vertex()) {
    const auto node = static_cast<std::size_t>(n);
    if ((solver.prescribed_dofs()[node] & fem::dof::translations) != fem::dof::translations)
      masses.push_back(solver.nodal_masses()[node]);
  }
  if (masses.empty()) return lines;  // nothing coupled moves
  const double node_mass = *std::min_element(masses.begin(), masses.end());  // kg, the lightest
  const std::size_t wall = world_.surfaces[surface_].mesh.material;
  const double speed = world_.spec.simulation.impact_speed ? world_.spec.simulation.impact_speed->value : 1.0;
  // The contact's normal stiffness (N/m): the linear law's k, or Hertz's tangent stiffness
  // 2E*√(R δ) at the overlap `overlap()` gives (m).
  const auto stiffness = [](const InteractionParameters& pair, double radius, auto overlap) {
    return pair.normal_model == NormalModel::linear
               ? pair.linear_normal_stiffness
               : contact::hertz_normal_spring(pair.effective_youngs_modulus, radius, overlap()).stiffness;
  };
  const auto damping_ratio = [](const InteractionParameters& pair) {
    return (pair.normal_model == NormalModel::linear ? 1.0 : std::sqrt(5.0 / 6.0)) * -pair.damping_ratio_beta;
  };
  struct Estimate {
    double radius = 0.0, particle_mass = 0.0;  // m, kg
    double stiffness = 0.0, omega = 0.0;        // N/m, rad/s
    double damping_ratio = 0.0, mass_ratio = 0.0, critical = 0.0;  // 1, 1, s
  };
  const auto estimate = [&](const Particle& particle) {
    const InteractionParameters& pair = world_.materials.between(particle.material, wall);
    const double effective_modulus = pair.effective_youngs_modulus;  // E* (Pa), a rigid wall's compliance 0
    Estimate e;
    e.radius = particle.radius;
    e.particle_mass = particle.mass;
    const double effective_mass = 1.0 / (1.0 / particle.mass + 1.0 / node_mass);  // kg
    e.stiffness = stiffness(pair, e.radius, [&] {
      return hertz_peak_overlap(effective_mass, e.radius, effective_modulus, speed);
    });
    e.damping_ratio = damping_ratio(pair);
    e.omega = std::sqrt(e.stiffness / effective_mass);
    e.mass_ratio = std::min(node_mass / e.particle_mass, 1.0);
    e.critical = critical_omega_period(e.damping_ratio, e.mass_ratio) / e.omega;
    return e;
  };
  Estimate worst = estimate(particles.front());
  for (std::size_t k = 1; k < particles.size(); ++k) {
    const Estimate e = estimate(particles[k]);
    if (e.critical < worst.critical) worst = e;
  }
  constexpr double margin = 0.5;
  if (worst.critical == 0.0) {  // restitution 1: nothing opposes the lag's negative damping
    lines.push_back(fmt::format(
        "warning: coupling PERIOD {:.4g} s: the particle–structure contact has no damping (restitution 1), so the "
        "exchange's lag grows its oscillation at any PERIOD (docs/fem.md, \"Stability of PERIOD\")",
        period));
    return lines;
  }
  if (period > margin * worst.critical)
    lines.push_back(fmt::format(
        "warning: coupling PERIOD {:.4g} s is long for the contact: a particle of radius {:.4g} m ({:.4g} kg) on a "
        "node of {:.4g} kg (S_n {:.4g} N/m at {:.3g} m/s, ω {:.4g} rad/s, damping ratio {:.3g}, mass ratio {:.3g}) "
        "makes the exchange unstable (growing) for PERIOD > {:.4g} s (ω·PERIOD > {:.3g}); use PERIOD ≤ {:.4g} s, "
        "with a smaller DEM step if that is under 2 DEM steps (docs/fem.md, \"Stability of PERIOD\")",
        period, worst.radius, worst.particle_mass, node_mass, worst.stiffness, speed, worst.omega,
        worst.damping_ratio, worst.mass_ratio, worst.critical, worst.critical * worst.omega, margin * worst.critical));

  // The structure's own modes (period_stability.h, the node with its mode Ω and the damping α):
  // the held force of a period reaches a mode with Ω·P between about 1 and π a period late and
  // drives it, at any PERIOD (a shorter one moves the band to higher modes); the damping that
  // stops it is about proportional to ω, not to the PERIOD. Modes up to the structure's highest,
  // 2/dt at its stable step. The contact that lasts, not an impact's: a particle at rest under its
  // own weight (a bed's weight stiffens it), on a node of the surface's median mass taken at most
  // as heavy as the particle (a column above it); the largest need of the particles above. On two
  // measured beds (docs/fem.md, "Damping the structure") the damping that stops the growth lay
  // between 0.21 and 0.77 of this estimate.
  std::nth_element(masses.begin(), masses.begin() + static_cast<std::ptrdiff_t>(masses.size() / 2), masses.end());
  const double median_mass = masses[masses.size() / 2];  // kg
  const double gravity = norm(world_.spec.simulation.gravity.value);  // m/s²
  const double highest = 2.0 * period / solver.stable_time_step().time_step;  // Ω_max·P
  struct Resting {
    double radius = 0.0, stiffness = 0.0, omega = 0.0;  // m, N/m, rad/s
    DampingNeed need;
  };
  const auto resting = [&](const Particle& particle) {
    const InteractionParameters& pair = world_.materials.between(particle.material, wall);
    const double effective_modulus = pair.effective_youngs_modulus;  // E* (Pa)
    const double node = std::min(median_mass, particle.mass);        // kg
    Resting r;
    r.radius = particle.radius;
    // Hertz at rest: m g = (4/3) E* √R δ^(3/2) (Johnson, Contact Mechanics, §4.2); without
    // gravity, the impact overlap of the PERIOD check.
    r.stiffness = stiffness(pair, r.radius, [&] {
      return gravity > 0.0
                 ? std::pow(3.0 * particle.mass * gravity / (4.0 * effective_modulus * std::sqrt(r.radius)), 2.0 / 3.0)
                 : hertz_peak_overlap(1.0 / (1.0 / particle.mass + 1.0 / node), r.radius, effective_modulus, speed);
    });
    r.omega = std::sqrt(r.stiffness * (1.0 / particle.mass + 1.0 / node));
    const double zeta = damping_ratio(pair);
    r.need = zeta > 0.0 ? required_damping_over_modes(r.omega * period, zeta, node / particle.mass, highest)
                        : DampingNeed{std::numeric_limits<double>::infinity(), 0.0};
    return r;
  };
  Resting neediest = resting(particles.front());
  for (std::size_t k = 1; k < particles.size(); ++k) {
    const Resting other = resting(particles[k]);
    if (other.need.damping_period > neediest.need.damping_period) neediest = other;
  }
  const double alpha = solver.damping();                           // 1/s
  const double required = neediest.need.damping_period / period;  // 1/s (+∞: more than 100/PERIOD)
  if (!(alpha < required)) return lines;
  const DampingNeed& need = neediest.need;
  const std::string modes = need.node_omega_period == 0.0
                                ? std::string("the contact mode (the node as a free mass)")
                                : fmt::format("the structure's modes near {:.4g} rad/s (Ω·PERIOD {:.3g})",
                                              need.node_omega_period / period, need.node_omega_period);
  const std::string amount = std::isfinite(required) ? fmt::format("α ≈ {:.4g} 1/s", required)
                                                      : fmt::format("more than α = {:.4g} 1/s", 100.0 / period);
  lines.push_back(fmt::format(
      "warning: the structure's damping α = {:.4g} 1/s may be too low for the exchange at PERIOD {:.4g} s: a "
      "particle of radius {:.4g} m at rest on a node of {:.4g} kg (the median; S_n {:.4g} N/m, ω {:.4g} rad/s) "
      "drives {} unless the structure is damped at {} (mass-proportional: `damping` in the deck's structures "
      "entry){}; on two measured beds the damping that stopped it lay between 0.2 and 0.8 of this estimate; "
      "watch the structure's kinetic energy (docs/fem.md, \"Damping the structure\")",
      alpha, period, neediest.radius, median_mass, neediest.stiffness, neediest.omega, modes, amount,
      need.node_omega_period == 0.0 ? " or a shorter PERIOD"
                                    : "; a shorter PERIOD moves the band of such modes, it does not remove it"));
  return lines;
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
