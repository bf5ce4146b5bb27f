// The batch kernel with eight lanes, compiled for AVX-512 (shell_element_batch.h): called only
// where quad_kernel_available says the processor has it. The target pragma comes after every
// header, so the inline functions those headers define (and that the linker may share with the
// rest of the program) keep the build's baseline instructions; only what follows, the kernel's
// own internal-linkage code, uses AVX-512.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "core/vec3.h"
#include "fem/plane_stress_j2.h"
#include "fem/shell_element.h"
#include "fem/shell_element_batch.h"

#if defined(__x86_64__)
#pragma GCC target("avx512f,avx512dq,avx512vl,avx512bw")
#include "fem/shell_element_batch_kernel.h"

namespace quarry::fem {

void shell_internal_forces_quads_avx512(const Vec3* x, const Vec3* v, const Vec3* omega,
                                        const Nodes& nodes, double dt,
                                        const SectionProperties& section,
                                        const QuadBatchState& states, const QuadBatchOutput& out) {
  quads<8>(x, v, omega, nodes, 0, dt, section, states, out);
}

}  // namespace quarry::fem
#endif
