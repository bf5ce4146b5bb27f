// Test helpers shared by the coupled-plate tests (structure_coupler_test.cpp,
// settled_bed_deflection_test.cpp): a DEM world with the generated plate's coupled surface, the
// plate's reference statics (the shell solver alone under given loads or a uniform pressure),
// and the time means of a coupled run.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "fsi/plate_bulk_data.h"
#include "fsi/structure_adapter.h"
#include "fsi/structure_coupler.h"
#include "io/deck.h"
#include "sim/step.h"

namespace quarry::fsi::testing {

// The DEM side: glass beads (R 1.8–2.2 mm, E 10 MPa) between four frictionless vertical walls
// standing on the plate's edges, so that the plate carries the bed's whole weight.
inline std::string bed_deck(const std::string& gravity, const std::string& factory, const std::string& step) {
  return R"(simulation:
  end_time: 1.0
  time_step: )" + step + R"(
  impact_speed: 0.5
  gravity: )" + gravity + R"(
  domain: {min: [-0.01, -0.01, -0.03], max: [0.07, 0.07, 0.1]}
materials:
  - {name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
  - {name: steel, density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3}
  - {name: smooth, density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3}
interactions:
  - {materials: [glass, glass], restitution: 0.3, static_friction: 0.5}
  - {materials: [glass, steel], restitution: 0.3, static_friction: 0.5}
  - {materials: [glass, smooth], restitution: 0.3, static_friction: 0.0}
particle_types:
  - {name: bead, material: glass, size: {distribution: uniform, min_radius: 0.0018, max_radius: 0.0022}}
surfaces:
  - {name: wall_x0, type: plane, point: [0, 0.03, 0.05], normal: [1, 0, 0], size: 0.1, material: smooth}
  - {name: wall_x1, type: plane, point: [0.06, 0.03, 0.05], normal: [-1, 0, 0], size: 0.1, material: smooth}
  - {name: wall_y0, type: plane, point: [0.03, 0, 0.05], normal: [0, 1, 0], size: 0.1, material: smooth}
  - {name: wall_y1, type: plane, point: [0.03, 0.06, 0.05], normal: [0, -1, 0], size: 0.1, material: smooth}
factories:
)" + factory + R"(
output: {directory: out_fsi, interval: 0, plots: false}
)";
}

struct CoupledScene {
  AdaptedStructure adapted;
  CouplingMesh mesh;
  World world;
  std::size_t surface = 0;
};

// Reads the plate's bulk data, adapts it, and builds the DEM world with the EDEM card's SURF 2
// as its coupled surface (the deck's first equipment material, steel, as the seed says).
inline CoupledScene make_scene(const PlateCards& plate, const std::string& deck) {
  CoupledScene scene;
  CoupledStructure structure = coupled_structure_from_text(plate_bulk_data(plate), "plate.bdf");
  scene.adapted = std::move(structure.adapted);
  scene.mesh = std::move(structure.mesh);
  SimulationSpec spec = parse_deck_string(deck, "bed.yaml");
  spec.surfaces.push_back(coupling_surface_spec(scene.mesh, "plate", "steel"));
  scene.surface = spec.surfaces.size() - 1;
  scene.world = build_world(spec);
  sim::initialize(scene.world);
  return scene;
}

inline double bed_weight(const World& world, double g) {
  double mass = 0.0;  // kg
  for (double inverse : world.particles.inv_mass) mass += 1.0 / inverse;
  return mass * g;
}

inline double kinetic_energy(const World& world) {
  const ParticleStore& p = world.particles;
  double energy = 0.0;  // J
  for (std::size_t i = 0; i < p.size(); ++i) energy += 0.5 / p.inv_mass[i] * dot(p.velocity[i], p.velocity[i]);
  return energy;
}

// The node at the plate's centre (a/2, a/2), −1 if there is none (odd divisions).
inline int centre_node(const fem::ShellModel& model, double side) {
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (std::abs(model.nodes[n].x - 0.5 * side) < 1e-9 && std::abs(model.nodes[n].y - 0.5 * side) < 1e-9)
      return static_cast<int>(n);
  return -1;
}

// D = E t³ / (12 (1 − ν²)) (N·m).
inline double flexural_rigidity(const PlateCards& plate) {
  const double nu = plate.poisson_ratio;
  return plate.youngs_modulus * std::pow(plate.thickness, 3.0) / (12.0 * (1.0 - nu * nu));
}

// Kirchhoff's centre deflection (m) of a clamped square plate under a uniform pressure q (Pa):
// w = α q a⁴/D, α = 0.00126 for ν = 0.3 (Timoshenko & Woinowsky-Krieger, "Theory of Plates and
// Shells", 1959, §44, Table 35).
inline double kirchhoff_clamped_deflection(const PlateCards& plate, double pressure) {
  return 0.00126 * pressure * std::pow(plate.side, 4.0) / flexural_rigidity(plate);
}

// Mass-proportional damping critical for the plate's first mode: α = 2ω₁, ω₁ = 35.99/a² √(D/(ρt))
// for a clamped square plate (Leissa, "Vibration of Plates", NASA SP-160, 1969, Table 4.23), ρt
// from the solver's (mass-scaled) mass. It changes the way to the static state, not the state.
inline double critical_damping(const fem::ShellSolver& solver, const PlateCards& plate) {
  const double mass_per_area = solver.total_mass() / (plate.side * plate.side);  // kg/m²
  return 2.0 * 35.99 / (plate.side * plate.side) * std::sqrt(flexural_rigidity(plate) / mass_per_area);
}

// 1D integrals of a linear element's two shape functions on [x0, x1] over [u0, u1] ∩ [x0, x1]:
// ∫ (x1 − x)/h dx and ∫ (x − x0)/h dx (m).
inline std::array<double, 2> shape_integrals(double x0, double x1, double u0, double u1) {
  const double a = std::max(x0, u0), b = std::min(x1, u1), h = x1 - x0;
  if (b <= a) return {0.0, 0.0};
  return {((x1 - a) * (x1 - a) - (x1 - b) * (x1 - b)) / (2.0 * h), ((b - x0) * (b - x0) - (a - x0) * (a - x0)) / (2.0 * h)};
}

// Nodal positions (m) of the plate alone at rest under nodal `loads`: critically damped for
// 0.1 s (tens of its damping times).
inline std::vector<Vec3> static_positions_under_loads(const fem::ShellModel& model,
                                                      const fem::ShellSolverOptions& options, const PlateCards& plate,
                                                      const std::vector<fem::NodalLoad>& loads) {
  fem::ShellSolver solver(model, options);
  solver.set_damping(critical_damping(solver, plate));
  solver.set_loads(loads);
  const double dt = 0.9 * solver.stable_time_step().time_step;
  while (solver.time() < 0.1) solver.step(dt);
  return {solver.positions().begin(), solver.positions().end()};
}

// Centre deflection (m, downward) of the plate alone under nodal `loads`, damped to rest.
inline double static_deflection_under_loads(const fem::ShellModel& model, const fem::ShellSolverOptions& options,
                                            const PlateCards& plate, const std::vector<fem::NodalLoad>& loads,
                                            int centre) {
  return -static_positions_under_loads(model, options, plate, loads)[static_cast<std::size_t>(centre)].z;
}

// Consistent nodal forces (N) of `force` (N, downward) spread as a uniform pressure over
// [margin, a − margin]²: q ∫ N_i dA of the bilinear quads (products of the 1D integrals, corners
// counter-clockwise from (x0, y0)).
inline std::vector<fem::NodalLoad> uniform_pressure_loads(const fem::ShellModel& model, const PlateCards& plate,
                                                          double force, double margin) {
  const double lo = margin, hi = plate.side - margin;
  const double pressure = force / ((hi - lo) * (hi - lo));  // Pa
  std::vector<fem::NodalLoad> loads(model.nodes.size());
  for (const fem::ShellElement& e : model.elements) {
    const Vec3& corner = model.nodes[static_cast<std::size_t>(e.nodes[0])];
    const Vec3& opposite = model.nodes[static_cast<std::size_t>(e.nodes[2])];
    const auto x = shape_integrals(corner.x, opposite.x, lo, hi), y = shape_integrals(corner.y, opposite.y, lo, hi);
    const std::array<double, 4> share = {x[0] * y[0], x[1] * y[0], x[1] * y[1], x[0] * y[1]};  // m²
    for (int k = 0; k < 4; ++k)
      loads[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(k)])].force.z -= pressure * share[static_cast<std::size_t>(k)];
  }
  return loads;
}

// Centre deflection (m, downward) of the plate alone under `force` (N) spread as a uniform
// pressure over [margin, a − margin]² (uniform_pressure_loads), damped to rest.
inline double static_deflection_under_pressure(const fem::ShellModel& model, const fem::ShellSolverOptions& options,
                                               const PlateCards& plate, double force, double margin, int centre) {
  const std::vector<fem::NodalLoad> loads = uniform_pressure_loads(model, plate, force, margin);
  return static_deflection_under_loads(model, options, plate, loads, centre);
}

// Time means of a coupled run over `duration` (s) of DEM time from now, period by period.
struct CoupledMeans {
  double nodal_force = 0.0;  // N, downward, the sum of the nodal loads weighted by the time they acted
  double deflection = 0.0;   // m, downward, the centre node's, weighted by the DEM's time
  std::vector<fem::NodalLoad> loads;  // N per node, time-weighted as nodal_force
};

// The loads set at an exchange act during the structure's next period (a whole number of its
// steps): the force means weight each period's loads by the structure's time it acted, the
// deflection mean weights the centre's deflection at each sync by the DEM's period.
// `after_period`, if given, runs after each period (a test that holds the plate zeroes the
// solver's loads there).
inline CoupledMeans coupled_means(StructureCoupler& coupler, const World& world, fem::ShellSolver& solver,
                                  int centre, double duration, const std::function<void()>& after_period = {}) {
  CoupledMeans means;
  means.loads.assign(static_cast<std::size_t>(solver.node_count()), fem::NodalLoad{});  // N·s, then N
  double force_time = 0.0, time_sum = 0.0;  // s
  const double start = world.time;
  while (world.time < start + duration) {
    const std::vector<fem::NodalLoad> loads = coupler.loads();
    const double before = world.time, structure_before = solver.time();
    coupler.advance_period();
    if (after_period) after_period();
    const double acted = solver.time() - structure_before;  // s
    double total = 0.0;  // N, downward
    for (const fem::NodalLoad& load : loads) total -= load.force.z;
    means.nodal_force += total * acted;
    for (std::size_t n = 0; n < loads.size(); ++n) means.loads[n].force += loads[n].force * acted;
    force_time += acted;
    const double span = world.time - before;
    means.deflection += -solver.positions()[static_cast<std::size_t>(centre)].z * span;
    time_sum += span;
  }
  means.nodal_force /= force_time;
  means.deflection /= time_sum;
  for (fem::NodalLoad& load : means.loads) load.force = load.force / force_time;
  return means;
}

}  // namespace quarry::fsi::testing
