// The time step, read top to bottom (DESIGN §2). Velocity Verlet (Swope et al. 1982): half
// kick, drift, move the geometry, forces at the new configuration, half kick. Symplectic Euler:
// full kick with the forces of the previous configuration, drift, geometry, forces. The order
// matters: forces are always computed at one consistent configuration of particles and
// surfaces, and every stage leaves the state whole for the next one.
#include "sim/step.h"

#include <omp.h>

#include <algorithm>
#include <memory>

#include "sim/exchange.h"
#include "sim/output.h"

namespace quarry::sim {

namespace {

bool velocity_verlet(const World& world) {
  return world.spec.simulation.integrator.value == Integrator::velocity_verlet;
}

// The forces of the configuration as it stands: body forces, contacts, then the hooks that add
// velocity-dependent forces. h (s): the lead of the force's time over the velocities
// (set_velocity_leads), read from the forces still held from the step before.
void compute_forces(World& world, double h) {
  {
    ScopedStage timer(world.timers, world.timers.stage("integrate"));
    set_velocity_leads(world, h);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("body forces"));
    set_body_forces(world);
  }
  compute_contact_forces(world);  // times itself: "pair forces", "surface forces"
  run_hooks(world, HookStage::post_force);
}

// The alongside hooks of one step (HookStage::alongside). When the world's team has a thread to
// spare they start on the world's worker thread once the clock has advanced, and the stages run
// on the rest of the team; else they run in turn at finish(). finish() (before the end_of_step
// hooks) waits for them and gives the thread back; so does the destructor if a stage threw.
class AlongsideHooks {
 public:
  explicit AlongsideHooks(World& world) : world_(world), configured_(world.threading.threads) {
    for (const StepHook& hook : world.hooks) present_ = present_ || hook.stage == HookStage::alongside;
    if (!present_) return;
    const int team = configured_ > 0 ? configured_ : omp_get_max_threads();
    threaded_ = team >= 2;
    world.alongside_threading = world.threading;
    if (threaded_) {
      world.threading.threads = team - 1;
      world.alongside_threading.threads = 1;
    }
  }
  AlongsideHooks(const AlongsideHooks&) = delete;
  AlongsideHooks& operator=(const AlongsideHooks&) = delete;
  ~AlongsideHooks() {
    if (started_) {
      try {
        world_.alongside->wait();
      } catch (...) {  // the stage's own error is the one on its way out
      }
    }
    if (threaded_) world_.threading.threads = configured_;  // also when a stage threw before start()
  }

  void start() {
    if (!threaded_) return;
    if (!world_.alongside) world_.alongside = std::make_unique<WorkerThread>();
    // Their one-thread loops shared with this thread once it waits for them in finish().
    world_.alongside_threading.shared = &world_.alongside->shared_loops();
    world_.alongside->start([this] { run(world_.alongside_timers); });
    started_ = true;
  }

  void finish() {
    if (!present_) return;
    if (!threaded_) {
      run(world_.timers);
      return;
    }
    ScopedStage timer(world_.timers, world_.timers.stage("alongside (waited)"));
    started_ = false;
    world_.threading.threads = configured_;
    world_.alongside->wait();
  }

 private:
  void run(StageTimers& timers) {
    for (StepHook& hook : world_.hooks) {
      if (hook.stage != HookStage::alongside) continue;
      ScopedStage timer(timers, timers.stage("hook " + hook.name));
      hook.run(world_);
    }
  }

  World& world_;
  const int configured_;  // the world's threads setting, given back at the end
  bool present_ = false, threaded_ = false, started_ = false;
};

}  // namespace

void initialize(World& world) {
  const ThreadScope threads(world.threading);
  drive_surfaces(world, world.time);
  insert_and_remove(world);
  rebuild_lists(world);
  compute_forces(world, 0.0);  // the velocities are those of the configuration
  world.initialized = true;
  if (world.output) {
    ScopedStage timer(world.timers, world.timers.stage("output"));
    world.output->start(world);  // the first monitor row and frame
  }
}

void step(World& world) {
  AlongsideHooks alongside(world);  // takes a thread from the team for them when it can
  const ThreadScope threads(world.threading);
  const double dt = world.dt;  // s
  const bool verlet = velocity_verlet(world);
  DriftScan scan;  // what the drift saw: NaNs, particles outside the domain, displacements
  {
    // The kicks add the one-step loads a partner set (ParticleStore::apart_once_loads).
    ScopedStage timer(world.timers, world.timers.stage("integrate"));
    scan = kick_drift_scan(world, verlet ? 0.5 * dt : dt, dt);
  }
  world.time += dt;
  world.step_count += 1;
  alongside.start();
  {
    // Before anything else looks at positions: a NaN particle must stop the run, not be
    // mistaken for one that left the domain.
    ScopedStage timer(world.timers, world.timers.stage("guards"));
    check_finite(world, scan);
    check_tunnelling(world, scan, dt);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("geometry"));
    drive_surfaces(world, world.time);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("insert/remove"));
    insert_and_remove(world, scan);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("neighbor"));
    update_neighbors(world, scan);
  }
  // Body forces, contacts, post_force hooks. Velocity Verlet's velocities are half a step
  // behind the positions here; the dashpots take them forward by the previous forces' half kick.
  compute_forces(world, verlet ? 0.5 * dt : 0.0);
  if (verlet) {
    ScopedStage timer(world.timers, world.timers.stage("integrate"));
    closing_kick(world, 0.5 * dt);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("guards"));
    check_overlaps(world);
  }
  {
    ScopedStage timer(world.timers, world.timers.stage("loads"));
    end_of_step_loads(world);
  }
  alongside.finish();
  run_hooks(world, HookStage::end_of_step);
  if (world.output) {
    ScopedStage timer(world.timers, world.timers.stage("output"));
    world.output->after_step(world);  // monitors, frames, load export, checkpoints when due
  }
}

void advance(World& world, std::uint64_t steps) {
  for (std::uint64_t s = 0; s < steps; ++s) step(world);
}

void run_hooks(World& world, HookStage stage) {
  for (StepHook& hook : world.hooks) {
    if (hook.stage != stage) continue;
    ScopedStage timer(world.timers, world.timers.stage("hook " + hook.name));
    hook.run(world);
  }
}

void end_of_step_loads(World& world) {
  for (WorldSurface& s : world.surfaces) {
    if (s.output_window.sized()) s.output_window.accumulate(s.mesh, world.dt);
    if (s.coupling_window.sized()) s.coupling_window.accumulate(s.mesh, world.dt);
  }
  ParticleStore& p = world.particles;
  if (!p.has_external_loads() || p.once_loads == 0) return;
  // One-step loads acted in both kicks of this step: out of the forces if something had put
  // them there (a read inside a hook), and zeroed for the next one.
  unsettle_once_loads(world);
  const bool force = p.once_loads & ParticleStore::kForceLoads, torque = p.once_loads & ParticleStore::kTorqueLoads;
  p.once_loads = 0;
  const std::size_t n = p.size();
  const std::span<const std::uint32_t> ranges = particle_ranges(world);
#pragma omp parallel num_threads(world.threading.team(n))
  {
    const auto [first, end] = thread_block(n, omp_get_thread_num(), omp_get_num_threads(), ranges);
    if (force) std::fill(p.external_force_once.begin() + first, p.external_force_once.begin() + end, Vec3{});
    if (torque) std::fill(p.external_torque_once.begin() + first, p.external_torque_once.begin() + end, Vec3{});
  }
}

}  // namespace quarry::sim
