/* Quarry coupling interface: a stable C ABI (C11) to a Quarry DEM simulation, in this process or
 * in a `quarry serve` process (the same calls; how the handle is opened decides). Modelled on
 * the EDEM coupling interface (seed 004): particle data in particle-type order with persistent
 * 64-bit ids, external force and torque set per particle in 3n arrays, custom particle
 * properties, Monte-Carlo sample points per type; plus coupled surfaces whose nodes a structural
 * solver moves and whose window-mean nodal forces it reads back. docs/coupling.md is the
 * reference: call order, units, ownership, thread safety, error codes and versioning.
 *
 * Conventions. SI units everywhere (m, s, kg, N, Pa). Vectors are 3 doubles (x, y, z); arrays of
 * vectors are 3n doubles, particle k at [3k, 3k+2]. "Type order": all particles of type 0, then
 * type 1, ... (within a type in the engine's order, which changes on re-sorts, insertions and
 * removals: use ids to follow a particle). Every call returns a quarry_status; on an error the
 * handle's last-error text says what and where (quarry_last_error) and nothing was changed.
 * Input structs begin with their size (struct_size = sizeof the struct as the caller compiled
 * it), so fields added at their end in later minor versions keep old callers working. */
#ifndef QUARRY_QUARRY_H
#define QUARRY_QUARRY_H

#include <stddef.h>
#include <stdint.h>

#if defined(QUARRY_BUILDING_LIBRARY)
#define QUARRY_API __attribute__((visibility("default")))
#else
#define QUARRY_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- versioning ---------------------------------------------------------------------------
 * Major: incompatible changes (a caller built for another major is refused at quarry_open).
 * Minor: additions only (new calls, new trailing struct fields, new enum values). A struct_size
 * of any earlier minor's struct is accepted (its later fields take their defaults); a field a
 * minor added is honoured by libraries of that minor or later only, so a caller that needs one
 * checks quarry_abi_version() first.
 * 1.1: quarry_settings.periodic.
 * 1.2: quarry_view_next_step_loads (the next step's external loads, written in place). */
#define QUARRY_ABI_MAJOR 1
#define QUARRY_ABI_MINOR 2
#define QUARRY_ABI_VERSION ((uint32_t)((QUARRY_ABI_MAJOR << 16) | QUARRY_ABI_MINOR))

/* The library's ABI version, (major << 16) | minor. */
QUARRY_API uint32_t quarry_abi_version(void);
/* The library's version text, e.g. "0.2.0" (static storage). */
QUARRY_API const char* quarry_version_string(void);

/* ---- status codes --------------------------------------------------------------------------- */
typedef int32_t quarry_status;
enum {
  QUARRY_OK = 0,
  QUARRY_ERROR_INVALID_HANDLE = -1, /* not a handle, closed, or from another process's server */
  QUARRY_ERROR_NULL_POINTER = -2,   /* a required pointer is NULL */
  QUARRY_ERROR_BAD_LENGTH = -3,     /* an array's length is not the one the call needs */
  QUARRY_ERROR_BAD_VALUE = -4,      /* a value out of range, not finite, an unknown name or enum */
  QUARRY_ERROR_WRONG_STATE = -5,    /* not allowed now (e.g. adding a material after start) */
  QUARRY_ERROR_NOT_FOUND = -6,      /* a particle id, surface or property that does not exist */
  QUARRY_ERROR_INPUT = -7,          /* a deck, mesh or checkpoint file is wrong (file:line:col) */
  QUARRY_ERROR_PHYSICS = -8,        /* the simulation went unstable (step, particle, hint) */
  QUARRY_ERROR_IO = -9,             /* a file could not be read or written */
  QUARRY_ERROR_VERSION = -10,       /* the caller's and the library's (or server's) ABI majors differ */
  QUARRY_ERROR_TRANSPORT = -11,     /* remote: the server is gone, unreachable, or answered garbage */
  QUARRY_ERROR_TIMEOUT = -12,       /* remote: no answer within the open's timeout */
  QUARRY_ERROR_UNSUPPORTED = -13,   /* not available on this handle (e.g. hooks on a remote one) */
  QUARRY_ERROR_HOOK = -14,          /* a step hook returned non-zero; the step stopped there */
  QUARRY_ERROR_INTERNAL = -99       /* a bug in Quarry: please report it with the message */
};
/* The code's name, e.g. "QUARRY_ERROR_BAD_LENGTH" (static storage). */
QUARRY_API const char* quarry_status_name(quarry_status status);

/* ---- handles --------------------------------------------------------------------------------
 * A handle names one simulation. It is a value (copy it freely); a closed or never-opened handle
 * is refused with QUARRY_ERROR_INVALID_HANDLE, never dereferenced. Calls on one handle may come
 * from any thread; they are serialised. Different handles are independent. */
typedef struct quarry_sim {
  uint64_t id;
} quarry_sim;
#ifdef __cplusplus
#define QUARRY_NO_SIM (quarry_sim{0})
#else
#define QUARRY_NO_SIM ((quarry_sim){0})
#endif

/* The last error of the handle (thread-safe), or with QUARRY_NO_SIM the calling thread's last
 * error of a call that had no valid handle (a failed quarry_open, an invalid handle). Copies at
 * most size − 1 bytes and a terminating NUL into `buffer` (if size > 0); *length (optional) gets
 * the full length. An empty text means no error since the last successful call. */
QUARRY_API quarry_status quarry_last_error(quarry_sim sim, char* buffer, size_t size, size_t* length);

/* ---- opening and closing ---------------------------------------------------------------------- */
typedef struct quarry_open_info {
  uint32_t struct_size;         /* sizeof(quarry_open_info) */
  uint32_t abi_version;         /* QUARRY_ABI_VERSION, as the caller was compiled */
  const char* deck_path;        /* a YAML deck (docs/deck.md); NULL: see checkpoint_path */
  const char* checkpoint_path;  /* restore this checkpoint; both NULL: an empty simulation to
                                   build with quarry_set_settings, quarry_add_* and quarry_start */
  const char* output_directory; /* NULL: write nothing; else the deck's outputs (frames, monitors,
                                   load export, checkpoints) go there as `quarry run` writes them */
  const char* endpoint;         /* NULL: in this process; "ipc:///path" or "tcp://host:port": the
                                   simulation of a `quarry serve` listening there */
  int32_t threads;              /* > 0: OpenMP threads of this simulation; 0: the deck's or the
                                   OpenMP default */
  int32_t timeout_ms;           /* remote: longest wait for an answer; 0: 60 000 ms (an advance
                                   may take longer: it waits as long as the server is alive) */
} quarry_open_info;
#define QUARRY_OPEN_INFO_INIT {sizeof(quarry_open_info), QUARRY_ABI_VERSION, NULL, NULL, NULL, NULL, 0, 0}

/* Opens a simulation. A deck or checkpoint gives a started simulation (particles of the
 * factories due at t = 0 inserted, forces computed); an empty one is started by quarry_start.
 * Remote: connects to the server and attaches to its simulation (deck/checkpoint paths, if
 * given, are opened by the server, on its file system). Errors: VERSION, INPUT (with the deck's
 * file:line:col), IO, TRANSPORT, TIMEOUT. Cost: the deck's build (meshes, lists). */
QUARRY_API quarry_status quarry_open(const quarry_open_info* info, quarry_sim* sim);
/* Closes the handle (the outputs' last frame and files are finished). Remote: detaches; the
 * server goes on serving. */
QUARRY_API quarry_status quarry_close(quarry_sim sim);

/* ---- building a simulation without a deck (before quarry_start) ------------------------------ */
enum {
  QUARRY_INTEGRATOR_VELOCITY_VERLET = 0,
  QUARRY_INTEGRATOR_SYMPLECTIC_EULER = 1
};
typedef struct quarry_settings {
  uint32_t struct_size;
  double time_step;             /* s; 0: rayleigh_fraction × the Rayleigh time step */
  double rayleigh_fraction;     /* (0, 1], default 0.2 */
  double gravity[3];            /* m/s², default (0, 0, −9.81) */
  double domain_min[3];         /* m: particles leaving [min, max] are removed, except through
                                   periodic faces (required) */
  double domain_max[3];
  double end_time;              /* s, for the outputs' schedule (default 1) */
  double impact_speed;          /* m/s for the Hertz contact-time check; 0: 1 m/s */
  double skin;                  /* m; < 0: chosen at every list build (default; docs/deck.md) */
  int32_t integrator;           /* QUARRY_INTEGRATOR_* */
  int32_t sort_interval;        /* steps between spatial re-sorts (default 1000; 0: never) */
  double max_overlap_fraction;  /* overlap guard, fraction of the smaller radius (default 0.1) */
  uint64_t seed;                /* random seed (default 12345) */
  /* ---- ABI 1.1 (a caller's struct of 1.0 ends above: these take their defaults) ---- */
  int32_t periodic[3];          /* 1: the domain repeats along x, y, z (period = max − min there;
                                   a particle leaving re-enters at the other side, contacts act
                                   through the faces, as a deck's `periodic: [x, y]`); 0: not
                                   (default) */
} quarry_settings;
/* A quarry_settings holding every default (domain empty: set it). Returned by value, so the
 * struct's size is the caller's: libquarry.so keeps this symbol's ABI 1.0 form (the 1.0 struct)
 * for binaries linked before 1.1, which bind to it (ELF symbol versions QUARRY_1.0 / QUARRY_1.1). */
QUARRY_API quarry_settings quarry_default_settings(void);
/* Errors: BAD_VALUE for an integrator or a periodic entry out of range, a periodic axis along
 * which the domain has no extent (min ≥ max), or a period shorter than the neighbour search
 * needs for the particle types added so far (3 × (2 R_max + skin), docs/deck.md); nothing is
 * changed then. quarry_add_particle_type and quarry_start check the period again. */
QUARRY_API quarry_status quarry_set_settings(quarry_sim sim, const quarry_settings* settings);

typedef struct quarry_material {
  uint32_t struct_size;
  const char* name;
  double density;               /* kg/m³ */
  double youngs_modulus;        /* Pa */
  double poisson_ratio;         /* 1, in (−1, 0.5) */
} quarry_material;
QUARRY_API quarry_status quarry_add_material(quarry_sim sim, const quarry_material* material, uint32_t* index);

enum {
  QUARRY_ROLLING_NONE = 0,
  QUARRY_ROLLING_CONSTANT_TORQUE = 1,
  QUARRY_ROLLING_EPSD = 2
};
typedef struct quarry_interaction {
  uint32_t struct_size;
  const char* material_a;       /* names of two materials (may be the same) */
  const char* material_b;
  double restitution;           /* (0, 1] */
  double static_friction;       /* ≥ 0 */
  double rolling_friction;      /* ≥ 0 */
  int32_t rolling_model;        /* QUARRY_ROLLING_* */
  double cohesion_energy_density; /* J/m³ (SJKR), ≥ 0 */
} quarry_interaction;
/* Hertz–Mindlin no-slip contact between two materials (docs/deck.md, interactions). */
QUARRY_API quarry_status quarry_add_interaction(quarry_sim sim, const quarry_interaction* interaction);

typedef struct quarry_particle_type {
  uint32_t struct_size;
  const char* name;
  const char* material;
  double radius;                /* m: every particle of the type (when max_radius is 0) */
  double max_radius;            /* m: > 0 for radii uniform in [radius, max_radius] */
} quarry_particle_type;
/* With periodic axes set: BAD_VALUE (and no type added) if the type's largest radius makes a
 * period shorter than the neighbour search needs (see quarry_set_settings). */
QUARRY_API quarry_status quarry_add_particle_type(quarry_sim sim, const quarry_particle_type* type, uint32_t* index);

/* Builds the simulation from what was added and brings it to t = 0 (forces computed). After it,
 * settings, materials, interactions and types are fixed; surfaces and particles may still be
 * added. Errors: INPUT (what is missing or wrong, e.g. an interaction never given). */
QUARRY_API quarry_status quarry_start(quarry_sim sim);

/* ---- time ------------------------------------------------------------------------------------ */
/* The simulation's time (s), its own stable time step (s) and the steps taken so far; any
 * pointer may be NULL. */
QUARRY_API quarry_status quarry_get_time(quarry_sim sim, double* time, double* time_step, uint64_t* steps);

typedef struct quarry_advance_result {
  uint32_t struct_size;
  uint64_t steps;               /* steps taken by this call */
  double time;                  /* s, the simulation's time after it */
} quarry_advance_result;
/* Advances by `duration` (s) in steps of the simulation's own time step: as many whole steps as
 * end at or before time + duration (never past it; a remainder under one step is not taken and
 * the next call starts from where this one ended). result may be NULL. After it the state is
 * complete: positions, velocities, forces and loads belong to the new time. Errors: PHYSICS (the
 * simulation stopped at the step named; its state is that step's), HOOK. */
QUARRY_API quarry_status quarry_advance(quarry_sim sim, double duration, quarry_advance_result* result);
/* Exactly `steps` steps. */
QUARRY_API quarry_status quarry_step(quarry_sim sim, uint64_t steps);

/* ---- checkpoints -------------------------------------------------------------------------------
 * A checkpoint holds the whole state, the effective deck and every surface's mesh: it restores
 * bit-exactly without the deck's files (open it with quarry_open_info.checkpoint_path). */
QUARRY_API quarry_status quarry_save_checkpoint(quarry_sim sim, const char* path);
/* The same into memory: with buffer NULL or too small only *needed is set (and BAD_LENGTH is
 * returned for a buffer too small); then call again. */
QUARRY_API quarry_status quarry_save_state(quarry_sim sim, void* buffer, uint64_t size, uint64_t* needed);
/* Puts the handle's simulation back into a state saved by quarry_save_state (e.g. for implicit
 * coupling iterations); hooks and outputs of the handle are kept. */
QUARRY_API quarry_status quarry_restore_state(quarry_sim sim, const void* buffer, uint64_t size);

/* ---- particles (seed 004) ------------------------------------------------------------------- */
QUARRY_API quarry_status quarry_num_types(quarry_sim sim, uint32_t* count);
/* The type's name into buffer (NUL-terminated, truncated to size − 1). */
QUARRY_API quarry_status quarry_type_name(quarry_sim sim, uint32_t type, char* buffer, size_t size);
/* Particles of one type, or of all types with type = −1. */
QUARRY_API quarry_status quarry_num_particles(quarry_sim sim, int32_t type, uint64_t* count);
/* Bumped whenever particles are re-sorted, inserted or removed: indices, views and copies of
 * another epoch no longer match the particles. */
QUARRY_API quarry_status quarry_epoch(quarry_sim sim, uint64_t* epoch);

/* Caller-allocated copies, in type order. Every array pointer may be NULL (not wanted); the
 * others must hold capacity entries (vectors: 3 × capacity doubles). */
typedef struct quarry_particle_data {
  uint32_t struct_size;
  uint64_t capacity;            /* particles the arrays can hold (≥ the particle count) */
  uint64_t* id;                 /* persistent ids */
  uint32_t* type;               /* type index */
  double* position;             /* m, 3n */
  double* velocity;             /* m/s, 3n */
  double* angular_velocity;     /* rad/s, 3n */
  double* radius;               /* m */
  double* mass;                 /* kg */
  double* volume;               /* m³ */
  double* force;                /* N, 3n: the total of the step (contacts, gravity, external, hooks) */
  double* torque;               /* N·m, 3n */
  uint64_t count;               /* out: particles written */
  uint64_t epoch;               /* out: their epoch */
} quarry_particle_data;
/* Errors: BAD_LENGTH if capacity < the particle count (count is then set to the count needed). */
QUARRY_API quarry_status quarry_get_particles(quarry_sim sim, quarry_particle_data* data);
/* The type-order index of the particle with this id (NOT_FOUND if there is none). O(1) after
 * the first call of an epoch (O(n) then). */
QUARRY_API quarry_status quarry_particle_index(quarry_sim sim, uint64_t id, uint64_t* index);

/* Zero-copy views of the engine's own arrays (in-process handles; on a remote handle the view
 * is a copy held by the handle, over ipc:// written by the server into shared memory). A view
 * is in ENGINE order, not type order (with one particle type the two are the same; QUARRY_FIELD_TYPE_ORDER gives order[k] = engine index of the k-th
 * particle in type order). Valid until the next call on the handle that changes the simulation
 * (advance, step, add, remove, set, restore, close); its epoch tells whether the particles are
 * still the same ones. Read-only, except custom properties (quarry_view_property). */
enum {
  QUARRY_FIELD_ID = 1,               /* uint64 */
  QUARRY_FIELD_TYPE = 2,             /* uint16 */
  QUARRY_FIELD_POSITION = 3,         /* double × 3, m */
  QUARRY_FIELD_VELOCITY = 4,         /* double × 3, m/s */
  QUARRY_FIELD_ANGULAR_VELOCITY = 5, /* double × 3, rad/s */
  QUARRY_FIELD_RADIUS = 6,           /* double, m */
  QUARRY_FIELD_INVERSE_MASS = 7,     /* double, 1/kg */
  QUARRY_FIELD_FORCE = 8,            /* double × 3, N (the step's total) */
  QUARRY_FIELD_TORQUE = 9,           /* double × 3, N·m */
  QUARRY_FIELD_TYPE_ORDER = 10       /* uint32: engine index of the k-th particle in type order */
};
enum {
  QUARRY_DTYPE_FLOAT64 = 1,
  QUARRY_DTYPE_UINT64 = 2,
  QUARRY_DTYPE_UINT32 = 3,
  QUARRY_DTYPE_UINT16 = 4
};
typedef struct quarry_view {
  void* data;                   /* first element; NULL when count is 0 */
  uint64_t count;               /* particles */
  uint32_t dtype;               /* QUARRY_DTYPE_* */
  uint32_t components;          /* values per particle */
  int64_t stride;               /* bytes from one particle to the next */
  uint64_t epoch;               /* quarry_epoch at the time of the view */
  uint32_t writable;            /* 1: the caller may write through data */
} quarry_view;
QUARRY_API quarry_status quarry_view_particles(quarry_sim sim, int32_t field, quarry_view* view);

/* Adds particles between steps (they are in contact from the next step's force stage on). */
typedef struct quarry_new_particles {
  uint32_t struct_size;
  uint64_t count;
  const uint32_t* types;        /* count types; NULL: every particle is of `type` */
  uint32_t type;
  const double* position;       /* m, 3 × count (required) */
  const double* velocity;       /* m/s, 3 × count; NULL: at rest */
  const double* angular_velocity; /* rad/s, 3 × count; NULL: not spinning */
  const double* radius;         /* m, count; NULL or an entry ≤ 0: drawn from the type's sizes */
  uint64_t* ids;                /* out, count: the new particles' ids (may be NULL) */
} quarry_new_particles;
QUARRY_API quarry_status quarry_add_particles(quarry_sim sim, const quarry_new_particles* particles);
/* Removes particles by id (NOT_FOUND naming the first unknown id: then nothing is removed). */
QUARRY_API quarry_status quarry_remove_particles(quarry_sim sim, const uint64_t* ids, uint64_t count);

/* ---- external force and torque (EDEM's setForceAndTorque) ----------------------------------- */
enum {
  QUARRY_LOAD_REPLACE = 0,      /* the value replaces the particle's load of that hold */
  QUARRY_LOAD_ADD = 1           /* the value is added to it */
};
enum {
  QUARRY_HOLD_NEXT_STEP = 0,    /* acts in the next step only */
  QUARRY_HOLD_UNTIL_CHANGED = 1 /* acts in every step until set again or cleared */
};
/* force and torque: 3 × count doubles in type order, count = every particle (BAD_LENGTH
 * otherwise); either may be NULL (left as it is). The loads act from the next step on (both of
 * its half kicks); they show in the particles' force at once. */
QUARRY_API quarry_status quarry_set_external_loads(quarry_sim sim, const double* force, const double* torque,
                                                   uint64_t count, int32_t mode, int32_t hold);
/* The same for the particles with these ids (entry k for ids[k]). */
QUARRY_API quarry_status quarry_set_external_loads_by_id(quarry_sim sim, const uint64_t* ids, uint64_t count,
                                                         const double* force, const double* torque,
                                                         int32_t mode, int32_t hold);
/* Every external load (of both holds) back to zero. */
QUARRY_API quarry_status quarry_clear_external_loads(quarry_sim sim);
/* ABI 1.2. A writable view of the next step's external loads (hold NEXT_STEP), field
 * QUARRY_FIELD_FORCE (N) or QUARRY_FIELD_TORQUE (N·m), 3 doubles a particle in ENGINE order (see
 * quarry_view_particles): the zero-copy way to set them. It holds the loads set so far for the
 * next step (zeros after a step); what the caller leaves there acts in the next step exactly as
 * quarry_set_external_loads(…, QUARRY_LOAD_REPLACE, QUARRY_HOLD_NEXT_STEP) with those values
 * would (after a step, the same bits). The values are not checked: a non-finite one stops the
 * next step, naming the particle. They show in the particles' force wherever it is read (copies,
 * views); the step adds them in its kicks. In process the view is the engine's own array; on a remote handle it is
 * a copy held by the handle, sent to the server before the handle's next call other than a view.
 * Valid as views are; not inside a hook (WRONG_STATE). */
QUARRY_API quarry_status quarry_view_next_step_loads(quarry_sim sim, int32_t field, quarry_view* view);

/* ---- custom particle properties ----------------------------------------------------------------
 * Per-particle values a partner keeps with the particles: they follow their particle through
 * re-sorts, are given `initial` for new particles, are checkpointed and written to the particle
 * frames (VTU point data under their name). */
/* Registers (name, components ≥ 1, unit text such as "K" or "m/s", initial value); registering a
 * name again returns its existing index (BAD_VALUE if the components differ). */
QUARRY_API quarry_status quarry_register_property(quarry_sim sim, const char* name, uint32_t components,
                                                  const char* unit, double initial, uint32_t* index);
QUARRY_API quarry_status quarry_num_properties(quarry_sim sim, uint32_t* count);
/* name and unit are copied NUL-terminated (truncated to their sizes); pointers may be NULL. */
QUARRY_API quarry_status quarry_property_info(quarry_sim sim, uint32_t index, char* name, size_t name_size,
                                              uint32_t* components, char* unit, size_t unit_size);
/* values: particles × components doubles in type order, each particle's components together. */
QUARRY_API quarry_status quarry_get_property(quarry_sim sim, uint32_t index, double* values, uint64_t count);
QUARRY_API quarry_status quarry_set_property(quarry_sim sim, uint32_t index, const double* values, uint64_t count);
/* A writable view in engine order (see quarry_view_particles). */
QUARRY_API quarry_status quarry_view_property(quarry_sim sim, uint32_t index, quarry_view* view);

/* ---- sample points (EDEM's collectSamplePoints) ----------------------------------------------
 * Monte-Carlo points inside a particle of the type (uniform in its volume; seeded, the same on
 * every platform), for volume fractions: a particle's solid volume in a cell is V_p × n_c / N. */
/* `points` points of the unit particle (centre 0, radius 1) into unit_points (3 × points). */
QUARRY_API quarry_status quarry_sample_points(quarry_sim sim, uint32_t type, uint32_t points, uint64_t seed,
                                              double* unit_points);
/* The same points placed in every particle of the type, in type order: particle p's point k at
 * positions[3(p·points + k)]; capacity in doubles; *particles (optional) gets the count. */
QUARRY_API quarry_status quarry_sample_point_positions(quarry_sim sim, uint32_t type, uint32_t points, uint64_t seed,
                                                       double* positions, uint64_t capacity, uint64_t* particles);

/* ---- surfaces and coupled surfaces ---------------------------------------------------------- */
enum {
  QUARRY_DRIVER_FIXED = 0,      /* never moves */
  QUARRY_DRIVER_PRESCRIBED = 1, /* the deck's motion (cannot be set through this interface) */
  QUARRY_DRIVER_COUPLED = 2     /* nodes set by the partner (quarry_set_surface_nodes) */
};
typedef struct quarry_surface_desc {
  uint32_t struct_size;
  const char* name;
  const char* material;
  uint64_t node_count;
  const double* nodes;          /* m, 3 × node_count */
  uint64_t triangle_count;
  const uint32_t* triangles;    /* 3 × triangle_count node indices (0-based) */
  uint64_t quad_count;
  const uint32_t* quads;        /* 4 × quad_count node indices; each is split into two triangles
                                   of one element */
  int32_t driver;               /* QUARRY_DRIVER_FIXED or QUARRY_DRIVER_COUPLED */
} quarry_surface_desc;
/* Elements are numbered triangles first, then quads, in the order given; nodes as given (not
 * merged). Allowed before and after quarry_start. */
QUARRY_API quarry_status quarry_add_surface(quarry_sim sim, const quarry_surface_desc* surface, uint32_t* index);
QUARRY_API quarry_status quarry_num_surfaces(quarry_sim sim, uint32_t* count);
QUARRY_API quarry_status quarry_find_surface(quarry_sim sim, const char* name, uint32_t* index);
typedef struct quarry_surface_info {
  uint32_t struct_size;
  uint64_t node_count;
  uint64_t element_count;
  uint64_t triangle_count;
  int32_t driver;               /* QUARRY_DRIVER_* */
} quarry_surface_info;
QUARRY_API quarry_status quarry_get_surface_info(quarry_sim sim, uint32_t surface, quarry_surface_info* info);
/* Makes a fixed surface coupled or a coupled one fixed (a prescribed one stays prescribed:
 * WRONG_STATE). */
QUARRY_API quarry_status quarry_set_surface_driver(quarry_sim sim, uint32_t surface, int32_t driver);
/* A coupled surface's nodes now: positions (m) and velocities (m/s; NULL: at rest), 3 × count
 * doubles with count = its node count. Until the next call the surface moves on with these
 * velocities, x(t) = x + v (t − t_set), its normals and search grid following; the neighbour
 * lists are rebuilt when a node has moved more than half the skin. */
QUARRY_API quarry_status quarry_set_surface_nodes(quarry_sim sim, uint32_t surface, const double* positions,
                                                  const double* velocities, uint64_t count);
/* The surface's nodes now (either pointer may be NULL). */
QUARRY_API quarry_status quarry_get_surface_nodes(quarry_sim sim, uint32_t surface, double* positions,
                                                  double* velocities, uint64_t count);

/* The loads the particles put on the surface, as time means over the window since the last call
 * for this surface (or since it was first asked for): impulse / window length, so that a partner
 * that syncs every period receives exactly the momentum the particles transferred. The window
 * then restarts. Any array may be NULL. */
typedef struct quarry_surface_loads {
  uint32_t struct_size;
  uint64_t node_count;          /* entries of nodal_force (must equal the surface's) */
  double* nodal_force;          /* N, 3 × node_count: consistent (barycentric) nodal forces */
  uint64_t element_count;       /* entries of the per-element arrays (must equal the surface's) */
  double* pressure;             /* Pa, compressive normal stress */
  double* shear_stress;         /* Pa, 3 × element_count: tangential traction */
  double* element_force;        /* N, 3 × element_count */
  double window;                /* out: s, the window's length */
  double time;                  /* out: s, its end (now) */
} quarry_surface_loads;
QUARRY_API quarry_status quarry_get_surface_loads(quarry_sim sim, uint32_t surface, quarry_surface_loads* loads);

/* ---- step hooks (in-process handles only) ------------------------------------------------------
 * Called inside every step: POST_FORCE after the contact and body forces of the new positions,
 * before the closing half kick (positions are x(t + dt), velocities the half-step v(t + dt/2):
 * the place for velocity-dependent forces such as drag, added with quarry_add_hook_forces);
 * END_OF_STEP when the step is complete. A non-zero return stops the step with QUARRY_ERROR_HOOK.
 * Inside a hook, calls on the same handle may read (get, view) and, in POST_FORCE, add forces;
 * other calls return WRONG_STATE. */
enum {
  QUARRY_HOOK_POST_FORCE = 1,
  QUARRY_HOOK_END_OF_STEP = 2
};
typedef int (*quarry_hook_fn)(quarry_sim sim, int32_t stage, void* user_data);
/* Sets (fn non-NULL) or removes (fn NULL) the handle's hook of a stage. */
QUARRY_API quarry_status quarry_set_hook(quarry_sim sim, int32_t stage, quarry_hook_fn fn, void* user_data);
/* Inside a POST_FORCE hook only: adds force and torque (3 × count doubles in type order, count =
 * every particle; either may be NULL) to this step's forces. */
QUARRY_API quarry_status quarry_add_hook_forces(quarry_sim sim, const double* force, const double* torque,
                                                uint64_t count);

#ifdef __cplusplus
}
#endif

#endif /* QUARRY_QUARRY_H */
