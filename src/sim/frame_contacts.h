// The contacts of the world as it stands at the end of a step, gathered for output only (the
// contacts VTU, the particles' coordination number and largest overlap, the stress monitor):
// never in the step itself, which keeps no per-contact forces.
#pragma once

#include <cstdint>
#include <vector>

#include "io/vtu_writer.h"
#include "sim/world.h"

namespace quarry::sim {

inline constexpr std::uint32_t kSurfacePartner = 0xffffffffu;

struct FrameContact {
  std::uint32_t particle = 0;               // index i (the line's `from`)
  std::uint32_t partner = kSurfacePartner;  // index j > i, or kSurfacePartner for a surface
  ContactLine line;                         // forces on i, ends, overlap, kind
};

// Every touching pair of the neighbour list and every particle–surface contact of the last force
// stage, pairs first (list order), then surface contacts (particle order).
// Particle–particle forces are evaluated again by the contact law at the current positions,
// velocities and stored spring history, with no history increment (dt = 0): the history was
// already advanced by this step's force stage, so this is the force of the frame's state, not
// another step's. Particle–surface forces are those of the last force stage (the surface
// contacts keep them). Pairs are skipped when the list was not built for these particles
// (only right after particles were added from outside). Cost: O(pairs + surface contacts),
// serial; call once per frame or monitor row, not per step.
std::vector<FrameContact> frame_contacts(const World& world);

// Contacts per particle (surfaces included) and the largest overlap / own radius of each.
ParticleContactFields particle_contact_fields(const World& world, const std::vector<FrameContact>& contacts);

}  // namespace quarry::sim
