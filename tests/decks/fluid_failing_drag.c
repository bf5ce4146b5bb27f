/* A drag UDF that refuses every call after 1 ms of simulated time: the run that uses it (fluid_udf_fails.yaml)
 * must stop with exit code 3, the particle, its inputs and this message (issue #18 §4). */
#include <quarry/drag_udf.h>

QUARRY_DRAG_UDF_EXPORT_ABI()

QUARRY_DRAG_UDF_PROTOTYPE(usrFailingDrag);

int usrFailingDrag(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)user;
  if (in->time > 1.0e-3) return quarry_drag_fail(out, "refusing after 1 ms, as the test wants");
  const double beta = 3.0 * QUARRY_DRAG_UDF_PI * in->particle_diameter * in->fluid_viscosity;
  for (int i = 0; i < 3; ++i) out->force[i] = beta * (in->fluid_velocity[i] - in->particle_velocity[i]);
  return 0;
}
