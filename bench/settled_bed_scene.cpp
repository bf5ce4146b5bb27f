// The settled-bed reference problem built in code (no deck, no factory): spec, jittered lattice,
// first force evaluation, and the measurements compared with LIGGGHTS/LAMMPS.
#include "bench/settled_bed_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <sys/resource.h>

#include <fmt/format.h>

#include "bench/lammps_data.h"
#include "core/diagnostics.h"
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
  sim.max_overlap_fraction = parameters.max_overlap_fraction;

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
        const Vec3 site{(i + 0.5) * a + jx, (j + 0.5) * a + jy, (k + 0.5) * a + jz + parameters.lift};
        p.add(world.next_id++, 0, 0, site, Vec3{}, parameters.particle_radius, parameters.density, 0.0);
      }
  world.lists_stale = true;
  return world;
}

void replace_particles(World& world, const SettledBedParameters& parameters, const LammpsData& data) {
  const std::size_t n = parameters.particle_count();
  const std::string lattice =
      fmt::format("--nx {} --ny {} --nz {}", parameters.cells_x, parameters.cells_y, parameters.cells_z);
  if (data.atoms.size() != n)
    throw UserError(SourceLocation{data.path, 0, 0},
                    fmt::format("{} atoms, but the lattice {} has {} particles", data.atoms.size(), lattice, n),
                    "pass the --nx/--ny/--nz the peers' bed was settled with (bench/run.sh, geom)");
  // The walls stand on Quarry's box [0, box_max]; the peers' box must be the same one.
  // Tolerance: 1e-9 of the box size, far below a particle's 1e-3 m radius.
  const Vec3 box = parameters.box_max();  // m
  const double tolerance = 1e-9 * std::max({box.x, box.y, box.z});  // m
  for (int d = 0; d < 3; ++d)
    if (std::abs(data.box_lo[d]) > tolerance || std::abs(data.box_hi[d] - box[d]) > tolerance)
      throw UserError(SourceLocation{data.path, 0, 0},
                      fmt::format("the file's box [{}, {}] m along {} is not the problem's [0, {}] m "
                                  "({}, spacing {} m, lift {} m)",
                                  data.box_lo[d], data.box_hi[d], "xyz"[d], box[d], lattice,
                                  parameters.lattice_spacing, parameters.lift),
                      "pass the --nx/--ny/--nz the peers' bed was settled with (bench/run.sh, geom)");
  for (const LammpsAtom& atom : data.atoms) {
    const SourceLocation where{data.path, atom.line, 0};
    if (atom.type != 1)
      throw UserError(where, fmt::format("atom-ID {} has atom-type {}; the problem has one particle type",
                                         atom.id, atom.type),
                      "the peers' settle creates every atom as type 1");
    const double radius = 0.5 * atom.diameter;  // m
    // The neighbour grid's cells are 2 max_radius + skin wide: a larger sphere could miss contacts.
    if (radius > world.max_radius * (1.0 + 1e-12))
      throw UserError(where, fmt::format("atom-ID {}: radius {} m exceeds the problem's {} m", atom.id,
                                         radius, world.max_radius),
                      "the reference problem's spheres are 2 mm across (SettledBedParameters)");
    for (int d = 0; d < 3; ++d)
      if (!(atom.position[d] >= 0.0 && atom.position[d] <= box[d]))
        throw UserError(where, fmt::format("atom-ID {}: {} = {} m lies outside the box [0, {}] m", atom.id,
                                           "xyz"[d], atom.position[d], box[d]),
                        "the walls are the box faces: every centre must lie inside");
  }
  // As make_lattice_world does: straight into the store, type and material 0, then stale lists.
  ParticleStore& p = world.particles;
  p.clear();
  p.reserve(n);
  for (const LammpsAtom& atom : data.atoms) {  // ascending id
    const std::size_t i = p.add(atom.id, 0, 0, atom.position, atom.velocity, 0.5 * atom.diameter,
                                atom.density, world.time);
    p.angular_velocity[i] = atom.angular_velocity;
  }
  world.next_id = data.atoms.empty() ? 1 : data.atoms.back().id + 1;
  world.lists_stale = true;
}

LammpsData to_lammps_data(const World& world, const SettledBedParameters& parameters) {
  LammpsData data;
  data.title = fmt::format("Quarry bench lattice {}x{}x{}, spacing {} m, lift {} m, seed {}", parameters.cells_x,
                           parameters.cells_y, parameters.cells_z, parameters.lattice_spacing, parameters.lift,
                           parameters.seed);
  data.atom_types = 1;
  data.box_hi = parameters.box_max();
  const ParticleStore& p = world.particles;
  data.atom_count = p.size();
  data.atoms.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    LammpsAtom& a = data.atoms[i];
    a.id = p.id[i];
    a.diameter = 2.0 * p.radius[i];
    a.density = parameters.density;
    a.position = p.position[i];
    a.velocity = p.velocity[i];
    a.angular_velocity = p.angular_velocity[i];
  }
  return data;
}

void prepare_first_step(World& world) { sim::initialize(world); }

double kinetic_energy_per_particle(const World& world) {
  const ParticleStore& p = world.particles;
  double energy = 0.0;  // J
  for (std::size_t i = 0; i < p.size(); ++i)
    energy += 0.5 * norm2(p.velocity[i]) / p.inv_mass[i] +
              0.5 * norm2(p.angular_velocity[i]) / p.inv_inertia(i);
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
  state.floor_force = -world.surfaces[floor_wall].mesh.total_force.z;
  for (const WorldSurface& s : world.surfaces) state.all_walls_force_z -= s.mesh.total_force.z;
  state.contact_pairs = static_cast<double>(world.pair_contact_count());
  state.neighbor_pairs = static_cast<double>(world.pairs.size());
  return state;
}

double peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) * 1024.0;  // Linux reports ru_maxrss in KiB
}

std::string bench_result_line(const World& world, int threads, long steps, double loop_seconds,
                              std::uint64_t rebuilds) {
  const BedState bed = measure_bed(world);
  const double n = static_cast<double>(world.particles.size());
  const double rss = peak_rss_bytes();  // bytes
  const auto& names = world.timers.names();
  const auto neighbor = std::find(names.begin(), names.end(), "neighbor");
  const double neighbor_seconds =  // s
      neighbor == names.end() ? 0.0 : world.timers.seconds(static_cast<int>(neighbor - names.begin()));
  // contacts_pp: contacting pairs / N; coordination: 2 × contacting pairs / N (what the peers'
  // "compute contact/atom" sums to, their CONTACTS_PER_PARTICLE).
  return fmt::format(
      "QUARRY_BENCH n={:.0f} threads={} steps={} loop_s={:.6g} pss={:.6g} contacts_pp={:.4f} "
      "coordination={:.4f} neigh_pp={:.4f} rss_peak_bytes={:.0f} rss_bytes_pp={:.1f} zmax={:.7g} "
      "zmean={:.7g} floor_force={:.7g} walls_force_z={:.7g} weight={:.7g} rebuilds={} ke_pp={:.6g} "
      "neigh_share={:.4f}\n",
      n, threads, steps, loop_seconds, n * static_cast<double>(steps) / loop_seconds, bed.contact_pairs / n,
      2.0 * bed.contact_pairs / n, bed.neighbor_pairs / n, rss, rss / n, bed.max_height, bed.mean_height,
      bed.floor_force, bed.all_walls_force_z, bed.weight, rebuilds, kinetic_energy_per_particle(world),
      neighbor_seconds / loop_seconds);
}

}  // namespace quarry::bench
