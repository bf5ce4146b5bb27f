// The shell solver's step as named stages: half kick → drift → internal forces (element loop,
// then a fixed-order gather per node) → half kick → energies. Central differences in
// velocity-Verlet form (Belytschko, Liu & Moran 2000, §6.2.2, Box 6.1): with a constant dt it is
// the classic central-difference scheme, and after every step x, v, a and the stresses are all
// at the same time t_n+1.
#include "fem/shell_solver.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include <fmt/format.h>

#include "core/diagnostics.h"
#include "core/shared_loop.h"
#include "fem/shell_element_batch.h"

namespace quarry::fem {
namespace {

// A node field's values as one array of 3N doubles (x, y, z of node 0, then node 1, …): Vec3 is
// three doubles without padding, so the node stages are plain loops over DOFs, which the
// compiler vectorises.
static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3>);
double* dofs(std::vector<Vec3>& field) { return &field.data()->x; }

// body(i) for i in [0, count) on `team` threads (static schedule); for a team of one shared
// with a waiting thread where `threading` has one (SharedLoop: the structure beside the DEM), else
// as a plain loop: libgomp ends even a one-thread region with a futex wake, a system call (with
// the 4 regions of a step, 5 % of the samples on the 1,296-quad plate: n 36, one thread, +7 %).
// Every body here writes only its own item's results: the same bits however it runs.
template <class Body>
void parallel_for(const Threading& threading, int team, int count, const Body& body) {
  if (team <= 1) {
    if (threading.shared != nullptr) {
      threading.shared->run(count, body);
      return;
    }
    for (int i = 0; i < count; ++i) body(i);
    return;
  }
#pragma omp parallel for schedule(static) num_threads(team)
  for (int i = 0; i < count; ++i) body(i);
}

double plate_wave_speed(const ShellMaterial& material, double density) {
  // c = √(E / (ρ (1 − ν²))), the plate (membrane) wave speed.
  const double nu = material.poisson_ratio;
  return std::sqrt(material.youngs_modulus / (density * (1.0 - nu * nu)));
}

}  // namespace

ShellSolver::ShellSolver(ShellModel model, ShellSolverOptions options)
    : model_(std::move(model)), options_(options) {
  validate_shell_model(model_);
  if (!(options_.damping >= 0.0) || !(options_.mass_scaling_time_step >= 0.0)) {
    throw std::invalid_argument(fmt::format(
        "shell solver: damping {} 1/s and mass-scaling step {} s must be ≥ 0", options_.damping,
        options_.mass_scaling_time_step));
  }
  if (!quad_kernel_available(options_.quad_kernel)) {
    throw std::invalid_argument(fmt::format("shell solver: this processor cannot run the {} quad kernel",
                                            quad_kernel_name(options_.quad_kernel)));
  }
  const std::size_t nodes = model_.nodes.size();
  const std::size_t elements = model_.elements.size();

  // Sections: integration rule and the constants the element kernel reads.
  rules_.reserve(model_.sections.size());
  for (const ShellSection& section : model_.sections) {
    rules_.push_back(thickness_points(section.rule, section.integration_points));
  }
  for (std::size_t s = 0; s < model_.sections.size(); ++s) {
    const ShellSection& section = model_.sections[s];
    const ShellMaterial& material = model_.materials[section.material];
    SectionProperties p;
    p.thickness = section.thickness;
    p.points = section.integration_points;
    p.coordinate = rules_[s].coordinate.data();
    p.weight = rules_[s].weight.data();
    p.material = {material.youngs_modulus, material.poisson_ratio, material.yield_stress,
                  material.hardening_modulus};
    p.shear_modulus = material.youngs_modulus / (2.0 * (1.0 + material.poisson_ratio));
    p.shear_factor = options_.shear_factor;
    p.hourglass_membrane = options_.hourglass_membrane;
    p.hourglass_transverse = options_.hourglass_transverse;
    p.hourglass_bending = options_.hourglass_bending;
    p.quad_shear = options_.quad_shear;
    p.drilling = options_.drilling;
    properties_.push_back(p);
  }

  positions_ = model_.nodes;
  midpoint_positions_ = model_.nodes;
  velocities_.assign(nodes, Vec3{});
  angular_velocities_.assign(nodes, Vec3{});
  rotations_.assign(nodes, Vec3{});
  load_force_.assign(nodes, Vec3{});
  load_moment_.assign(nodes, Vec3{});
  internal_force_.assign(nodes, Vec3{});
  internal_moment_.assign(nodes, Vec3{});
  reactions_.assign(nodes, {});
  previous_reactions_.assign(nodes, {});
  mass_.assign(nodes, 0.0);
  std::vector<double> rotary_inertia(nodes, 0.0);  // kg·m², per node (into dof_inertia_ below)

  // Mass: row-sum lumping, ρ t A / n per node; rotary inertia m_node · max(t²/12, A/8), scaled
  // up from the physical t²/12 so that rotations never limit the step (Hughes, Cohen & Haroun
  // 1978; Kennedy, Belytschko & Lin 1986; research note §1.4). Mass scaling multiplies ρ of
  // each element whose L_c/c is below the target by (target / (L_c/c))², since c ∝ 1/√ρ: the
  // element's step becomes exactly the target.
  density_.resize(elements);
  state_offset_.resize(elements + 1);
  int offset = 0;
  for (std::size_t e = 0; e < elements; ++e) {
    const ShellElement& element = model_.elements[e];
    const ShellSection& section = model_.sections[element.section];
    const ShellMaterial& material = model_.materials[section.material];
    const std::array<Vec3, 4> x = gather(positions_, static_cast<int>(e));
    const double area = element_area(x, element.node_count);
    double density = material.density;
    const double target = options_.mass_scaling_time_step;
    if (target > 0.0) {
      const double step = characteristic_length(x, element.node_count) /
                          plate_wave_speed(material, density);
      if (step < target) density *= (target / step) * (target / step);
    }
    density_[e] = density;
    added_mass_ += (density - material.density) * section.thickness * area;
    const double node_mass = density * section.thickness * area / element.node_count;
    const double t = section.thickness;
    const double inertia = node_mass * std::max(t * t / 12.0, area / 8.0);
    for (int i = 0; i < element.node_count; ++i) {
      mass_[element.nodes[i]] += node_mass;
      rotary_inertia[element.nodes[i]] += inertia;
    }
    state_offset_[e] = offset;
    offset += section.integration_points;
  }
  state_offset_[elements] = offset;
  for (const double m : mass_) total_mass_ += m;
  stress_.assign(3 * static_cast<std::size_t>(offset), 0.0);
  plastic_.assign(offset, 0.0);
  shear_.assign(3 * elements, 0.0);
  hourglass_.assign(5 * elements, 0.0);
  for (std::size_t n = 0; n < nodes; ++n) {
    if (!(mass_[n] > 0.0)) {
      throw std::invalid_argument(
          fmt::format("shell model: node {} belongs to no element (it would have no mass)", n));
    }
  }

  // Node → (element, slot) incidence in element order: the fixed gather order.
  incidence_offset_.assign(nodes + 1, 0);
  for (const ShellElement& element : model_.elements) {
    for (int i = 0; i < element.node_count; ++i) ++incidence_offset_[element.nodes[i] + 1];
  }
  for (std::size_t n = 0; n < nodes; ++n) incidence_offset_[n + 1] += incidence_offset_[n];
  incidence_.resize(incidence_offset_[nodes]);
  std::vector<int> fill(incidence_offset_.begin(), incidence_offset_.end() - 1);
  for (std::size_t e = 0; e < elements; ++e) {
    const ShellElement& element = model_.elements[e];
    for (int i = 0; i < element.node_count; ++i) {
      incidence_[fill[element.nodes[i]]++] = 6 * (4 * static_cast<std::uint32_t>(e) + i);
    }
  }
  element_forces_.assign(elements, {});
  // Batches: each section's quads in element order, kQuadLanes at a time; the rest stay scalar.
  // Every element writes only its own outputs, so the grouping changes no sum.
  std::vector<std::vector<std::int32_t>> pending(model_.sections.size());
  for (std::size_t e = 0; e < elements; ++e) {
    const ShellElement& element = model_.elements[e];
    const int s = element.section;
    if (!options_.batched_quads || element.node_count != 4 || !batchable(properties_[s])) {
      scalar_elements_.push_back(static_cast<std::int32_t>(e));
      continue;
    }
    pending[s].push_back(static_cast<std::int32_t>(e));
    if (pending[s].size() == kQuadLanes) {
      std::array<std::int32_t, kQuadLanes> batch{};
      std::copy(pending[s].begin(), pending[s].end(), batch.begin());
      quad_batches_.push_back(batch);
      pending[s].clear();
    }
  }
  for (const std::vector<std::int32_t>& rest : pending) {
    scalar_elements_.insert(scalar_elements_.end(), rest.begin(), rest.end());
  }
  element_internal_energy_.assign(elements, 0.0);
  element_hourglass_energy_.assign(elements, 0.0);

  // Where each element's history lives in stress_, plastic_, shear_, hourglass_: the batches'
  // quads first, each batch one interleaved block (QuadBatchState), then the scalar elements,
  // each contiguous (ElementState). state() and set_state convert to and from element order.
  slots_.resize(elements);
  {
    int point = 0, element_slot = 0;
    for (const std::array<std::int32_t, kQuadLanes>& batch : quad_batches_) {
      const int points = model_.sections[model_.elements[batch[0]].section].integration_points;
      for (int l = 0; l < kQuadLanes; ++l) {
        slots_[batch[l]] = {3 * point + l, point + l, 3 * element_slot + l, 5 * element_slot + l,
                            kQuadLanes};
      }
      point += kQuadLanes * points;
      element_slot += kQuadLanes;
    }
    for (const std::int32_t e : scalar_elements_) {
      slots_[e] = {3 * point, point, 3 * element_slot, 5 * element_slot, 1};
      point += model_.sections[model_.elements[e].section].integration_points;
      ++element_slot;
    }
  }

  prescribed_mask_.assign(nodes, 0);
  prescribed_velocity_.assign(nodes, {});
  for (const BoundaryCondition& bc : model_.boundary_conditions) {
    for (const std::int32_t n : bc.nodes) {
      prescribed_mask_[n] |= bc.dofs;
      for (int k = 0; k < 6; ++k) {
        if (bc.dofs & (1u << k)) prescribed_velocity_[n][k] = bc.velocity[k];
      }
    }
  }
  // Per DOF: the masses and their inverses (the kicks multiply: divisions would bound them),
  // and the masses the damping acts on (0 at prescribed DOFs).
  dof_mass_.resize(nodes);
  dof_inertia_.resize(nodes);
  dof_inverse_mass_.resize(nodes);
  dof_inverse_inertia_.resize(nodes);
  free_mass_.resize(nodes);
  free_inertia_.resize(nodes);
  const int blocks = static_cast<int>((nodes + kNodeBlock - 1) / kNodeBlock);
  prescribed_block_offset_.assign(static_cast<std::size_t>(blocks) + 1, 0);
  for (std::size_t n = 0; n < nodes; ++n) {
    for (int k = 0; k < 3; ++k) {
      dof_mass_[n][k] = mass_[n];
      dof_inertia_[n][k] = rotary_inertia[n];
      dof_inverse_mass_[n][k] = 1.0 / mass_[n];
      dof_inverse_inertia_[n][k] = 1.0 / rotary_inertia[n];
      free_mass_[n][k] = prescribed_mask_[n] & (1u << k) ? 0.0 : mass_[n];
      free_inertia_[n][k] = prescribed_mask_[n] & (1u << (k + 3)) ? 0.0 : rotary_inertia[n];
    }
    if (prescribed_mask_[n] != 0) {
      prescribed_nodes_.push_back(static_cast<std::int32_t>(n));
      ++prescribed_block_offset_[n / kNodeBlock + 1];
    }
  }
  for (int b = 0; b < blocks; ++b) prescribed_block_offset_[b + 1] += prescribed_block_offset_[b];
  apply_prescribed();
}

std::array<Vec3, 4> ShellSolver::gather(const std::vector<Vec3>& field, int element) const {
  const ShellElement& el = model_.elements[element];
  std::array<Vec3, 4> out{};
  for (int i = 0; i < el.node_count; ++i) out[i] = field[el.nodes[i]];
  return out;
}

// The coupling asks at every PERIOD, and each element's exact estimate (its frame, local
// coordinates and area: characteristic_length) was a visible share of the two-way flagship's
// profile (docs/performance.md). So a screen
// first: the squared step from the area as ½ |x31 × x42| (½ |x21 × x31| for a triangle), the
// same area as the frame's in exact arithmetic (the frame's normal is that cross product's
// direction), so the two differ by round-off only. Only elements whose screen lies within
// kMargin of the least go through the exact estimate, in element order as before: the same
// element and step, to the bit, as estimating every element (a NaN is never chosen, as before).
StableTimeStep ShellSolver::stable_time_step() const {
  constexpr double kMargin = 1e-9;  // relative; round-off of either form is ~1e-15
  const std::size_t elements = model_.elements.size();
  std::vector<double> screen(elements);  // s²
  double least = INFINITY;  // s²
  for (std::size_t e = 0; e < elements; ++e) {
    const ShellElement& element = model_.elements[e];
    const ShellMaterial& material =
        model_.materials[model_.sections[element.section].material];
    const std::array<Vec3, 4> x = gather(positions_, static_cast<int>(e));
    const int n = element.node_count;
    const Vec3 normal = n == 4 ? cross(x[2] - x[0], x[3] - x[1]) : cross(x[1] - x[0], x[2] - x[0]);
    double longest = 0.0;  // m²
    for (int i = 0; i < n; ++i) longest = std::max(longest, norm2(x[(i + 1) % n] - x[i]));
    // (L_c / c)²: L_c = A / longest (quad), 2A / longest (triangle), A = ½ |normal|, and
    // 1 / c² = ρ (1 − ν²) / E.
    const double nu = material.poisson_ratio;
    screen[e] = (n == 4 ? 0.25 : 1.0) * density_[e] * (1.0 - nu * nu) / material.youngs_modulus *
                norm2(normal) / longest;
    if (screen[e] < least) least = screen[e];
  }
  const double bound = least * (1.0 + kMargin);
  StableTimeStep best;
  best.time_step = INFINITY;
  for (std::size_t e = 0; e < elements; ++e) {
    if (!(screen[e] <= bound)) continue;
    const ShellElement& element = model_.elements[e];
    const ShellMaterial& material =
        model_.materials[model_.sections[element.section].material];
    const double length =
        characteristic_length(gather(positions_, static_cast<int>(e)), element.node_count);
    const double speed = plate_wave_speed(material, density_[e]);
    if (length / speed < best.time_step) {
      best = {length / speed, static_cast<int>(e), length, speed};
    }
  }
  return best;
}

void ShellSolver::set_loads(std::span<const NodalLoad> loads) {
  if (loads.size() != load_force_.size()) {
    throw std::invalid_argument(fmt::format("shell solver: {} nodal loads given for {} nodes",
                                            loads.size(), load_force_.size()));
  }
  for (std::size_t n = 0; n < loads.size(); ++n) {
    load_force_[n] = loads[n].force;
    load_moment_[n] = loads[n].moment;
  }
}

void ShellSolver::set_damping(double alpha) {
  if (!(alpha >= 0.0) || !std::isfinite(alpha)) {
    throw std::invalid_argument(fmt::format("shell solver: damping {} 1/s must be ≥ 0", alpha));
  }
  options_.damping = alpha;
}

void ShellSolver::set_prescribed_velocity(int node, const std::array<double, 6>& velocity) {
  const std::uint8_t mask = prescribed_mask_.at(node);
  for (int k = 0; k < 6; ++k) {
    if (mask & (1u << k)) prescribed_velocity_[node][k] = velocity[k];
  }
  apply_prescribed();
}

void ShellSolver::set_velocity(int node, const Vec3& velocity, const Vec3& angular_velocity) {
  velocities_.at(node) = velocity;
  angular_velocities_.at(node) = angular_velocity;
  apply_prescribed();
}

[[gnu::always_inline]] inline void ShellSolver::apply_prescribed(int n) {
  const std::uint8_t mask = prescribed_mask_[n];
  if (mask == 0) return;
  for (int k = 0; k < 3; ++k) {
    if (mask & (1u << k)) velocities_[n][k] = prescribed_velocity_[n][k];
    if (mask & (1u << (k + 3))) angular_velocities_[n][k] = prescribed_velocity_[n][k + 3];
  }
}

void ShellSolver::apply_prescribed() {
  for (const std::int32_t n : prescribed_nodes_) apply_prescribed(n);
}

// Stage "internal forces", its element loop: each element writes its own force block (parallel,
// no sharing); the nodes sum their blocks in the second half kick's pass (step).
void ShellSolver::compute_element_forces(double dt) {
  const int elements = static_cast<int>(model_.elements.size());
  // Below the team's threshold (2,048) one thread: a 1,260-quad bed coupled to a pour took
  // 80.9 s on two threads against 66.4 s on one (130 µs per step: docs/performance.md).
  const int element_team = options_.threading.team(static_cast<std::size_t>(elements));
  const auto state_of = [this](int e) {  // a scalar element's (stride 1) or a batch's lane 0
    const StateSlot& slot = slots_[e];
    return ElementState{stress_.data() + slot.stress, plastic_.data() + slot.plastic,
                        shear_.data() + slot.shear, hourglass_.data() + slot.hourglass};
  };
  const int batches = static_cast<int>(quad_batches_.size());
  const int singles = static_cast<int>(scalar_elements_.size());
  const auto run_batch = [&](int b) {
    const std::array<std::int32_t, kQuadLanes>& batch = quad_batches_[b];
    std::array<std::array<std::int32_t, 4>, kQuadLanes> nodes;
    for (int l = 0; l < kQuadLanes; ++l) nodes[l] = model_.elements[batch[l]].nodes;
    const ElementState block = state_of(batch[0]);
    const QuadBatchState states{block.stress, block.plastic_strain, block.shear, block.hourglass};
    QuadBatchOutput out;
    for (int l = 0; l < kQuadLanes; ++l) {
      out.nodal[l] = &element_forces_[batch[l]];
      out.internal_energy_increment[l] = &element_internal_energy_[batch[l]];
      out.hourglass_energy_increment[l] = &element_hourglass_energy_[batch[l]];
    }
    shell_internal_forces_quads(midpoint_positions_.data(), velocities_.data(),
                                angular_velocities_.data(), nodes, dt,
                                properties_[model_.elements[batch[0]].section], states, out,
                                options_.quad_kernel);
  };
  const auto run_single = [&](int k) {
    const int e = scalar_elements_[k];
    const ShellElement& element = model_.elements[e];
    // The element's nodal x, v, ω in one pass over its nodes (unused 4th slot of a triangle: 0).
    std::array<Vec3, 4> x{}, v{}, omega{};
    for (int i = 0; i < element.node_count; ++i) {
      const std::int32_t node = element.nodes[i];
      x[i] = midpoint_positions_[node];
      v[i] = velocities_[node];
      omega[i] = angular_velocities_[node];
    }
    const ElementForces forces = shell_internal_forces(x, v, omega, element.node_count, dt,
                                                       properties_[element.section], state_of(e));
    element_forces_[e] = forces.nodal;
    element_internal_energy_[e] = forces.internal_energy_increment;
    element_hourglass_energy_[e] = forces.hourglass_energy_increment;
  };
  if (element_team <= 1) {
    // Items of kBatchesPerItem batches (32 quads, some 5 µs: a share for a waiting thread,
    // parallel_for), then the singles, one item each; in order, on one thread.
    constexpr int kBatchesPerItem = 4;
    const int batch_items = (batches + kBatchesPerItem - 1) / kBatchesPerItem;
    parallel_for(options_.threading, 1, batch_items + singles, [&](int item) {
      if (item >= batch_items) return run_single(item - batch_items);
      const int end = std::min(batches, (item + 1) * kBatchesPerItem);
      for (int b = item * kBatchesPerItem; b < end; ++b) run_batch(b);
    });
  } else {
#pragma omp parallel num_threads(element_team)
    {
#pragma omp for schedule(static) nowait
      for (int b = 0; b < batches; ++b) run_batch(b);
#pragma omp for schedule(static)
      for (int k = 0; k < singles; ++k) run_single(k);
    }
  }
}

namespace {

// Stage "accelerations → velocities" on DOFs [begin, end) of one kind (translations: forces and
// masses; rotations: moments and inertias): v += h (f_ext − f_int)/m with the damping force
// −α m v taken at the old velocity in the first half kick and at the new one in the second (so
// the pair is the central-difference damping update of Belytschko, Liu & Moran eq. 6.2.23).
// A plain loop over DOFs, which the compiler runs four per instruction; it multiplies by the
// inverse mass, as divisions would bound it.
void half_kick(double* __restrict v, const double* __restrict load,
               const double* __restrict internal, const double* __restrict inverse_mass, int begin,
               int end, double half_dt, double alpha, bool first_half) {
  if (first_half) {
    for (int j = begin; j < end; ++j)
      v[j] += half_dt * ((load[j] - internal[j]) * inverse_mass[j] - alpha * v[j]);
    return;
  }
  for (int j = begin; j < end; ++j)
    v[j] = v[j] + half_dt * ((load[j] - internal[j]) * inverse_mass[j]);
  const double factor = 1.0 / (1.0 + alpha * half_dt);
  if (factor == 1.0) return;  // undamped: x · 1 is x
  for (int j = begin; j < end; ++j) v[j] *= factor;
}

// Stage "drift" on DOFs [begin, end): x(t + dt) = x(t) + dt v, the elements' configuration
// x(t + dt/2) and the accumulated rotation Σ ω dt. A function of its own so that the arrays are
// known not to overlap: the compiler then runs it four DOFs per instruction.
void drift(double* __restrict x, double* __restrict midpoint, double* __restrict rotation,
           const double* __restrict v, const double* __restrict w, int begin, int end, double dt) {
  for (int j = begin; j < end; ++j) {
    const double displacement = dt * v[j];
    midpoint[j] = x[j] + 0.5 * displacement;  // x(t + dt/2)
    x[j] += displacement;
    rotation[j] += dt * w[j];
  }
}

// Σ_j term(j) over [begin, end) in four partial sums (j mod 4) added at the end: independent
// chains, and the same bits wherever the range is summed.
template <class Term>
double sum_by_fours(int begin, int end, const Term& term) {
  double partial[4] = {0.0, 0.0, 0.0, 0.0};
  int j = begin;
  for (; j + 4 <= end; j += 4)
    for (int l = 0; l < 4; ++l) partial[l] += term(j + l);
  for (int l = 0; j < end; ++j, ++l) partial[l] += term(j);
  return (partial[0] + partial[1]) + (partial[2] + partial[3]);
}

}  // namespace

// The step's node stages in two passes over blocks of kNodeBlock nodes (kick + drift; gather +
// kick + reactions), each a few plain loops over the block's DOFs (a node field seen as 3N
// doubles: dofs()), with per DOF the operations of one pass per stage: the motion does not
// depend on the blocks or on the team. Energies are summed per block, then the blocks in order:
// the same bits for any team.
void ShellSolver::step(double dt) {
  const int nodes = static_cast<int>(positions_.size());
  const int elements = static_cast<int>(model_.elements.size());
  const double half = 0.5 * dt;
  const double alpha = options_.damping;
  const int node_blocks = (nodes + kNodeBlock - 1) / kNodeBlock;
  const int node_team = options_.threading.team(static_cast<std::size_t>(nodes));
  block_sums_.resize(static_cast<std::size_t>(node_blocks));
  previous_reactions_.swap(reactions_);  // reactions of t, for the constraint work
  double* const v = dofs(velocities_);
  double* const w = dofs(angular_velocities_);
  double* const x = dofs(positions_);
  double* const midpoint = dofs(midpoint_positions_);
  double* const rotation = dofs(rotations_);
  const double* const force = dofs(load_force_);
  const double* const moment = dofs(load_moment_);
  double* const internal_force = dofs(internal_force_);
  double* const internal_moment = dofs(internal_moment_);
  const double* const mass = dofs(dof_mass_);
  const double* const inertia = dofs(dof_inertia_);
  const double* const inverse_mass = dofs(dof_inverse_mass_);
  const double* const inverse_inertia = dofs(dof_inverse_inertia_);
  const auto dof_range = [nodes](int block) {
    return std::pair{3 * block * kNodeBlock, 3 * std::min(nodes, (block + 1) * kNodeBlock)};
  };
  // The blocks' two partial sums, the blocks in order.
  const auto sum_blocks = [this](int blocks) {
    std::array<double, 2> sum{0.0, 0.0};
    for (int b = 0; b < blocks; ++b) {
      sum[0] += block_sums_[b][0];
      sum[1] += block_sums_[b][1];
    }
    return sum;
  };
  const auto prescribe = [this](int block) {
    for (int k = prescribed_block_offset_[block]; k < prescribed_block_offset_[block + 1]; ++k)
      apply_prescribed(prescribed_nodes_[k]);
  };

  // 1. Half kick to t + dt/2 with the forces of t (external loads as set now); the damping's
  // work over the step, α m v² dt on the free DOFs at v(t + dt/2).
  // 2. Drift: x(t + dt) = x(t) + dt v(t + dt/2); the work of the loads over it.
  parallel_for(options_.threading, node_team, node_blocks, [&](int block) {
    const auto [begin, end] = dof_range(block);
    half_kick(v, force, internal_force, inverse_mass, begin, end, half, alpha, true);
    half_kick(w, moment, internal_moment, inverse_inertia, begin, end, half, alpha, true);
    prescribe(block);
    double damping_work = 0.0;
    if (alpha > 0.0) {
      const double* free_mass = dofs(free_mass_);
      const double* free_inertia = dofs(free_inertia_);
      damping_work = alpha * dt * sum_by_fours(begin, end, [&](int j) {
                       return free_mass[j] * v[j] * v[j] + free_inertia[j] * w[j] * w[j];
                     });
    }
    drift(x, midpoint, rotation, v, w, begin, end, dt);
    const double external_work = sum_by_fours(begin, end, [&](int j) {
      return force[j] * (dt * v[j]) + moment[j] * (dt * w[j]);
    });
    block_sums_[block] = {damping_work, external_work};
  });
  const auto [damping_work, external_work] = sum_blocks(node_blocks);

  // 3. Internal forces at t + dt: stresses advanced with the midpoint velocities, each element
  // evaluated on the mid-step configuration x(t + dt/2), where a rigid rotation has no strain
  // rate (Hughes & Winget 1980); on x(t + dt) it had ½(Ω dt)², which ratcheted membrane stress
  // under vibration (docs/fem.md "Elements").
  compute_element_forces(dt);

  // 3b. Each node sums its element blocks in element order (the fixed gather: the sums do not
  // depend on the threads). 4. Half kick to t + dt; the reactions at the prescribed DOFs and
  // their work; the kinetic energy.
  const double* const element_forces = element_forces_.data()->data()->data();
  parallel_for(options_.threading, node_team, node_blocks, [&](int block) {
    const int end_node = std::min(nodes, (block + 1) * kNodeBlock);
    for (int n = block * kNodeBlock; n < end_node; ++n) {
      std::array<double, 6> sum{};
      for (int k = incidence_offset_[n]; k < incidence_offset_[n + 1]; ++k) {
        const double* forces = element_forces + incidence_[k];
        for (int d = 0; d < 6; ++d) sum[d] += forces[d];
      }
      internal_force_[n] = {sum[0], sum[1], sum[2]};
      internal_moment_[n] = {sum[3], sum[4], sum[5]};
    }
    const auto [begin, end] = dof_range(block);
    half_kick(v, force, internal_force, inverse_mass, begin, end, half, alpha, false);
    half_kick(w, moment, internal_moment, inverse_inertia, begin, end, half, alpha, false);
    prescribe(block);
    double constraint_work = 0.0;
    for (int k = prescribed_block_offset_[block]; k < prescribed_block_offset_[block + 1]; ++k) {
      const int n = prescribed_nodes_[k];
      const std::uint8_t mask = prescribed_mask_[n];
      for (int d = 0; d < 6; ++d) {
        const double applied = d < 3 ? load_force_[n][d] : load_moment_[n][d - 3];
        const double internal = d < 3 ? internal_force_[n][d] : internal_moment_[n][d - 3];
        reactions_[n][d] = (mask & (1u << d)) ? internal - applied : 0.0;
      }
      for (int d = 0; d < 6; ++d) {
        if (!(mask & (1u << d))) continue;
        const double rate = prescribed_velocity_[n][d];
        constraint_work += 0.5 * (previous_reactions_[n][d] + reactions_[n][d]) * rate * dt;
      }
    }
    const double kinetic = sum_by_fours(begin, end, [&](int j) {
      return 0.5 * mass[j] * v[j] * v[j] + 0.5 * inertia[j] * w[j] * w[j];
    });
    block_sums_[block] = {constraint_work, kinetic};
  });
  const auto [constraint_work, kinetic] = sum_blocks(node_blocks);

  // 5. The elements' energy increments, summed as the nodes' terms (serial: two per element).
  const double internal = sum_by_fours(0, elements, [&](int e) { return element_internal_energy_[e]; });
  const double hourglass = sum_by_fours(0, elements, [&](int e) { return element_hourglass_energy_[e]; });
  energies_.kinetic = kinetic;
  energies_.internal += internal;
  energies_.hourglass += hourglass;
  energies_.damping += damping_work;
  energies_.external_work += external_work;
  energies_.constraint_work += constraint_work;
  energies_.hourglass_warning = energies_.hourglass > 0.05 * std::abs(energies_.internal);
  time_ += dt;
  ++steps_;
  if (!std::isfinite(kinetic) || !std::isfinite(energies_.internal)) {
    const StableTimeStep stable = stable_time_step();
    throw PhysicsError(fmt::format(
        "shell solver: the solution diverged at step {} (t = {} s): kinetic energy {} J, "
        "internal energy {} J; dt = {} s against the stable estimate {} s (element {}): use a "
        "time step ≤ 0.8 of it",
        steps_, time_, kinetic, energies_.internal, dt, stable.time_step, stable.element));
  }
}

// Element e's value k of each history field in storage order (slots_) and in element order.
template <class Copy>
void ShellSolver::for_each_state_value(Copy copy) const {
  for (std::size_t e = 0; e < model_.elements.size(); ++e) {
    const StateSlot& slot = slots_[e];
    const std::size_t point0 = static_cast<std::size_t>(state_offset_[e]);
    const int points = state_offset_[e + 1] - state_offset_[e];
    for (int k = 0; k < 3 * points; ++k)
      copy(0, slot.stress + std::size_t(k) * slot.stride, 3 * point0 + k);
    for (int k = 0; k < points; ++k)
      copy(1, slot.plastic + std::size_t(k) * slot.stride, point0 + k);
    for (int k = 0; k < 3; ++k) copy(2, slot.shear + std::size_t(k) * slot.stride, 3 * e + k);
    for (int k = 0; k < 5; ++k) copy(3, slot.hourglass + std::size_t(k) * slot.stride, 5 * e + k);
  }
}

ShellSolverState ShellSolver::state() const {
  // The histories are filled below, in element order.
  ShellSolverState s{positions_, velocities_, angular_velocities_, rotations_, {},
                     {}, reactions_, previous_reactions_, prescribed_velocity_,
                     {}, {}, {}, {}, options_.damping, time_, steps_, energies_};
  s.loads.resize(positions_.size());
  s.internal_force.resize(positions_.size());
  for (std::size_t n = 0; n < positions_.size(); ++n) {
    s.loads[n] = {load_force_[n], load_moment_[n]};
    const Vec3 &f = internal_force_[n], &m = internal_moment_[n];
    s.internal_force[n] = {f.x, f.y, f.z, m.x, m.y, m.z};
  }
  s.stress.resize(stress_.size());
  s.plastic.resize(plastic_.size());
  s.shear.resize(shear_.size());
  s.hourglass.resize(hourglass_.size());
  const std::vector<double>* from[] = {&stress_, &plastic_, &shear_, &hourglass_};
  std::vector<double>* to[] = {&s.stress, &s.plastic, &s.shear, &s.hourglass};
  for_each_state_value([&](int field, std::size_t stored, std::size_t ordered) {
    (*to[field])[ordered] = (*from[field])[stored];
  });
  return s;
}

namespace {

void expect_count(std::size_t given, std::size_t expected, const char* what) {
  if (given != expected)
    throw std::invalid_argument(fmt::format("shell solver state: {} has {} entries, the model {}", what, given, expected));
}

bool finite_values(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite_values(double v) { return std::isfinite(v); }
bool finite_values(const NodalLoad& l) { return finite_values(l.force) && finite_values(l.moment); }
bool finite_values(const std::array<double, 6>& a) {
  return std::all_of(a.begin(), a.end(), [](double v) { return std::isfinite(v); });
}

template <class T>
void expect_finite(const std::vector<T>& values, std::size_t expected, const char* what) {
  expect_count(values.size(), expected, what);
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!finite_values(values[k]))
      throw std::invalid_argument(fmt::format("shell solver state: {} entry {} is not finite", what, k));
}

}  // namespace

void ShellSolver::check_state(const ShellSolverState& s) const {
  const std::size_t nodes = positions_.size(), elements = model_.elements.size();
  const std::size_t points = plastic_.size();
  expect_finite(s.positions, nodes, "the nodal positions");
  expect_finite(s.velocities, nodes, "the nodal velocities");
  expect_finite(s.angular_velocities, nodes, "the nodal angular velocities");
  expect_finite(s.rotations, nodes, "the nodal rotations");
  expect_finite(s.loads, nodes, "the nodal loads");
  expect_finite(s.internal_force, nodes, "the internal forces");
  expect_finite(s.reactions, nodes, "the reactions");
  expect_finite(s.previous_reactions, nodes, "the previous reactions");
  expect_finite(s.prescribed_velocity, nodes, "the prescribed velocities");
  expect_finite(s.stress, 3 * points, "the stresses");
  expect_finite(s.plastic, points, "the plastic strains");
  expect_finite(s.shear, 3 * elements, "the shear resultants");
  expect_finite(s.hourglass, 5 * elements, "the hourglass resultants");
  for (std::size_t k = 0; k < points; ++k)
    if (s.plastic[k] < 0.0)
      throw std::invalid_argument(fmt::format("shell solver state: plastic strain {} is {} < 0", k, s.plastic[k]));
  const ShellEnergies& e = s.energies;
  for (const double v : {e.kinetic, e.internal, e.hourglass, e.damping, e.external_work, e.constraint_work, s.time})
    if (!std::isfinite(v)) throw std::invalid_argument("shell solver state: an energy or the time is not finite");
  if (!(s.damping >= 0.0) || !std::isfinite(s.damping) || s.steps < 0 || s.time < 0.0)
    throw std::invalid_argument(fmt::format("shell solver state: damping {} 1/s, {} steps or time {} s out of range",
                                            s.damping, s.steps, s.time));
}

void ShellSolver::set_state(ShellSolverState s) {
  check_state(s);
  positions_ = std::move(s.positions);
  velocities_ = std::move(s.velocities);
  angular_velocities_ = std::move(s.angular_velocities);
  rotations_ = std::move(s.rotations);
  for (std::size_t n = 0; n < positions_.size(); ++n) {
    load_force_[n] = s.loads[n].force;
    load_moment_[n] = s.loads[n].moment;
    const std::array<double, 6>& f = s.internal_force[n];
    internal_force_[n] = {f[0], f[1], f[2]};
    internal_moment_[n] = {f[3], f[4], f[5]};
  }
  reactions_ = std::move(s.reactions);
  previous_reactions_ = std::move(s.previous_reactions);
  prescribed_velocity_ = std::move(s.prescribed_velocity);
  const std::vector<double>* from[] = {&s.stress, &s.plastic, &s.shear, &s.hourglass};
  std::vector<double>* to[] = {&stress_, &plastic_, &shear_, &hourglass_};
  for_each_state_value([&](int field, std::size_t stored, std::size_t ordered) {
    (*to[field])[stored] = (*from[field])[ordered];
  });
  options_.damping = s.damping;
  time_ = s.time;
  steps_ = s.steps;
  energies_ = s.energies;
}

ElementResult ShellSolver::element_result(int element) const {
  const int points = model_.sections[model_.elements.at(element).section].integration_points;
  auto vm = [&](int p) { return von_mises(element_stress(element, p)); };
  ElementResult r;
  r.von_mises_bottom = vm(0);
  r.von_mises_top = vm(points - 1);
  r.von_mises_mid = points % 2 == 1 ? vm(points / 2) : 0.5 * (vm(points / 2 - 1) + vm(points / 2));
  for (int p = 0; p < points; ++p) {
    r.plastic_strain_max = std::max(r.plastic_strain_max, element_plastic_strain(element, p));
  }
  return r;
}

Voigt3 ShellSolver::element_stress(int element, int point) const {
  const StateSlot& slot = slots_.at(element);
  const double* s = stress_.data() + slot.stress + std::size_t(3 * point) * slot.stride;
  return {s[0], s[slot.stride], s[2 * slot.stride]};
}

double ShellSolver::element_plastic_strain(int element, int point) const {
  const StateSlot& slot = slots_.at(element);
  return plastic_.at(slot.plastic + std::size_t(point) * slot.stride);
}

ElementFrame ShellSolver::current_frame(int element) const {
  return element_frame(gather(positions_, element), model_.elements.at(element).node_count);
}

}  // namespace quarry::fem
