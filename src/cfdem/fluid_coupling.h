// Two-way CFD-DEM coupling of a World with the built-in fluid solver (issue #18 §2-3): every
// `coupling_steps` DEM steps the particles give the fluid its void fraction and drag (one
// kernel, cell_kernel.h), the fluid takes one step, and the particles then feel drag with the
// exchange coefficient frozen and the pressure-gradient force −V_p ∇p at each DEM step. The
// drag the particles felt beyond what the fluid step took (their velocity changed during the
// interval) goes to the fluid in the next step, so momentum is exchanged exactly.
// Zhou, Kuang, Chu & Yu 2010 model A (default) or B. docs/cfd.md "Coupling" gives the timeline.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cfd/drag_laws.h"
#include "cfd/drag_udf.h"
#include "cfd/fluid_solver.h"
#include "cfdem/cell_kernel.h"
#include "core/stage_timer.h"
#include "sim/world.h"

namespace quarry::cfdem {

struct FluidCouplingOptions {
  cfd::FluidGrid grid;
  SourceLocation grid_where;  // where the deck sets the cell size (for the cell-size check)
  cfd::FluidProperties properties;
  cfd::FluidBoundaries boundaries;
  // Tolerances and model of the fluid solver. Its gravity (stored here by the constructor) and
  // threads are taken from the world. Model A (default): the particles feel the laws' drag and
  // −V_p ∇p. Model B: the drag divided by ε at the particle and Archimedes' −ρ_f V_p g, whose
  // reaction the fluid takes.
  cfd::FluidSolverOptions solver;
  int coupling_steps = 1;                // DEM steps per fluid step (≥ 1): Δt_f = n Δt_DEM
  cfd::DragLaw drag_law = cfd::DragLaw::stokes;
  std::optional<cfd::DragUdf> drag_udf;  // replaces drag_law when set
  // A cell whose void fraction falls below this stops the run (PhysicsError with a hint): the
  // particles crowd a cell more than any packing, so the grid is too fine for them.
  double minimum_void_fraction = 0.05;
  // Cells without fluid (flat FluidGrid::cell_index order, 1 = blocked; empty: none), fixed for
  // the run: the solver holds u = 0 on their faces, and the particles' weights avoid them
  // (cell_kernel.h). cfdem/fluid_blocked.h makes it from the deck's fluid.blocked.
  std::vector<std::uint8_t> blocked;
};

// The coupling's state between exchanges, per particle (engine index at `layout_epoch`; kept
// with its particle by id when the particles are reordered), in three arrays: what add_forces
// reads at every DEM step (FrozenForce, 56 B), what it adds up there (VelocitySum, 32 B), and
// the rest, read at exchanges, layout changes and checkpoints (FrozenParticle; the exchange's
// weights are weights()). The DEM-step loop then reads no byte it does not use.
struct FrozenForce {
  Vec3 fluid_velocity;       // u at the particle after the fluid step (m/s)
  double coefficient = 0.0;  // β_p (kg/s), frozen over the coupling step
  Vec3 pressure_force;       // −V_p ∇p_p (model A) or −ρ_f V_p g (model B), constant (N)
};
struct VelocitySum {
  Vec3 sum;         // Σ v_p over the DEM steps' force evaluations since the exchange (m/s)
  int samples = 0;  // how many
};
struct FrozenParticle {
  ParticleId id = 0;
  double volume = 0.0;     // V_p (m³)
  Vec3 pressure_gradient;  // ∇p at the particle after the fluid step (Pa/m)
  Vec3 exchange_velocity;  // v_p the fluid step took (m/s)
};
static_assert(sizeof(FrozenForce) == 56 && sizeof(VelocitySum) == 32, "the sizes the comment gives");

class FluidCoupling {
 public:
  // Checks the options and the world: coupling_steps ≥ 1, the grid inside the
  // world's domain is not required (particles outside it are clamped onto its border cells).
  // Throws UserError with a hint when a cell holds less than 3 times the volume of the largest
  // particle the world can hold (world.max_radius): the void fraction of such cells swings
  // between 1 and ~0 as a particle passes (coupling-notes §3.4); std::invalid_argument for
  // other bad options (a blocked mask of the wrong size, or blocking every cell). The fluid
  // starts at rest with ε = 1.
  FluidCoupling(const World& world, FluidCouplingOptions options);

  // Builds the coupling and adds its hook to the world (post_force: the exchange when a
  // coupling step begins, at steps 0, n, 2n, …, then the fluid forces), and its checkpoint
  // section "fluid" (save_state, load_state). Both share the returned object. Call before
  // sim::initialize, whose force evaluation makes the first exchange — or, to restart, on the
  // world restored from a checkpoint, then sim::restore_sections.
  static std::shared_ptr<FluidCoupling> attach(World& world, FluidCouplingOptions options);

  // The coupling step at the world's time: weights of the particles now, ε, β_p from the drag
  // law at the current slip, β and β_p v_p deposited (with the previous interval's correction
  // β_p (v̄_p − v_p), v̄_p the mean velocity of its force evaluations, on its weights), one
  // fluid step of coupling_steps · dt, then u and ∇p at the particles frozen for the DEM steps
  // until the next exchange.
  // Throws PhysicsError (cells too crowded, DEM step longer than a particle's relaxation time
  // m/β_p, a fluid solve failing) or cfd::DragUdfError. Cost: O(particles + fluid step).
  void exchange(World& world);

  // Adds to particles.force, for each particle: β_p (u_p − v_p) − V_p ∇p_p (model B: − ρ_f V_p g)
  // with the frozen β_p, u_p, ∇p_p and the particle's velocity now. Refreezes first if the particles were
  // reordered, added or removed since the exchange. Cost: O(particles).
  void add_forces(World& world);

  const cfd::FluidSolver& fluid() const { return *fluid_; }
  const FluidCouplingOptions& options() const { return options_; }
  // This exchange's void fraction per cell, and each particle's frozen values and the weights
  // they were frozen with (at the exchange, or when the particle came in since).
  const std::vector<double>& void_fraction() const { return void_fraction_; }
  const std::vector<FrozenParticle>& frozen() const { return frozen_; }
  const std::vector<FrozenForce>& frozen_forces() const { return forces_; }
  const std::vector<VelocitySum>& velocity_sums() const { return velocity_sums_; }
  const std::vector<CellWeights>& weights() const { return weights_; }
  long long exchanges() const { return exchanges_; }
  // Wall time (s) of the coupling's parts, summed over the run: "void fraction" (weights and ε),
  // "drag" (β_p per particle and the deposits), "fluid step", "fluid values" (cell fields, the
  // frozen values at the particles, checks) in each exchange, and "particle forces" (add_forces,
  // every DEM step). Not saved in checkpoints: they time this process.
  const StageTimers& timers() const { return timers_; }
  // The blocked cells (options.blocked) with each one's nearest fluid cell.
  const BlockedCells& blocked_cells() const { return blocked_; }
  // The drag of particle i as add_forces applies it now (N): β_p (u_p − v_p).
  Vec3 drag_force(const World& world, std::size_t i) const;
  // Fluid momentum Σ ρ ε_f u_f V over the faces between two cells (periodic faces once; faces
  // on a non-periodic border left out), ε_f the mean of the two cells' ε of the last step
  // (kg·m/s): the quantity both models' momentum equations conserve.
  Vec3 fluid_momentum() const;
  // What the fluid step of the last exchange took from the particles and they have not felt
  // yet, when read right after the DEM step that made the exchange with the symplectic Euler
  // integrator (that step's forces are applied by the next step's kick): Δt_f Σ_p (β_p (u_p − v_p)
  // − V_p ∇p_p) at the exchange's velocities (N·s). The particles feel it over the interval;
  // what their changing velocity adds reaches the fluid at the next exchange.
  Vec3 pending_particle_impulse() const;

  // Checkpoints (fluid_checkpoint.cpp): the fluid solver's state and everything the coupling
  // keeps between exchanges, so that a run restarted at any step — also inside a coupling
  // interval — takes the same steps, to the bit, as the run that went on. load_state takes
  // what save_state wrote, into a coupling built with the same options on `world` restored to
  // the same step; it reads everything and checks it first (sizes against this grid and the
  // world's particles, finite values, cells and ids in range) and throws std::runtime_error or
  // std::invalid_argument saying what is wrong, the coupling then unchanged. Cost: O(cells +
  // particles).
  void save_state(BinaryWriter& out) const;
  void load_state(BinaryReader& in, const World& world);

 private:
  cfd::DragResult evaluate_drag(const World& world, std::size_t i, const Vec3& fluid_velocity,
                                double porosity, const Vec3& pressure_gradient) const;
  void compute_weights(const World& world);
  void warn_particles_among_blocked_cells(World& world);  // after compute_weights
  void freeze_fluid_values(const World& world);  // u_p, ∇p_p from the fluid now
  void freeze_particle(const World& world, std::size_t i);  // particle i's values but β_p, from weights_[i]
  void follow_layout(const World& world);        // after a layout change: frozen values by id
  void check_relaxation(World& world);
  void update_cell_fields(int threads = 1);      // cell velocities and ∇p from the fluid
  cfd::DragResult to_model(cfd::DragResult drag, double porosity) const;  // ÷ ε in model B
  Vec3 pressure_force(const FrozenParticle& f) const;  // −V_p ∇p (A) or −ρ_f V_p g (B), N

  static constexpr int kVoidFractionStage = 0, kDragStage = 1, kFluidStage = 2, kFluidValuesStage = 3,
                       kParticleForcesStage = 4;
  StageTimers timers_;
  struct Scratch {  // exchange()'s per-particle work arrays, reused
    std::vector<CellWeights> old_weights;
    std::vector<Vec3> correction, archimedes;
    std::vector<double> coefficient;
    std::vector<char> failed;
    DepositOrder order, old_order;  // of weights_ and old_weights, when deposited on threads
  } scratch_;
  FluidCouplingOptions options_;
  std::unique_ptr<cfd::FluidSolver> fluid_;
  PeriodicAxes periodic_{};
  std::vector<CellWeights> weights_;
  BlockedCells blocked_;
  std::vector<char> moved_to_nearest_;  // per particle of compute_weights: all its weight was blocked
  bool blocked_warned_ = false;         // the warning about such a particle, once per run
  std::vector<double> void_fraction_;
  std::vector<FrozenParticle> frozen_;
  std::vector<FrozenForce> forces_;
  std::vector<VelocitySum> velocity_sums_;
  std::vector<Vec3> cell_velocity_, cell_pressure_gradient_;
  bool order_is_current_ = false;  // scratch_.order is that of weights_ (particles not moved since)
  std::uint64_t layout_epoch_ = ~std::uint64_t{0};
  std::size_t frozen_count_ = 0;
  long long exchanges_ = 0;
  std::uint64_t last_exchange_step_ = ~std::uint64_t{0};
  double coupling_step_ = 0.0;  // Δt_f of the last exchange (s)
  bool relaxation_warned_ = false;
};

}  // namespace quarry::cfdem
