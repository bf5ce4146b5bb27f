// The batch kernel's dispatch and its four-lane form (shell_element_batch.h); the body is
// shell_element_batch_kernel.h, the eight-lane form shell_element_batch_avx512.cpp.
#include "fem/shell_element_batch.h"

#include <stdexcept>

#include "fem/shell_element_batch_kernel.h"

namespace quarry::fem {

#if defined(__x86_64__)
// shell_element_batch_avx512.cpp.
void shell_internal_forces_quads_avx512(const Vec3* x, const Vec3* v, const Vec3* omega,
                                        const Nodes& nodes, double dt,
                                        const SectionProperties& section,
                                        const QuadBatchState& states, const QuadBatchOutput& out);
#endif

bool quad_kernel_available(QuadKernel kernel) {
  if (kernel == QuadKernel::four_lanes) return true;
#if defined(__x86_64__)
  // libgcc's check includes the operating system's saving of the AVX-512 registers (XCR0).
  static const bool avx512 =
      __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw");
  return avx512;
#else
  return false;
#endif
}

QuadKernel fastest_quad_kernel() {
  return quad_kernel_available(QuadKernel::eight_lanes) ? QuadKernel::eight_lanes
                                                        : QuadKernel::four_lanes;
}

const char* quad_kernel_name(QuadKernel kernel) {
  return kernel == QuadKernel::eight_lanes ? "8 lanes (AVX-512)" : "4 lanes (AVX2)";
}

void shell_internal_forces_quads(const Vec3* x, const Vec3* v, const Vec3* omega,
                                 const Nodes& nodes, double dt, const SectionProperties& section,
                                 const QuadBatchState& states, const QuadBatchOutput& out,
                                 QuadKernel kernel) {
#if defined(__x86_64__)
  if (kernel == QuadKernel::eight_lanes) {
    if (!quad_kernel_available(kernel))
      throw std::invalid_argument("shell_internal_forces_quads: this processor has no AVX-512");
    shell_internal_forces_quads_avx512(x, v, omega, nodes, dt, section, states, out);
    return;
  }
#else
  if (kernel == QuadKernel::eight_lanes)
    throw std::invalid_argument(
        "shell_internal_forces_quads: eight lanes need an x86-64 processor");
#endif
  quads<4>(x, v, omega, nodes, 0, dt, section, states, out);
  quads<4>(x, v, omega, nodes, 4, dt, section, states, out);
}

}  // namespace quarry::fem
