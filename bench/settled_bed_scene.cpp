// The settled-bed reference problem built in code (no deck, no factory): spec, jittered lattice,
// first force evaluation, and the measurements compared with LIGGGHTS/LAMMPS.
#include "bench/settled_bed_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "sim/step.h"

namespace quarry::bench {

namespace {

constexpr double kStandardGravity = 9.81;  // m/s², as in the peers' "fix gravity 9.81"

SurfaceSpec plane_wall(const std::string& name, const Vec3& point, const Vec3& normal, double size) {
  SurfaceSpec wall;
  wall.name = name;
  wall.kind = SurfaceKind::plane;
  wall.point = point;
  wall.normal = normal;
  wall.size = size;
  wall.material = std::string("glass");
  return wall;
}

}  // namespace

SimulationSpec settled_bed_spec(const SettledBedParameters& parameters) {
  SimulationSpec spec;
  const Vec3 box = parameters.box_max();  // m
  SimulationSettings& sim = spec.simulation;
  sim.end_time = 1.0;  // s; the bench steps by hand, the run loop is not used
  sim.fixed_time_step = Located<double>{parameters.time_step};
  // Free fall over the box height is the largest speed the settling can see (m/s); it only
  // feeds the Hertz contact-time check of build_world.
  sim.impact_speed = Located<double>{std::sqrt(2.0 * kStandardGravity * box.z)};
  sim.gravity = Vec3{0.0, 0.0, -kStandardGravity};
  // Domain a little larger than the box, so that no particle is ever removed.
  const double margin = 10.0 * parameters.particle_radius;  // m
  Aabb domain;
  domain.lo = Vec3{-margin, -margin, -margin};
  domain.hi = box + Vec3{margin, margin, margin};
  sim.domain = domain;
  sim.skin = parameters.skin;

  MaterialSpec glass;
  glass.name = std::string("glass");
  glass.density = parameters.density;
  glass.youngs_modulus = parameters.youngs_modulus;
  glass.poisson_ratio = parameters.poisson_ratio;
  spec.materials.push_back(glass);

  InteractionSpec contact;
  contact.material_a = std::string("glass");
  contact.material_b = std::string("glass");
  contact.restitution = parameters.restitution;
  contact.static_friction = parameters.friction;
  contact.rolling_friction = 0.0;
  contact.rolling_model = RollingModel::none;
  contact.normal_model = NormalModel::hertz_mindlin;
  spec.interactions.push_back(contact);

  ParticleTypeSpec sphere;
  sphere.name = std::string("sphere");
  sphere.material = std::string("glass");
  sphere.size.kind = SizeDistributionKind::fixed;
  sphere.size.radius = parameters.particle_radius;
  spec.particle_types.push_back(sphere);

  // Six plane walls (the peers' xplane/yplane/zplane pairs). Each square patch is larger than
  // the box face it closes, so no particle can reach a patch edge.
  const double size = 2.0 * std::max({box.x, box.y, box.z});  // m
  const Vec3 centre = box * 0.5;
  spec.surfaces.push_back(plane_wall("floor", {centre.x, centre.y, 0.0}, {0, 0, 1}, size));
  spec.surfaces.push_back(plane_wall("top", {centre.x, centre.y, box.z}, {0, 0, -1}, size));
  spec.surfaces.push_back(plane_wall("x_low", {0.0, centre.y, centre.z}, {1, 0, 0}, size));
  spec.surfaces.push_back(plane_wall("x_high", {box.x, centre.y, centre.z}, {-1, 0, 0}, size));
  spec.surfaces.push_back(plane_wall("y_low", {centre.x, 0.0, centre.z}, {0, 1, 0}, size));
  spec.surfaces.push_back(plane_wall("y_high", {centre.x, box.y, centre.z}, {0, -1, 0}, size));

  spec.output.plots = false;
  return spec;
}

World make_lattice_world(const SettledBedParameters& parameters) {
  World world = build_world(settled_bed_spec(parameters));
  std::mt19937_64 random(parameters.seed);
  std::uniform_real_distribution<double> jitter(-parameters.jitter, parameters.jitter);  // m
  ParticleStore& p = world.particles;
  p.reserve(parameters.particle_count());
  const double a = parameters.lattice_spacing;  // m
  // Same site order as LAMMPS' create_atoms on an sc lattice with origin ½: x fastest.
  for (int k = 0; k < parameters.cells_z; ++k)
    for (int j = 0; j < parameters.cells_y; ++j)
      for (int i = 0; i < parameters.cells_x; ++i) {
        const double jx = jitter(random), jy = jitter(random), jz = jitter(random);
        const Vec3 site{(i + 0.5) * a + jx, (j + 0.5) * a + jy, (k + 0.5) * a + jz};
        p.add(world.next_id++, 0, 0, site, Vec3{}, parameters.particle_radius, parameters.density, 0.0);
      }
  world.lists_stale = true;
  return world;
}

void prepare_first_step(World& world) {
  sim::insert_and_remove(world);  // no factories: only sizes the wall slots
  sim::update_neighbors(world, true);
  sim::compute_forces(world);
}

double kinetic_energy_per_particle(const World& world) {
  const ParticleStore& p = world.particles;
  double energy = 0.0;  // J
  for (std::size_t i = 0; i < p.size(); ++i)
    energy += 0.5 * norm2(p.velocity[i]) / p.inv_mass[i] +
              0.5 * norm2(p.angular_velocity[i]) / p.inv_inertia[i];
  return p.size() > 0 ? energy / static_cast<double>(p.size()) : 0.0;
}

BedState measure_bed(const World& world) {
  BedState state;
  const ParticleStore& p = world.particles;
  double sum_height = 0.0;  // m
  for (std::size_t i = 0; i < p.size(); ++i) {
    state.max_height = std::max(state.max_height, p.position[i].z);
    sum_height += p.position[i].z;
    state.weight += kStandardGravity / p.inv_mass[i];
  }
  state.mean_height = p.size() > 0 ? sum_height / static_cast<double>(p.size()) : 0.0;
  // total_force is the force the particles exert on a surface; down is −z.
  state.floor_force = -world.surfaces[floor_wall].total_force.z;
  for (const Surface& s : world.surfaces) state.all_walls_force_z -= s.total_force.z;
  state.contact_pairs = static_cast<double>(world.pair_contact_count());
  state.neighbor_pairs = static_cast<double>(world.pairs.size());
  return state;
}

}  // namespace quarry::bench
