// shell_internal_forces (shell_element.h) for four Belytschko–Tsay quads at once: the solver's
// common case (quads of one section, edge-tied shear). The element kernel is flat arithmetic
// with two square roots and sixteen divisions per quad, much of it on one dependency chain;
// computing four quads per AVX2 instruction (structure of arrays across the quads) runs them
// side by side: 3.4× the element-steps per second on the 10k-quad plate, one thread.
//
// Bit-identical to the scalar kernel: each lane performs the same IEEE operations in the same
// order (no FMA contraction in this project; vector square root and division are correctly
// rounded like the scalar ones), and a point whose elastic trial leaves the yield surface is
// finished by the scalar return map of its own lane. shell_element_batch_test checks this bit
// for bit on random distorted quads, elastic and yielding.
#pragma once

#include <array>
#include <cstdint>

#include "core/vec3.h"
#include "fem/shell_element.h"

namespace quarry::fem {

inline constexpr int kQuadLanes = 4;

// Whether a section's quads can go through shell_internal_forces_quads (edge-tied shear; the
// centre-shear variant stays scalar).
inline bool batchable(const SectionProperties& section) {
  return section.quad_shear == QuadShear::edge_tied;
}

// Where the results of each lane go: ElementForces' fields, as pointers so that the solver's
// arrays take them directly (a local ElementForces per lane, zeroed by its initialisers and
// then copied, took 28 % of the solver's batch loop outside the kernel).
struct QuadBatchOutput {
  std::array<std::array<std::array<double, 6>, 4>*, kQuadLanes> nodal;
  std::array<double*, kQuadLanes> internal_energy_increment, hourglass_energy_increment;
};

// The histories of a batch's four quads, interleaved (structure of arrays in blocks of
// kQuadLanes): value k of lane l at [kQuadLanes * k + l], k as in ElementState (stress 3 per
// point, plastic strain per point, shear 3, hourglass 5). The kernel then loads and stores each
// value of the four lanes as one vector instead of four scalars (the solver keeps its batched
// quads' state so: n 36 plate, one thread, +8 % element-steps/s).
struct QuadBatchState {
  double* stress = nullptr;
  double* plastic_strain = nullptr;
  double* shear = nullptr;
  double* hourglass = nullptr;
};

// shell_internal_forces for the four quads whose nodes are nodes[l] (indices into x, v, omega),
// all of `section` (pre: batchable(section)), with their states; lane l's results go where
// out's pointers l point, equal to the bit to shell_internal_forces of quad l. Cost: O(points);
// the four together about one scalar quad (10k-quad plate, docs/performance.md).
void shell_internal_forces_quads(const Vec3* x, const Vec3* v, const Vec3* omega,
                                 const std::array<std::array<std::int32_t, 4>, kQuadLanes>& nodes,
                                 double dt, const SectionProperties& section,
                                 const QuadBatchState& states, const QuadBatchOutput& out);
// The same with each lane's history where states[l] points (interleaved into a copy and back;
// for tests and callers that keep element-wise histories).
void shell_internal_forces_quads(const Vec3* x, const Vec3* v, const Vec3* omega,
                                 const std::array<std::array<std::int32_t, 4>, kQuadLanes>& nodes,
                                 double dt, const SectionProperties& section,
                                 const std::array<ElementState, kQuadLanes>& states,
                                 const QuadBatchOutput& out);

}  // namespace quarry::fem
