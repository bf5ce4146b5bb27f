// Two-way coupling of a DEM bed and the built-in shell solver through the EDEM card's exchange
// (structure_coupler.h): the plate is generated as bulk data, read, adapted and coupled, so the
// whole path from a model file is exercised.
#include "fsi/structure_coupler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fsi/coupled_scene_test_util.h"
#include "fsi/plate_bulk_data.h"
#include "io/deck.h"
#include "sim/step.h"

namespace quarry::fsi {
namespace {

using testing::bed_weight;
using testing::centre_node;
using testing::CoupledScene;
using testing::critical_damping;
using testing::bed_deck;
using testing::kinetic_energy;
using testing::kirchhoff_clamped_deflection;
using testing::make_scene;
using testing::static_deflection_under_loads;
using testing::static_deflection_under_pressure;

const std::string kFill = R"(  - name: fill
    particle_type: bead
    region: {type: box, min: [0.0025, 0.0025, 0.003], max: [0.0575, 0.0575, 0.095]}
    count: 900)";

// A settled bed on a clamped plate (gravity on). Static equilibrium: the nodal forces the plate
// receives sum to the bed's weight within 0.5 % (the side walls are frictionless, so they carry
// none of it). The coupled plate's centre deflection is that of the shell solver alone under the
// run's time-mean nodal loads within 1 % (linear statics: the mean deflection answers the mean
// load). Reported beside it, not asserted: the same force as a uniform pressure over the whole
// plate and over [R̄, a − R̄]² (a sphere touches the plate at least its radius from a wall):
// the walls and a fill drawn at least a radius inside its box load the centre more than a
// uniform pressure does (docs/fem.md, "Coupling"); the weight's uniform pressure is asserted on a
// bed without walls (settled_bed_deflection_test.cpp).
// The mesh against Kirchhoff, w = α q a⁴/D, α = 0.00126 for a clamped square plate, ν = 0.3
// (Timoshenko & Woinowsky-Krieger, "Theory of Plates and Shells", 1959, §44, Table 35): 2 %.
// The plate is mass scaled to a 10 µs step (statics do not depend on mass) and critically damped.
TEST(StructureCoupler, SettledBedOnClampedPlate) {
  const testing::PlateCards plate{.divisions = 8, .side = 0.06, .thickness = 0.001};
  CoupledScene scene = make_scene(plate, bed_deck("[0, 0, -9.81]", kFill, "{rayleigh_fraction: 0.2}"));
  World& world = scene.world;
  fem::ShellSolverOptions options;
  options.mass_scaling_time_step = 1e-5;  // s
  fem::ShellSolver solver(scene.adapted.model, options);
  solver.set_damping(critical_damping(solver, plate));
  const double dt_dem = world.dt;
  StructureCoupler coupler(world, scene.surface, solver, scene.mesh.node_of_vertex,
                           {.schedule = resolve_schedule(dt_dem, std::nullopt, 1.0)});
  coupler.advance_to(0.4);
  const double weight = bed_weight(world, 9.81);  // N
  const int centre = centre_node(scene.adapted.model, plate.side);
  ASSERT_GE(centre, 0);
  // Time means over the next 0.1 s of the settled state: the total nodal force, weighted by the
  // structure's time it acted (its periods are whole numbers of its steps), and the deflection.
  const testing::CoupledMeans means = testing::coupled_means(coupler, world, solver, centre, 0.1);
  const double nodal_force = means.nodal_force, deflection = means.deflection;
  const double kinetic = kinetic_energy(world);

  // The same plate under a uniform pressure of the same total force, solver alone, over the
  // whole plate and over the square the contact points can reach: a sphere resting on the
  // plate touches it at least its radius from a wall, [R̄, a − R̄]² with R̄ the mean radius.
  const double mean_radius = 0.002;  // m
  const double own = static_deflection_under_loads(scene.adapted.model, options, plate, means.loads, centre);
  const double whole = static_deflection_under_pressure(scene.adapted.model, options, plate, nodal_force, 0.0, centre);
  const double reachable =
      static_deflection_under_pressure(scene.adapted.model, options, plate, nodal_force, mean_radius, centre);
  const double kirchhoff = kirchhoff_clamped_deflection(plate, nodal_force / (plate.side * plate.side));
  std::printf("settled bed: %zu particles, weight %.6e N, mean nodal force %.6e N (%+.3f %%), bed KE %.3e J\n"
              "  centre deflection coupled %.5e m; shell alone under the coupled run's time-mean nodal loads %.5e m "
              "(coupled %+.3f %%);\n  shell alone under the same force as uniform pressure over "
              "[R, a-R]^2 %.5e m (coupled %+.2f %%), over the whole plate %.5e m (coupled %+.2f %%); "
              "Kirchhoff (whole plate) %.5e m (alone %+.2f %%)\n"
              "  structure: %lld steps of %.3e s, added mass %.4e kg of %.4e kg; DEM dt %.3e s; %zu messages\n",
              world.particles.size(), weight, nodal_force, 100.0 * (nodal_force / weight - 1.0), kinetic,
              deflection, own, 100.0 * (deflection / own - 1.0), reachable, 100.0 * (deflection / reachable - 1.0), whole, 100.0 * (deflection / whole - 1.0),
              kirchhoff, 100.0 * (whole / kirchhoff - 1.0),
              static_cast<long long>(coupler.structure_steps()), coupler.structure_step(), solver.added_mass(),
              solver.total_mass(), dt_dem, coupler.messages().size());
  for (const std::string& line : coupler.messages()) std::printf("  %s\n", line.c_str());
  ASSERT_EQ(world.particles.size(), 900u);
  EXPECT_NEAR(nodal_force, weight, 0.005 * weight);
  EXPECT_NEAR(deflection, own, 0.01 * own);
  EXPECT_NEAR(whole, kirchhoff, 0.02 * kirchhoff);  // the mesh against plate theory
}

// Linear momentum through the exchange (gravity off, free plate, no damping): beads thrown at
// 0.5 m/s onto a free plate. Velocity Verlet conserves the particles' mid-step momentum
// p + (dt/2) Σ f exactly against the impulses the load window collects (Σ f dt per step); the
// structure receives each period's impulse as loads × its steps; what has been given but not yet
// applied is in transit. Their sum stays at its initial value to round-off.
TEST(StructureCoupler, MomentumConservedThroughTheExchange) {
  const testing::PlateCards plate{.divisions = 4, .side = 0.06, .thickness = 0.001, .clamped = false};
  const std::string throw_beads = R"(  - name: throw
    particle_type: bead
    region: {type: box, min: [0.005, 0.005, 0.003], max: [0.055, 0.055, 0.02]}
    count: 40
    velocity: [0.1, 0, -0.5])";
  CoupledScene scene = make_scene(plate, bed_deck("[0, 0, 0]", throw_beads, "{rayleigh_fraction: 0.2}"));
  World& world = scene.world;
  fem::ShellSolver solver(scene.adapted.model);
  StructureCoupler coupler(world, scene.surface, solver, scene.mesh.node_of_vertex,
                           {.schedule = resolve_schedule(3.0 * world.dt, std::nullopt, 1.0)});
  const auto total_momentum = [&] {
    Vec3 sum;  // N·s
    const ParticleStore& p = world.particles;
    for (std::size_t i = 0; i < p.size(); ++i) sum += p.velocity[i] / p.inv_mass[i] + 0.5 * world.dt * p.force[i];
    for (int n = 0; n < solver.node_count(); ++n)
      sum += solver.nodal_masses()[static_cast<std::size_t>(n)] * solver.velocities()[static_cast<std::size_t>(n)];
    return sum + coupler.impulse_in_transit();
  };
  double scale = 0.0;  // N·s, Σ m |v| at the start
  for (std::size_t i = 0; i < world.particles.size(); ++i)
    scale += std::sqrt(dot(world.particles.velocity[i], world.particles.velocity[i])) / world.particles.inv_mass[i];
  const Vec3 initial = total_momentum();
  double worst = 0.0;
  while (world.time < 0.06) {
    coupler.advance_period();
    const Vec3 drift = total_momentum() - initial;
    worst = std::max(worst, std::sqrt(dot(drift, drift)));
  }
  Vec3 structure;  // N·s
  for (int n = 0; n < solver.node_count(); ++n)
    structure += solver.nodal_masses()[static_cast<std::size_t>(n)] * solver.velocities()[static_cast<std::size_t>(n)];
  std::printf("momentum: %zu beads, Σ m|v| %.6e N·s; structure gained p_z %.6e N·s; worst drift %.3e N·s "
              "(%.2e of Σ m|v|) over %lld syncs\n",
              world.particles.size(), scale, structure.z, worst, worst / scale,
              static_cast<long long>(coupler.schedule().synchronisations()));
  EXPECT_LT(structure.z, -0.2 * scale);  // the plate really was hit
  EXPECT_LT(worst, 1e-12 * scale);  // round-off (a lost or doubled step of force would be ~1e-3)
}

// One bead thrown at 0.5 m/s onto the centre of a clamped steel plate (gravity off, no mass
// scaling): the bead's rebound speed and the plate's peak centre deflection for PERIOD = 2, 4, 8,
// 16 DEM steps (FILTER = PERIOD). Holding the forces for a period lags the exchange by up to one
// period, a first-order error: the results converge to the shortest PERIOD as PERIOD → small
// (research notes §2.5), each halving of PERIOD bringing them closer.
struct Impact {
  double rebound = 0.0;     // m/s, bead's v_z after the impact
  double deflection = 0.0;  // m, peak downward centre deflection
};

Impact throw_bead(double period_steps) {
  const testing::PlateCards plate{.divisions = 8, .side = 0.06, .thickness = 0.001};
  const std::string one_bead = R"(  - name: throw
    particle_type: bead
    region: {type: box, min: [0.0277, 0.0277, 0.0027], max: [0.0323, 0.0323, 0.0073]}
    count: 1
    velocity: [0, 0, -0.5])";
  CoupledScene scene = make_scene(plate, bed_deck("[0, 0, 0]", one_bead, "5.0e-6"));
  World& world = scene.world;
  fem::ShellSolver solver(scene.adapted.model);
  StructureCoupler coupler(world, scene.surface, solver, scene.mesh.node_of_vertex,
                           {.schedule = resolve_schedule(period_steps * world.dt, std::nullopt, 1.0)});
  const int centre = centre_node(scene.adapted.model, plate.side);
  Impact impact;
  while (world.time < 0.02) {
    coupler.advance_period();
    impact.deflection = std::max(impact.deflection, -solver.positions()[static_cast<std::size_t>(centre)].z);
  }
  impact.rebound = world.particles.velocity.at(0).z;
  return impact;
}

TEST(StructureCoupler, PeriodSweepConverges) {
  const std::vector<double> steps = {2, 4, 8, 16};
  std::vector<Impact> impacts;
  for (double k : steps) impacts.push_back(throw_bead(k));
  const Impact& reference = impacts.front();
  std::vector<double> rebound_error, deflection_error;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    rebound_error.push_back(std::abs(impacts[i].rebound - reference.rebound));
    deflection_error.push_back(std::abs(impacts[i].deflection - reference.deflection));
    std::printf("PERIOD %2.0f DEM steps: rebound %.6f m/s (%+.3f %%), peak centre deflection %.5e m (%+.3f %%)\n",
                steps[i], impacts[i].rebound, 100.0 * (impacts[i].rebound / reference.rebound - 1.0),
                impacts[i].deflection, 100.0 * (impacts[i].deflection / reference.deflection - 1.0));
  }
  EXPECT_GT(reference.rebound, 0.0);  // it did bounce off
  for (std::size_t i = 2; i < steps.size(); ++i) {
    EXPECT_LT(rebound_error[i - 1], rebound_error[i]) << "PERIOD " << steps[i];
    EXPECT_LT(deflection_error[i - 1], deflection_error[i]) << "PERIOD " << steps[i];
  }
}

// A free 4 × 4 plate and 20 beads thrown down onto it (the hook tests' scene).
testing::PlateCards free_plate() {
  return {.divisions = 4, .side = 0.06, .thickness = 0.001, .clamped = false};
}
std::string thrown_beads_deck() {
  const std::string throw_beads = R"(  - name: throw
    particle_type: bead
    region: {type: box, min: [0.005, 0.005, 0.003], max: [0.055, 0.055, 0.02]}
    count: 20
    velocity: [0, 0, -0.5])";
  return bed_deck("[0, 0, -9.81]", throw_beads, "{rayleigh_fraction: 0.2}");
}

// The structure's pace between syncs (StructureSide::keep_up): each DEM step gets the steps left
// to the structure's sync point over the DEM steps left to the DEM's, so within a period no DEM
// step gets more than one structure step more than another (PERIOD 2.13 DEM steps of 16.3
// structure steps, the flagship's proportions: stepped up to the DEM's time instead, the
// structure ran 2 steps in one DEM step and 30 in the next). The pace moves no bit: at every
// sync the state is that of a structure stepped a whole period at once (finish_period).
TEST(StructureSide, SpreadsAPeriodsStepsEvenlyOverItsDemSteps) {
  const CoupledScene scene = make_scene(free_plate(), thrown_beads_deck());
  fem::ShellSolver paced_solver(scene.adapted.model), whole_solver(scene.adapted.model);
  const double structure_dt = 0.9 * paced_solver.stable_time_step().time_step;  // s
  const double dem_dt = 16.3 * structure_dt;                                     // s
  const ScheduleSettings schedule = resolve_schedule(2.13 * dem_dt, std::nullopt, 1.0);
  StructureSide paced(paced_solver, scene.mesh.node_of_vertex, 0.9, schedule);
  StructureSide whole(whole_solver, scene.mesh.node_of_vertex, 0.9, schedule);
  paced.begin_period(dem_dt);
  whole.begin_period(dem_dt);
  std::vector<Vec3> force(scene.mesh.node_of_vertex.size());  // N per vertex, a load that varies
  std::vector<std::int64_t> shares;  // structure steps per DEM step, this period
  int periods_checked = 0;
  double last_sync = 0.0;  // s, the DEM's
  for (int n = 1; n <= 400; ++n) {
    const double time = n * dem_dt;  // s, the end of DEM step n
    const std::int64_t before = paced.structure_steps();
    paced.keep_up(time, dem_dt);
    if (!paced.schedule().reached(time, dem_dt)) {
      shares.push_back(paced.structure_steps() - before);
      continue;
    }
    paced.finish_period(dem_dt);
    whole.finish_period(dem_dt);
    shares.push_back(paced.structure_steps() - before);
    // The first period holds the cycle-2 reset, which recounts its steps once under way.
    if (paced.schedule().synchronisations() > 0) {
      const auto [fewest, most] = std::minmax_element(shares.begin(), shares.end());
      EXPECT_LE(*most - *fewest, 1) << "period ending at DEM step " << n;
      ++periods_checked;
    }
    shares.clear();
    ASSERT_EQ(paced_solver.time(), whole_solver.time());
    ASSERT_EQ(paced_solver.state().positions, whole_solver.state().positions);
    ASSERT_EQ(paced_solver.state().velocities, whole_solver.state().velocities);
    for (std::size_t k = 0; k < force.size(); ++k)
      force[k] = Vec3{0.0, 0.01 * std::sin(0.1 * n + k), -0.02 * (1.0 + std::cos(0.3 * n))};
    for (StructureSide* side : {&paced, &whole}) {
      side->receive(force, time - last_sync);  // the DEM's window since its last sync
      side->synchronised();
      side->begin_period(dem_dt);
    }
    last_sync = time;
  }
  EXPECT_GT(periods_checked, 150);
  EXPECT_GT(paced_solver.step_count(), 6000);
}

// The run loop's path: the coupler as an end-of-step hook of plain sim::step calls gives the
// same states, bit for bit, as advance_period (between syncs neither solver sees the other).
TEST(StructureCoupler, StepHookMatchesAdvancePeriod) {
  const testing::PlateCards plate = free_plate();
  const std::string deck = thrown_beads_deck();
  CoupledScene by_period = make_scene(plate, deck), by_hook = make_scene(plate, deck);
  fem::ShellSolver solver_period(by_period.adapted.model), solver_hook(by_hook.adapted.model);
  const CouplerOptions options{.schedule = resolve_schedule(5.0 * by_period.world.dt, std::nullopt, 1.0)};
  StructureCoupler period(by_period.world, by_period.surface, solver_period, by_period.mesh.node_of_vertex, options);
  StructureCoupler hook(by_hook.world, by_hook.surface, solver_hook, by_hook.mesh.node_of_vertex, options);
  by_hook.world.hooks.push_back(hook.step_hook());
  period.advance_to(0.03);
  while (by_hook.world.time < by_period.world.time - 0.5 * by_hook.world.dt) sim::step(by_hook.world);
  ASSERT_EQ(by_hook.world.step_count, by_period.world.step_count);
  EXPECT_EQ(hook.schedule().synchronisations(), period.schedule().synchronisations());
  EXPECT_EQ(by_hook.world.particles.position, by_period.world.particles.position);
  const auto x_hook = solver_hook.positions(), x_period = solver_period.positions();
  EXPECT_TRUE(std::equal(x_hook.begin(), x_hook.end(), x_period.begin()));
  EXPECT_GT(period.schedule().synchronisations(), 100);
}

// The structure alongside the DEM (structure_run.cpp's hooks): its steps between syncs as an
// alongside hook, on a thread of its own when the world has two, and the sync at the end of the
// DEM's step give the states of the end-of-step hook alone, bit for bit.
TEST(StructureCoupler, AlongsideOnItsOwnThreadMatchesTheEndOfStepHook) {
  const testing::PlateCards plate = free_plate();
  const std::string deck = thrown_beads_deck();
  CoupledScene in_turn = make_scene(plate, deck), alongside = make_scene(plate, deck);
  in_turn.world.threading = Threading{1, 0};
  alongside.world.threading = Threading{2, 0};
  fem::ShellSolver solver_in_turn(in_turn.adapted.model), solver_alongside(alongside.adapted.model);
  const CouplerOptions options{.schedule = resolve_schedule(5.0 * in_turn.world.dt, std::nullopt, 1.0)};
  StructureCoupler hook(in_turn.world, in_turn.surface, solver_in_turn, in_turn.mesh.node_of_vertex, options);
  StructureCoupler beside(alongside.world, alongside.surface, solver_alongside, alongside.mesh.node_of_vertex,
                          options);
  in_turn.world.hooks.push_back(hook.step_hook());
  alongside.world.hooks.push_back({HookStage::alongside, "structure", [&beside](World& w) {
                                     beside.keep_up(w.time, w.dt, w.alongside_threading);
                                   }});
  alongside.world.hooks.push_back(beside.step_hook());
  while (in_turn.world.time < 0.03) sim::step(in_turn.world);
  while (alongside.world.step_count < in_turn.world.step_count) sim::step(alongside.world);
  EXPECT_EQ(beside.schedule().synchronisations(), hook.schedule().synchronisations());
  EXPECT_EQ(alongside.world.particles.position, in_turn.world.particles.position);
  EXPECT_EQ(alongside.world.particles.velocity, in_turn.world.particles.velocity);
  EXPECT_EQ(solver_alongside.state().positions, solver_in_turn.state().positions);
  EXPECT_EQ(solver_alongside.state().velocities, solver_in_turn.state().velocities);
  EXPECT_EQ(solver_alongside.energies().internal, solver_in_turn.energies().internal);
  EXPECT_GT(hook.schedule().synchronisations(), 100);
  // It did run on its own thread, for most of the structure's steps.
  const StageTimers& own = alongside.world.alongside_timers;
  ASSERT_EQ(own.names().size(), 1u);
  EXPECT_GT(own.seconds(0), 0.0);
  EXPECT_GT(solver_alongside.step_count(), 0);
}

// Determinism (DESIGN §3): the coupled run on 1 and on 2 threads (threshold 0, so that even
// this small scene runs its loops on both) ends in bit-identical particles and structure.
TEST(StructureCoupler, BitIdenticalOnOneAndTwoThreads) {
  const testing::PlateCards plate{.divisions = 4, .side = 0.06, .thickness = 0.001};
  const std::string beads = R"(  - name: fill
    particle_type: bead
    region: {type: box, min: [0.0025, 0.0025, 0.003], max: [0.0575, 0.0575, 0.03]}
    count: 150)";
  const std::string deck = bed_deck("[0, 0, -9.81]", beads, "{rayleigh_fraction: 0.2}");
  struct Result {
    std::vector<Vec3> particles, nodes;
  };
  const auto run = [&](int threads) {
    CoupledScene scene = make_scene(plate, deck);
    scene.world.threading = Threading{threads, 0};
    fem::ShellSolverOptions options;
    options.threading = Threading{threads, 0};
    options.mass_scaling_time_step = 1e-5;
    fem::ShellSolver solver(scene.adapted.model, options);
    StructureCoupler coupler(scene.world, scene.surface, solver, scene.mesh.node_of_vertex,
                             {.schedule = resolve_schedule(4.0 * scene.world.dt, std::nullopt, 1.0)});
    coupler.advance_to(0.04);  // s: the lowest beads start 3 mm up, 25 ms of fall
    const auto x = solver.positions();
    return Result{scene.world.particles.position, std::vector<Vec3>(x.begin(), x.end())};
  };
  const Result one = run(1), two = run(2);
  EXPECT_EQ(one.particles, two.particles);
  EXPECT_EQ(one.nodes, two.nodes);
  double largest = 0.0;  // m, the plate did move
  for (const Vec3& x : one.nodes) largest = std::max(largest, std::abs(x.z));
  EXPECT_GT(largest, 0.0);
}

}  // namespace
}  // namespace quarry::fsi
