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
#include "fsi/coupled_scene_test_util.h"

namespace quarry::fsi {
namespace {

namespace fs = std::filesystem;

// 120 glass beads (R 1.8–2.2 mm, E 10 MPa) dropped from up to 60 mm onto a clamped steel plate
// (60 mm, t 1 mm, 8×8 quads) between frictionless walls on its edges.
const std::string kDrop = R"(  - name: drop
    particle_type: bead
    region: {type: box, min: [0.0025, 0.0025, 0.003], max: [0.0575, 0.0575, 0.06]}
    count: 120)";

// The plate is mass scaled to a 10 µs step and critically damped (testing::critical_damping),
// so that it comes to rest under the beads.
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
  testing::CoupledScene scene =
      testing::make_scene(plate, testing::bed_deck("[0, 0, -9.81]", kDrop, "{rayleigh_fraction: 0.2}"));
  World& world = scene.world;
  const std::size_t surface = scene.surface;
  world.surfaces[surface].mesh.export_loads = true;  // as a structures: entry's export: true
  ASSERT_TRUE(world.surfaces[surface].mesh.moving);

  fem::ShellSolverOptions options;
  options.mass_scaling_time_step = 1e-5;  // s
  fem::ShellSolver solver(scene.adapted.model, options);
  solver.set_damping(testing::critical_damping(solver, plate));
  StructureCoupler coupler(world, surface, solver, scene.mesh.node_of_vertex,
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
  const double weight = testing::bed_weight(world, 9.81);  // N
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
  EXPECT_EQ(med.nodes, scene.mesh.vertices);  // the reference mesh, node k = surface vertex k
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
    const auto node = static_cast<std::size_t>(scene.mesh.node_of_vertex[v]);
    const Vec3 u = solver.positions()[node] - scene.adapted.model.nodes[node];
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
