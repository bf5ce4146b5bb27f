// Whole-simulation verification cases (tests/verification/NN-name/): each compares the engine,
// all stages together, with a closed-form result; the formula and its source are cited per test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geometry/stl_reader.h"
#include "integrate/integrator.h"
#include "sim/exchange.h"
#include "sim/run.h"
#include "verification/test_support.h"

namespace quarry {
namespace {

using testing_support::deck_path;
using testing_support::start_world;
using testing_support::total_mass;

// 01 — Static equilibrium of a settled bed (Newton's first law for the whole bed): once the
// kinetic energy has decayed, the walls carry the weight, Σ F_wall,z = Σ m g, to 0.5 %.
TEST(Verification, SettledBedWallsCarryTheWeight) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/01-settled-bed/deck.yaml"));
  World world = start_world(spec);
  ASSERT_EQ(world.particles.size(), 300u);
  const double end = spec.simulation.end_time.value;
  while (world.time < end - 0.05) sim::step(world);
  // Average over the last 0.05 s to remove the remaining rattling (N).
  double wall_force = 0.0;
  int samples = 0;
  while (world.time < end) {
    sim::step(world);
    wall_force += world.surfaces[0].mesh.total_force.z;
    ++samples;
  }
  wall_force /= samples;
  const double weight = total_mass(world) * 9.81;  // N
  EXPECT_EQ(world.particles.size(), 300u);
  // The bed pushes the floor down: force on the box is −weight in z.
  EXPECT_NEAR(-wall_force / weight, 1.0, 0.005) << "wall force " << wall_force << " N, weight " << weight;
}

// Drops the single sphere of `spec` on its floor; returns rebound / impact speed (1).
double measured_restitution(const SimulationSpec& spec) {
  World world = start_world(spec);
  EXPECT_EQ(world.particles.size(), 1u);
  double impact = 0.0, rebound = 0.0;  // m/s
  bool touched = false;
  while (world.time < spec.simulation.end_time.value) {
    const double vz = world.particles.velocity[0].z;
    if (world.wall_contact_count() == 0) {
      if (!touched) impact = std::max(impact, -vz);
      else rebound = std::max(rebound, vz);
      // Past the apex, or without gravity off the floor for good: done.
      if (touched && (vz <= 0 || spec.simulation.gravity.value == Vec3{})) break;
    } else {
      touched = true;
    }
    sim::step(world);
  }
  EXPECT_TRUE(touched);
  return rebound / impact;
}

// 02 — Restitution of a sphere dropped on a tessellated floor: v_out / v_in = e for the
// Hertz-Mindlin law with EDEM's damping, β = ln e / sqrt(ln² e + π²) (Tsuji et al. 1992; EDEM
// theory guide). Gravity acts during the ~0.1 ms contact; its effect g·T ≈ 1e-3 m/s is 0.1 % of
// the 1 m/s impact speed, inside the 1 % tolerance.
TEST(Verification, BouncingSphereReboundsWithRestitution) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/02-bouncing-sphere/deck.yaml"));
  EXPECT_NEAR(measured_restitution(spec), 0.5, 0.005);
}

// 02 at the default step, at any phase, sphere on sphere too: restitution_test.cpp.

// 05 — Determinism: the same deck gives a bit-identical state for 1, 2, 3 and 4 threads
// (DESIGN §3). With 3 and 4 threads a particle receives pair forces computed in several earlier
// threads' ranges (sim/forces.cpp), the hardest case of the fixed summation order.
TEST(Verification, StateIsBitIdenticalForOneToFourThreads) {
  const SimulationSpec spec = parse_deck(deck_path("tests/verification/05-determinism/deck.yaml"));
  std::uint64_t hashes[4];
  std::size_t counts[4];
  for (int threads : {1, 2, 3, 4}) {
    World world = start_world(spec, threads);
    for (int n = 0; n < 800; ++n) sim::step(world);
    hashes[threads - 1] = sim::state_hash(world);
    counts[threads - 1] = world.particles.size();
    EXPECT_GT(world.pair_contact_count(), 0u);
  }
  for (int t = 1; t < 4; ++t) {
    EXPECT_EQ(counts[0], counts[t]) << t + 1 << " threads";
    EXPECT_EQ(hashes[0], hashes[t]) << t + 1 << " threads";
  }
}

// 05 — The thread governor (sim/thread_governor.h) changes the team between steps: a run whose
// team changes at irregular steps (1, 2, 3 threads) ends bit-identical to one thread throughout.
TEST(Verification, StateIsBitIdenticalWhenTheTeamChangesBetweenSteps) {
  const SimulationSpec spec = parse_deck(deck_path("tests/verification/05-determinism/deck.yaml"));
  World steady = start_world(spec, 1);
  World changing = start_world(spec, 2);
  for (int n = 0; n < 800; ++n) {
    sim::step(steady);
    changing.threading.threads = 1 + (n * 7 / 5 + n / 13) % 3;
    sim::step(changing);
  }
  EXPECT_GT(changing.pair_contact_count(), 0u);
  EXPECT_EQ(sim::state_hash(steady), sim::state_hash(changing));
}

// 05 — Determinism with symplectic Euler: its step has no closing half kick.
TEST(Verification, SymplecticEulerStateIsBitIdenticalForOneToThreeThreads) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/05-determinism/deck.yaml"));
  spec.simulation.integrator.value = Integrator::symplectic_euler;
  std::uint64_t hashes[3];
  for (int threads : {1, 2, 3}) {
    World world = start_world(spec, threads);
    for (int n = 0; n < 600; ++n) sim::step(world);
    EXPECT_GT(world.pair_contact_count(), 0u);
    EXPECT_FALSE(world.wall_contacts.empty());
    hashes[threads - 1] = sim::state_hash(world);
  }
  EXPECT_EQ(hashes[0], hashes[1]) << "2 threads";
  EXPECT_EQ(hashes[0], hashes[2]) << "3 threads";
}

// 05 — Many worlds in one process: each keeps its own thread count and threshold (no process-
// wide settings), so two worlds stepped in turn, one on 1 thread and one on 3, each end in the
// state it reaches alone.
TEST(Verification, WorldsSteppedInTurnEachReachTheirOwnState) {
  const SimulationSpec spec = parse_deck(deck_path("tests/verification/05-determinism/deck.yaml"));
  SimulationSpec other = spec;
  other.simulation.gravity.value = Vec3{0.0, 0.0, -5.0};
  World alone_a = start_world(spec, 1), alone_b = start_world(other, 3);
  sim::advance(alone_a, 300);
  sim::advance(alone_b, 300);
  World a = start_world(spec, 1), b = start_world(other, 3);
  for (int n = 0; n < 300; ++n) sim::step(a), sim::step(b);
  EXPECT_EQ(sim::state_hash(a), sim::state_hash(alone_a));
  EXPECT_EQ(sim::state_hash(b), sim::state_hash(alone_b));
  EXPECT_NE(sim::state_hash(a), sim::state_hash(b));
}

// 05 — Determinism whatever the split: the threads' row ranges follow their measured speed
// and are drawn again between list builds when it changes (sim/forces.cpp). Here the shares
// are forced to swing every step (a thread 3× slower, then the other), so a new split is made
// on most steps in the middle of each list's life; the state must stay bit-identical to one
// thread's. The uneven split also makes the threads with less work take chunks of surface
// contacts whose particles another thread is still summing: their sums are then added after
// the barrier instead of at once, which must not change the state either.
TEST(Verification, StateIsBitIdenticalWhenTheThreadRangesMoveEveryStep) {
  const SimulationSpec spec = parse_deck(deck_path("tests/verification/05-determinism/deck.yaml"));
  std::size_t deferred = 0;  // surface sums added after the barrier, over all steps
  const auto run = [&spec, &deferred](int threads, bool swing) {
    World world = start_world(spec, threads);
    std::uint64_t plans = 0, last_start = 0;
    for (int n = 0; n < 800; ++n) {
      auto& share = world.force_workspace.range_share;
      if (swing && share.size() == static_cast<std::size_t>(threads)) {
        std::fill(share.begin(), share.end(), 1.0);
        share[n % threads] = 3.0;
        double sum = 0.0;
        for (double x : share) sum += x;
        for (double& x : share) x /= sum;
      }
      sim::step(world);
      for (const auto& kept : world.force_workspace.wall_deferred) deferred += kept.size();
      const auto& plan = world.force_workspace.plan;
      if (threads > 1 && plan.range_start.size() > 1 && plan.range_start[1] != last_start)
        ++plans, last_start = plan.range_start[1];
    }
    if (swing) {
      EXPECT_GT(plans, 400u) << threads << " threads: the split should move on most steps";
    }
    return sim::state_hash(world);
  };
  const std::uint64_t one = run(1, false);
  EXPECT_EQ(one, run(2, true)) << "2 threads";
  EXPECT_EQ(one, run(3, true)) << "3 threads";
  EXPECT_GT(deferred, 0u) << "no surface sum was kept for after the barrier: that path went untested";
}

// 05 — Restart: a run stopped at its checkpoint and restarted ends bit-identical to the run
// that went through.
TEST(Verification, RestartContinuesBitIdentically) {
  namespace fs = std::filesystem;
  const std::string deck = deck_path("tests/verification/05-determinism/deck.yaml");
  const SimulationSpec spec = parse_deck(deck);
  const fs::path straight = fs::path(testing::TempDir()) / "quarry_restart_straight";
  const fs::path split = fs::path(testing::TempDir()) / "quarry_restart_split";
  fs::remove_all(straight);
  fs::remove_all(split);
  sim::RunOptions options;
  options.quiet = true;
  std::ostringstream sink;
  options.log = &sink;

  World through = build_world(spec);
  options.output_directory = straight.string();
  sim::run(through, options);

  World first = build_world(spec);
  options.output_directory = split.string();
  options.end_time = 0.025;  // the checkpoint at 0.015 s is the last one written
  sim::run(first, options);
  options.end_time.reset();
  const sim::RunSummary second = sim::restart((split / "checkpoint.qck").string(), options);
  EXPECT_FALSE(second.interrupted());
  EXPECT_NEAR(second.simulated_time, through.time, 1e-12);
  EXPECT_EQ(second.particles, through.particles.size());
  EXPECT_EQ(second.final_state_hash, sim::state_hash(through));
}

// 05 — The run loop is plain steps with the output stage attached: its final state is that of
// plain steps to the bit (writing frames, monitors and checkpoints changes nothing).
TEST(Verification, RunEndsInTheStateOfPlainSteps) {
  const SimulationSpec spec = parse_deck(deck_path("tests/verification/05-determinism/deck.yaml"));
  const std::filesystem::path directory = std::filesystem::path(testing::TempDir()) / "quarry_run_plain";
  std::filesystem::remove_all(directory);
  sim::RunOptions options;
  options.quiet = true;
  std::ostringstream sink;
  options.log = &sink;
  options.output_directory = directory.string();
  World ran = build_world(spec);
  const sim::RunSummary summary = sim::run(ran, options);
  World stepped = start_world(spec);
  std::uint64_t steps = 0;
  while (stepped.time < spec.simulation.end_time.value - 0.5 * stepped.dt) sim::step(stepped), ++steps;
  EXPECT_EQ(summary.steps, steps);
  EXPECT_EQ(summary.final_state_hash, sim::state_hash(stepped));
}

// 05 — A checkpoint taken between any two steps restores the complete state: the restored world
// and the original go on to the same bits, and the restore needs no file of the deck.
TEST(Verification, CheckpointBetweenStepsRestoresTheCompleteState) {
  const SimulationSpec spec = parse_deck(deck_path("tests/verification/05-determinism/deck.yaml"));
  World world = start_world(spec, 2);
  for (int n = 0; n < 137; ++n) sim::step(world);  // not at any output time
  const std::string bytes = sim::checkpoint_bytes(world, 0);
  sim::RestoredWorld restored = sim::read_checkpoint_bytes(bytes, "memory");
  restored.world.threading = world.threading;
  EXPECT_EQ(sim::state_hash(restored.world), sim::state_hash(world));
  sim::advance(world, 200);
  sim::advance(restored.world, 200);
  EXPECT_EQ(sim::state_hash(restored.world), sim::state_hash(world));
}

}  // namespace
}  // namespace quarry

namespace quarry {
namespace {

// 01b — Per-triangle pressure: the floor's mean normal stress over an output window, integrated
// over the floor, Σ p_t A_t, equals the normal force the bed puts on it (the definition of the
// mean stress, DESIGN §5). At rest the floor and the side walls' vertical friction carry the
// weight together (static equilibrium, within 0.5 %). Which way the walls' friction points hangs
// on how the bed came to rest (a bed that slid down leans on the walls, one that sprang back
// after the impacts is held down by them: floor / weight 0.94–1.01 over five factory seeds), but
// Coulomb bounds it whichever way: |Σ f_z| ≤ μ_w Σ N over the side walls, so
// |W − N_floor| ≤ μ_w N_side (μ_w = 0.5, glass on steel in the deck).
TEST(Verification, SettledBedFloorPressureIntegratesToTheLoad) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/01-settled-bed/deck.yaml"));
  World world = start_world(spec);
  const double end = spec.simulation.end_time.value;
  while (world.time < end - 0.05) sim::step(world);
  const Surface& box = world.surfaces[0].mesh;
  LoadWindow window(box);
  while (world.time < end) {
    sim::step(world);
    window.accumulate(box, world.dt);
  }
  LoadFrame means;
  window.take_means(box, world.time, means);
  const std::vector<double>& pressure = means.pressure;
  const std::vector<Vec3>& force = means.force;
  double normal_on_floor = 0.0, vertical_total = 0.0;  // N
  double side_normal = 0.0, side_vertical = 0.0;         // N, the side walls' (normals horizontal)
  for (std::size_t t = 0; t < box.triangle_count(); ++t) {
    const Vec3& n = box.triangle_normals[t];  // into the box
    vertical_total += force[t].z;
    if (n.z > 0.99) normal_on_floor += pressure[t] * box.triangle_areas[t];
    if (std::abs(n.z) < 0.01) {
      side_normal += -dot(force[t], n);
      side_vertical += force[t].z;
    }
  }
  const double weight = total_mass(world) * 9.81;  // N
  const double wall_friction = 0.5;                // μ glass–steel, the deck's
  EXPECT_NEAR(-vertical_total / weight, 1.0, 0.005);
  EXPECT_GT(normal_on_floor, 0.0);
  EXPECT_GT(side_normal, 0.0);
  EXPECT_LE(std::abs(side_vertical), wall_friction * side_normal);
  EXPECT_LE(std::abs(weight - normal_on_floor), wall_friction * side_normal + 0.005 * weight);
  std::printf("[ settled  ] floor / W %.4f, side walls' friction / (mu N_side) %.3f\n",
              normal_on_floor / weight, -side_vertical / (wall_friction * side_normal));
  // The floor's pressure integral is its own vertical force (the floor is horizontal).
  double floor_vertical = 0.0;
  for (std::size_t t = 0; t < box.triangle_count(); ++t)
    if (box.triangle_normals[t].z > 0.99) floor_vertical += -force[t].z;
  EXPECT_NEAR(normal_on_floor / floor_vertical, 1.0, 1e-9);
}

// 06 — Conveyor surface: a sphere set down at rest on a belt moving at U is dragged by sliding
// friction until it rolls without slip. Linear and angular impulse of the same friction J give
// v = J/m and ω R = J R²/I; no slip, v + ω R = U with I = 2/5 m R², gives v = 2/7 U (classic
// rigid-body result, e.g. Brilliantov & Pöschel 2004, the sliding-to-rolling transition).
TEST(Verification, SphereOnConveyorEndsAtTwoSeventhsOfBeltSpeed) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/02-bouncing-sphere/deck.yaml"));
  spec.factories.clear();
  spec.surfaces[0].conveyor_velocity = Vec3{0.5, 0, 0};
  World world = start_world(spec);
  const double radius = 0.005;  // m, the type's
  sim::NewParticle sphere;
  sphere.position = {0, 0, radius * 0.9999};
  sim::add_particles(world, std::span(&sphere, 1));
  while (world.time < 0.1) sim::step(world);
  EXPECT_NEAR(world.particles.velocity[0].x / (2.0 / 7.0 * 0.5), 1.0, 0.01);
  EXPECT_NEAR(world.particles.angular_velocity[0].y * radius / (5.0 / 7.0 * 0.5), -1.0, 0.01);
}

// 11 — Guard: a particle that leaves the domain is removed and counted, the others stay.
TEST(Verification, ParticlesLeavingTheDomainAreRemovedAndCounted) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/02-bouncing-sphere/deck.yaml"));
  spec.factories.clear();
  World world = start_world(spec);
  std::vector<sim::NewParticle> added(2);
  added[0].position = {0.0, 0.0, 0.05};
  added[1].position = {0.09, 0.0, 0.15};
  added[1].velocity = {5, 0, 0};  // m/s: out through x = 0.1 m in about 2 ms
  const std::vector<ParticleId> ids = sim::add_particles(world, added);
  for (int n = 0; n < 2000; ++n) sim::step(world);
  ASSERT_EQ(world.particles.size(), 1u);
  EXPECT_EQ(world.particles.id[0], ids[0]);
  EXPECT_EQ(world.removed_outside, 1u);
}

}  // namespace
}  // namespace quarry

namespace quarry {
namespace {

// 11 — Guard: a non-finite state stops the run with the step, the particle id, the values and
// a hint (instead of silently spreading NaN through the bed).
TEST(Verification, NonFiniteStateStopsWithStepParticleAndHint) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/02-bouncing-sphere/deck.yaml"));
  World world = start_world(spec);
  world.particles.velocity[0].z = std::nan("");
  try {
    sim::step(world);
    FAIL() << "expected a PhysicsError";
  } catch (const PhysicsError& e) {
    const std::string text = e.what();
    EXPECT_NE(text.find("step 1 "), std::string::npos) << text;
    EXPECT_NE(text.find("particle id 1 "), std::string::npos) << text;
    EXPECT_NE(text.find("nan"), std::string::npos) << text;
    EXPECT_NE(text.find("hint:"), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace quarry

namespace quarry {
namespace {

// The time step folds the NaN guard, the domain check and the list's displacement check into
// the drift's pass (sim::kick_drift_scan). Its findings must be those of the separate passes:
// same state after the kick-drift, same first non-finite particle, same "someone left", and the
// same rebuild decision (Verlet criterion max |x − x_build| > skin/2, Allen & Tildesley 1987).
TEST(Verification, DriftScanAgreesWithTheSeparatePasses) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/01-settled-bed/deck.yaml"));
  World fused = start_world(spec);
  const int team = fused.threading.team(fused.particles.size());
  for (int n = 0; n < 50; ++n) sim::step(fused);
  const std::size_t n = fused.particles.size();
  ASSERT_GT(n, 100u);
  const double h = 0.5 * fused.dt, dt = fused.dt;  // s
  const auto separate_largest = [](const World& w) {
    double largest = 0.0;  // m²
    for (std::size_t i = 0; i < w.particles.size(); ++i)
      largest = std::max(largest, norm2(w.particles.position[i] - w.pairs.reference_positions[i]));
    return largest;
  };
  {
    World separate = fused;
    const sim::DriftScan scan = sim::kick_drift_scan(fused, h, dt);
    integrate::kick_drift(separate.particles, h, dt, team);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(fused.particles.position[i], separate.particles.position[i]);
    EXPECT_EQ(scan.particles, n);
    EXPECT_EQ(scan.first_non_finite, n);
    EXPECT_FALSE(scan.any_outside);
    EXPECT_TRUE(scan.list_compared);
    EXPECT_FALSE(scan.ids_changed);
    EXPECT_EQ(scan.largest_displacement_squared, separate_largest(separate));
    EXPECT_EQ(pair_list_needs_rebuild(fused.pairs, scan.largest_displacement_squared, scan.ids_changed, 0.0),
              pair_list_needs_rebuild(separate.particles, separate.pairs));
  }
  {
    // One particle moved past the skin/2 criterion in one drift: a rebuild.
    World w = fused;
    w.particles.velocity[n / 3] = {0.6 * w.skin / dt, 0.0, 0.0};  // m/s
    const sim::DriftScan scan = sim::kick_drift_scan(w, h, dt);
    EXPECT_FALSE(scan.any_outside);
    EXPECT_TRUE(pair_list_needs_rebuild(w.pairs, scan.largest_displacement_squared, false, 0.0));
    EXPECT_TRUE(pair_list_needs_rebuild(w.particles, w.pairs));
  }
  {
    // One particle outside the domain, two made NaN: the first of them is reported.
    World w = fused;
    w.particles.position[n / 2] = w.spec.simulation.domain.value.hi + Vec3{1.0, 1.0, 1.0};
    w.particles.angular_velocity[n - 2].y = std::nan("");
    w.particles.angular_velocity[n - 1].x = std::nan("");
    const sim::DriftScan scan = sim::kick_drift_scan(w, h, dt);
    EXPECT_EQ(scan.first_non_finite, n - 2);
    EXPECT_TRUE(scan.any_outside);
    EXPECT_THROW(sim::check_finite(w, scan), PhysicsError);
  }
}

// The opening pass takes four particles at a time (sim/opening_lanes.h) and the rest one by one.
// Both must give the scalar pass's values to the bit: the kick v += F h/m, ω += τ h/I
// (I = 2/5 m R², a solid sphere) and the drift x += v dt, the largest |x − x_build|², and every
// flag, whatever lane of a block of four (or the tail) a particle falls in, on one thread or two
// (other splits into blocks), with and without the one-step loads a partner keeps apart.
TEST(Verification, TheOpeningPassInBlocksOfFourIsTheScalarPass) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/01-settled-bed/deck.yaml"));
  World base = start_world(spec);
  for (int s = 0; s < 20; ++s) sim::step(base);
  base.threading.threshold = 0;  // two threads even for this small bed
  const std::size_t n = base.particles.size();
  ASSERT_GT(n, 100u);
  // Every particle different from its neighbours in every lane: random kinematics and loads,
  // the velocities and spins of the order of one kick's change (so that a last bit of the
  // change shows in the sum), every seventh at rest (the sum is the change itself).
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto vec = [&](double scale) { return Vec3{unit(random), unit(random), unit(random)} * scale; };
  for (std::size_t i = 0; i < n; ++i) {
    ParticleStore& p = base.particles;
    p.force[i] = vec(1e-3);   // N
    p.torque[i] = vec(1e-7);  // N·m
    const double h = 0.5 * base.dt;  // s
    const bool rest = i % 7 == 0;
    p.velocity[i] = rest ? Vec3{} : vec(h * p.inv_mass[i] * 1e-3);                // m/s
    p.angular_velocity[i] = rest ? Vec3{} : vec(h * p.inv_inertia(i) * 1e-7);      // rad/s
  }
  const double h = 0.5 * base.dt, dt = base.dt;  // s
  const Aabb domain = base.spec.simulation.domain.value;
  // The scalar pass, particle by particle.
  const auto scalar = [&](World w) {
    const ParticleStore::ApartLoads apart = w.particles.apart_once_loads();
    sim::DriftScan expected;
    expected.first_non_finite = n;  // none found yet
    for (std::size_t i = 0; i < n; ++i) {
      integrate::kick_drift_particle(w.particles, i, h, dt, apart);
      const Vec3 x = w.particles.position[i], v = w.particles.velocity[i], o = w.particles.angular_velocity[i];
      const bool finite = std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z) &&
                          std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) &&
                          std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z);
      if (!finite && expected.first_non_finite == n) expected.first_non_finite = i;
      expected.any_outside |= !domain.contains(x);
      const double r = w.particles.radius[i];  // m
      expected.fast |= norm2(v) * (dt * dt) > 0.25 * r * r;
      const double d2 = norm2(x - w.pairs.reference_positions[i]);  // m²
      if (d2 > expected.largest_displacement_squared) expected.largest_displacement_squared = d2;
      expected.ids_changed |= w.particles.id[i] != w.pairs.ids_at_build[i];
    }
    return std::pair{w, expected};
  };
  const auto same_bits = [](const Vec3& a, const Vec3& b) {
    return std::memcmp(&a, &b, sizeof(Vec3)) == 0;
  };
  const auto check = [&](const World& start, const std::string& what) {
    const auto [reference, expected] = scalar(start);
    for (const int threads : {1, 2}) {
      SCOPED_TRACE(what + ", " + std::to_string(threads) + " thread(s)");
      World w = start;
      w.threading.threads = threads;
      const ThreadScope scope(w.threading);
      const sim::DriftScan scan = sim::kick_drift_scan(w, h, dt);
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_TRUE(same_bits(w.particles.position[i], reference.particles.position[i])) << i;
        ASSERT_TRUE(same_bits(w.particles.velocity[i], reference.particles.velocity[i])) << i;
        ASSERT_TRUE(same_bits(w.particles.angular_velocity[i], reference.particles.angular_velocity[i])) << i;
      }
      EXPECT_EQ(scan.first_non_finite, expected.first_non_finite);
      EXPECT_EQ(scan.any_outside, expected.any_outside);
      EXPECT_EQ(scan.fast, expected.fast);
      EXPECT_EQ(scan.ids_changed, expected.ids_changed);
      EXPECT_EQ(scan.largest_displacement_squared, expected.largest_displacement_squared);
      EXPECT_TRUE(scan.list_compared);
    }
  };
  check(base, "random state");
  {
    World loaded = base;  // one-step loads kept apart from the forces
    loaded.particles.enable_external_loads();
    for (std::size_t i = 0; i < n; ++i) {
      loaded.particles.external_force_once[i] = vec(1e-3);
      loaded.particles.external_torque_once[i] = vec(1e-7);
    }
    loaded.particles.once_loads = ParticleStore::kForceLoads | ParticleStore::kTorqueLoads;
    ASSERT_TRUE(loaded.particles.apart_once_loads().any());
    check(loaded, "one-step loads");
    loaded.particles.once_loads = ParticleStore::kTorqueLoads;  // torques only
    check(loaded, "one-step torques");
  }
  // One particle at a time in each lane of the first block, of a block in the middle, and at
  // the end (a block's or the tail's): each finding is made whichever lane holds it.
  std::vector<std::size_t> where;
  for (std::size_t l = 0; l < 4; ++l) where.insert(where.end(), {l, n / 2 + l, n - 1 - l});
  for (const std::size_t i : where) {
    const std::string at = " at particle " + std::to_string(i);
    {
      World w = base;  // leaves the domain
      w.particles.position[i] = domain.hi + Vec3{0.0, 0.0, 1.0};
      check(w, "outside" + at);
    }
    {
      World w = base;  // moves more than half its radius in one drift
      w.particles.velocity[i] = {0.0, 0.6 * w.particles.radius[i] / dt, 0.0};
      check(w, "fast" + at);
    }
    {
      World w = base;  // the largest displacement since the list's build
      w.particles.position[i] += Vec3{0.0, 0.0, 0.4 * w.skin};
      check(w, "displaced" + at);
    }
    {
      World w = base;  // another particle where the list had this one
      w.particles.id[i] += 1000000;
      check(w, "id" + at);
    }
    for (int c = 0; c < 3; ++c) {
      World w = base;  // one non-finite component: spin, velocity or position
      Vec3* const what[] = {&w.particles.angular_velocity[i], &w.particles.velocity[i], &w.particles.position[i]};
      (*what[c])[c] = c == 1 ? std::numeric_limits<double>::infinity() : std::nan("");
      check(w, "non-finite" + at);
    }
  }
}


// The step's other per-particle passes take four particles at a time too
// (sim/particle_passes.cpp): the body forces F = m g + held load, τ = held torque; the
// velocity leads h F/m, h τ/I; the closing kick v += h F/m, ω += h τ/I (I = 2/5 m R², a solid
// sphere). Each must give the scalar formulas' values to the bit in every lane of a block of
// four and in the tail, on one thread or two, with and without held and one-step loads, and
// for fixed particles (1/m = 0: no weight, no kick) wherever they fall.
TEST(Verification, TheKicksLeadsAndBodyForcesInBlocksOfFourAreTheScalarPasses) {
  SimulationSpec spec = parse_deck(deck_path("tests/verification/01-settled-bed/deck.yaml"));
  World base = start_world(spec);
  for (int s = 0; s < 5; ++s) sim::step(base);
  base.threading.threshold = 0;  // two threads even for this small bed
  // A count that leaves a tail of three after the blocks of four, whatever the split.
  while (base.particles.size() % 4 != 3) base.particles.remove_flagged([&] {
    std::vector<char> last(base.particles.size(), 0);
    last.back() = 1;
    return last;
  }());
  const std::size_t n = base.particles.size();
  ASSERT_GT(n, 100u);
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto vec = [&](double scale) { return Vec3{unit(random), unit(random), unit(random)} * scale; };
  const double h = 0.5 * base.dt;  // s
  ParticleStore& bp = base.particles;
  for (std::size_t i = 0; i < n; ++i) {
    bp.force[i] = vec(1e-3);   // N
    bp.torque[i] = vec(1e-7);  // N·m
    bp.velocity[i] = vec(h * bp.inv_mass[i] * 1e-3);            // m/s, of the order of a kick
    bp.angular_velocity[i] = vec(h * bp.inv_inertia(i) * 1e-7);  // rad/s
  }
  // Fixed particles in every lane of the first block, mid-way and in the tail.
  for (std::size_t l = 0; l < 4; ++l)
    for (const std::size_t i : {l, n / 2 + l, n - 1 - l}) bp.make_fixed(i);
  bp.enable_external_loads();
  const auto same_bits = [](const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; };
  const Vec3 gravity = base.spec.simulation.gravity.value;  // m/s²
  const auto check = [&](const World& start, const std::string& what) {
    // The scalar passes, particle by particle.
    World reference = start;
    ParticleStore& rp = reference.particles;
    const ParticleStore::ApartLoads apart = rp.apart_once_loads();
    std::vector<Vec3> lead(n), spin_lead(n), body_force(n), body_torque(n);
    const bool held_force = rp.held_loads & ParticleStore::kForceLoads;
    const bool held_torque = rp.held_loads & ParticleStore::kTorqueLoads;
    for (std::size_t i = 0; i < n; ++i) {
      lead[i] = integrate::kick_force(rp, i, apart) * (h * rp.inv_mass[i]);
      spin_lead[i] = integrate::kick_torque(rp, i, apart) * (h * rp.inv_inertia(i));
      integrate::kick_particle(rp, i, h, apart);
      body_force[i] = rp.inv_mass[i] > 0.0 ? gravity / rp.inv_mass[i] : Vec3{};
      if (held_force) body_force[i] += rp.external_force[i];
      if (held_torque) body_torque[i] += rp.external_torque[i];
    }
    for (const int threads : {1, 2}) {
      SCOPED_TRACE(what + ", " + std::to_string(threads) + " thread(s)");
      World w = start;
      w.threading.threads = threads;
      const ThreadScope scope(w.threading);
      sim::set_velocity_leads(w, h);
      sim::closing_kick(w, h);
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_TRUE(same_bits(w.force_workspace.velocity_lead[i], lead[i])) << i;
        ASSERT_TRUE(same_bits(w.force_workspace.angular_velocity_lead[i], spin_lead[i])) << i;
        ASSERT_TRUE(same_bits(w.particles.velocity[i], rp.velocity[i])) << i;
        ASSERT_TRUE(same_bits(w.particles.angular_velocity[i], rp.angular_velocity[i])) << i;
      }
      sim::set_body_forces(w);
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_TRUE(same_bits(w.particles.force[i], body_force[i])) << i;
        ASSERT_TRUE(same_bits(w.particles.torque[i], body_torque[i])) << i;
      }
      EXPECT_FALSE(w.particles.once_in_forces);
    }
    // The physics, not only the agreement: a fixed particle carries no weight (only a held
    // load) and does not move.
    EXPECT_EQ(body_force[0], held_force ? rp.external_force[0] : Vec3{});
    EXPECT_EQ(rp.velocity[n - 1], start.particles.velocity[n - 1]);
  };
  check(base, "no loads");
  {
    World loaded = base;
    for (std::size_t i = 0; i < n; ++i) {
      loaded.particles.external_force[i] = vec(1e-3);
      loaded.particles.external_torque[i] = vec(1e-7);
      loaded.particles.external_force_once[i] = vec(1e-3);
      loaded.particles.external_torque_once[i] = vec(1e-7);
    }
    loaded.particles.held_loads = ParticleStore::kForceLoads | ParticleStore::kTorqueLoads;
    loaded.particles.once_loads = ParticleStore::kForceLoads | ParticleStore::kTorqueLoads;
    ASSERT_TRUE(loaded.particles.apart_once_loads().any());
    check(loaded, "held and one-step loads");
    loaded.particles.held_loads = ParticleStore::kTorqueLoads;
    loaded.particles.once_loads = ParticleStore::kForceLoads;
    check(loaded, "held torques, one-step forces");
    loaded.particles.held_loads = ParticleStore::kForceLoads;
    loaded.particles.once_loads = ParticleStore::kTorqueLoads;
    check(loaded, "held forces, one-step torques");
  }
  {
    // A free particle without loads weighs m g (the weight of its 4/3 π R³ ρ).
    World w = base;
    sim::set_body_forces(w);
    const std::size_t i = 4;
    ASSERT_FALSE(w.particles.fixed(i));
    const double mass = 1.0 / w.particles.inv_mass[i];  // kg
    EXPECT_NEAR(w.particles.force[i].z, mass * gravity.z, 1e-12 * std::abs(mass * gravity.z));
  }
}

}  // namespace
}  // namespace quarry
