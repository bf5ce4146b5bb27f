// shell_internal_forces (shell_element.h) for a batch of eight Belytschko–Tsay quads: the
// solver's common case (quads of one section, edge-tied shear). The element kernel is flat
// arithmetic with two square roots and sixteen divisions per quad, much of it on one dependency
// chain; computing several quads per vector instruction (structure of arrays across the quads)
// runs them side by side. Two kernels: four lanes (AVX2 in the release build: 3.4× the scalar
// kernel's element-steps per second on the 10k-quad plate, one thread) on any x86-64, and eight
// lanes (AVX-512: 32 vector registers, so the eight quads' values mostly stay in them) where the
// processor has it, chosen at run time (docs/performance.md).
//
// Bit-identical to the scalar kernel: each lane performs the same IEEE operations in the same
// order (no FMA contraction in this project; vector square root and division are correctly
// rounded like the scalar ones), and a point whose elastic trial leaves the yield surface is
// finished by the scalar return map of its own lane. shell_element_batch_test checks this bit
// for bit on random distorted quads, elastic and yielding, for each kernel the machine has.
#pragma once

#include <array>
#include <cstdint>

#include "core/vec3.h"
#include "fem/shell_element.h"

namespace quarry::fem {

// Quads per batch (the lanes of the interleaved histories); the four-lane kernel takes a batch
// in two halves.
inline constexpr int kQuadLanes = 8;

enum class QuadKernel { four_lanes, eight_lanes };
// Whether this processor (and its operating system) runs the kernel: eight lanes need AVX-512
// F, DQ, VL and BW; four lanes run anywhere.
bool quad_kernel_available(QuadKernel kernel);
// Eight lanes where available, else four. Both give the same bits.
QuadKernel fastest_quad_kernel();
const char* quad_kernel_name(QuadKernel kernel);  // "4 lanes (AVX2)", "8 lanes (AVX-512)"

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

// The histories of a batch's quads, interleaved (structure of arrays in blocks of
// kQuadLanes): value k of lane l at [kQuadLanes * k + l], k as in ElementState (stress 3 per
// point, plastic strain per point, shear 3, hourglass 5). The kernel then loads and stores each
// value of its lanes as one vector instead of one scalar per lane (the solver keeps its batched
// quads' state so: n 36 plate, one thread, +8 % element-steps/s).
struct QuadBatchState {
  double* stress = nullptr;
  double* plastic_strain = nullptr;
  double* shear = nullptr;
  double* hourglass = nullptr;
};

// shell_internal_forces for the eight quads whose nodes are nodes[l] (indices into x, v,
// omega), all of `section` (pre: batchable(section)), with their states; lane l's results go
// where out's pointers l point, equal to the bit to shell_internal_forces of quad l, whichever
// kernel (pre: quad_kernel_available(kernel)). Cost: O(points); four quads about one scalar
// quad with four lanes (10k-quad plate, docs/performance.md).
void shell_internal_forces_quads(const Vec3* x, const Vec3* v, const Vec3* omega,
                                 const std::array<std::array<std::int32_t, 4>, kQuadLanes>& nodes,
                                 double dt, const SectionProperties& section,
                                 const QuadBatchState& states, const QuadBatchOutput& out,
                                 QuadKernel kernel);

}  // namespace quarry::fem
