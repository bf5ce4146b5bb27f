// LocalBackend: the C ABI's calls on a simulation in this process. Arrays cross in type order
// (seed 004) through sim::TypeOrder; every change goes through the sim functions that keep the
// state complete between steps (sim/exchange.h, sim/step.h).
#include "api/local_backend.h"

#include <fmt/format.h>

#include <cmath>

#include "fsi/structure_run.h"
#include "coupling/sample_points.h"
#include "core/sphere.h"
#include "io/deck.h"
#include "io/deck_writer.h"
#include "sim/output.h"
#include "sim/run.h"
#include "sim/step.h"

namespace quarry::api {

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(quarry_status status, const std::string& message) { throw ApiError(status, message); }

Vec3 vec(const double* v, std::size_t k) { return {v[3 * k], v[3 * k + 1], v[3 * k + 2]}; }
void put(double* out, std::size_t k, const Vec3& v) {
  out[3 * k] = v.x, out[3 * k + 1] = v.y, out[3 * k + 2] = v.z;
}

bool finite3(const double* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

template <class T>
Located<T> at(const T& value) {
  return Located<T>(value);
}

// Maps std::invalid_argument and std::logic_error from the sim functions to the ABI's codes.
template <class F>
auto translated(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw ApiError(QUARRY_ERROR_BAD_VALUE, e.what());
  } catch (const std::out_of_range& e) {
    throw ApiError(QUARRY_ERROR_NOT_FOUND, e.what());
  } catch (const std::logic_error& e) {
    throw ApiError(QUARRY_ERROR_WRONG_STATE, e.what());
  }
}

// Where the structures' lines go through the ABI (the coupling messages, the end-of-run
// summary): nowhere; a library does not print. Their frames and monitors go to the handle's
// output folder, as the fluid's.
std::ostream& discarded_lines() {
  static std::ostream nowhere(nullptr);
  return nowhere;
}

// The periodic axes of `settings` against the types (docs/deck.md's checks, io/deck.h): BAD_VALUE
// naming the call, each problem with its hint.
void check_periodic(const char* call, const SimulationSettings& settings, const std::vector<ParticleTypeSpec>& types) {
  Diagnostics problems;
  check_periodic_domain(settings, types, problems);
  if (!problems.has_errors()) return;
  std::string text;
  for (const Diagnostic& d : problems.all())
    text += fmt::format("{}{} (hint: {})", text.empty() ? "" : "; ", d.message, d.hint);
  fail(QUARRY_ERROR_BAD_VALUE, fmt::format("{}: {}", call, text));
}

}  // namespace

LocalBackend::LocalBackend(const quarry_open_info& info) {
  threads_ = info.threads;
  if (info.output_directory) output_directory_ = fs::path(info.output_directory);
  if (info.deck_path && info.checkpoint_path)
    fail(QUARRY_ERROR_BAD_VALUE, "give deck_path or checkpoint_path, not both");
  if (info.deck_path) {
    world_ = build_world(parse_deck(info.deck_path));
    attach_built_in();
    if (threads_ > 0) world_.threading.threads = threads_;
    start();
  } else if (info.checkpoint_path) {
    sim::RestoredWorld restored = sim::read_checkpoint(info.checkpoint_path);
    world_ = std::move(restored.world);
    // The fluid and structures the run had, made again from the checkpoint's deck and given
    // their state back.
    attach_built_in();
    sim::restore_sections(world_, restored.sections, info.checkpoint_path);
    if (threads_ > 0) world_.threading.threads = threads_;
    if (output_directory_) attach_output(world_.time, restored.frame_index);
    started_ = true;
  } else {
    // An empty simulation: the definition grows by calls until start().
    spec_.deck_path = "";
    spec_.output.plots = false;
  }
}

LocalBackend::~LocalBackend() = default;

// The deck's fluid: and structures: sections, attached as `quarry run` attaches them (the
// fluid first), so that stepping through the ABI runs the same simulation.
void LocalBackend::attach_built_in() { built_in_ = attach_built_in_solvers(world_, discarded_lines()); }

void LocalBackend::close() {
  // The structures' last frame and monitor row, as at the end of `quarry run`.
  if (started_ && built_in_.structures) built_in_.structures->finish(discarded_lines());
  if (started_ && world_.output) {
    world_.output->finish(world_, false);
    world_.output.reset();
  }
}

void LocalBackend::require_started(const char* call) const {
  if (!started_) fail(QUARRY_ERROR_WRONG_STATE, fmt::format("{}: the simulation is not started yet (call quarry_start)", call));
}

void LocalBackend::require_not_started(const char* call) const {
  if (started_)
    fail(QUARRY_ERROR_WRONG_STATE,
         fmt::format("{}: the simulation is started; settings, materials, interactions and types are fixed", call));
}

void LocalBackend::require_outside_hook(const char* call) const {
  if (in_hook_ != 0) fail(QUARRY_ERROR_WRONG_STATE, fmt::format("{}: not allowed inside a step hook", call));
}

void LocalBackend::attach_output(std::optional<double> resume_time, std::uint64_t frame_index) {
  sim::OutputOptions options;
  options.directory = *output_directory_;
  options.end_time = world_.spec.simulation.end_time.value;
  options.resume_time = resume_time;
  options.frame_index = frame_index;
  world_.output = std::make_unique<sim::Output>(world_, options);
}

World& LocalBackend::world() {
  require_started("world");
  return world_;
}

// ---- building ----

void LocalBackend::set_settings(const quarry_settings& s) {
  require_not_started("quarry_set_settings");
  // Built aside and kept only once every check passed: a refused call changes nothing.
  SimulationSettings out = spec_.simulation;
  if (s.time_step > 0.0) out.fixed_time_step = at(s.time_step);
  else out.fixed_time_step.reset();
  out.rayleigh_fraction = at(s.rayleigh_fraction);
  out.gravity = at(Vec3{s.gravity[0], s.gravity[1], s.gravity[2]});
  Aabb domain;
  domain.lo = Vec3{s.domain_min[0], s.domain_min[1], s.domain_min[2]};
  domain.hi = Vec3{s.domain_max[0], s.domain_max[1], s.domain_max[2]};
  out.domain = at(domain);
  out.end_time = at(s.end_time);
  if (s.impact_speed > 0.0) out.impact_speed = at(s.impact_speed);
  else out.impact_speed.reset();
  out.skin = at(s.skin);
  if (s.integrator != QUARRY_INTEGRATOR_VELOCITY_VERLET && s.integrator != QUARRY_INTEGRATOR_SYMPLECTIC_EULER)
    fail(QUARRY_ERROR_BAD_VALUE, fmt::format("integrator {} is not a QUARRY_INTEGRATOR_* value", s.integrator));
  out.integrator = at(s.integrator == QUARRY_INTEGRATOR_VELOCITY_VERLET ? Integrator::velocity_verlet
                                                                         : Integrator::symplectic_euler);
  out.sort_interval = at(static_cast<int>(s.sort_interval));
  out.max_overlap_fraction = at(s.max_overlap_fraction);
  out.seed = s.seed;
  out.threads = at(static_cast<int>(threads_));
  std::array<bool, 3> periodic{};
  for (int a = 0; a < 3; ++a) {
    if (s.periodic[a] != 0 && s.periodic[a] != 1)
      fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_set_settings: periodic[{}] (axis {}) is {}; give 1 for a periodic "
                                               "axis, 0 for one that is not",
                                               a, "xyz"[a], s.periodic[a]));
    periodic[a] = s.periodic[a] == 1;
  }
  out.periodic = at(periodic);
  check_periodic("quarry_set_settings", out, spec_.particle_types);
  spec_.simulation = out;
}

std::uint32_t LocalBackend::add_material(const quarry_material& m) {
  require_not_started("quarry_add_material");
  if (!m.name) fail(QUARRY_ERROR_NULL_POINTER, "quarry_add_material: name is NULL");
  MaterialSpec material;
  material.name = at(std::string(m.name));
  material.density = at(m.density);
  material.youngs_modulus = at(m.youngs_modulus);
  material.poisson_ratio = at(m.poisson_ratio);
  for (std::size_t k = 0; k < spec_.materials.size(); ++k)
    if (spec_.materials[k].name.value == material.name.value)
      fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_add_material: material '{}' exists already", m.name));
  spec_.materials.push_back(material);
  return static_cast<std::uint32_t>(spec_.materials.size() - 1);
}

void LocalBackend::add_interaction(const quarry_interaction& i) {
  require_not_started("quarry_add_interaction");
  if (!i.material_a || !i.material_b) fail(QUARRY_ERROR_NULL_POINTER, "quarry_add_interaction: a material name is NULL");
  InteractionSpec interaction;
  interaction.material_a = at(std::string(i.material_a));
  interaction.material_b = at(std::string(i.material_b));
  interaction.restitution = at(i.restitution);
  interaction.static_friction = at(i.static_friction);
  interaction.rolling_friction = at(i.rolling_friction);
  switch (i.rolling_model) {
    case QUARRY_ROLLING_NONE: interaction.rolling_model = at(RollingModel::none); break;
    case QUARRY_ROLLING_CONSTANT_TORQUE: interaction.rolling_model = at(RollingModel::constant_torque); break;
    case QUARRY_ROLLING_EPSD: interaction.rolling_model = at(RollingModel::epsd); break;
    default: fail(QUARRY_ERROR_BAD_VALUE, fmt::format("rolling_model {} is not a QUARRY_ROLLING_* value", i.rolling_model));
  }
  interaction.cohesion_energy_density = at(i.cohesion_energy_density);
  spec_.interactions.push_back(interaction);
}

std::uint32_t LocalBackend::add_particle_type(const quarry_particle_type& t) {
  require_not_started("quarry_add_particle_type");
  if (!t.name || !t.material) fail(QUARRY_ERROR_NULL_POINTER, "quarry_add_particle_type: name or material is NULL");
  ParticleTypeSpec type;
  type.name = at(std::string(t.name));
  type.material = at(std::string(t.material));
  if (t.max_radius > 0.0) {
    type.size.kind = at(SizeDistributionKind::uniform);
    type.size.min_radius = at(t.radius);
    type.size.max_radius = at(t.max_radius);
  } else {
    type.size.kind = at(SizeDistributionKind::fixed);
    type.size.radius = at(t.radius);
  }
  // The period the settings give must hold this type's particles too (checked on a copy: a
  // refused type is not added).
  std::vector<ParticleTypeSpec> types = spec_.particle_types;
  types.push_back(type);
  check_periodic("quarry_add_particle_type", spec_.simulation, types);
  spec_.particle_types.push_back(type);
  return static_cast<std::uint32_t>(spec_.particle_types.size() - 1);
}

void LocalBackend::start() {
  if (!started_ && world_.spec.materials.empty()) {
    // Built by calls: the definition goes through the deck's checks (names, ranges, every
    // interaction that can occur), reported with the keys and values at fault.
    if (spec_.simulation.end_time.value <= 0.0) spec_.simulation.end_time = at(1.0);
    SimulationSpec checked;
    try {
      checked = parse_deck_string(write_deck(spec_), "quarry_start");
    } catch (const UserError& e) {
      fail(QUARRY_ERROR_INPUT, "the simulation's definition is incomplete or wrong:\n" + e.diagnostics().format());
    }
    world_ = build_world(checked);
    if (threads_ > 0) world_.threading.threads = threads_;
  } else if (started_) {
    fail(QUARRY_ERROR_WRONG_STATE, "quarry_start: the simulation is started already");
  }
  if (output_directory_) attach_output(std::nullopt, 0);
  sim::initialize(world_);
  started_ = true;
}

// ---- time ----

void LocalBackend::get_time(double* time, double* time_step, std::uint64_t* steps) {
  if (!started_) {
    if (time) *time = 0.0;
    if (time_step) *time_step = 0.0;
    if (steps) *steps = 0;
    return;
  }
  if (time) *time = world_.time;
  if (time_step) *time_step = world_.dt;
  if (steps) *steps = world_.step_count;
}

void LocalBackend::run_steps(std::uint64_t steps) {
  for (std::uint64_t s = 0; s < steps; ++s) {
    if (stop_ && stop_->load(std::memory_order_relaxed) != 0)
      fail(QUARRY_ERROR_TRANSPORT, fmt::format("quarry serve is stopping (signal {}): the advance ended after {} of {} "
                                               "steps, at step {} (t = {:.6g} s)",
                                               stop_->load(), s, steps, world_.step_count, world_.time));
    sim::step(world_);
  }
}

quarry_advance_result LocalBackend::advance(double duration) {
  require_started("quarry_advance");
  require_outside_hook("quarry_advance");
  if (!std::isfinite(duration) || duration < 0.0)
    fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_advance: duration {} s is not a finite number ≥ 0", duration));
  // Whole steps that end at or before time + duration; the relative 1e-9 of a step keeps a
  // duration that is a multiple of dt from losing its last step to rounding.
  const double steps = std::floor(duration / world_.dt + 1e-9);
  if (steps > 1e15) fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_advance: {} s is {} steps", duration, steps));
  quarry_advance_result result{};
  result.struct_size = sizeof result;
  result.steps = static_cast<std::uint64_t>(steps);
  run_steps(result.steps);
  result.time = world_.time;
  return result;
}

void LocalBackend::step(std::uint64_t steps) {
  require_started("quarry_step");
  require_outside_hook("quarry_step");
  run_steps(steps);
}

// ---- checkpoints ----

void LocalBackend::save_checkpoint(const std::string& path) {
  require_started("quarry_save_checkpoint");
  require_outside_hook("quarry_save_checkpoint");
  sim::settle_once_loads(world_);
  sim::write_checkpoint(world_, path, world_.output ? world_.output->frame_index() : 0);
}

std::string LocalBackend::save_state() {
  require_started("quarry_save_state");
  require_outside_hook("quarry_save_state");
  sim::settle_once_loads(world_);
  return sim::checkpoint_bytes(world_, world_.output ? world_.output->frame_index() : 0);
}

void LocalBackend::restore_state(const void* bytes, std::uint64_t size) {
  require_started("quarry_restore_state");
  require_outside_hook("quarry_restore_state");
  sim::RestoredWorld restored =
      sim::read_checkpoint_bytes(std::string(static_cast<const char*>(bytes), size), "quarry_restore_state");
  // The handle's own settings stay: threads, hooks (the fluid's and structures' among them), the
  // output stream. The attached fluid and structures take their saved state (each section
  // checked whole before it changes anything); a state from a deck with another fluid or other
  // structures, or none, is refused and the handle left as it was.
  restored.world.threading = world_.threading;
  restored.world.hooks = std::move(world_.hooks);
  restored.world.checkpoint_sections = std::move(world_.checkpoint_sections);
  try {
    sim::restore_sections(restored.world, restored.sections, "quarry_restore_state");
  } catch (...) {
    world_.hooks = std::move(restored.world.hooks);
    world_.checkpoint_sections = std::move(restored.world.checkpoint_sections);
    throw;
  }
  restored.world.output = std::move(world_.output);
  // Every view and index taken before is stale: the epoch moves past both the current one and
  // the saved one (which may be equal to the current one for a different particle order).
  const std::uint64_t epoch = std::max(world_.particles.layout_epoch, restored.world.particles.layout_epoch) + 1;
  world_ = std::move(restored.world);
  world_.particles.layout_epoch = epoch;
}

// ---- particles ----

const sim::TypeOrder& LocalBackend::order() {
  sim::update_type_order(world_, order_);
  return order_;
}

std::uint32_t LocalBackend::num_types() {
  return static_cast<std::uint32_t>(started_ ? world_.types.size() : spec_.particle_types.size());
}

std::string LocalBackend::type_name(std::uint32_t type) {
  if (type >= num_types()) fail(QUARRY_ERROR_NOT_FOUND, fmt::format("type {} does not exist ({} types)", type, num_types()));
  return started_ ? world_.type_names[type] : spec_.particle_types[type].name.value;
}

std::uint64_t LocalBackend::num_particles(std::int32_t type) {
  if (!started_) return 0;
  if (type < -1 || type >= static_cast<std::int32_t>(world_.types.size()))
    fail(QUARRY_ERROR_NOT_FOUND, fmt::format("type {} does not exist ({} types; −1 for all)", type, world_.types.size()));
  if (type == -1) return world_.particles.size();
  const sim::TypeOrder& o = order();
  return o.type_start[type + 1] - o.type_start[type];
}

std::uint64_t LocalBackend::epoch() { return started_ ? world_.particles.layout_epoch : 0; }

void LocalBackend::get_particles(quarry_particle_data& data) {
  require_started("quarry_get_particles");
  if (data.force || data.torque) sim::settle_once_loads(world_);
  const ParticleStore& p = world_.particles;
  const std::size_t n = p.size();
  data.count = n;
  data.epoch = p.layout_epoch;
  if (data.capacity < n)
    fail(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_get_particles: capacity {} < {} particles", data.capacity, n));
  const sim::TypeOrder& o = order();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = o.order[k];
    if (data.id) data.id[k] = p.id[i];
    if (data.type) data.type[k] = p.type[i];
    if (data.position) put(data.position, k, p.position[i]);
    if (data.velocity) put(data.velocity, k, p.velocity[i]);
    if (data.angular_velocity) put(data.angular_velocity, k, p.angular_velocity[i]);
    if (data.radius) data.radius[k] = p.radius[i];
    if (data.mass) data.mass[k] = p.mass(i);
    if (data.volume) data.volume[k] = sphere_volume(p.radius[i]);
    if (data.force) put(data.force, k, p.force[i]);
    if (data.torque) put(data.torque, k, p.torque[i]);
  }
}

std::uint64_t LocalBackend::particle_index(std::uint64_t id) {
  require_started("quarry_particle_index");
  sim::update_id_index(world_, ids_);
  const auto found = ids_.index.find(id);
  if (found == ids_.index.end()) fail(QUARRY_ERROR_NOT_FOUND, fmt::format("particle id {} does not exist", id));
  // Type-order index: the type's start plus the engine indices of that type before it.
  const sim::TypeOrder& o = order();
  const std::uint32_t engine = found->second;
  const std::uint16_t type = world_.particles.type[engine];
  const auto begin = o.order.begin() + static_cast<std::ptrdiff_t>(o.type_start[type]);
  const auto end = o.order.begin() + static_cast<std::ptrdiff_t>(o.type_start[type + 1]);
  return static_cast<std::uint64_t>(std::lower_bound(begin, end, engine) - o.order.begin());
}

quarry_view LocalBackend::view_particles(std::int32_t field) {
  require_started("quarry_view_particles");
  ParticleStore& p = world_.particles;
  quarry_view view{};
  view.count = p.size();
  view.epoch = p.layout_epoch;
  const auto vectors = [&view](std::vector<Vec3>& a) {
    view.data = a.empty() ? nullptr : a.data();
    view.dtype = QUARRY_DTYPE_FLOAT64, view.components = 3, view.stride = sizeof(Vec3);
  };
  const auto scalars = [&view](auto& a, std::uint32_t dtype) {
    view.data = a.empty() ? nullptr : a.data();
    view.dtype = dtype, view.components = 1, view.stride = sizeof(a[0]);
  };
  switch (field) {
    case QUARRY_FIELD_ID: scalars(p.id, QUARRY_DTYPE_UINT64); break;
    case QUARRY_FIELD_TYPE: scalars(p.type, QUARRY_DTYPE_UINT16); break;
    case QUARRY_FIELD_POSITION: vectors(p.position); break;
    case QUARRY_FIELD_VELOCITY: vectors(p.velocity); break;
    case QUARRY_FIELD_ANGULAR_VELOCITY: vectors(p.angular_velocity); break;
    case QUARRY_FIELD_RADIUS: scalars(p.radius, QUARRY_DTYPE_FLOAT64); break;
    case QUARRY_FIELD_INVERSE_MASS: scalars(p.inv_mass, QUARRY_DTYPE_FLOAT64); break;
    case QUARRY_FIELD_FORCE: sim::settle_once_loads(world_), vectors(p.force); break;
    case QUARRY_FIELD_TORQUE: sim::settle_once_loads(world_), vectors(p.torque); break;
    case QUARRY_FIELD_TYPE_ORDER:
      sim::update_type_order(world_, order_);
      scalars(order_.order, QUARRY_DTYPE_UINT32);
      break;
    default: fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_view_particles: field {} is not a QUARRY_FIELD_* value", field));
  }
  return view;
}

quarry_view LocalBackend::view_next_step_loads(std::int32_t field) {
  require_started("quarry_view_next_step_loads");
  require_outside_hook("quarry_view_next_step_loads");
  if (field != QUARRY_FIELD_FORCE && field != QUARRY_FIELD_TORQUE)
    fail(QUARRY_ERROR_BAD_VALUE,
         fmt::format("quarry_view_next_step_loads: field {} is neither QUARRY_FIELD_FORCE ({}) nor "
                     "QUARRY_FIELD_TORQUE ({})",
                     field, static_cast<int>(QUARRY_FIELD_FORCE), static_cast<int>(QUARRY_FIELD_TORQUE)));
  sim::open_once_loads(world_, field == QUARRY_FIELD_FORCE ? ParticleStore::kForceLoads : ParticleStore::kTorqueLoads);
  ParticleStore& p = world_.particles;
  std::vector<Vec3>& loads = field == QUARRY_FIELD_FORCE ? p.external_force_once : p.external_torque_once;
  quarry_view view{};
  view.data = loads.empty() ? nullptr : loads.data();
  view.count = p.size();
  view.dtype = QUARRY_DTYPE_FLOAT64;
  view.components = 3;
  view.stride = sizeof(Vec3);
  view.epoch = p.layout_epoch;
  view.writable = 1;
  return view;
}

void LocalBackend::add_particles(const quarry_new_particles& q) {
  require_started("quarry_add_particles");
  require_outside_hook("quarry_add_particles");
  if (q.count > 0 && !q.position) fail(QUARRY_ERROR_NULL_POINTER, "quarry_add_particles: position is NULL");
  std::vector<sim::NewParticle> added(q.count);
  for (std::size_t k = 0; k < q.count; ++k) {
    const std::uint32_t type = q.types ? q.types[k] : q.type;
    if (type >= world_.types.size())
      fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_add_particles: particle {} has type {} ({} types)", k, type, world_.types.size()));
    added[k].type = static_cast<std::uint16_t>(type);
    added[k].position = vec(q.position, k);
    if (q.velocity) added[k].velocity = vec(q.velocity, k);
    if (q.angular_velocity) added[k].angular_velocity = vec(q.angular_velocity, k);
    if (q.radius) added[k].radius = q.radius[k];
  }
  const std::vector<ParticleId> ids = translated([&] { return sim::add_particles(world_, added); });
  if (q.ids) std::copy(ids.begin(), ids.end(), q.ids);
}

void LocalBackend::remove_particles(const std::uint64_t* ids, std::uint64_t count) {
  require_started("quarry_remove_particles");
  require_outside_hook("quarry_remove_particles");
  try {
    sim::remove_particles(world_, std::span<const ParticleId>(ids, count));
  } catch (const std::invalid_argument& e) {
    fail(QUARRY_ERROR_NOT_FOUND, fmt::format("quarry_remove_particles: {}; nothing was removed", e.what()));
  }
}

// ---- external loads ----

namespace {

sim::LoadMode load_mode(std::int32_t mode) {
  if (mode == QUARRY_LOAD_ADD) return sim::LoadMode::add;
  if (mode == QUARRY_LOAD_REPLACE) return sim::LoadMode::replace;
  fail(QUARRY_ERROR_BAD_VALUE, fmt::format("mode {} is not QUARRY_LOAD_ADD or QUARRY_LOAD_REPLACE", mode));
}

sim::LoadHold load_hold(std::int32_t hold) {
  if (hold == QUARRY_HOLD_NEXT_STEP) return sim::LoadHold::next_step;
  if (hold == QUARRY_HOLD_UNTIL_CHANGED) return sim::LoadHold::until_changed;
  fail(QUARRY_ERROR_BAD_VALUE, fmt::format("hold {} is not QUARRY_HOLD_NEXT_STEP or QUARRY_HOLD_UNTIL_CHANGED", hold));
}

std::vector<Vec3> vectors_of(const double* values, std::size_t count) {
  std::vector<Vec3> out;
  if (!values) return out;
  out.resize(count);
  for (std::size_t k = 0; k < count; ++k) out[k] = vec(values, k);
  return out;
}

// A caller's 3 × count doubles as a span (empty for NULL).
std::span<const double> triples(const double* values, std::size_t count) {
  return values ? std::span<const double>(values, 3 * count) : std::span<const double>();
}

}  // namespace

void LocalBackend::set_external_loads(const double* force, const double* torque, std::uint64_t count,
                                      std::int32_t mode, std::int32_t hold) {
  require_started("quarry_set_external_loads");
  require_outside_hook("quarry_set_external_loads");
  const std::size_t n = world_.particles.size();
  if (count != n)
    fail(QUARRY_ERROR_BAD_LENGTH,
         fmt::format("quarry_set_external_loads: {} entries for {} particles (one per particle, type order)", count, n));
  const sim::LoadMode m = load_mode(mode);
  const sim::LoadHold h = load_hold(hold);
  // Type order; when it is the engine's (one type, or types already grouped) the loads go in
  // without an index list.
  const sim::TypeOrder& o = order();
  const std::span<const std::uint32_t> indices = o.identity ? std::span<const std::uint32_t>() : o.order;
  translated([&] {
    sim::set_external_loads(world_, indices, triples(force, count), triples(torque, count), m, h);
    return 0;
  });
}

void LocalBackend::set_external_loads_by_id(const std::uint64_t* ids, std::uint64_t count, const double* force,
                                            const double* torque, std::int32_t mode, std::int32_t hold) {
  require_started("quarry_set_external_loads_by_id");
  require_outside_hook("quarry_set_external_loads_by_id");
  const sim::LoadMode m = load_mode(mode);
  const sim::LoadHold h = load_hold(hold);
  sim::update_id_index(world_, ids_);
  load_indices_.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    const auto found = ids_.index.find(ids[k]);
    if (found == ids_.index.end())
      fail(QUARRY_ERROR_NOT_FOUND, fmt::format("quarry_set_external_loads_by_id: particle id {} (entry {}) does not exist", ids[k], k));
    load_indices_[k] = found->second;
  }
  translated([&] {
    sim::set_external_loads(world_, load_indices_, triples(force, count), triples(torque, count), m, h);
    return 0;
  });
}

void LocalBackend::clear_external_loads() {
  require_started("quarry_clear_external_loads");
  require_outside_hook("quarry_clear_external_loads");
  ParticleStore& p = world_.particles;
  if (!p.has_external_loads()) return;
  const std::vector<double> zeros(3 * p.size(), 0.0);
  sim::set_external_loads(world_, {}, zeros, zeros, sim::LoadMode::replace, sim::LoadHold::until_changed);
  sim::set_external_loads(world_, {}, zeros, zeros, sim::LoadMode::replace, sim::LoadHold::next_step);
}

// ---- custom properties ----

std::uint32_t LocalBackend::register_property(const std::string& name, std::uint32_t components,
                                              const std::string& unit, double initial) {
  require_started("quarry_register_property");
  require_outside_hook("quarry_register_property");
  if (name.empty()) fail(QUARRY_ERROR_BAD_VALUE, "quarry_register_property: the name is empty");
  if (components == 0) fail(QUARRY_ERROR_BAD_VALUE, "quarry_register_property: components must be ≥ 1");
  if (!std::isfinite(initial)) fail(QUARRY_ERROR_BAD_VALUE, "quarry_register_property: the initial value is not finite");
  for (const char* built_in : {"id", "type", "radius", "mass", "velocity", "angular_velocity", "force"})
    if (name == built_in)
      fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_register_property: '{}' is a built-in particle array", name));
  return static_cast<std::uint32_t>(
      translated([&] { return world_.particles.register_custom(name, components, initial, unit); }));
}

std::uint32_t LocalBackend::num_properties() {
  return started_ ? static_cast<std::uint32_t>(world_.particles.custom.size()) : 0;
}

void LocalBackend::property_info(std::uint32_t index, std::string& name, std::uint32_t& components, std::string& unit) {
  if (index >= num_properties())
    fail(QUARRY_ERROR_NOT_FOUND, fmt::format("custom property {} does not exist ({} registered)", index, num_properties()));
  const auto& c = world_.particles.custom[index];
  name = c.name, components = c.components, unit = c.unit;
}

void LocalBackend::get_property(std::uint32_t index, double* values, std::uint64_t count) {
  if (index >= num_properties())
    fail(QUARRY_ERROR_NOT_FOUND, fmt::format("custom property {} does not exist ({} registered)", index, num_properties()));
  const auto& c = world_.particles.custom[index];
  const std::size_t n = world_.particles.size();
  if (count != n * c.components)
    fail(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_get_property '{}': {} values for {} particles × {} components",
                                              c.name, count, n, c.components));
  const sim::TypeOrder& o = order();
  for (std::size_t k = 0; k < n; ++k)
    for (std::uint32_t j = 0; j < c.components; ++j) values[k * c.components + j] = c.values[o.order[k] * c.components + j];
}

void LocalBackend::set_property(std::uint32_t index, const double* values, std::uint64_t count) {
  require_outside_hook("quarry_set_property");
  if (index >= num_properties())
    fail(QUARRY_ERROR_NOT_FOUND, fmt::format("custom property {} does not exist ({} registered)", index, num_properties()));
  auto& c = world_.particles.custom[index];
  const std::size_t n = world_.particles.size();
  if (count != n * c.components)
    fail(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_set_property '{}': {} values for {} particles × {} components",
                                              c.name, count, n, c.components));
  for (std::uint64_t k = 0; k < count; ++k)
    if (!std::isfinite(values[k])) fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_set_property '{}': value {} is not finite", c.name, k));
  const sim::TypeOrder& o = order();
  for (std::size_t k = 0; k < n; ++k)
    for (std::uint32_t j = 0; j < c.components; ++j) c.values[o.order[k] * c.components + j] = values[k * c.components + j];
}

quarry_view LocalBackend::view_property(std::uint32_t index) {
  if (index >= num_properties())
    fail(QUARRY_ERROR_NOT_FOUND, fmt::format("custom property {} does not exist ({} registered)", index, num_properties()));
  auto& c = world_.particles.custom[index];
  quarry_view view{};
  view.data = c.values.empty() ? nullptr : c.values.data();
  view.count = world_.particles.size();
  view.dtype = QUARRY_DTYPE_FLOAT64;
  view.components = c.components;
  view.stride = static_cast<std::int64_t>(sizeof(double) * c.components);
  view.epoch = world_.particles.layout_epoch;
  view.writable = 1;
  return view;
}

// ---- sample points ----

void LocalBackend::sample_points(std::uint32_t type, std::uint32_t points, std::uint64_t seed, double* unit_points) {
  if (type >= num_types()) fail(QUARRY_ERROR_NOT_FOUND, fmt::format("type {} does not exist ({} types)", type, num_types()));
  if (points == 0) fail(QUARRY_ERROR_BAD_VALUE, "quarry_sample_points: at least one point");
  // Every type is a sphere today: the unit sphere's points (seeded per call, not per type).
  const std::vector<Vec3> unit = coupling::sphere_sample_points(points, seed);
  for (std::size_t k = 0; k < unit.size(); ++k) put(unit_points, k, unit[k]);
}

std::uint64_t LocalBackend::sample_point_positions(std::uint32_t type, std::uint32_t points, std::uint64_t seed,
                                                   double* positions, std::uint64_t capacity) {
  require_started("quarry_sample_point_positions");
  if (type >= world_.types.size()) fail(QUARRY_ERROR_NOT_FOUND, fmt::format("type {} does not exist", type));
  if (points == 0) fail(QUARRY_ERROR_BAD_VALUE, "quarry_sample_point_positions: at least one point");
  const sim::TypeOrder& o = order();
  const std::uint64_t first = o.type_start[type], count = o.type_start[type + 1] - first;
  const std::uint64_t needed = 3 * count * points;
  if (capacity < needed)
    fail(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_sample_point_positions: capacity {} doubles < {} ({} particles × {} points × 3)",
                                              capacity, needed, count, points));
  const std::vector<Vec3> unit = coupling::sphere_sample_points(points, seed);
  const ParticleStore& p = world_.particles;
  std::vector<Vec3> centres(count), out(count * points);
  std::vector<double> radii(count);
  for (std::uint64_t k = 0; k < count; ++k) {
    centres[k] = p.position[o.order[first + k]];
    radii[k] = p.radius[o.order[first + k]];
  }
  coupling::place_sample_points(unit, centres, radii, out);
  for (std::size_t k = 0; k < out.size(); ++k) put(positions, k, out[k]);
  return count;
}

// ---- surfaces ----

std::size_t LocalBackend::surface_index(std::uint32_t surface) const {
  const std::size_t count = started_ ? world_.surfaces.size() : spec_.surfaces.size();
  if (surface >= count) fail(QUARRY_ERROR_NOT_FOUND, fmt::format("surface {} does not exist ({} surfaces)", surface, count));
  return surface;
}

std::uint32_t LocalBackend::add_surface(const quarry_surface_desc& d) {
  require_outside_hook("quarry_add_surface");
  if (!d.name || !d.material) fail(QUARRY_ERROR_NULL_POINTER, "quarry_add_surface: name or material is NULL");
  if (d.node_count > 0 && !d.nodes) fail(QUARRY_ERROR_NULL_POINTER, "quarry_add_surface: nodes is NULL");
  if (d.triangle_count > 0 && !d.triangles) fail(QUARRY_ERROR_NULL_POINTER, "quarry_add_surface: triangles is NULL");
  if (d.quad_count > 0 && !d.quads) fail(QUARRY_ERROR_NULL_POINTER, "quarry_add_surface: quads is NULL");
  if (d.triangle_count + d.quad_count == 0) fail(QUARRY_ERROR_BAD_LENGTH, "quarry_add_surface: no triangle or quad");
  if (d.driver != QUARRY_DRIVER_FIXED && d.driver != QUARRY_DRIVER_COUPLED)
    fail(QUARRY_ERROR_BAD_VALUE, "quarry_add_surface: driver must be QUARRY_DRIVER_FIXED or QUARRY_DRIVER_COUPLED");
  SurfaceSpec s;
  s.name = at(std::string(d.name));
  s.kind = at(SurfaceKind::mesh);
  s.material = at(std::string(d.material));
  s.coupled = at(d.driver == QUARRY_DRIVER_COUPLED);
  for (std::uint64_t k = 0; k < d.node_count; ++k) {
    if (!finite3(d.nodes + 3 * k)) fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_add_surface: node {} is not finite", k));
    s.mesh_vertices.push_back(vec(d.nodes, k));
  }
  const auto index_ok = [&](std::uint32_t v, const char* what, std::uint64_t k) {
    if (v >= d.node_count)
      fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_add_surface: {} {} uses node {} ({} nodes)", what, k, v, d.node_count));
  };
  for (std::uint64_t k = 0; k < d.triangle_count; ++k) {
    std::array<std::uint32_t, 3> t{d.triangles[3 * k], d.triangles[3 * k + 1], d.triangles[3 * k + 2]};
    for (std::uint32_t v : t) index_ok(v, "triangle", k);
    s.mesh_triangles.push_back(t);
  }
  for (std::uint64_t k = 0; k < d.quad_count; ++k) {
    std::array<std::uint32_t, 4> q{d.quads[4 * k], d.quads[4 * k + 1], d.quads[4 * k + 2], d.quads[4 * k + 3]};
    for (std::uint32_t v : q) index_ok(v, "quad", k);
    s.mesh_quads.push_back(q);
  }
  if (!usable_in_file_names(d.name))
    fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_add_surface: the name \"{}\" cannot be part of a file name (it names "
                                             "the surface's output files): no '/', '\\' or control characters, and no '.' "
                                             "first", d.name));
  const auto& names = started_ ? world_.spec.surfaces : spec_.surfaces;
  for (const SurfaceSpec& other : names)
    if (other.name.value == s.name.value)
      fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_add_surface: a surface named '{}' exists already", d.name));
  if (!started_) {
    spec_.surfaces.push_back(s);
    return static_cast<std::uint32_t>(spec_.surfaces.size() - 1);
  }
  try {
    return static_cast<std::uint32_t>(quarry::add_surface(world_, s));
  } catch (const UserError& e) {
    fail(QUARRY_ERROR_BAD_VALUE, "quarry_add_surface: " + e.diagnostics().format());
  }
}

std::uint32_t LocalBackend::num_surfaces() {
  return static_cast<std::uint32_t>(started_ ? world_.surfaces.size() : spec_.surfaces.size());
}

std::uint32_t LocalBackend::find_surface(const std::string& name) {
  const auto& surfaces = started_ ? world_.spec.surfaces : spec_.surfaces;
  for (std::size_t s = 0; s < surfaces.size(); ++s)
    if (surfaces[s].name.value == name) return static_cast<std::uint32_t>(s);
  fail(QUARRY_ERROR_NOT_FOUND, fmt::format("no surface is named '{}'", name));
}

quarry_surface_info LocalBackend::surface_info(std::uint32_t surface) {
  require_started("quarry_get_surface_info");
  const WorldSurface& s = world_.surfaces[surface_index(surface)];
  quarry_surface_info info{};
  info.struct_size = sizeof info;
  info.node_count = s.mesh.vertex_count();
  info.element_count = s.element_count;
  info.triangle_count = s.mesh.triangle_count();
  info.driver = s.driver.kind == SurfaceDriverKind::fixed        ? QUARRY_DRIVER_FIXED
                : s.driver.kind == SurfaceDriverKind::prescribed ? QUARRY_DRIVER_PRESCRIBED
                                                                 : QUARRY_DRIVER_COUPLED;
  return info;
}

void LocalBackend::set_surface_driver(std::uint32_t surface, std::int32_t driver) {
  require_started("quarry_set_surface_driver");
  require_outside_hook("quarry_set_surface_driver");
  WorldSurface& s = world_.surfaces[surface_index(surface)];
  if (driver != QUARRY_DRIVER_FIXED && driver != QUARRY_DRIVER_COUPLED)
    fail(QUARRY_ERROR_BAD_VALUE, "quarry_set_surface_driver: driver must be QUARRY_DRIVER_FIXED or QUARRY_DRIVER_COUPLED");
  if (s.driver.kind == SurfaceDriverKind::prescribed)
    fail(QUARRY_ERROR_WRONG_STATE, fmt::format("surface '{}' has a prescribed motion in the deck; it cannot be coupled or fixed",
                                               s.mesh.name));
  s.driver.kind = driver == QUARRY_DRIVER_COUPLED ? SurfaceDriverKind::coupled : SurfaceDriverKind::fixed;
  s.driver.set_positions.clear();
  s.driver.set_velocities.clear();
  world_.spec.surfaces[surface].coupled = at(driver == QUARRY_DRIVER_COUPLED);  // checkpoints keep it
  if (driver == QUARRY_DRIVER_FIXED) {
    // A fixed surface rests where it is, and its search grid is made for that pose.
    for (Vec3& v : s.mesh.vertex_velocities) v = Vec3{};
    world_.lists_stale = true;
    s.vertices_at_build = s.mesh.vertices;
    build_search_grid(world_, s);
  }
}

void LocalBackend::set_surface_nodes(std::uint32_t surface, const double* positions, const double* velocities,
                                     std::uint64_t count) {
  require_started("quarry_set_surface_nodes");
  require_outside_hook("quarry_set_surface_nodes");
  WorldSurface& s = world_.surfaces[surface_index(surface)];
  if (count != s.mesh.vertex_count())
    fail(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_set_surface_nodes: {} nodes given, surface '{}' has {}", count,
                                              s.mesh.name, s.mesh.vertex_count()));
  if (s.driver.kind != SurfaceDriverKind::coupled)
    fail(QUARRY_ERROR_WRONG_STATE, fmt::format("surface '{}' is not coupled (quarry_set_surface_driver first)", s.mesh.name));
  for (std::uint64_t k = 0; k < count; ++k)
    if (!finite3(positions + 3 * k) || (velocities && !finite3(velocities + 3 * k)))
      fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_set_surface_nodes: node {} is not finite", k));
  const std::vector<Vec3> x = vectors_of(positions, count), v = vectors_of(velocities, count);
  translated([&] {
    sim::set_surface_vertices(world_, surface, x, v);
    return 0;
  });
}

void LocalBackend::get_surface_nodes(std::uint32_t surface, double* positions, double* velocities, std::uint64_t count) {
  require_started("quarry_get_surface_nodes");
  const WorldSurface& s = world_.surfaces[surface_index(surface)];
  if (count != s.mesh.vertex_count())
    fail(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_get_surface_nodes: room for {} nodes, surface '{}' has {}", count,
                                              s.mesh.name, s.mesh.vertex_count()));
  for (std::uint64_t k = 0; k < count; ++k) {
    if (positions) put(positions, k, s.mesh.vertices[k]);
    if (velocities) put(velocities, k, s.mesh.vertex_velocities[k]);
  }
}

void LocalBackend::get_surface_loads(std::uint32_t surface, quarry_surface_loads& loads) {
  require_started("quarry_get_surface_loads");
  require_outside_hook("quarry_get_surface_loads");
  WorldSurface& s = world_.surfaces[surface_index(surface)];
  if ((loads.nodal_force && loads.node_count != s.mesh.vertex_count()) ||
      ((loads.pressure || loads.shear_stress || loads.element_force) && loads.element_count != s.element_count))
    fail(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_get_surface_loads: surface '{}' has {} nodes and {} elements, "
                                              "the arrays are for {} and {}", s.mesh.name, s.mesh.vertex_count(),
                                              s.element_count, loads.node_count, loads.element_count));
  // The window starts when a partner first asks (then this read is of an empty window).
  if (!s.coupling_window.sized()) s.coupling_window = LoadWindow(s.mesh, s.element_of_triangle, s.element_count);
  LoadFrame frame;
  s.coupling_window.take_means(s.mesh, world_.time, frame);
  loads.window = frame.duration;
  loads.time = world_.time;
  for (std::size_t n = 0; n < frame.nodal_force.size() && loads.nodal_force; ++n) put(loads.nodal_force, n, frame.nodal_force[n]);
  for (std::size_t e = 0; e < frame.pressure.size(); ++e) {
    if (loads.pressure) loads.pressure[e] = frame.pressure[e];
    if (loads.shear_stress) put(loads.shear_stress, e, frame.shear_stress[e]);
    if (loads.element_force) put(loads.element_force, e, frame.force[e]);
  }
}

// ---- hooks ----

void LocalBackend::set_hook(quarry_sim sim, std::int32_t stage, quarry_hook_fn fn, void* user_data) {
  require_outside_hook("quarry_set_hook");
  if (stage != QUARRY_HOOK_POST_FORCE && stage != QUARRY_HOOK_END_OF_STEP)
    fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_set_hook: stage {} is not a QUARRY_HOOK_* value", stage));
  if (!started_) fail(QUARRY_ERROR_WRONG_STATE, "quarry_set_hook: start the simulation first");
  hooks_[stage - 1] = Hook{fn, user_data, sim};
  const std::string name = stage == QUARRY_HOOK_POST_FORCE ? "post_force (C ABI)" : "end_of_step (C ABI)";
  std::erase_if(world_.hooks, [&](const StepHook& h) { return h.name == name; });
  if (!fn) return;
  StepHook hook;
  hook.stage = stage == QUARRY_HOOK_POST_FORCE ? HookStage::post_force : HookStage::end_of_step;
  hook.name = name;
  hook.run = [this, stage](World&) {
    const Hook& h = hooks_[stage - 1];
    in_hook_ = stage;
    const int result = h.fn(h.sim, stage, h.user_data);
    in_hook_ = 0;
    if (result != 0)
      throw ApiError(QUARRY_ERROR_HOOK, fmt::format("the {} hook returned {} at step {} (t = {:.6g} s); the step stopped there",
                                                    stage == QUARRY_HOOK_POST_FORCE ? "POST_FORCE" : "END_OF_STEP",
                                                    result, world_.step_count, world_.time));
  };
  world_.hooks.push_back(std::move(hook));
}

void LocalBackend::add_hook_forces(const double* force, const double* torque, std::uint64_t count) {
  if (in_hook_ != QUARRY_HOOK_POST_FORCE)
    fail(QUARRY_ERROR_WRONG_STATE, "quarry_add_hook_forces: only inside a POST_FORCE hook");
  ParticleStore& p = world_.particles;
  if (count != p.size())
    fail(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_add_hook_forces: {} entries for {} particles", count, p.size()));
  for (std::uint64_t k = 0; k < count; ++k)
    if ((force && !finite3(force + 3 * k)) || (torque && !finite3(torque + 3 * k)))
      fail(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_add_hook_forces: entry {} is not finite", k));
  const sim::TypeOrder& o = order();
  for (std::uint64_t k = 0; k < count; ++k) {
    if (force) p.force[o.order[k]] += vec(force, k);
    if (torque) p.torque[o.order[k]] += vec(torque, k);
  }
}

}  // namespace quarry::api
