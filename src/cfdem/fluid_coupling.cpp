// The coupled step of CFD-DEM (docs/cfd.md "Coupling"): exchange (void fraction, frozen drag
// coefficient, fluid step) every coupling_steps DEM steps, fluid forces on the particles at
// every DEM step. Model A of Zhou, Kuang, Chu & Yu 2010 (J. Fluid Mech. 661:482-510): the
// particle feels drag and −V_p ∇p, the fluid −ε∇p and minus the deposited drag.
#include "cfdem/fluid_coupling.h"

#include <chrono>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "core/diagnostics.h"
#include "core/sphere.h"

namespace quarry::cfdem {

namespace {

void add_warning_once(World& world, const std::string& text) {
  if (std::find(world.warnings.begin(), world.warnings.end(), text) == world.warnings.end())
    world.warnings.push_back(text);
}

}  // namespace

FluidCoupling::FluidCoupling(const World& world, FluidCouplingOptions options)
    : options_(std::move(options)) {
  if (options_.coupling_steps < 1)
    throw std::invalid_argument(fmt::format("coupling_steps must be ≥ 1, got {}", options_.coupling_steps));
  if (!(options_.minimum_void_fraction > 0.0 && options_.minimum_void_fraction < 1.0))
    throw std::invalid_argument(fmt::format("minimum_void_fraction must be in (0, 1), got {}",
                                            options_.minimum_void_fraction));
  // Cells too small for the particles (coupling-notes §3.4: V_cell ≥ 3 V_p as a hard floor).
  const double largest_particle = sphere_volume(world.max_radius);
  const double cell_volume = options_.grid.cell_volume();
  if (world.max_radius > 0.0 && cell_volume < 3.0 * largest_particle)
    throw UserError(
        options_.grid_where,
        fmt::format("fluid cells of {:.4g} m³ ({:.4g} x {:.4g} x {:.4g} m) hold less than 3 times the "
                    "volume of the largest particle ({:.4g} m³, radius {:.4g} m): ratio {:.3g}",
                    cell_volume, options_.grid.cell_size.x, options_.grid.cell_size.y,
                    options_.grid.cell_size.z, largest_particle, world.max_radius,
                    cell_volume / largest_particle),
        "unresolved CFD-DEM averages over cells larger than the particles: use cells of at least "
        "3 particle diameters per side (the void fraction of a smaller cell jumps between 1 and ~0)");
  for (int axis = 0; axis < 3; ++axis)
    periodic_[static_cast<std::size_t>(axis)] =
        options_.boundaries.face(axis, 0).kind == cfd::BoundaryKind::periodic;
  options_.solver.gravity = world.spec.simulation.gravity.value;
  cfd::FluidSolverOptions solver = options_.solver;
  solver.threading = world.threading;
  fluid_ = std::make_unique<cfd::FluidSolver>(options_.grid, options_.properties, options_.boundaries,
                                              solver);
  if (!options_.blocked.empty()) {
    blocked_ = make_blocked_cells(options_.grid, options_.blocked);  // checks the size, not all blocked
    std::span<std::uint8_t> mask = fluid_->blocked();
    for (std::size_t c = 0; c < mask.size(); ++c) mask[c] = blocked_.blocked(c) ? 1 : 0;
  }
  void_fraction_.assign(options_.grid.cell_count(), 1.0);
  update_cell_fields();
  // In this order, so that the indices are the constants of the header.
  for (const char* name : {"void fraction", "drag", "fluid step", "fluid values", "particle forces"})
    timers_.stage(name);
}

std::shared_ptr<FluidCoupling> FluidCoupling::attach(World& world, FluidCouplingOptions options) {
  auto coupling = std::make_shared<FluidCoupling>(world, std::move(options));
  StepHook forces;
  forces.stage = HookStage::post_force;
  forces.name = "fluid coupling";
  forces.run = [coupling](World& w) {
    const auto steps = static_cast<std::uint64_t>(coupling->options().coupling_steps);
    if (w.step_count % steps == 0 && w.step_count != coupling->last_exchange_step_)
      coupling->exchange(w);
    coupling->add_forces(w);
  };
  world.hooks.push_back(std::move(forces));
  CheckpointSection section;
  section.name = "fluid";
  section.save = [coupling](const World&, BinaryWriter& out) { coupling->save_state(out); };
  section.load = [coupling](World& w, BinaryReader& in) { coupling->load_state(in, w); };
  world.checkpoint_sections.push_back(std::move(section));
  return coupling;
}

void FluidCoupling::update_cell_fields(int threads) {
  const cfd::FluidGrid& g = options_.grid;
  cell_velocity_.resize(g.cell_count());
  cell_pressure_gradient_.resize(g.cell_count());
  const std::array<int, 3> n = g.cells;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t c = g.cell_index(i, j, k);
        if (blocked_.blocked(c)) {  // no fluid: no particle weight reads it (cell_kernel.h)
          cell_velocity_[c] = Vec3{};
          cell_pressure_gradient_[c] = Vec3{};
          continue;
        }
        cell_velocity_[c] = fluid_->cell_velocity(i, j, k);
        // ∇p by central differences of the cell pressures (one-sided at a non-periodic border
        // or a blocked neighbour; exact for the hydrostatic field, which is linear). A cell with
        // fluid on neither side along an axis takes the hydrostatic ρ_f g there (model A at rest).
        Vec3 gradient;
        const std::array<int, 3> at{i, j, k};
        for (int axis = 0; axis < 3; ++axis) {
          const auto a = static_cast<std::size_t>(axis);
          if (n[a] == 1) continue;
          std::array<int, 3> low = at, high = at;
          low[a] -= 1;
          high[a] += 1;
          double span = 2.0;
          if (periodic_[a]) {
            low[a] = (low[a] + n[a]) % n[a];
            high[a] = high[a] % n[a];
          } else {
            if (low[a] < 0) low[a] = 0, span = 1.0;
            if (high[a] >= n[a]) high[a] = n[a] - 1, span = 1.0;
          }
          if (blocked_.blocked(g.cell_index(low[0], low[1], low[2]))) low = at, span -= 1.0;
          if (blocked_.blocked(g.cell_index(high[0], high[1], high[2]))) high = at, span -= 1.0;
          gradient[axis] = span > 0.0 ? (fluid_->pressure(high[0], high[1], high[2]) -
                                         fluid_->pressure(low[0], low[1], low[2])) /
                                            (span * g.cell_size[axis])
                                      : options_.properties.density * options_.solver.gravity[axis];
        }
        cell_pressure_gradient_[c] = gradient;
      }
}

void FluidCoupling::compute_weights(const World& world) {
  const ParticleStore& p = world.particles;
  const auto n = static_cast<std::ptrdiff_t>(p.size());
  weights_.resize(p.size());
  moved_to_nearest_.assign(p.size(), 0);
#pragma omp parallel for schedule(static) num_threads(world.threading.team(p.size()))
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    bool moved = false;
    weights_[i] = cell_weights(options_.grid, periodic_, blocked_, p.position[i], &moved);
    moved_to_nearest_[i] = moved ? 1 : 0;
  }
}

void FluidCoupling::warn_particles_among_blocked_cells(World& world) {
  // Once per run, the lowest index of this exchange (the same for any thread count).
  const auto first = std::find(moved_to_nearest_.begin(), moved_to_nearest_.end(), char{1});
  if (blocked_warned_ || first == moved_to_nearest_.end()) return;
  blocked_warned_ = true;
  const auto i = static_cast<std::size_t>(first - moved_to_nearest_.begin());
  const ParticleStore& p = world.particles;
  const std::size_t cell = weights_[i].cell[0];
  const cfd::FluidGrid& g = options_.grid;
  const auto nx = static_cast<std::size_t>(g.cells[0]), ny = static_cast<std::size_t>(g.cells[1]);
  add_warning_once(world, fmt::format(
      "particle {} at ({:.6g}, {:.6g}, {:.6g}) m, t = {:.6g} s, is among blocked fluid cells only: its "
      "volume and drag go to the nearest fluid cell ({}, {}, {}) while it stays there ({} such "
      "particles at this exchange); keep particles out of blocked regions (a surface around them)",
      p.id[i], p.position[i].x, p.position[i].y, p.position[i].z, world.time, cell % nx, (cell / nx) % ny,
      cell / (nx * ny), std::count(moved_to_nearest_.begin(), moved_to_nearest_.end(), char{1})));
}

cfd::DragResult FluidCoupling::evaluate_drag(const World& world, std::size_t i,
                                             const Vec3& fluid_velocity, double porosity,
                                             const Vec3& pressure_gradient) const {
  const ParticleStore& p = world.particles;
  cfd::DragInput input;
  input.diameter = 2.0 * p.radius[i];
  input.particle_velocity = p.velocity[i];
  input.fluid_velocity = fluid_velocity;
  // The interpolated ε is Σ w_c ε_c with Σ w_c = 1 only to round-off: in particle-free cells it
  // can come out 1 + 2e-16, which the laws rightly refuse as a fraction.
  input.porosity = std::min(porosity, 1.0);
  input.fluid_density = options_.properties.density;
  input.fluid_viscosity = options_.properties.viscosity;
  if (options_.drag_udf) {
    cfd::DragUdfContext context;
    context.pressure_gradient = pressure_gradient;
    context.particle_id = p.id[i];
    context.particle_type = p.type[i];
    context.time = world.time;
    context.particle_volume = sphere_volume(p.radius[i]);
    return to_model(options_.drag_udf->evaluate(input, context), input.porosity);
  }
  return to_model(cfd::drag_force(options_.drag_law, input), input.porosity);
}

// The laws give model-A drag; model B's particle feels it divided by ε at the particle (Zhou et
// al. 2010: in a uniform bed, f_d − V_p ∇p = f_d/ε − V_p ρ_f g), and the fluid takes the same.
cfd::DragResult FluidCoupling::to_model(cfd::DragResult drag, double porosity) const {
  if (options_.solver.model == cfd::VolumeAveragedModel::b) {
    drag.force = drag.force / porosity;
    drag.coefficient /= porosity;
  }
  return drag;
}

Vec3 FluidCoupling::pressure_force(const FrozenParticle& f) const {
  if (options_.solver.model == cfd::VolumeAveragedModel::b)
    return options_.solver.gravity * (-options_.properties.density * f.volume);  // Archimedes, −ρ_f V_p g
  return f.pressure_gradient * (-f.volume);                      // −V_p ∇p
}

void FluidCoupling::freeze_particle(const World& world, std::size_t i) {
  const ParticleStore& p = world.particles;
  FrozenParticle& f = frozen_[i];
  f.id = p.id[i];
  f.volume = sphere_volume(p.radius[i]);
  f.pressure_gradient = interpolate(weights_[i], cell_pressure_gradient_);
  f.exchange_velocity = p.velocity[i];
  forces_[i].fluid_velocity = interpolate(weights_[i], cell_velocity_);
  forces_[i].pressure_force = pressure_force(f);
  velocity_sums_[i] = VelocitySum{};
}

void FluidCoupling::freeze_fluid_values(const World& world) {
  const ParticleStore& p = world.particles;
  const auto n = static_cast<std::ptrdiff_t>(p.size());
#pragma omp parallel for schedule(static) num_threads(world.threading.team(p.size()))
  for (std::ptrdiff_t k = 0; k < n; ++k) freeze_particle(world, static_cast<std::size_t>(k));
  layout_epoch_ = p.layout_epoch;
  frozen_count_ = p.size();
}

void FluidCoupling::check_relaxation(World& world) {
  // The particle side updates v each DEM step with β_p frozen (explicit in v): stable and
  // accurate only while dt ≪ m/β_p, the particle's relaxation time.
  const ParticleStore& p = world.particles;
  const double coupling_step = options_.coupling_steps * world.dt;
  const auto rate = [&](std::size_t i) { return forces_[i].coefficient * p.inv_mass[i]; };  // 1/τ_p (1/s)
  // The lowest index over each limit (the same for any thread count); coupling_step ≥ dt, so a
  // particle over the first is over the second too.
  const std::size_t n = p.size();
  std::size_t too_fast = n, lagging = n;
#pragma omp parallel for schedule(static) reduction(min : too_fast, lagging) num_threads(world.threading.team(n))
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(n); ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (world.dt * rate(i) > 1.0) too_fast = std::min(too_fast, i);
    if (coupling_step * rate(i) > 1.0) lagging = std::min(lagging, i);
  }
  if (lagging < too_fast && !relaxation_warned_) {
    relaxation_warned_ = true;  // once per run: the first particle and time it happened
    add_warning_once(world, fmt::format(
        "the fluid coupling step {:.4g} s is longer than the drag relaxation time m/β_p = {:.4g} s "
        "of particle {} at t = {:.6g} s: the frozen drag coefficient lags the slip; use fewer "
        "DEM steps per fluid step",
        coupling_step, 1.0 / rate(lagging), p.id[lagging], world.time));
  }
  if (too_fast < n)
    throw PhysicsError(fmt::format(
        "step {}, t = {:.6g} s: particle {} has a drag relaxation time m/β_p = {:.4g} s shorter "
        "than the DEM time step {:.4g} s (β_p = {:.4g} kg/s, m = {:.4g} kg); the drag would "
        "overshoot. hint: a smaller time_step, or larger particles",
        world.step_count, world.time, p.id[too_fast], 1.0 / rate(too_fast), world.dt,
        forces_[too_fast].coefficient, 1.0 / p.inv_mass[too_fast]));
}

void FluidCoupling::exchange(World& world) {
  const ParticleStore& p = world.particles;
  const cfd::FluidGrid& g = options_.grid;
  // Wall time of the exchange's parts (timers()): each lap adds the time since the last one.
  auto last = std::chrono::steady_clock::now();
  const auto lap = [&](int stage) {
    const auto now = std::chrono::steady_clock::now();
    timers_.add(stage, std::chrono::duration<double>(now - last).count());
    last = now;
  };
  // The previous interval's drag beyond what its fluid step took: the particles felt
  // β_p (u_p − v_p) at each force evaluation, the fluid β_p (u_p − v_p at the exchange).
  follow_layout(world);
  // Deposits on several threads go by an order of the particles that gives the bits of one
  // (cell_kernel.h); one thread needs none.
  const int threads = world.threading.team(p.size());
  DepositOrder* const order = threads > 1 ? &scratch_.order : nullptr;
  DepositOrder* const old_order = threads > 1 ? &scratch_.old_order : nullptr;
  // The last exchange's order is that of the old weights unless the particles moved since.
  const bool old_order_ready = order && order_is_current_ && scratch_.order.threads == threads;
  if (old_order_ready) std::swap(scratch_.order, scratch_.old_order);
  order_is_current_ = false;
  // Per-particle scratch kept from exchange to exchange (not allocated and faulted in anew).
  std::vector<CellWeights>& old_weights = scratch_.old_weights;
  std::vector<Vec3>& correction = scratch_.correction;  // N
  old_weights.swap(weights_);  // the last exchange's, each particle's since follow_layout
  correction.assign(frozen_.size(), Vec3{});
  const auto n = static_cast<std::ptrdiff_t>(p.size());
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const VelocitySum& v = velocity_sums_[i];
    if (v.samples > 0)
      correction[i] = (v.sum / v.samples - frozen_[i].exchange_velocity) * forces_[i].coefficient;
  }
  compute_weights(world);
  warn_particles_among_blocked_cells(world);
  if (order) order_deposits(g, weights_, threads, *order);
  order_is_current_ = order != nullptr;
  const double smallest = cfdem::void_fraction(g, weights_, p.radius, void_fraction_, order);
  if (smallest < options_.minimum_void_fraction) {
    const auto crowded = static_cast<std::size_t>(
        std::min_element(void_fraction_.begin(), void_fraction_.end()) - void_fraction_.begin());
    throw PhysicsError(fmt::format(
        "step {}, t = {:.6g} s: the void fraction of fluid cell {} fell to {:.4g} (minimum {:.4g}): "
        "more particle volume than the cell holds. hint: coarser fluid cells (≥ 3 particle "
        "diameters), or check for particles piled against a wall of the fluid grid",
        world.step_count, world.time, crowded, smallest, options_.minimum_void_fraction));
  }
  fluid_->set_void_fraction(void_fraction_);
  lap(kVoidFractionStage);

  // β_p at the slip now, with u, ε and ∇p at the particle by the same weights.
  std::span<double> beta = fluid_->drag_coefficient();
  std::span<Vec3> force = fluid_->force_density();
  std::fill(beta.begin(), beta.end(), 0.0);
  std::fill(force.begin(), force.end(), Vec3{});
  std::vector<double>& coefficient = scratch_.coefficient;
  coefficient.assign(p.size(), 0.0);
  // Each particle on its own (threads); a law or UDF that throws is evaluated again after the
  // loop for the lowest such index, so the error is the same for any thread count.
  std::vector<char>& failed = scratch_.failed;
  failed.assign(p.size(), 0);
  // ∇p at the particle only for a user's law (the built-in ones do not read it).
  const auto drag_of = [&](std::size_t i) {
    return evaluate_drag(world, i, interpolate(weights_[i], cell_velocity_),
                         interpolate(weights_[i], void_fraction_),
                         options_.drag_udf ? interpolate(weights_[i], cell_pressure_gradient_) : Vec3{});
  };
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    try {
      coefficient[i] = drag_of(i).coefficient;
    } catch (...) {
      failed[i] = 1;
    }
    forces_[i].coefficient = coefficient[i];
  }
  if (const auto first = std::find(failed.begin(), failed.end(), char{1}); first != failed.end())
    drag_of(static_cast<std::size_t>(first - failed.begin()));  // throws as it did in the loop
  // The fluid's share of the drag, −Σ_p β_p (u − v_p) spread by the weights: β u implicit in the
  // fluid step, β_p v_p explicit.
  deposit_drag(g, weights_, coefficient, p.velocity, beta, force, order);
  if (old_order && !old_order_ready) order_deposits(g, old_weights, threads, *old_order);
  deposit(g, old_weights, correction, force, old_order);
  if (options_.solver.model == cfd::VolumeAveragedModel::b) {
    // Model B's fluid carries −∇p whole: it takes the reaction of the particles' Archimedes
    // force, +ρ_f V_p g, which they feel instead of −V_p ∇p (constant over the interval).
    std::vector<Vec3>& archimedes = scratch_.archimedes;
    archimedes.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      archimedes[i] = options_.solver.gravity * (options_.properties.density * sphere_volume(p.radius[i]));
    deposit(g, weights_, archimedes, force, order);
  }
  lap(kDragStage);
  coupling_step_ = options_.coupling_steps * world.dt;
  fluid_->set_threading(world.threading);  // the world's team now (the governor may change it)
  fluid_->step(coupling_step_);
  lap(kFluidStage);
  update_cell_fields(world.threading.team(g.cell_count()));
  freeze_fluid_values(world);
  ++exchanges_;
  last_exchange_step_ = world.step_count;
  check_relaxation(world);
  lap(kFluidValuesStage);
}

void FluidCoupling::follow_layout(const World& world) {
  const ParticleStore& p = world.particles;
  if (p.layout_epoch == layout_epoch_ && p.size() == frozen_count_) return;
  // Particles reordered, added or removed: each keeps its frozen values by id; a new particle
  // gets its values from the fluid as it is now (its drag reaches the fluid from the next
  // exchange on).
  std::unordered_map<ParticleId, std::size_t> previous;
  previous.reserve(frozen_.size());
  for (std::size_t i = 0; i < frozen_.size(); ++i) previous.emplace(frozen_[i].id, i);
  std::vector<FrozenParticle> frozen(p.size());
  std::vector<FrozenForce> forces(p.size());
  std::vector<VelocitySum> sums(p.size());
  std::vector<CellWeights> weights(p.size());
  std::vector<std::size_t> added;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (const auto found = previous.find(p.id[i]); found != previous.end()) {
      const std::size_t k = found->second;
      frozen[i] = frozen_[k], forces[i] = forces_[k], sums[i] = velocity_sums_[k], weights[i] = weights_[k];
    } else {
      added.push_back(i);
    }
  }
  frozen_ = std::move(frozen);
  forces_ = std::move(forces);
  velocity_sums_ = std::move(sums);
  weights_ = std::move(weights);
  order_is_current_ = false;
  for (const std::size_t i : added) {
    weights_[i] = cell_weights(options_.grid, periodic_, blocked_, p.position[i]);
    freeze_particle(world, i);
    forces_[i].coefficient = evaluate_drag(world, i, forces_[i].fluid_velocity,
                                           interpolate(weights_[i], void_fraction_), frozen_[i].pressure_gradient)
                                 .coefficient;
  }
  layout_epoch_ = p.layout_epoch;
  frozen_count_ = p.size();
}

Vec3 FluidCoupling::drag_force(const World& world, std::size_t i) const {
  return (forces_[i].fluid_velocity - world.particles.velocity[i]) * forces_[i].coefficient;
}

void FluidCoupling::add_forces(World& world) {
  ScopedStage timed(timers_, kParticleForcesStage);
  follow_layout(world);
  ParticleStore& p = world.particles;
  const auto n = static_cast<std::ptrdiff_t>(p.size());
#pragma omp parallel for schedule(static) num_threads(world.threading.team(p.size()))
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    p.force[i] += drag_force(world, i) + forces_[i].pressure_force;
    VelocitySum& v = velocity_sums_[i];
    v.sum += p.velocity[i];
    v.samples += 1;
  }
}

Vec3 FluidCoupling::fluid_momentum() const {
  const cfd::FluidGrid& g = options_.grid;
  Vec3 momentum;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    for (int k = 0; k < g.cells[2]; ++k)
      for (int j = 0; j < g.cells[1]; ++j)
        for (int i = 0; i < g.cells[0]; ++i) {
          std::array<int, 3> low{i, j, k};
          const std::array<int, 3> high{i, j, k};
          low[a] -= 1;  // the face at the low side of cell (i, j, k)
          if (low[a] < 0) {
            if (!periodic_[a]) continue;
            low[a] += g.cells[a];
          }
          const double face_void_fraction =
              0.5 * (void_fraction_[g.cell_index(low[0], low[1], low[2])] +
                     void_fraction_[g.cell_index(high[0], high[1], high[2])]);
          momentum[axis] += options_.properties.density * face_void_fraction *
                            fluid_->face_velocity(axis, i, j, k) * g.cell_volume();
        }
  }
  return momentum;
}

Vec3 FluidCoupling::pending_particle_impulse() const {
  Vec3 force;  // N
  for (std::size_t i = 0; i < frozen_.size(); ++i)
    force += (forces_[i].fluid_velocity - frozen_[i].exchange_velocity) * forces_[i].coefficient +
             forces_[i].pressure_force;
  return force * coupling_step_;
}

}  // namespace quarry::cfdem
