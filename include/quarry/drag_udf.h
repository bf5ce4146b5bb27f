/* Quarry user-defined drag: a plain C ABI (C11) for a drag law written by the user, compiled into
 * a shared library (`quarry udf build usrDrag.c` → usrDrag.so) and named, with the function, in
 * the deck. Modelled on AcuSolve's EDEM drag user functions (seed 001): the inputs are what such
 * a function reads with udfGetEDEMData, the output is the force (and optionally the coefficient)
 * that it writes into outVec. docs/cfd.md ("User-defined drag") is the reference, with a complete
 * example (examples/stokes_settling/usrStokesDrag.c).
 *
 * A library holds:
 *   #include <quarry/drag_udf.h>
 *   QUARRY_DRAG_UDF_EXPORT_ABI()            (once per library: the version it was built for)
 *   QUARRY_DRAG_UDF_PROTOTYPE(usrMyDrag);   (any number of drag functions, named in the deck)
 *   int usrMyDrag(const quarry_drag_input* in, quarry_drag_output* out, void* user) { ... }
 *
 * Conventions. SI units everywhere (m, s, kg, N, Pa). Vectors are 3 doubles (x, y, z) in the
 * simulation's frame, the same axes as the deck's gravity. All values are at the particle's
 * centre at the time of the call. Structs begin with their size (struct_size = sizeof the struct
 * as Quarry compiled it), so fields added at their end in later minor versions keep old
 * libraries working; a library built against a newer minor reads a field only when
 * QUARRY_DRAG_HAS_FIELD says Quarry gave it.
 *
 * Threads. Quarry calls the function from several threads at once, for different particles,
 * with a different `in` and `out` for each call. It must therefore not keep state between calls
 * in global or static variables (unless it locks them itself) and must not call Quarry. The
 * function must not keep the pointers after it returns.
 *
 * Cost. The function is called once per particle per fluid coupling step: for 100k particles
 * that is 100k calls per coupling step, so it should cost what a built-in law costs (a few
 * hundred floating-point operations at most): no file or terminal I/O, no allocation, no locks
 * on the normal path. */
#ifndef QUARRY_DRAG_UDF_H
#define QUARRY_DRAG_UDF_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#define QUARRY_DRAG_UDF_EXTERN extern "C"
#else
#define QUARRY_DRAG_UDF_EXTERN
#endif

/* Exported from the library whatever its default visibility (-fvisibility=hidden included). */
#define QUARRY_DRAG_UDF_EXPORT QUARRY_DRAG_UDF_EXTERN __attribute__((visibility("default")))

/* ---- versioning -------------------------------------------------------------------------------
 * Major: incompatible changes (Quarry refuses a library built for another major, naming both).
 * Minor: additions only (new trailing struct fields, new optional exported functions). */
#define QUARRY_DRAG_UDF_ABI_MAJOR 1
#define QUARRY_DRAG_UDF_ABI_MINOR 0
#define QUARRY_DRAG_UDF_ABI_VERSION \
  ((uint32_t)(((uint32_t)QUARRY_DRAG_UDF_ABI_MAJOR << 16) | (uint32_t)QUARRY_DRAG_UDF_ABI_MINOR))

/* Required in every library: returns the QUARRY_DRAG_UDF_ABI_VERSION it was compiled with,
 * (major << 16) | minor. Define it with QUARRY_DRAG_UDF_EXPORT_ABI(). */
QUARRY_DRAG_UDF_EXPORT uint32_t quarry_drag_udf_abi(void);
#define QUARRY_DRAG_UDF_EXPORT_ABI()                          \
  QUARRY_DRAG_UDF_EXPORT uint32_t quarry_drag_udf_abi(void) { \
    return QUARRY_DRAG_UDF_ABI_VERSION;                       \
  }

/* π to double precision (strict C11's math.h has no M_PI). The same double as C++'s
 * std::numbers::pi, which Quarry's built-in laws use. */
#define QUARRY_DRAG_UDF_PI 3.14159265358979323846

/* ---- the input: one particle and the fluid around it ---------------------------------------- */
typedef struct quarry_drag_input {
  uint32_t struct_size;        /* sizeof(quarry_drag_input) as Quarry compiled it */
  uint32_t particle_type;      /* index of the particle's type (the deck's order), diagnostics */
  uint64_t particle_id;        /* the particle's persistent id, for diagnostics */
  double time;                 /* s, simulated time of the call */
  double particle_volume;      /* m³, V_p (π d³/6 for a sphere) */
  double particle_diameter;    /* m, d */
  double particle_velocity[3]; /* m/s, v */
  double fluid_velocity[3];    /* m/s, u: the interstitial (not superficial) fluid velocity */
  double porosity;             /* 1, ε: fluid volume fraction of the cell, in (0, 1] */
  double fluid_viscosity;      /* Pa·s, μ: dynamic viscosity */
  double fluid_density;        /* kg/m³, ρ_f */
  double pressure_gradient[3]; /* Pa/m, ∇p of the fluid (its force on the particle, −V_p ∇p,
                                  is applied by Quarry separately: do not add it to the drag) */
  double reynolds_number;      /* 1, Re_p = ρ_f ε |u − v| d / μ: on the superficial slip
                                  ε |u − v| (divide by ε for the interstitial Re) */
} quarry_drag_input;

/* ---- the output ------------------------------------------------------------------------------
 * Quarry zeroes it and sets struct_size before each call (as AcuSolve's outVec arrives zeroed). */
#define QUARRY_DRAG_UDF_MESSAGE_SIZE 256
typedef struct quarry_drag_output {
  uint32_t struct_size;          /* sizeof(quarry_drag_output) as Quarry compiled it */
  uint32_t has_drag_coefficient; /* set to 1 when drag_coefficient was written */
  double force[3];               /* N, the fluid's drag on the particle (towards u − v for a
                                    drag law); the solver applies the opposite to the fluid */
  double drag_coefficient;       /* kg/s, optional: β_p ≥ 0 with force = β_p (u − v), the per-
                                    particle momentum-exchange coefficient that the semi-implicit
                                    drag freezes over a fluid step (not the dimensionless C_d).
                                    Not set: Quarry takes force·(u − v)/|u − v|² (0 at no slip) */
  char message[QUARRY_DRAG_UDF_MESSAGE_SIZE]; /* on an error: what went wrong, NUL-terminated
                                                 (quarry_drag_fail writes it) */
} quarry_drag_output;

/* The drag function. Returns 0 on success with out->force set; non-zero on an error, with a
 * message in out->message: the run then stops (exit code 3), naming the particle, every input
 * value and the message. A force that is NaN or infinite stops the run the same way. `user` is
 * NULL in ABI 1.0 (reserved). Called concurrently from several threads (see the file's head). */
typedef int (*quarry_drag_fn)(const quarry_drag_input* in, quarry_drag_output* out, void* user);

/* Declares an exported drag function `name` (as AcuSolve's UDF_PROTOTYPE does); the definition
 * that follows it is then exported too. Use it also in C++ sources: it gives the function C
 * linkage, so that its symbol is the plain name the deck gives. */
#define QUARRY_DRAG_UDF_PROTOTYPE(name) \
  QUARRY_DRAG_UDF_EXPORT int name(const quarry_drag_input* in, quarry_drag_output* out, void* user)

/* Whether Quarry's struct has `field` (a library built against a newer minor asks before it
 * reads a field that minor added): e.g. QUARRY_DRAG_HAS_FIELD(quarry_drag_input, in, porosity). */
#define QUARRY_DRAG_HAS_FIELD(type, pointer, field) \
  ((pointer)->struct_size >= offsetof(type, field) + sizeof(((type*)0)->field))

/* Copies `message` into out->message (truncated to fit, NUL-terminated) and returns 1, so that
 * a function can end with `return quarry_drag_fail(out, "particle volume must be > 0");`. */
static inline int quarry_drag_fail(quarry_drag_output* out, const char* message) {
  size_t length = 0;
  while (message[length] != '\0' && length + 1 < sizeof out->message) {
    out->message[length] = message[length];
    ++length;
  }
  out->message[length] = '\0';
  return 1;
}

#ifdef __cplusplus
}
#endif

#endif /* QUARRY_DRAG_UDF_H */
