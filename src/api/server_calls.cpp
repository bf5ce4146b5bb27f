// The server's side of each operation (api/server.h, CallHandler): the fields read in the order
// the client writes them (api/remote.cpp), every array's length checked against the counts the
// call implies before the backend sees a pointer (the backend trusts its pointers, as the C
// functions check them in process), and the results written back.
#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <tuple>
#include <type_traits>

#include "api/protocol.h"
#include "api/server.h"
#include "api/struct_versions.h"

namespace quarry::api {

namespace {

using wire::Reader;
using wire::WireError;
using wire::Writer;

// count × factor, refused when it would wrap.
std::uint64_t times(std::uint64_t count, std::uint64_t factor, const char* what) {
  if (factor != 0 && count > std::numeric_limits<std::uint64_t>::max() / factor)
    throw WireError(fmt::format("{} = {} is too large", what, count));
  return count * factor;
}

// An array that was given must hold exactly the values the call needs.
void check_length(const void* data, std::uint64_t got, std::uint64_t wanted, const char* what) {
  if (data && got != wanted)
    throw WireError(fmt::format("{} holds {} values, the call needs {}", what, got, wanted));
}

void require(const void* data, const char* what) {
  if (!data) throw WireError(fmt::format("{} is missing", what));
}

// Reads the fields named, and checks that nothing follows them.
template <class... T>
void read_all(Reader& in, T&... values) {
  in(values...);
  in.expect_end();
}

// The handler of a call whose arguments and result are plain values (numbers, texts, structs
// with a field list): the request's fields are the method's parameters in order, the reply
// holds its result. The client's side is RemoteBackend::ask.
template <class Method>
struct Signature;
template <class R, class... A>
struct Signature<R (Backend::*)(A...)> {
  using Result = R;
  using Arguments = std::tuple<std::remove_cvref_t<A>...>;
};

template <auto method>
void plain(Backend& b, Reader& in, Writer& out) {
  using Call = Signature<decltype(method)>;
  typename Call::Arguments arguments;
  std::apply(
      [&in](auto&... a) {
        ((a = protocol::read_value<std::remove_cvref_t<decltype(a)>>(in)), ...);
      },
      arguments);
  in.expect_end();
  const auto call = [&b](auto&... a) { return (b.*method)(a...); };
  if constexpr (std::is_void_v<typename Call::Result>)
    std::apply(call, arguments);
  else
    protocol::write_values(out, std::apply(call, arguments));
}

// A view's description and its values, packed (count × components values, no stride).
void write_view(Writer& out, const quarry_view& view) {
  protocol::fields(out, view);
  out.align();
  copy_view(view, out.extend(view_bytes(view)));
}

// ---- building ----

// The settings as far as the client's ABI minor has them (its request header's version): a 1.0
// client sends no periodic axes, which keep their default (none).
void set_settings(Backend& b, Reader& in, Writer&) {
  quarry_settings settings = default_settings();
  protocol::fields(in, settings, in.abi_version());
  in.expect_end();
  b.set_settings(settings);
}

// ---- time and checkpoints ----

void get_time(Backend& b, Reader& in, Writer& out) {
  in.expect_end();
  double time = 0.0, time_step = 0.0;
  std::uint64_t steps = 0;
  b.get_time(&time, &time_step, &steps);
  out(time, time_step, steps);
}

void save_state(Backend& b, Reader& in, Writer& out) {
  in.expect_end();
  const std::string bytes = b.save_state();
  out.put(static_cast<std::uint64_t>(bytes.size()));
  out.align();
  out.raw(bytes.data(), bytes.size());
}

void restore_state(Backend& b, Reader& in, Writer&) {
  std::uint64_t size = 0;
  const std::byte* bytes = in.input<std::byte>(size);
  in.expect_end();
  require(bytes, "the state");
  b.restore_state(bytes, size);
}

// ---- particles ----

void get_particles(Backend& b, Reader& in, Writer& out) {
  quarry_particle_data d{};
  d.struct_size = sizeof d;
  d.capacity = in.get<std::uint64_t>();
  std::uint64_t n[10];
  d.id = in.output<std::uint64_t>(n[0]);
  d.type = in.output<std::uint32_t>(n[1]);
  d.position = in.output<double>(n[2]);
  d.velocity = in.output<double>(n[3]);
  d.angular_velocity = in.output<double>(n[4]);
  d.radius = in.output<double>(n[5]);
  d.mass = in.output<double>(n[6]);
  d.volume = in.output<double>(n[7]);
  d.force = in.output<double>(n[8]);
  d.torque = in.output<double>(n[9]);
  in.expect_end();
  const void* arrays[10] = {d.id,     d.type, d.position, d.velocity, d.angular_velocity,
                            d.radius, d.mass, d.volume,   d.force,    d.torque};
  const int components[10] = {1, 1, 3, 3, 3, 1, 1, 1, 3, 3};
  for (int k = 0; k < 10; ++k)
    if (arrays[k])
      check_length(arrays[k], n[k], times(d.capacity, components[k], "capacity"), "an array");
  try {
    b.get_particles(d);
  } catch (...) {
    out(d.count, d.epoch);  // BAD_LENGTH: the count needed goes back with the error
    throw;
  }
  out(d.count, d.epoch);
  for (int k = 0; k < 10; ++k) in.set_used(k, d.count * components[k]);
}

void view_particles(Backend& b, Reader& in, Writer& out) {
  std::int32_t field = 0;
  read_all(in, field);
  write_view(out, b.view_particles(field));
}

void view_next_step_loads(Backend& b, Reader& in, Writer& out) {
  std::int32_t field = 0;
  read_all(in, field);
  write_view(out, b.view_next_step_loads(field));
}

// The client's copy of the next step's loads (engine order, 3 × count doubles each, either may
// be absent) written into the engine's (as the caller's writes through an in-process view).
void put_next_step_loads(Backend& b, Reader& in, Writer&) {
  std::uint64_t n_force = 0, n_torque = 0, count = 0;
  const double* force = in.input<double>(n_force);
  const double* torque = in.input<double>(n_torque);
  read_all(in, count);
  check_length(force, n_force, times(count, 3, "count"), "force");
  check_length(torque, n_torque, times(count, 3, "count"), "torque");
  if (force) write_next_step_loads(b, QUARRY_FIELD_FORCE, force, count);
  if (torque) write_next_step_loads(b, QUARRY_FIELD_TORQUE, torque, count);
}

void add_particles(Backend& b, Reader& in, Writer&) {
  quarry_new_particles q{};
  q.struct_size = sizeof q;
  std::uint64_t n_types = 0, n_position = 0, n_velocity = 0, n_spin = 0, n_radius = 0, n_ids = 0;
  q.count = in.get<std::uint64_t>();
  q.types = in.input<std::uint32_t>(n_types);
  q.type = in.get<std::uint32_t>();
  q.position = in.input<double>(n_position);
  q.velocity = in.input<double>(n_velocity);
  q.angular_velocity = in.input<double>(n_spin);
  q.radius = in.input<double>(n_radius);
  q.ids = in.output<std::uint64_t>(n_ids);
  in.expect_end();
  const std::uint64_t vectors = times(q.count, 3, "count");
  check_length(q.types, n_types, q.count, "types");
  check_length(q.position, n_position, vectors, "position");
  check_length(q.velocity, n_velocity, vectors, "velocity");
  check_length(q.angular_velocity, n_spin, vectors, "angular_velocity");
  check_length(q.radius, n_radius, q.count, "radius");
  check_length(q.ids, n_ids, q.count, "ids");
  b.add_particles(q);
}

void remove_particles(Backend& b, Reader& in, Writer&) {
  std::uint64_t count = 0;
  const std::uint64_t* ids = in.input<std::uint64_t>(count);
  in.expect_end();
  b.remove_particles(ids, count);
}

// ---- external loads ----

void set_external_loads(Backend& b, Reader& in, Writer&) {
  std::uint64_t n_force = 0, n_torque = 0, count = 0;
  std::int32_t mode = 0, hold = 0;
  const double* force = in.input<double>(n_force);
  const double* torque = in.input<double>(n_torque);
  read_all(in, count, mode, hold);
  check_length(force, n_force, times(count, 3, "count"), "force");
  check_length(torque, n_torque, times(count, 3, "count"), "torque");
  b.set_external_loads(force, torque, count, mode, hold);
}

void set_external_loads_by_id(Backend& b, Reader& in, Writer&) {
  std::uint64_t count = 0, n_force = 0, n_torque = 0;
  std::int32_t mode = 0, hold = 0;
  const std::uint64_t* ids = in.input<std::uint64_t>(count);
  const double* force = in.input<double>(n_force);
  const double* torque = in.input<double>(n_torque);
  read_all(in, mode, hold);
  check_length(force, n_force, times(count, 3, "count"), "force");
  check_length(torque, n_torque, times(count, 3, "count"), "torque");
  b.set_external_loads_by_id(ids, count, force, torque, mode, hold);
}

// ---- custom properties ----

void property_info(Backend& b, Reader& in, Writer& out) {
  std::uint32_t index = 0, components = 0;
  read_all(in, index);
  std::string name, unit;
  b.property_info(index, name, components, unit);
  out(name, components, unit);
}

void get_property(Backend& b, Reader& in, Writer&) {
  const auto index = in.get<std::uint32_t>();
  std::uint64_t count = 0;
  double* values = in.output<double>(count);
  in.expect_end();
  b.get_property(index, values, count);
}

void set_property(Backend& b, Reader& in, Writer&) {
  const auto index = in.get<std::uint32_t>();
  std::uint64_t count = 0;
  const double* values = in.input<double>(count);
  in.expect_end();
  b.set_property(index, values, count);
}

void view_property(Backend& b, Reader& in, Writer& out) {
  std::uint32_t index = 0;
  read_all(in, index);
  write_view(out, b.view_property(index));
}

// ---- sample points ----

void sample_points(Backend& b, Reader& in, Writer&) {
  std::uint32_t type = 0, points = 0;
  std::uint64_t seed = 0, count = 0;
  in(type, points, seed);
  double* unit_points = in.output<double>(count);
  in.expect_end();
  require(unit_points, "unit_points");
  check_length(unit_points, count, times(points, 3, "points"), "unit_points");
  b.sample_points(type, points, seed, unit_points);
}

void sample_point_positions(Backend& b, Reader& in, Writer& out) {
  std::uint32_t type = 0, points = 0;
  std::uint64_t seed = 0, capacity = 0;
  in(type, points, seed);
  double* positions = in.output<double>(capacity);
  in.expect_end();
  const std::uint64_t particles = b.sample_point_positions(type, points, seed, positions, capacity);
  out.put(particles);
  in.set_used(0, std::min(capacity, 3 * particles * points));
}

// ---- surfaces ----

void add_surface(Backend& b, Reader& in, Writer& out) {
  quarry_surface_desc d{};
  d.struct_size = sizeof d;
  std::uint64_t n_nodes = 0, n_triangles = 0, n_quads = 0;
  in(d.name, d.material, d.node_count);
  d.nodes = in.input<double>(n_nodes);
  d.triangle_count = in.get<std::uint64_t>();
  d.triangles = in.input<std::uint32_t>(n_triangles);
  d.quad_count = in.get<std::uint64_t>();
  d.quads = in.input<std::uint32_t>(n_quads);
  read_all(in, d.driver);
  check_length(d.nodes, n_nodes, times(d.node_count, 3, "node_count"), "nodes");
  check_length(d.triangles, n_triangles, times(d.triangle_count, 3, "triangle_count"), "triangles");
  check_length(d.quads, n_quads, times(d.quad_count, 4, "quad_count"), "quads");
  out.put(b.add_surface(d));
}

void set_surface_nodes(Backend& b, Reader& in, Writer&) {
  const auto surface = in.get<std::uint32_t>();
  std::uint64_t n_positions = 0, n_velocities = 0, count = 0;
  const double* positions = in.input<double>(n_positions);
  const double* velocities = in.input<double>(n_velocities);
  read_all(in, count);
  require(positions, "positions");
  check_length(positions, n_positions, times(count, 3, "count"), "positions");
  check_length(velocities, n_velocities, times(count, 3, "count"), "velocities");
  b.set_surface_nodes(surface, positions, velocities, count);
}

void get_surface_nodes(Backend& b, Reader& in, Writer&) {
  const auto surface = in.get<std::uint32_t>();
  std::uint64_t n_positions = 0, n_velocities = 0, count = 0;
  double* positions = in.output<double>(n_positions);
  double* velocities = in.output<double>(n_velocities);
  read_all(in, count);
  check_length(positions, n_positions, times(count, 3, "count"), "positions");
  check_length(velocities, n_velocities, times(count, 3, "count"), "velocities");
  b.get_surface_nodes(surface, positions, velocities, count);
}

void get_surface_loads(Backend& b, Reader& in, Writer& out) {
  quarry_surface_loads loads{};
  loads.struct_size = sizeof loads;
  std::uint32_t surface = 0;
  std::uint64_t n[4];
  in(surface, loads.node_count, loads.element_count);
  loads.nodal_force = in.output<double>(n[0]);
  loads.pressure = in.output<double>(n[1]);
  loads.shear_stress = in.output<double>(n[2]);
  loads.element_force = in.output<double>(n[3]);
  in.expect_end();
  const std::uint64_t elements = loads.element_count;
  check_length(loads.nodal_force, n[0], times(loads.node_count, 3, "node_count"), "nodal_force");
  check_length(loads.pressure, n[1], elements, "pressure");
  check_length(loads.shear_stress, n[2], times(elements, 3, "element_count"), "shear_stress");
  check_length(loads.element_force, n[3], times(elements, 3, "element_count"), "element_force");
  b.get_surface_loads(surface, loads);
  out(loads.window, loads.time);
}

}  // namespace

std::uint64_t view_bytes(const quarry_view& view) {
  return view.count * protocol::dtype_bytes(view.dtype) * view.components;
}

void copy_view(const quarry_view& view, std::byte* to) {
  const std::size_t row = protocol::dtype_bytes(view.dtype) * view.components;  // bytes a particle
  const auto* from = static_cast<const std::byte*>(view.data);
  if (static_cast<std::size_t>(view.stride) == row) {
    if (view.count > 0) std::memcpy(to, from, view.count * row);
    return;
  }
  for (std::uint64_t k = 0; k < view.count; ++k)
    std::memcpy(to + k * row, from + k * view.stride, row);
}

void write_next_step_loads(Backend& backend, std::int32_t field, const void* values, std::uint64_t count) {
  const quarry_view view = backend.view_next_step_loads(field);  // refuses other fields
  if (view.count != count)
    throw ApiError(QUARRY_ERROR_WRONG_STATE,
                   fmt::format("quarry_view_next_step_loads: the loads sent back are of {} particles, "
                               "the simulation has {}",
                               count, view.count));
  if (count > 0) std::memcpy(view.data, values, view_bytes(view));
}

CallHandler call_handler(wire::Op op) {
  using wire::Op;
  switch (op) {
    case Op::open:
    case Op::close:
      return nullptr;  // the session's own (Server)
    case Op::set_settings:
      return set_settings;
    case Op::add_material:
      return plain<&Backend::add_material>;
    case Op::add_interaction:
      return plain<&Backend::add_interaction>;
    case Op::add_particle_type:
      return plain<&Backend::add_particle_type>;
    case Op::start:
      return plain<&Backend::start>;
    case Op::get_time:
      return get_time;
    case Op::advance:
      return plain<&Backend::advance>;
    case Op::step:
      return plain<&Backend::step>;
    case Op::save_checkpoint:
      return plain<&Backend::save_checkpoint>;
    case Op::save_state:
      return save_state;
    case Op::restore_state:
      return restore_state;
    case Op::num_types:
      return plain<&Backend::num_types>;
    case Op::type_name:
      return plain<&Backend::type_name>;
    case Op::num_particles:
      return plain<&Backend::num_particles>;
    case Op::epoch:
      return plain<&Backend::epoch>;
    case Op::get_particles:
      return get_particles;
    case Op::particle_index:
      return plain<&Backend::particle_index>;
    case Op::view_particles:
      return view_particles;
    case Op::add_particles:
      return add_particles;
    case Op::remove_particles:
      return remove_particles;
    case Op::set_external_loads:
      return set_external_loads;
    case Op::set_external_loads_by_id:
      return set_external_loads_by_id;
    case Op::clear_external_loads:
      return plain<&Backend::clear_external_loads>;
    case Op::register_property:
      return plain<&Backend::register_property>;
    case Op::num_properties:
      return plain<&Backend::num_properties>;
    case Op::property_info:
      return property_info;
    case Op::get_property:
      return get_property;
    case Op::set_property:
      return set_property;
    case Op::view_property:
      return view_property;
    case Op::sample_points:
      return sample_points;
    case Op::sample_point_positions:
      return sample_point_positions;
    case Op::add_surface:
      return add_surface;
    case Op::num_surfaces:
      return plain<&Backend::num_surfaces>;
    case Op::find_surface:
      return plain<&Backend::find_surface>;
    case Op::surface_info:
      return plain<&Backend::surface_info>;
    case Op::set_surface_driver:
      return plain<&Backend::set_surface_driver>;
    case Op::set_surface_nodes:
      return set_surface_nodes;
    case Op::get_surface_nodes:
      return get_surface_nodes;
    case Op::get_surface_loads:
      return get_surface_loads;
    case Op::view_next_step_loads:
      return view_next_step_loads;
    case Op::put_next_step_loads:
      return put_next_step_loads;
    case Op::view_particles_shared:
    case Op::view_property_shared:
    case Op::view_next_step_loads_shared:
    case Op::put_next_step_loads_shared:
    case Op::attach_channel:
      return nullptr;  // the session's own (Server: the client's segments for them)
  }
  return nullptr;
}

}  // namespace quarry::api
