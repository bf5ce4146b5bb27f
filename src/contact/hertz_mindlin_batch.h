// The contact law of contact_law.h for many particle pairs at once, in the force loop's common
// case: the particles share one material whose pair law is Hertz–Mindlin, with or without SJKR
// cohesion and the constant directional rolling torque (batch_handles: no JKR, no EPSD, no
// clipping). Inputs and outputs are arrays (structure of arrays), so the compiler computes 4
// (AVX2) or 8 (AVX-512) contacts per instruction.
// Same formulas in the same order as evaluate_contact; contact_law_test checks that both give
// the same forces, torques and history to round-off.
//
// Determinism: every contact goes through the vector body of the loop — the batch is padded to
// a multiple of kLanes with harmless contacts — so a contact's result does not depend on where
// in a batch it falls, hence not on how the rows were split between threads.
#pragma once

#include <cstdint>

#include "contact/contact_law.h"

namespace quarry {

struct HertzMindlinBatch {
  static constexpr int kCapacity = 256;  // contacts per batch (a multiple of kLanes)
  static constexpr int kLanes = 8;       // the widest vector (AVX-512 doubles)
  // Array length: one cache line more than the capacity, so that the arrays do not start at
  // multiples of 4 KiB from each other (4K aliasing between stores to one array and loads from
  // another stalls the collecting loop; measured 25 % slower with kCapacity exactly).
  static constexpr int kStride = kCapacity + 8;
  int count = 0;
  // Where each contact's result goes (the caller's bookkeeping, not read here).
  std::uint32_t pair[kStride], slot[kStride];
  // Inputs: centre difference x_i − x_j (m) and its square (m²), radii (m), inverse masses
  // (1/kg), v_i − v_j (m/s), angular velocities (rad/s), their leads, tangential history δt (m).
  alignas(64) double dx[kStride], dy[kStride], dz[kStride], distance2[kStride];
  alignas(64) double radius_i[kStride], radius_j[kStride];
  alignas(64) double inv_mass_i[kStride], inv_mass_j[kStride];
  alignas(64) double vx[kStride], vy[kStride], vz[kStride];
  alignas(64) double wix[kStride], wiy[kStride], wiz[kStride];
  alignas(64) double wjx[kStride], wjy[kStride], wjz[kStride];
  // Leads to the force's time (ContactKinematics): of v_i − v_j (m/s), of ω_i and ω_j (rad/s).
  alignas(64) double lvx[kStride], lvy[kStride], lvz[kStride];
  alignas(64) double lwix[kStride], lwiy[kStride], lwiz[kStride];
  alignas(64) double lwjx[kStride], lwjy[kStride], lwjz[kStride];
  alignas(64) double hx[kStride], hy[kStride], hz[kStride];  // in: old δt, out: new δt
  alignas(64) double fn[kStride];  // in: the last step's normal force (N), out: this step's
  // Outputs: force on i (N; j gets −force), torques about i's and j's centres (N·m).
  alignas(64) double fx[kStride], fy[kStride], fz[kStride];
  alignas(64) double tix[kStride], tiy[kStride], tiz[kStride];
  alignas(64) double tjx[kStride], tjy[kStride], tjz[kStride];
  // Scratch: 1 where the scalar law finishes the contact (its window matters), else 0.
  alignas(64) double scalar_lane[kStride];

  bool full() const { return count == kCapacity; }
};

// True if evaluate_hertz_mindlin_batch computes evaluate_contact for these parameters.
inline bool batch_handles(const InteractionParameters& parameters) {
  return parameters.normal_model == NormalModel::hertz_mindlin &&
         (parameters.rolling_model == RollingModel::none ||
          parameters.rolling_model == RollingModel::constant_torque) &&
         !(parameters.surface_energy > 0.0) && !parameters.clip_attraction;
}

// Evaluates contacts [0, batch.count): touching pairs, and pairs short of contact whose step
// window may reach it (contact/dashpot_window.h). Those and the contacts whose window matters
// (a sizeable half path: impacts) are finished by the scalar law after the vector loop, which
// computes the settled contacts' common case. lead_time: ContactKinematics::lead_time (s).
// Returns true if some contact overlaps by more than overlap_limit × the smaller radius (the
// run's guard, simulation.max_overlap_fraction): checked here, in vector form, rather than
// per pair while the batch is collected.
// Cost: about a quarter (AVX2) to an eighth (AVX-512) of the scalar law per contact. Built for
// AVX-512 and for the release target; the loader picks the one the processor runs (both give
// the same bits: IEEE operations, no contraction, correctly rounded sqrt and division).
bool evaluate_hertz_mindlin_batch(const InteractionParameters& parameters, HertzMindlinBatch& batch,
                                  double dt, double lead_time, double overlap_limit);

}  // namespace quarry
