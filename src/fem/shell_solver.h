// Explicit dynamics of thin shells: Belytschko–Tsay quads and C0 triangles (shell_element.h),
// row-sum lumped mass with scaled rotary inertia, central differences in velocity-Verlet form,
// mass-proportional damping, optional mass scaling, boundary conditions on node sets and
// external nodal forces and moments (how the particles load the structure).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/threading.h"
#include "core/vec3.h"
#include "fem/shell_element.h"
#include "fem/shell_element_batch.h"
#include "fem/shell_model.h"

namespace quarry::fem {

struct ShellSolverOptions {
  // Mass-proportional damping: force −α m v on every free DOF (rotations: −α I ω). α (1/s).
  double damping = 0.0;
  // Mass scaling: elements whose L_c/c is below this get their density raised so that it is
  // met exactly; 0 disables. (s)
  double mass_scaling_time_step = 0.0;
  double shear_factor = SectionProperties{}.shear_factor;  // κ, transverse shear correction (1)
  // The element's coefficients, by default the section's (SectionProperties).
  double hourglass_membrane = SectionProperties{}.hourglass_membrane,
         hourglass_transverse = SectionProperties{}.hourglass_transverse,
         hourglass_bending = SectionProperties{}.hourglass_bending;
  QuadShear quad_shear = SectionProperties{}.quad_shear;
  double drilling = SectionProperties{}.drilling;  // α: drilling stiffness α G t A
  // Quads of one section (edge-tied shear) eight at a time through the vector kernel
  // (shell_element_batch.h); false: every element through the scalar kernel. Same bits either
  // way, and with either kernel (shell_element_batch_test checks it); the switches are there
  // for that test and for timing.
  bool batched_quads = true;
  QuadKernel quad_kernel = fastest_quad_kernel();
  Threading threading;
};

// The critical step estimate min over elements of L_c / c, c = √(E/(ρ(1 − ν²))) the plate wave
// speed (with scaled density). On a regular quad mesh it is the exact limit of the membrane
// modes; a run uses a fraction of it: 0.9 as LS-DYNA and Radioss, 0.8 where a quad's
// dilatational mode is not held by neighbours (a lone element: limit 1/√(1 + ν) ≈ 0.877 of
// it) or the mesh is irregular (docs/fem.md).
struct StableTimeStep {
  double time_step = 0.0;              // s
  int element = -1;                    // the limiting element (index in the model)
  double characteristic_length = 0.0;  // its L_c (m)
  double wave_speed = 0.0;             // its c (m/s)
};

struct NodalLoad {
  Vec3 force;   // N, global axes
  Vec3 moment;  // N·m, global axes
};

// Energies (J) at the end of the last step; the balance
// kinetic + internal + hourglass + damping − external_work − constraint_work is constant.
struct ShellEnergies {
  double kinetic = 0.0;          // ½ m v² + ½ I ω²
  double internal = 0.0;         // stress work (elastic + plastic, incl. transverse shear)
  double hourglass = 0.0;        // work of the hourglass resultants
  double damping = 0.0;          // dissipated by the mass-proportional damping
  double external_work = 0.0;    // work of the external nodal forces and moments
  double constraint_work = 0.0;  // work of the reactions at prescribed DOFs
  bool hourglass_warning = false;  // hourglass > 5 % of internal
};

// Per-element results. Top, mid and bottom are the outermost (+z, along the element normal),
// middle and innermost through-thickness points: with Lobatto rules the surfaces themselves;
// with an even count, mid is the mean of the two middle points.
struct ElementResult {
  double von_mises_top = 0.0, von_mises_mid = 0.0, von_mises_bottom = 0.0;  // Pa
  double plastic_strain_max = 0.0;  // largest ε̄_p over the points (1)
};

// Everything a step reads that is not fixed by the model and options: a run continued from
// this state (set_state) takes the same steps, to the bit, as the run it was taken from
// (checkpoints: fsi/structure_checkpoint.cpp). The per-element scratch of a step is not in it.
struct ShellSolverState {
  std::vector<Vec3> positions, velocities, angular_velocities, rotations;  // per node
  std::vector<NodalLoad> loads;                                            // per node
  // Per node: internal force and moment of the last step (the next step's first half kick),
  // reactions of the last step and the one before, prescribed velocities (set_prescribed_velocity).
  std::vector<std::array<double, 6>> internal_force, reactions, previous_reactions, prescribed_velocity;
  // Per through-thickness point: stress (3) and plastic strain; per element: shear (3) and
  // hourglass (5) resultants (shell_element.h ElementState).
  std::vector<double> stress, plastic, shear, hourglass;
  double damping = 0.0;  // α (1/s), as set_damping left it
  double time = 0.0;     // s
  std::int64_t steps = 0;
  ShellEnergies energies;
};

class ShellSolver {
 public:
  // Validates the model (validate_shell_model, throws std::invalid_argument naming the element,
  // node, section or material) and sets up masses, state and the node → element gather.
  // Nodes start at rest. Cost: O(model size).
  explicit ShellSolver(ShellModel model, ShellSolverOptions options = {});

  // The current critical step estimate and the element that limits it. Cost: O(elements).
  StableTimeStep stable_time_step() const;
  // Mass added by mass scaling (kg), 0 without it.
  double added_mass() const { return added_mass_; }
  QuadKernel quad_kernel() const { return options_.quad_kernel; }  // the batch kernel in use
  double total_mass() const { return total_mass_; }

  // External force and moment per node, held constant over the following steps until set
  // again. Pre: loads.size() == node count (throws std::invalid_argument otherwise).
  void set_loads(std::span<const NodalLoad> loads);
  // Changes the mass-proportional damping α (1/s, ≥ 0) from the next step on.
  void set_damping(double alpha);
  double damping() const { return options_.damping; }  // α (1/s)
  // The team of the following steps (a coupled run passes its world's at every exchange, so that
  // the run loop's thread governor applies here too). Results do not depend on it.
  void set_threading(const Threading& threading) { options_.threading = threading; }
  // Changes the prescribed velocity of a node's constrained DOFs (components outside the
  // node's DOF mask are ignored): a time-dependent boundary condition, set between steps.
  void set_prescribed_velocity(int node, const std::array<double, 6>& velocity);
  // Sets a node's velocity (m/s) and angular velocity (rad/s); prescribed DOFs keep their value.
  void set_velocity(int node, const Vec3& velocity, const Vec3& angular_velocity);

  // One central-difference step of length dt (s): half kick, drift, internal forces on the new
  // configuration, half kick, energies. Pre: 0 < dt ≤ the stable step (not checked; a
  // diverging run throws PhysicsError naming the step and the node). Cost: O(elements · points).
  void step(double dt);

  double time() const { return time_; }
  std::int64_t step_count() const { return steps_; }
  std::span<const Vec3> positions() const { return positions_; }
  std::span<const Vec3> velocities() const { return velocities_; }
  std::span<const Vec3> angular_velocities() const { return angular_velocities_; }
  // Accumulated rotation vector Σ ω dt per node (rad): small-rotation measure for output.
  std::span<const Vec3> rotations() const { return rotations_; }
  // Force and moment the constraints exert on each node (N, N·m; zero on free DOFs):
  // f_int − f_ext at the prescribed DOFs.
  std::span<const std::array<double, 6>> reactions() const { return reactions_; }
  std::span<const double> nodal_masses() const { return mass_; }
  // Per node, the DOFs (dof:: bits) that boundary conditions prescribe.
  std::span<const std::uint8_t> prescribed_dofs() const { return prescribed_mask_; }
  const ShellEnergies& energies() const { return energies_; }

  // The state (ShellSolverState) as it is now, and set back. set_state checks every size
  // against the model and every value (finite, plastic strain ≥ 0, steps ≥ 0, α ≥ 0) and throws
  // std::invalid_argument naming what is wrong before it changes anything.
  ShellSolverState state() const;
  void set_state(ShellSolverState state);
  // set_state's checks alone (a caller that takes several states checks them all first).
  void check_state(const ShellSolverState& state) const;

  ElementResult element_result(int element) const;
  // Stress at a through-thickness point in the element's co-rotational frame (σxx, σyy, σxy; Pa)
  // and that frame at the current configuration.
  Voigt3 element_stress(int element, int point) const;
  double element_plastic_strain(int element, int point) const;
  ElementFrame current_frame(int element) const;
  int element_count() const { return static_cast<int>(model_.elements.size()); }
  int node_count() const { return static_cast<int>(model_.nodes.size()); }

 private:
  std::array<Vec3, 4> gather(const std::vector<Vec3>& field, int element) const;
  void compute_element_forces(double dt);
  void apply_prescribed();          // every node's prescribed DOFs
  void apply_prescribed(int node);  // one node's
  // copy(field, index in storage order, index in element order) for every history value;
  // field 0-3: stress, plastic strain, shear, hourglass.
  template <class Copy>
  void for_each_state_value(Copy copy) const;

  ShellModel model_;
  ShellSolverOptions options_;
  std::vector<ThicknessPoints> rules_;            // per section
  std::vector<SectionProperties> properties_;     // per section
  std::vector<double> density_;                   // per element, after mass scaling (kg/m³)
  std::vector<int> state_offset_;                 // per element, its first point in element order
  // Histories in storage order: slots_[e] is where element e's values start in each array,
  // and the distance between its consecutive values (kQuadLanes in a batch's interleaved
  // block, else 1).
  struct StateSlot {
    int stress = 0, plastic = 0, shear = 0, hourglass = 0, stride = 1;
  };
  std::vector<StateSlot> slots_;
  std::vector<double> stress_, plastic_, shear_, hourglass_;

  std::vector<Vec3> positions_, velocities_, angular_velocities_, rotations_;
  std::vector<Vec3> midpoint_positions_;  // x(t + dt/2) of the last step: the elements' configuration
  std::vector<double> mass_;  // kg per node
  std::vector<Vec3> load_force_, load_moment_;          // N, N·m (set_loads)
  std::vector<Vec3> internal_force_, internal_moment_;  // of the last step (N, N·m)
  std::vector<std::array<double, 6>> reactions_, previous_reactions_;
  std::vector<std::uint8_t> prescribed_mask_;
  std::vector<std::array<double, 6>> prescribed_velocity_;
  // Per DOF (x, y, z of a node): mass and rotary inertia, their inverses (the kicks'), and the
  // same with 0 at prescribed DOFs (the damping acts on free DOFs only).
  std::vector<Vec3> dof_mass_, dof_inertia_, dof_inverse_mass_, dof_inverse_inertia_;
  std::vector<Vec3> free_mass_, free_inertia_;
  // The step's node stages run over blocks of kNodeBlock nodes; the nodes with prescribed DOFs
  // in node order, and per block where its entries start.
  static constexpr int kNodeBlock = 256;
  std::vector<std::int32_t> prescribed_nodes_;
  std::vector<int> prescribed_block_offset_;

  // Deterministic gather: element force blocks, then per node its (element, slot) in order.
  std::vector<std::array<std::array<double, 6>, 4>> element_forces_;
  std::vector<double> element_internal_energy_, element_hourglass_energy_;
  // incidence_: where a (element, slot) block starts among element_forces_'s doubles,
  // 6 (4 element + slot).
  std::vector<int> incidence_offset_;
  std::vector<std::uint32_t> incidence_;
  // The element loop's work: groups of kQuadLanes quads of one section for the vector kernel (in
  // element order as they fill up, per section), and the elements left to the scalar kernel.
  std::vector<std::array<std::int32_t, kQuadLanes>> quad_batches_;
  std::vector<std::int32_t> scalar_elements_;
  std::vector<std::array<double, 2>> block_sums_;  // a step's energy sums per node block

  double added_mass_ = 0.0, total_mass_ = 0.0;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  ShellEnergies energies_;
};

}  // namespace quarry::fem
