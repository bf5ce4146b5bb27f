/* A coupling partner written in C11 against include/quarry/quarry.h only (issue 16, §5): it
 * builds a simulation through the ABI, drives it with a drag force it computes itself every
 * step, and checks the engine against closed forms. Run in this process by default, or against
 * a `quarry serve` with --endpoint ENDPOINT (then the same checks, and the same final state hash
 * must come out: tests/capi/CMakeLists.txt compares them). With --load-view the drag goes in
 * through the writable view of the next step's loads (ABI 1.2, engine order, placed through the
 * type-order map), but on every seventh step through quarry_set_external_loads: the same bits
 * must come out as with the copies alone.
 *
 * Checks:
 *  1. Linear drag F = −c v set each step (replace, next step only): v(t) = v_t (1 − e^{−t/τ}),
 *     v_t = m g / c, τ = m / c. The partner sets F_n = −c v_n before step n; the engine applies it in
 *     both half kicks of that step, with gravity, so v_{n+1} = v_n + dt (g − v_n / τ): forward Euler
 *     for the ODE. Its exact discrete solution is v_n = v_t (1 − (1 − a)^n), a = dt/τ, which the
 *     engine must reproduce to round-off; and its distance to the continuous solution is
 *     v_t [e^{−an} − (1 − a)^n] ≈ v_t (a/2)(t/τ) e^{−t/τ} ≤ v_t a / (2e) (maximum at t = τ), the
 *     tolerance used (×1.05 for the O(a²) remainder).
 *  2. Momentum: Σ m (v_end − v_0) = Σ_steps Σ_particles (m g + F) dt (no contacts), to round-off:
 *     each step adds two half kicks to v, each rounded by at most half an ulp of |v| ≤ v_t, so the
 *     bound is steps × ε × Σ m v_t (ε = DBL_EPSILON); the partner sums its impulses in long double
 *     so that its own rounding stays far below that.
 *  3. Ids stay with their particle through spatial re-sorts (each keeps its own x, y while it
 *     falls) and insertions; custom properties (two components) follow them, new particles get
 *     the initial value, and a checkpoint restores them and continues bit-identically.
 *  4. Type order: the arrays hold type 0's particles, then type 1's. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "quarry/quarry.h"

static int failures = 0, checks = 0;

#define CHECK(condition, ...)                                  \
  do {                                                         \
    ++checks;                                                  \
    if (!(condition)) {                                        \
      ++failures;                                              \
      fprintf(stderr, "FAILED %s:%d: ", __FILE__, __LINE__);   \
      fprintf(stderr, __VA_ARGS__);                            \
      fprintf(stderr, "\n");                                   \
    }                                                          \
  } while (0)

/* A call that must succeed: on failure print its error and stop. */
static void must(quarry_sim sim, quarry_status status, const char* what) {
  if (status == QUARRY_OK) return;
  char text[2048];
  quarry_last_error(sim, text, sizeof text, NULL);
  fprintf(stderr, "FAILED: %s returned %s: %s\n", what, quarry_status_name(status), text);
  exit(1);
}
#define MUST(sim, call) must((sim), (call), #call)

enum { kParticles = 40, kSteps = 5000 };
static const double kRadius = 1e-3;      /* m */
static const double kDensity = 2500.0;   /* kg/m³ */
static const double kGravity = 9.81;     /* m/s² */
static const double kDt = 1e-4;          /* s */

static quarry_sim build(const char* endpoint) {
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  info.endpoint = endpoint;
  info.threads = 2;
  quarry_sim sim;
  MUST(QUARRY_NO_SIM, quarry_open(&info, &sim));
  quarry_settings settings = quarry_default_settings();
  settings.time_step = kDt;
  settings.gravity[2] = -kGravity;
  for (int k = 0; k < 3; ++k) settings.domain_min[k] = -2.0, settings.domain_max[k] = 2.0;
  settings.impact_speed = 0.05;
  settings.sort_interval = 25; /* re-sort often: ids must survive it */
  MUST(sim, quarry_set_settings(sim, &settings));
  quarry_material ore = {sizeof ore, "ore", kDensity, 1e6, 0.3};
  MUST(sim, quarry_add_material(sim, &ore, NULL));
  quarry_interaction contact = {sizeof contact, "ore", "ore", 0.5, 0.5, 0.0, QUARRY_ROLLING_NONE, 0.0};
  MUST(sim, quarry_add_interaction(sim, &contact));
  quarry_particle_type fine = {sizeof fine, "fine", "ore", kRadius, 0.0};
  quarry_particle_type coarse = {sizeof coarse, "coarse", "ore", kRadius, 0.0};
  MUST(sim, quarry_add_particle_type(sim, &fine, NULL));
  MUST(sim, quarry_add_particle_type(sim, &coarse, NULL));
  MUST(sim, quarry_start(sim));
  return sim;
}

/* Particles on a line in x, 1 cm apart (no contacts), types alternating 0, 1, 0, ... */
static void add_line(quarry_sim sim, int count, double y, uint64_t* ids) {
  double position[3 * kParticles];
  uint32_t types[kParticles];
  for (int k = 0; k < count; ++k) {
    position[3 * k] = -0.5 + 0.01 * k, position[3 * k + 1] = y, position[3 * k + 2] = 1.5;
    types[k] = (uint32_t)(k % 2);
  }
  quarry_new_particles add = {sizeof add, (uint64_t)count, types, 0, position, NULL, NULL, NULL, ids};
  MUST(sim, quarry_add_particles(sim, &add));
}

/* Drag coefficient of particle id (kg/s): τ = m/c from 0.02 to 0.06 s, so the particles fall at
 * different speeds and the spatial sort reorders them. */
static double drag_of(uint64_t id, double mass) { return mass / (0.02 + 0.001 * (double)(id % 41)); }

static uint64_t fnv(uint64_t h, const void* data, size_t n) {
  const unsigned char* b = (const unsigned char*)data;
  for (size_t k = 0; k < n; ++k) h = (h ^ b[k]) * 1099511628211ull;
  return h;
}

int main(int argc, char** argv) {
  const char* endpoint = NULL;
  const char* checkpoint = "coupling_partner.qck";
  int load_view = 0;
  for (int a = 1; a < argc; ++a) {
    if (strcmp(argv[a], "--load-view") == 0) load_view = 1;
    if (a + 1 < argc && strcmp(argv[a], "--endpoint") == 0) endpoint = argv[a + 1];
    if (a + 1 < argc && strcmp(argv[a], "--checkpoint") == 0) checkpoint = argv[a + 1];
  }
  CHECK((quarry_abi_version() >> 16) == QUARRY_ABI_MAJOR, "ABI major %u", (unsigned)(quarry_abi_version() >> 16));
  quarry_sim sim = build(endpoint);

  uint64_t ids[kParticles];
  add_line(sim, kParticles, 0.0, ids);
  uint32_t tag;
  MUST(sim, quarry_register_property(sim, "tag", 2, "1", -7.0, &tag));
  uint32_t again;
  MUST(sim, quarry_register_property(sim, "tag", 2, "1", 0.0, &again));
  CHECK(again == tag, "registering twice gives index %u, not %u", again, tag);

  uint64_t n = 0;
  MUST(sim, quarry_num_particles(sim, -1, &n));
  CHECK(n == kParticles, "%llu particles", (unsigned long long)n);
  uint64_t of_type[2];
  MUST(sim, quarry_num_particles(sim, 0, &of_type[0]));
  MUST(sim, quarry_num_particles(sim, 1, &of_type[1]));
  CHECK(of_type[0] == kParticles / 2 && of_type[1] == kParticles / 2, "types %llu, %llu",
        (unsigned long long)of_type[0], (unsigned long long)of_type[1]);

  /* Per particle, by id: its start (x, y), its mass, drag, and the tag written = (id, 2 id). */
  enum { kMax = 2 * kParticles + 8 };
  static uint64_t id[kMax];
  static uint32_t type[kMax];
  static double x[3 * kMax], v[3 * kMax], mass[kMax], force[3 * kMax], values[2 * kMax];
  quarry_particle_data data = {sizeof data, kMax, id, type, x, v, NULL, NULL, mass, NULL, force, NULL, 0, 0};
  MUST(sim, quarry_get_particles(sim, &data));
  for (uint64_t k = 0; k < data.count; ++k) values[2 * k] = (double)id[k], values[2 * k + 1] = 2.0 * (double)id[k];
  MUST(sim, quarry_set_property(sim, tag, values, 2 * data.count));
  static double start_x[kMax + 1], start_y[kMax + 1];
  for (uint64_t k = 0; k < data.count; ++k) start_x[id[k]] = x[3 * k], start_y[id[k]] = x[3 * k + 1];
  int type_order_ok = 1;
  for (uint64_t k = 1; k < data.count; ++k) type_order_ok &= type[k] >= type[k - 1];
  CHECK(type_order_ok, "particles are not in type order");

  /* ---- 1 and 2: the drag partner loop ---- */
  double momentum_start[3] = {0, 0, 0}; /* kg m/s */
  long double impulse[3] = {0, 0, 0};    /* N s */
  double momentum_bound = 0.0;           /* kg m/s */
  for (uint64_t k = 0; k < data.count; ++k)
    for (int c = 0; c < 3; ++c) momentum_start[c] += mass[k] * v[3 * k + c];
  uint64_t first_epoch = data.epoch, epochs_seen = 0, last_epoch = data.epoch;
  double worst_discrete = 0.0, worst_continuous_ratio = 0.0; /* relative to v_t, to the bound */
  static double drag[3 * kMax];
  for (int s = 0; s < kSteps; ++s) {
    MUST(sim, quarry_get_particles(sim, &data));
    if (data.epoch != last_epoch) ++epochs_seen, last_epoch = data.epoch;
    double t = 0.0;
    MUST(sim, quarry_get_time(sim, &t, NULL, NULL));
    for (uint64_t k = 0; k < data.count; ++k) {
      const double c = drag_of(id[k], mass[k]), tau = mass[k] / c, vt = kGravity * tau, a = kDt / tau;
      const double steps = floor(t / kDt + 0.5);
      const double discrete = -vt * (1.0 - pow(1.0 - a, steps));
      const double continuous = -vt * (1.0 - exp(-t / tau));
      const double bound = 1.05 * vt * a / (2.0 * exp(1.0));
      const double vz = v[3 * k + 2];
      if (fabs(vz - discrete) / vt > worst_discrete) worst_discrete = fabs(vz - discrete) / vt;
      if (fabs(vz - continuous) / bound > worst_continuous_ratio) worst_continuous_ratio = fabs(vz - continuous) / bound;
      for (int d = 0; d < 3; ++d) {
        drag[3 * k + d] = -c * v[3 * k + d];
        impulse[d] += (long double)drag[3 * k + d] * kDt;
      }
      impulse[2] -= (long double)mass[k] * kGravity * kDt;
      if (s == 0) momentum_bound += kSteps * DBL_EPSILON * mass[k] * vt;
    }
    if (load_view && s % 7 != 3) {
      quarry_view order, loads;
      MUST(sim, quarry_view_particles(sim, QUARRY_FIELD_TYPE_ORDER, &order));
      MUST(sim, quarry_view_next_step_loads(sim, QUARRY_FIELD_FORCE, &loads));
      CHECK(loads.writable == 1 && loads.count == data.count && loads.components == 3 && loads.epoch == data.epoch,
            "the load view: writable %u, %llu particles, %u components, epoch %llu (particles: %llu, epoch %llu)",
            (unsigned)loads.writable, (unsigned long long)loads.count, (unsigned)loads.components,
            (unsigned long long)loads.epoch, (unsigned long long)data.count, (unsigned long long)data.epoch);
      const uint32_t* engine = (const uint32_t*)order.data;
      for (uint64_t k = 0; k < data.count; ++k) {
        double* at = (double*)((char*)loads.data + (int64_t)engine[k] * loads.stride);
        CHECK(at[0] == 0.0 && at[1] == 0.0 && at[2] == 0.0, "step %d: the next step's loads are not zero", s);
        for (int d = 0; d < 3; ++d) at[d] = drag[3 * k + d];
      }
    } else {
      MUST(sim, quarry_set_external_loads(sim, drag, NULL, data.count, QUARRY_LOAD_REPLACE, QUARRY_HOLD_NEXT_STEP));
    }
    MUST(sim, quarry_step(sim, 1));
  }
  printf("drag: worst |v - discrete| / v_t = %.3g; worst |v - continuous| / bound = %.4f\n", worst_discrete,
         worst_continuous_ratio);
  CHECK(worst_discrete < 1e-11, "the engine departs from forward Euler's discrete solution by %.3g v_t", worst_discrete);
  CHECK(worst_continuous_ratio <= 1.0, "the error against v_t (1 - e^(-t/tau)) passes its bound (ratio %.4f)",
        worst_continuous_ratio);
  MUST(sim, quarry_get_particles(sim, &data));
  double momentum_end[3] = {0, 0, 0};
  for (uint64_t k = 0; k < data.count; ++k)
    for (int c = 0; c < 3; ++c) momentum_end[c] += mass[k] * v[3 * k + c];
  for (int c = 0; c < 3; ++c)
    CHECK(fabs((momentum_end[c] - momentum_start[c]) - (double)impulse[c]) <= momentum_bound,
          "momentum %c: change %.17g, impulse given %.17g, bound %.3g", 'x' + c, momentum_end[c] - momentum_start[c],
          (double)impulse[c], momentum_bound);
  printf("momentum: change %.17g N s, impulse %.17g N s (z), difference %.3g, bound %.3g\n",
         momentum_end[2] - momentum_start[2], (double)impulse[2],
         fabs((momentum_end[2] - momentum_start[2]) - (double)impulse[2]), momentum_bound);
  CHECK(epochs_seen > 0 && last_epoch != first_epoch, "no re-sort happened in %d steps: the id checks are idle", kSteps);

  /* ---- 3: ids and properties after re-sorts ---- */
  MUST(sim, quarry_get_property(sim, tag, values, 2 * data.count));
  int ids_ok = 1, tags_ok = 1;
  for (uint64_t k = 0; k < data.count; ++k) {
    ids_ok &= x[3 * k] == start_x[id[k]] && x[3 * k + 1] == start_y[id[k]];
    tags_ok &= values[2 * k] == (double)id[k] && values[2 * k + 1] == 2.0 * (double)id[k];
  }
  CHECK(ids_ok, "a particle's x, y changed: an id moved to another particle");
  CHECK(tags_ok, "a custom property did not follow its particle");
  uint64_t index = 0;
  MUST(sim, quarry_particle_index(sim, id[7], &index));
  CHECK(index == 7, "quarry_particle_index gives %llu for the 8th particle's id", (unsigned long long)index);

  /* Insertions: the new particles get the initial value; the old keep theirs. */
  uint64_t new_ids[8];
  add_line(sim, 8, 0.5, new_ids);
  MUST(sim, quarry_step(sim, 30));
  MUST(sim, quarry_get_particles(sim, &data));
  MUST(sim, quarry_get_property(sim, tag, values, 2 * data.count));
  int after_insert_ok = 1;
  for (uint64_t k = 0; k < data.count; ++k) {
    const int is_new = id[k] >= new_ids[0];
    after_insert_ok &= is_new ? (values[2 * k] == -7.0 && values[2 * k + 1] == -7.0)
                              : (values[2 * k] == (double)id[k] && x[3 * k] == start_x[id[k]]);
  }
  CHECK(data.count == kParticles + 8 && after_insert_ok, "after an insertion: %llu particles, tags %s",
        (unsigned long long)data.count, after_insert_ok ? "ok" : "wrong");

  /* ---- checkpoint and restore: properties back, and the same bits 50 steps on. One handle at a
   * time (a `quarry serve` serves one client session): the original runs on and is closed first. */
  MUST(sim, quarry_save_checkpoint(sim, checkpoint));
  static double values_restored[2 * kMax], x_a[3 * kMax], x_b[3 * kMax];
  MUST(sim, quarry_step(sim, 50));
  quarry_particle_data a = {sizeof a, kMax, NULL, NULL, x_a, NULL, NULL, NULL, NULL, NULL, NULL, NULL, 0, 0};
  quarry_particle_data b = a;
  b.position = x_b;
  MUST(sim, quarry_get_particles(sim, &a));

  /* The state hash the remote run must reproduce. */
  MUST(sim, quarry_get_particles(sim, &data));
  uint64_t h = 1469598103934665603ull;
  h = fnv(h, id, sizeof(uint64_t) * data.count);
  h = fnv(h, x, sizeof(double) * 3 * data.count);
  h = fnv(h, v, sizeof(double) * 3 * data.count);
  printf("state hash: %016llx\n", (unsigned long long)h);
  MUST(sim, quarry_close(sim));

  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  info.checkpoint_path = checkpoint;
  info.endpoint = endpoint;
  info.threads = 1; /* another thread count: the same bits */
  quarry_sim restored;
  MUST(QUARRY_NO_SIM, quarry_open(&info, &restored));
  MUST(restored, quarry_get_property(restored, tag, values_restored, 2 * data.count));
  CHECK(memcmp(values, values_restored, sizeof(double) * 2 * data.count) == 0, "the restored property differs");
  MUST(restored, quarry_step(restored, 50));
  MUST(restored, quarry_get_particles(restored, &b));
  CHECK(a.count == b.count && memcmp(x_a, x_b, sizeof(double) * 3 * a.count) == 0,
        "the restored simulation does not continue bit-identically");
  MUST(restored, quarry_close(restored));
  remove(checkpoint);
  printf("%d passed, %d failed\n", checks - failures, failures);
  return failures == 0 ? 0 : 1;
}
