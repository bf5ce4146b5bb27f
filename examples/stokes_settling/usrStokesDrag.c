/* usrStokesDrag: Stokes drag with the porosity factor of the AcuSolve-EDEM tutorial's user drag
 * function (seed 001), F = 3π ε d μ (u − v), written against Quarry's drag_udf.h.
 * Build: quarry udf build usrStokesDrag.c   (writes usrStokesDrag.so beside it) */
#include <quarry/drag_udf.h>

QUARRY_DRAG_UDF_EXPORT_ABI()

QUARRY_DRAG_UDF_PROTOTYPE(usrStokesDrag);

/* Quarry passes the diameter; the seed derived it from the volume, pow(6 V/π, 0.333333333333),
 * which is 9e-12 relative above d for d = 0.1 mm (the exponent is short of 1/3). The factors
 * are multiplied in the order of Quarry's built-in "stokes" law, so the two agree to round-off. */
int usrStokesDrag(const quarry_drag_input* in, quarry_drag_output* out, void* user) {
  (void)user;
  if (!(in->particle_diameter > 0.0)) return quarry_drag_fail(out, "particle diameter must be > 0");
  double slip[3]; /* m/s, u − v */
  for (int i = 0; i < 3; ++i) slip[i] = in->fluid_velocity[i] - in->particle_velocity[i];
  /* kg/s, β_p = 3π ε d μ */
  const double beta =
      3.0 * QUARRY_DRAG_UDF_PI * in->porosity * in->particle_diameter * in->fluid_viscosity;
  for (int i = 0; i < 3; ++i) out->force[i] = beta * slip[i]; /* N */
  out->drag_coefficient = beta; /* optional: the seed's fourth value, which it left out */
  out->has_drag_coefficient = 1;
  return 0;
}
