// Builds a World from a SimulationSpec: materials and their pair table, surfaces (STL files or
// primitives) with topology and search grids, factories, and the time step.
#include "sim/world.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "geometry/motion.h"
#include "geometry/primitives.h"
#include "geometry/stl_reader.h"
#include "insert/size_distribution.h"
#include "sim/memory_estimate.h"
#include "sim/output.h"
#include "sim/time_step_choice.h"

namespace quarry {

namespace {

std::size_t material_index(const SimulationSpec& spec, const std::string& name) {
  for (std::size_t k = 0; k < spec.materials.size(); ++k)
    if (spec.materials[k].name.value == name) return k;
  return spec.materials.size();
}

MaterialTable build_material_table(const SimulationSpec& spec) {
  MaterialTable table;
  const std::size_t n = spec.materials.size();
  for (const auto& m : spec.materials) {
    table.names.push_back(m.name.value);
    table.properties.push_back({m.density.value, m.youngs_modulus.value, m.poisson_ratio.value, m.rigid.value});
  }
  table.pairs.resize(n * n);
  std::vector<char> defined(n * n, 0);
  for (const auto& inter : spec.interactions) {
    const std::size_t a = material_index(spec, inter.material_a.value);
    const std::size_t b = material_index(spec, inter.material_b.value);
    if (a >= n || b >= n) continue;  // the deck parser reports unknown names
    const InteractionParameters p =
        make_interaction(table.properties[a], table.properties[b], inter);
    table.pairs[a * n + b] = p;
    table.pairs[b * n + a] = p;
    defined[a * n + b] = defined[b * n + a] = 1;
  }
  // Pairs the deck did not define keep neutral defaults (the parser already demanded every pair
  // that can meet; these are pairs that never touch).
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b)
      if (!defined[a * n + b])
        table.pairs[a * n + b] =
            make_interaction(table.properties[a], table.properties[b], InteractionSpec{});
  return table;
}

// A mesh given vertex by vertex (the deck's type: mesh, or the C ABI): vertices as given (not
// merged, so node n is the partner's node n), triangles, then each quad as two triangles.
Surface make_mesh_surface(const SurfaceSpec& s) {
  Surface surface;
  surface.reference_vertices = s.mesh_vertices;
  surface.vertices = s.mesh_vertices;
  surface.triangles = s.mesh_triangles;
  for (const auto& c : s.mesh_quads) {
    surface.triangles.push_back({c[0], c[1], c[2]});
    surface.triangles.push_back({c[0], c[2], c[3]});
  }
  surface.update_normals_and_areas();
  return surface;
}

// Element of each triangle of make_mesh_surface: triangle e is element e, both halves of quad q
// are element (triangles + q). Empty when there are no quads (element = triangle).
std::vector<std::uint32_t> mesh_element_map(const SurfaceSpec& s) {
  std::vector<std::uint32_t> element_of_triangle;
  if (s.mesh_quads.empty()) return element_of_triangle;
  for (std::uint32_t t = 0; t < s.mesh_triangles.size(); ++t) element_of_triangle.push_back(t);
  const auto first_quad = static_cast<std::uint32_t>(s.mesh_triangles.size());
  for (std::uint32_t q = 0; q < s.mesh_quads.size(); ++q)
    element_of_triangle.insert(element_of_triangle.end(), 2, first_quad + q);
  return element_of_triangle;
}

Surface make_surface(const SurfaceSpec& s, std::vector<std::string>& notes) {
  switch (s.kind.value) {
    case SurfaceKind::mesh:
      return make_mesh_surface(s);
    case SurfaceKind::stl:
      return read_stl(s.file.value, s.scale.value, s.offset.value, &notes);
    case SurfaceKind::plane:
      return make_plane(s.point.value, s.normal.value, s.size.value, 1);
    case SurfaceKind::box:
      return make_box(s.min.value, s.max.value, 1);
    case SurfaceKind::cylinder:
      return make_cylinder(s.base.value, s.axis.value, s.radius.value, s.length.value,
                           s.resolution.value, s.capped.value, true);
  }
  return {};
}

}  // namespace

std::vector<ParticleTypeInfo> particle_type_infos(const SimulationSpec& spec) {
  std::vector<ParticleTypeInfo> infos;
  for (std::size_t t = 0; t < spec.particle_types.size(); ++t) {
    const auto& type = spec.particle_types[t];
    const std::size_t m = material_index(spec, type.material.value);
    ParticleTypeInfo info;
    info.type_index = static_cast<std::uint16_t>(t);
    info.material_index = static_cast<std::uint16_t>(m);
    info.density = m < spec.materials.size() ? spec.materials[m].density.value : 0.0;
    info.size = type.size;
    info.fixed = type.fixed.value;
    infos.push_back(info);
  }
  return infos;
}

World::World() = default;
World::~World() = default;
World::World(const World&) = default;
World& World::operator=(const World&) = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

bool World::has_moving_surfaces() const {
  return std::any_of(surfaces.begin(), surfaces.end(),
                     [](const WorldSurface& s) { return s.moving(); });
}

std::size_t World::pair_contact_count() const {
  // The force stage's own test (contact_law.h): |xi − xj|² < (Ri + Rj)², or a JKR contact
  // that still adheres at negative overlap.
  std::size_t count = 0;
  const std::size_t n = pairs.offsets.empty() ? 0 : pairs.offsets.size() - 1;
  const bool jkr = !pairs.jkr_attached.empty();
  for (std::size_t i = 0; i < n && i < particles.size(); ++i)
    for (std::uint32_t k = pairs.offsets[i]; k < pairs.offsets[i + 1]; ++k) {
      const std::uint32_t j = pairs.partner[k];
      const double touch = particles.radius[i] + particles.radius[j];  // m
      const Vec3 d =
          pairs.periodic.minimum_image(particles.position[i] - particles.position[j]);  // m
      count += norm2(d) < touch * touch || (jkr && pairs.jkr_attached[k] != 0);
    }
  return count;
}

std::size_t World::wall_contact_count() const {
  return wall_contacts.size();
}

void reindex_wall_contacts(World& world, const std::vector<std::size_t>& order) {
  std::vector<std::uint32_t> new_index(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    new_index[order[k]] = static_cast<std::uint32_t>(k);
  for (WallContact& c : world.wall_contacts) c.particle = new_index[c.particle];
  std::stable_sort(
      world.wall_contacts.begin(), world.wall_contacts.end(),
      [](const WallContact& a, const WallContact& b) { return a.particle < b.particle; });
}

void drop_wall_contacts_of_removed(World& world, const std::vector<char>& removed) {
  const std::vector<std::uint32_t> new_index = indices_after_removal(removed);
  std::erase_if(world.wall_contacts,
                [&](const WallContact& c) { return removed[c.particle] != 0; });
  for (WallContact& c : world.wall_contacts) c.particle = new_index[c.particle];
}

namespace {

// Geometry the particles can never reach (issue 19): a fixed surface wholly outside the domain
// is an error (a misplaced or mis-scaled mesh: a file in mm read as m), triangles wholly outside
// are counted in a warning. Moving and coupled surfaces may come in later: warnings only.
void report_geometry_outside_domain(World& world, const SurfaceSpec& s,
                                    const WorldSurface& record) {
  const Aabb& domain = world.spec.simulation.domain.value;
  const Surface& mesh = record.mesh;
  std::size_t outside = 0;
  Aabb whole;
  for (const auto& t : mesh.triangles) {
    Aabb box;
    for (int k = 0; k < 3; ++k) box.expand(mesh.vertices[t[k]]);
    whole.expand(box.lo);
    whole.expand(box.hi);
    if (!overlaps(box, domain)) ++outside;
  }
  if (outside == 0) return;
  const auto corner = [](const Vec3& v) {
    return fmt::format("[{:.4g}, {:.4g}, {:.4g}]", v.x, v.y, v.z);
  };
  if (outside == mesh.triangle_count() && !record.moving())
    throw UserError(
        s.name.where,
        fmt::format("surface '{}' lies wholly outside the domain: its box is {} to {} m, "
                    "the domain {} to {} m; particles can never touch it",
                    s.name.value, corner(whole.lo), corner(whole.hi), corner(domain.lo),
                    corner(domain.hi)),
        s.kind.value == SurfaceKind::stl
            ? "check the STL's units (scale: 0.001 reads a file in mm) and offset, or enlarge "
              "simulation.domain"
            : "move the surface into the domain or enlarge simulation.domain");
  world.warnings.push_back(fmt::format(
      "surface '{}': {} of its {} triangles lie wholly outside the domain{}; particles never touch "
      "them",
      s.name.value, outside, mesh.triangle_count(), record.moving() ? " now (it moves)" : ""));
}

// Surfaces are not wrapped across periodic faces (docs/deck.md, "Periodic boundaries"): a fixed
// surface that reaches past a periodic face must span the whole period, a diameter beyond each
// face, or a particle wrapping through that face meets its cut edge, or finds itself inside it
// (a fuzzed periodic chute whose floor ended inside the period stopped on a particle 71 % of its
// radius deep in the floor). A warning: a surface inside the period acts only where it is.
void report_surface_across_periodic_faces(World& world, const SurfaceSpec& s,
                                          const WorldSurface& record) {
  if (record.moving() || record.mesh.vertices.empty()) return;
  const Aabb& domain = world.spec.simulation.domain.value;
  const double margin = 2.0 * world.max_radius;  // m, a diameter
  const Aabb extent = record.mesh.bounds();       // m
  static constexpr std::array<const char*, 3> kAxes{"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (!world.spec.simulation.periodic.value[static_cast<std::size_t>(a)]) continue;
    const double lo = extent.lo[a], hi = extent.hi[a];  // m, along the axis
    const bool crosses = lo < domain.lo[a] || hi > domain.hi[a];
    const bool spans = lo <= domain.lo[a] - margin && hi >= domain.hi[a] + margin;
    if (!crosses || spans) continue;
    world.warnings.push_back(fmt::format(
        "surface '{}' reaches past a periodic face of the domain along {} but spans only {:.4g} "
        "to {:.4g} m of the period {:.4g} to {:.4g} m: surfaces are not wrapped, so a particle "
        "passing through that face meets its cut edge or lands inside it; make it span the "
        "period and a particle diameter ({:.4g} m) beyond each face",
        s.name.value, kAxes[static_cast<std::size_t>(a)], lo, hi, domain.lo[a], domain.hi[a],
        margin));
  }
}

// A prescribed motion faster than the run can follow (a fuzzed drum turning about an axis
// 9e18 m away passed check, and its run stopped at step 1 on a particle struck at 3.9 km/s). A
// surface that moves more than half the smallest radius in one step strikes a particle within
// one step, unresolved, as the run's tunnelling guard would find (the same half radius): an
// error at the motion. The bound (max_vertex_speed) holds at all times: a motion that starts
// later is checked too.
// Returns that speed (m/s).
double check_surface_speed(const World& world, const SurfaceSpec& s, const Surface& surface) {
  const MotionSpec& motion = s.motion;
  const double speed = max_vertex_speed(motion, surface);  // m/s
  if (!(speed > 0.0) && std::isfinite(speed)) return speed;
  double smallest = INFINITY;  // m, the smallest radius any particle of the deck can have
  for (const SizeSampler& sampler : world.size_samplers)
    smallest = std::min(smallest, sampler.min_radius());
  const MotionKind kind = motion.kind.value;
  const SourceLocation& where = kind == MotionKind::rotation      ? motion.angular_velocity.where
                                : kind == MotionKind::translation ? motion.velocity.where
                                                                  : motion.amplitude.where;
  const char* const units =
      kind == MotionKind::rotation      ? "angular_velocity in rad/s, 30 rpm being 3.14, about "
                                          "the axis through axis_point, in m"
      : kind == MotionKind::translation ? "velocity in m/s"
                                        : "amplitude in m, frequency in Hz";
  if (!(speed * world.dt <= 0.5 * smallest) && std::isfinite(smallest))
    throw UserError(where,
                    fmt::format("surface '{}' moves at up to {:.4g} m/s: {:.4g} m in one step of "
                                "{:.4g} s, more than half the radius of the smallest particle "
                                "({:.4g} m); a particle it meets is struck within one step and "
                                "can pass through it",
                                s.name.value, speed, speed * world.dt, world.dt, smallest),
                    fmt::format("check the motion ({}), or use a time step ≤ {:.3g} s", units,
                                0.1 * smallest / speed));
  return speed;
}

}  // namespace

std::size_t add_surface(World& world, const SurfaceSpec& s, const Surface* given) {
  const std::size_t material = material_index(world.spec, s.material.value);
  if (material >= world.materials.count())
    throw UserError(
        s.material.where,
        fmt::format("unknown material '{}' for surface '{}'", s.material.value, s.name.value),
        "define the material first");
  WorldSurface record;
  Surface& surface = record.mesh;
  if (given) {
    surface.reference_vertices = given->reference_vertices;
    surface.triangles = given->triangles;
  } else {
    surface = make_surface(s, world.warnings);
  }
  record.element_of_triangle = mesh_element_map(s);
  record.element_count = record.element_of_triangle.empty()
                             ? surface.triangle_count()
                             : s.mesh_triangles.size() + s.mesh_quads.size();
  if (surface.reference_vertices.empty()) surface.reference_vertices = surface.vertices;
  surface.vertices = surface.reference_vertices;
  surface.name = s.name.value;
  surface.material = static_cast<std::uint16_t>(material);
  surface.conveyor_velocity = s.conveyor_velocity.value;
  surface.export_loads = s.export_loads.value;
  surface.update_normals_and_areas();
  surface.reset_loads();
  if (s.motion.kind.value != MotionKind::none) {
    record.driver.kind = SurfaceDriverKind::prescribed;
    record.driver.motion = s.motion;
    apply_motion(s.motion, world.time, surface);
    const double speed = check_surface_speed(world, s, surface);  // m/s
    if (speed > world.fastest_surface.speed) world.fastest_surface = {speed, s.name.value};
  } else if (s.coupled.value) {
    record.driver.kind = SurfaceDriverKind::coupled;  // at rest until the partner sets its vertices
  }
  surface.moving = record.driver.kind != SurfaceDriverKind::fixed;
  report_geometry_outside_domain(world, s, record);
  report_surface_across_periodic_faces(world, s, record);
  record.topology = build_topology(surface);
  // Search grid: cells about one particle diameter plus skin (fixed surfaces keep theirs for
  // the whole run; moving ones are rebuilt with the lists).
  record.vertices_at_build = surface.vertices;
  build_search_grid(world, record);
  world.surfaces.push_back(std::move(record));
  world.spec.surfaces.push_back(s);
  world.lists_stale = true;
  return world.surfaces.size() - 1;
}

void build_search_grid(const World& world, WorldSurface& s) {
  const double cell = 2.0 * world.max_radius + world.skin;  // m
  Aabb clip = world.spec.simulation.domain.value;
  clip.lo = clip.lo - Vec3{cell, cell, cell};
  clip.hi = clip.hi + Vec3{cell, cell, cell};
  if (s.vertices_at_build == s.mesh.vertices) {
    s.grid.build(s.mesh, cell, clip);
  } else {
    Surface at_build = s.mesh;
    at_build.vertices = s.vertices_at_build;
    s.grid.build(at_build, cell, clip);
  }
}

namespace {

// A factory's particles are centred at least their radius inside its region; a region that
// reaches further out of the domain than the largest radius places particles outside it, which
// leave at once (the mass asked for is never delivered) and, in a fluid run, pile into the
// fluid grid's edge cells. Periodic axes wrap the positions and are not checked.
void check_factory_inside_domain(const World& world, const FactorySpec& factory,
                                 const Region& region) {
  const Aabb bounds = region.bounds();                      // m
  const Aabb& domain = world.spec.simulation.domain.value;  // m
  const RegionSpec& r = factory.region;
  for (int a = 0; a < 3; ++a) {
    if (world.spec.simulation.periodic.value[a]) continue;
    const bool low = bounds.lo[a] < domain.lo[a] - world.max_radius;
    const bool high = bounds.hi[a] > domain.hi[a] + world.max_radius;
    if (!low && !high) continue;
    const RegionKind kind = r.kind.value;
    const SourceLocation& where = kind == RegionKind::box        ? (low ? r.min.where : r.max.where)
                                  : kind == RegionKind::cylinder ? r.base.where
                                                                 : r.position.where;
    throw UserError(where,
                    fmt::format("factory '{}': its region reaches {} = {:.6g} m, outside the "
                                "domain ({:.6g} to {:.6g} m): particles placed there would leave "
                                "at once",
                                factory.name.value, "xyz"[a], low ? bounds.lo[a] : bounds.hi[a],
                                domain.lo[a], domain.hi[a]),
                    "keep the region inside simulation.domain, or widen the domain");
  }
}

// A JKR contact adheres down to the overlap δ_c < 0, i.e. across a gap of up to |δ_c|; the
// pair list and the surface candidates hold only what lies within the skin, so the skin must
// exceed that gap (|δ_c| grows with R*^{1/3}: the largest radius against a wall bounds it).
void check_jkr_reach(const World& world) {
  Diagnostics problems;
  for (const InteractionSpec& interaction : world.spec.interactions) {
    if (interaction.cohesion_model.value != CohesionModel::jkr) continue;
    const std::vector<std::string>& names = world.materials.names;
    const auto index = [&names](const std::string& name) {
      return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
    };
    const std::size_t a = index(interaction.material_a.value), b = index(interaction.material_b.value);
    if (a >= world.materials.count() || b >= world.materials.count()) continue;
    const InteractionParameters& law = world.materials.between(a, b);
    const double gap = -contact::jkr_scales(law.surface_energy, law.effective_youngs_modulus,
                                            world.max_radius)
                            .break_overlap;  // m
    if (!(gap < world.skin)) {
      problems.error(interaction.surface_energy.where,
                     fmt::format("a JKR contact of this interaction holds across a gap of up to {:.4g} m, "
                                 "not less than the neighbour skin {:.4g} m",
                                 gap, world.skin),
                     "raise simulation.skin above the gap, or lower surface_energy");
    }
  }
  if (problems.has_errors()) throw UserError(problems);
}

// The periodic axes (issue #20) as the deck parser checks them (io/deck.cpp), again here for a
// spec made without a deck: a domain to take the period from, and a period the neighbour
// search can hold (core/periodic_box.h, shortest_period).
void set_periodic_axes(World& world) {
  const auto& periodic = world.spec.simulation.periodic;
  if (!(periodic.value[0] || periodic.value[1] || periodic.value[2])) return;
  const Aabb& domain = world.spec.simulation.domain.value;
  if (domain.empty())
    throw UserError(periodic.where, "periodic axes need a domain: its min and max are the period",
                    "give simulation.domain: {min: [...], max: [...]}");
  const double shortest = shortest_period(world.max_radius, world.skin);  // m
  for (int a = 0; a < 3; ++a)
    if (periodic.value[a] && domain.hi[a] - domain.lo[a] < shortest)
      throw UserError(
          periodic.where,
          fmt::format("the period along {} ({:.4g} m) is shorter than the neighbour search needs: "
                      "3 × (2 R_max + skin) = {:.4g} m",
                      "xyz"[a], domain.hi[a] - domain.lo[a], shortest),
          "lengthen the domain along that axis, or make it non-periodic");
  world.pairs.periodic = PeriodicBox::of(domain, periodic.value);
}

}  // namespace

World build_world(const SimulationSpec& spec, const std::vector<Surface>& meshes) {
  if (!meshes.empty() && meshes.size() != spec.surfaces.size())
    throw std::invalid_argument("build_world: one mesh per surface of the spec, or none");
  sim::refuse_if_it_cannot_fit(spec);  // before anything is allocated
  World world;
  world.spec = spec;
  world.threading.threads = spec.simulation.threads.value;
  world.materials = build_material_table(spec);
  // Rolling-torque history exists only for the EPSD model (contact_law.h).
  world.pairs.keep_rolling_history = std::any_of(
      world.materials.pairs.begin(), world.materials.pairs.end(),
      [](const InteractionParameters& p) { return p.rolling_model == RollingModel::epsd; });
  // Adhesion state exists only for JKR (contact_law.h).
  world.pairs.keep_jkr_history = std::any_of(
      world.materials.pairs.begin(), world.materials.pairs.end(),
      [](const InteractionParameters& p) { return p.surface_energy > 0.0; });
  world.types = particle_type_infos(spec);
  for (const auto& t : spec.particle_types) {
    world.type_names.push_back(t.name.value);
    world.size_samplers.emplace_back(t.size);
  }
  world.size_random = Random(spec.simulation.seed ^ 0xA5A5A5A55A5A5A5Aull);

  // Time step (throws with the deck location if the contact time is under-resolved). Its
  // warnings wait for the surfaces: a moving wall may raise the expected impact speed.
  const TimeStepChoice still = choose_time_step(spec);
  throw_time_step_errors(still);
  world.dt = still.dt;

  // Largest and smallest radius any particle can have (m): sizes the grids and the skin.
  double min_radius = 1e300;
  for (const auto& t : spec.particle_types) {
    SizeSampler sampler(t.size);
    world.max_radius = std::max(world.max_radius, sampler.max_radius());
    min_radius = std::min(min_radius, sampler.min_radius());
  }
  if (world.max_radius <= 0.0) world.max_radius = 1e-3;
  if (min_radius > 1e299) min_radius = world.max_radius;
  // Verlet skin: the deck's, or (unset or `auto`) chosen at every list build (automatic_skin)
  // from 10 % of the smallest diameter (the first build's, and the least) up to 40 %, within
  // what the periodic axes allow.
  const bool fixed_skin = spec.simulation.skin.value >= 0.0;
  world.skin = fixed_skin ? spec.simulation.skin.value : 0.2 * min_radius;
  check_jkr_reach(world);
  set_periodic_axes(world);
  if (!fixed_skin) {
    World::SkinChoice& skin = world.skin_choice;
    skin.automatic = true;
    skin.smallest_diameter = 2.0 * min_radius;
    skin.floor = world.skin;
    skin.ceiling = std::max(skin.floor, 0.8 * min_radius);
    const Aabb& domain = spec.simulation.domain.value;
    for (int a = 0; a < 3; ++a) {  // the period must stay at least 3 × (2 R_max + skin)
      if (!spec.simulation.periodic.value[a]) continue;
      const double widest = (domain.hi[a] - domain.lo[a]) / 3.0 - 2.0 * world.max_radius;  // m
      skin.ceiling = std::max(skin.floor, std::min(skin.ceiling, widest));
    }
  }

  world.spec.surfaces.clear();  // add_surface appends each again
  for (std::size_t s = 0; s < spec.surfaces.size(); ++s)
    add_surface(world, spec.surfaces[s], meshes.empty() ? nullptr : &meshes.at(s));
  // The Hertz checks again at the impact speed the moving walls add (the step is the same).
  const TimeStepChoice choice =
      world.fastest_surface.speed > 0.0 ? choose_time_step(spec, world.fastest_surface) : still;
  throw_time_step_errors(choice);
  for (const auto& d : choice.problems)
    if (d.severity == Severity::warning) world.warnings.push_back(d.message);

  for (std::size_t f = 0; f < spec.factories.size(); ++f) {
    const auto& fs = spec.factories[f];
    std::size_t type = 0;
    while (type < spec.particle_types.size() &&
           spec.particle_types[type].name.value != fs.particle_type.value)
      ++type;
    if (type >= world.types.size()) continue;
    // Each factory gets its own random stream derived from the deck seed.
    world.factories.emplace_back(fs, world.types[type],
                                 spec.simulation.seed + 0x9E3779B97F4A7C15ull * (f + 1));
    world.factories.back().set_periodic(world.pairs.periodic);
    check_factory_inside_domain(world, fs, world.factories.back().region());
  }
  // Factories are polled every 2 ms of simulated time (or every step if dt is larger).
  world.insertion_interval_steps = std::max(1, static_cast<int>(std::lround(2e-3 / world.dt)));
  place_initial_particles(world);
  return world;
}

}  // namespace quarry
