// The FEM load export of a coupled structure's surface (issue #17 §5, "the one-way export also
// accepts the deformed coupled surface"): the loads the export writes are the impulses the
// structure received, and the displacement it writes is the structure's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "export/load_exporter.h"
#include "export/med_file.h"
#include "fsi/plate_bulk_data.h"
#include "fsi/structure_adapter.h"
#include "fsi/structure_coupler.h"
#include "io/deck.h"
#include "sim/step.h"

namespace quarry::fsi {
namespace {

namespace fs = std::filesystem;

// 120 glass beads (R 1.8–2.2 mm, E 10 MPa) dropped from up to 60 mm onto a clamped steel plate
// (60 mm, t 1 mm, 8×8 quads) between frictionless walls on its edges.
std::string drop_deck() {
  return R"(simulation:
  end_time: 1.0
  time_step: {rayleigh_fraction: 0.2}
  impact_speed: 1.0
  gravity: [0, 0, -9.81]
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
  - name: drop
    particle_type: bead
    region: {type: box, min: [0.0025, 0.0025, 0.003], max: [0.0575, 0.0575, 0.06]}
    count: 120
output: {directory: out_fsi_export, interval: 0, plots: false}
)";
}

// The plate is mass scaled to a 10 µs step and damped at α = 2ω₁ (ω₁ = 35.99/a² √(D/(ρt)),
// Leissa 1969, Table 4.23, with the scaled mass), so that it comes to rest under the beads.
// PERIOD = 3 DEM steps (FILTER = PERIOD); export records every 30 DEM steps, a whole number of
// periods, with the structure's exchange as the run loop's end-of-step hook.
// 1. Momentum across the export: the impulse the export's records carry (Σ records of Σ nodes
//    nodal force × record length) is the impulse the structure received plus what the exchange
//    holds in transit at the end — both are sums of the same per-step surface loads × dt, so they
//    agree to round-off (a lost or doubled DEM step would be ~1e-3 of it).
// 2. The exported mesh is the reference one and the last record's mean displacement is the
//    structure's: once the plate is at rest the mean over the last record equals the solver's
//    nodal displacement at the end within 1 % of the largest deflection (what is left of the
//    damped vibration and the bed's creep over one 30-step record).
TEST(CoupledExport, RecordsCarryTheStructuresImpulseAndDisplacement) {
  const testing::PlateCards plate{.divisions = 8, .side = 0.06, .thickness = 0.001};
  CoupledStructure structure = coupled_structure_from_text(testing::plate_bulk_data(plate), "plate.bdf");
  SimulationSpec spec = parse_deck_string(drop_deck(), "drop.yaml");
  SurfaceSpec coupled = coupling_surface_spec(structure.mesh, "plate", "steel");
  coupled.export_loads = true;
  spec.surfaces.push_back(coupled);
  World world = build_world(spec);
  sim::initialize(world);
  const std::size_t surface = world.surfaces.size() - 1;
  ASSERT_TRUE(world.surfaces[surface].mesh.moving);

  fem::ShellSolverOptions options;
  options.mass_scaling_time_step = 1e-5;  // s
  fem::ShellSolver solver(structure.adapted.model, options);
  const double rigidity = plate.youngs_modulus * std::pow(plate.thickness, 3.0) /
                          (12.0 * (1.0 - plate.poisson_ratio * plate.poisson_ratio));  // N·m
  solver.set_damping(2.0 * 35.99 / (plate.side * plate.side) *
                     std::sqrt(rigidity / (solver.total_mass() / (plate.side * plate.side))));
  StructureCoupler coupler(world, surface, solver, structure.mesh.node_of_vertex,
                           {.schedule = resolve_schedule(3.0 * world.dt, std::nullopt, 1.0)});

  Vec3 delivered;  // N·s, Σ loads × the structure's time they acted
  world.hooks.push_back({HookStage::end_of_step, "structure", [&](World&) {
                           Vec3 total;  // N, the loads of the structure's current period
                           for (const fem::NodalLoad& load : coupler.loads()) total += load.force;
                           const double before = solver.time();
                           coupler.after_dem_step();
                           delivered += total * (solver.time() - before);
                         }});
  ExportSpec export_spec;
  export_spec.enabled = true;
  export_spec.interval = 30.0 * world.dt;
  export_spec.formats = {Located<ExportFormat>(ExportFormat::med)};
  const fs::path folder = fs::path(::testing::TempDir()) / "quarry_coupled_export";
  fs::remove_all(folder);
  const auto meshes = [&] {
    std::vector<const Surface*> list;
    for (const WorldSurface& s : world.surfaces) list.push_back(&s.mesh);
    return list;
  };
  const std::uint64_t steps = 600 * 30;  // 600 records
  // The particles' mid-step momentum p + (dt/2) Σ f (velocity Verlet's conserved form, as in
  // StructureCoupler.MomentumConservedThroughTheExchange) before and after.
  const auto particle_momentum = [&] {
    Vec3 sum;  // N·s
    const ParticleStore& p = world.particles;
    for (std::size_t i = 0; i < p.size(); ++i) sum += p.velocity[i] / p.inv_mass[i] + 0.5 * world.dt * p.force[i];
    return sum;
  };
  const Vec3 momentum_before = particle_momentum();
  double weight = 0.0;  // N
  for (double inverse : world.particles.inv_mass) weight += 9.81 / inverse;
  const double start = world.time;
  fem_export::LoadExporter exporter(export_spec, meshes(), folder, world.dt, world.dt * static_cast<double>(steps),
                                    std::nullopt);
  for (std::uint64_t n = 0; n < steps; ++n) {
    sim::step(world);
    exporter.after_step(meshes(), world.time, world.step_count, world.dt);
  }
  exporter.finish(meshes(), world.time, false);

  const fem_export::MedLoadFile med = fem_export::read_med_loads((folder / "fem_export" / "plate.med").string());
  ASSERT_EQ(med.frames.size(), 600u);
  ASSERT_EQ(med.displacements.size(), med.frames.size());
  EXPECT_EQ(med.nodes, structure.mesh.vertices);  // the reference mesh, node k = surface vertex k
  Vec3 exported;  // N·s
  double previous = 0.0;
  for (const LoadFrame& frame : med.frames) {
    for (const Vec3& f : frame.nodal_force) exported += f * (frame.time - previous);
    previous = frame.time;
  }
  const Vec3 received = delivered + coupler.impulse_in_transit();  // N·s
  // The beads' own balance (the side walls are frictionless: no vertical force): the impulse of
  // the particles on the plate is −(their weight × time + their momentum's change).
  const double by_particles = -(weight * (world.time - start) + (particle_momentum() - momentum_before).z);
  const double scale = std::abs(exported.z);

  // The solver's displacement of each surface vertex's node at the end against the last record.
  double largest = 0.0, worst = 0.0;  // m
  const std::vector<Vec3>& last = med.displacements.back();
  for (std::size_t v = 0; v < last.size(); ++v) {
    const auto node = static_cast<std::size_t>(structure.mesh.node_of_vertex[v]);
    const Vec3 u = solver.positions()[node] - structure.adapted.model.nodes[node];
    largest = std::max(largest, std::sqrt(dot(u, u)));
    const Vec3 d = last[v] - u;
    worst = std::max(worst, std::sqrt(dot(d, d)));
  }
  std::printf("coupled export: %zu beads, t %.4f s; impulse exported (%.6e, %.6e, %.6e) N·s, received + in "
              "transit (%.6e, %.6e, %.6e) N·s, |difference| %.3e of |J_z|; from the beads' balance J_z = %.6e "
              "N·s (%.2e of it); largest deflection %.4e m, last record's mean displacement against the "
              "solver's %.3e m (%.3f %%)\n",
              world.particles.size(), world.time, exported.x, exported.y, exported.z, received.x, received.y,
              received.z, std::sqrt(dot(exported - received, exported - received)) / scale, by_particles,
              (exported.z - by_particles) / scale, largest, worst, 100.0 * worst / largest);
  ASSERT_EQ(world.particles.size(), 120u);
  // Round-off: 18,000 steps of sums in two orders, ~N ε = 4e-12 at worst.
  EXPECT_LT(std::sqrt(dot(exported - received, exported - received)), 1e-11 * scale);
  EXPECT_NEAR(exported.z, by_particles, 1e-11 * scale);
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(worst, 0.01 * largest);
}

}  // namespace
}  // namespace quarry::fsi
