// Contacts of a frame: the pair list's touching pairs by the contact law, the surface contacts
// as the force stage left them.
#include "sim/frame_contacts.h"

#include <algorithm>
#include <cmath>

namespace quarry::sim {

std::vector<FrameContact> frame_contacts(const World& world) {
  const ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  const PairList& list = world.pairs;
  std::vector<FrameContact> contacts;
  if (list.built_for(n) && list.offsets.size() == n + 1) {
    const bool rolling = !list.rolling_torque.empty();
    for (std::uint32_t i = 0; i < n; ++i) {
      for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
        const std::uint32_t j = list.partner[k];
        // Across a periodic face: the minimum image; the line runs from i to that image of j.
        const Vec3 d = list.periodic.minimum_image(p.position[i] - p.position[j]);  // m
        const double distance = norm(d);
        const double overlap = p.radius[i] + p.radius[j] - distance;  // m
        if (!(overlap > 0.0) || !(distance > 0.0)) continue;
        ContactKinematics kin;
        kin.normal = d * (1.0 / distance);
        kin.overlap = overlap;
        kin.radius_i = p.radius[i];
        kin.radius_j = p.radius[j];
        kin.inv_mass_i = p.inv_mass[i];
        kin.inv_mass_j = p.inv_mass[j];
        kin.velocity_i = p.velocity[i];
        kin.velocity_j = p.velocity[j];
        kin.angular_velocity_i = p.angular_velocity[i];
        kin.angular_velocity_j = p.angular_velocity[j];
        ContactHistory history{list.tangential_displacement[k], rolling ? list.rolling_torque[k] : Vec3{}};
        const ContactResult r =
            evaluate_contact(world.materials.between(p.material[i], p.material[j]), kin, history, 0.0);
        FrameContact c;
        c.particle = i;
        c.partner = j;
        c.line.from = p.position[i];
        c.line.to = list.periodic.any() ? p.position[i] - d : p.position[j];
        c.line.normal_force = r.normal_force * kin.normal;
        c.line.tangential_force = r.force_i - c.line.normal_force;
        c.line.overlap = overlap;
        c.line.kind = ContactLineKind::particle_particle;
        contacts.push_back(c);
      }
    }
  }
  for (const WallContact& w : world.wall_contacts) {
    if (w.particle >= n) continue;
    FrameContact c;
    c.particle = w.particle;
    c.line.from = p.position[w.particle];
    c.line.to = w.point;
    // The force's component along the contact normal (N), the rest is tangential.
    c.line.normal_force = dot(w.force_on_particle, w.normal) * w.normal;
    c.line.tangential_force = w.force_on_particle - c.line.normal_force;
    // The contact point is the surface's closest point: overlap = R − |x − point| (m).
    c.line.overlap = p.radius[w.particle] - norm(p.position[w.particle] - w.point);
    c.line.kind = ContactLineKind::particle_surface;
    contacts.push_back(c);
  }
  return contacts;
}

ParticleContactFields particle_contact_fields(const World& world, const std::vector<FrameContact>& contacts) {
  const ParticleStore& p = world.particles;
  ParticleContactFields fields;
  fields.coordination_number.assign(p.size(), 0);
  fields.max_overlap_ratio.assign(p.size(), 0.0);
  const auto count = [&](std::uint32_t i, double overlap) {
    fields.coordination_number[i] += 1;
    fields.max_overlap_ratio[i] = std::max(fields.max_overlap_ratio[i], overlap / p.radius[i]);
  };
  for (const FrameContact& c : contacts) {
    count(c.particle, c.line.overlap);
    if (c.partner != kSurfacePartner) count(c.partner, c.line.overlap);
  }
  return fields;
}

}  // namespace quarry::sim
