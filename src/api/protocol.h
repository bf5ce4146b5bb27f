// The fields of the C ABI's structs as `quarry serve`'s messages carry them (api/wire.h), one
// list per struct that both sides use: the client writes with a wire::Writer, the server reads
// with a wire::Reader, so the two cannot drift apart. Fields in declaration order; a minor ABI
// version may append fields at a list's end (an older peer then reads the ones it knows).
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>

#include "api/wire.h"
#include "quarry/quarry.h"

namespace quarry::api::protocol {

// S is T or const T (one list serves writing and reading).
template <class S, class T>
concept Of = std::same_as<std::remove_const_t<S>, T>;

// The fields a peer of ABI `abi_version` knows: 1.0's, then those later minors appended. A
// client writes what the server's version knows (RemoteBackend::set_settings), the server reads
// what the request's header says its client wrote; fields not sent keep the reader's defaults.
template <class A, Of<quarry_settings> S>
void fields(A& a, S& s, std::uint32_t abi_version) {
  a(s.time_step, s.rayleigh_fraction, s.gravity, s.domain_min, s.domain_max, s.end_time,
    s.impact_speed, s.skin, s.integrator, s.sort_interval, s.max_overlap_fraction, s.seed);
  const std::uint32_t minor =
      (abi_version >> 16) == QUARRY_ABI_MAJOR ? (abi_version & 0xffffu) : 0u;
  if (minor >= 1) a(s.periodic);
}
// Between peers of this build's version.
template <class A, Of<quarry_settings> S>
void fields(A& a, S& s) {
  fields(a, s, QUARRY_ABI_VERSION);
}

template <class A, Of<quarry_material> S>
void fields(A& a, S& s) {
  a(s.name, s.density, s.youngs_modulus, s.poisson_ratio);
}

template <class A, Of<quarry_interaction> S>
void fields(A& a, S& s) {
  a(s.material_a, s.material_b, s.restitution, s.static_friction, s.rolling_friction,
    s.rolling_model, s.cohesion_energy_density);
}

template <class A, Of<quarry_particle_type> S>
void fields(A& a, S& s) {
  a(s.name, s.material, s.radius, s.max_radius);
}

template <class A, Of<quarry_advance_result> S>
void fields(A& a, S& s) {
  a(s.steps, s.time);
}

template <class A, Of<quarry_surface_info> S>
void fields(A& a, S& s) {
  a(s.node_count, s.element_count, s.triangle_count, s.driver);
}

// A view's description; its values follow it (dense: count × components elements).
template <class A, Of<quarry_view> S>
void fields(A& a, S& s) {
  a(s.count, s.dtype, s.components, s.epoch);
}

// quarry_open's request: the caller's open info (minus the endpoint), who the client is, and
// the name of its shared-memory segment (absent over tcp).
struct OpenRequest {
  std::uint32_t caller_abi_version = QUARRY_ABI_VERSION;
  const char* deck_path = nullptr;
  const char* checkpoint_path = nullptr;
  const char* output_directory = nullptr;
  std::int32_t threads = 0;
  std::int64_t client_pid = 0;
  const char* segment = nullptr;
};
template <class A, Of<OpenRequest> S>
void fields(A& a, S& s) {
  a(s.caller_abi_version, s.deck_path, s.checkpoint_path, s.output_directory, s.threads,
    s.client_pid, s.segment);
}

// Its reply: the session the client's later requests name, whether the server mapped the
// segment (else arrays travel in the messages), and the server's version text; then, since the
// shared views, a u32 after these fields: the last wire::Op the server knows (a client asks no
// later one of it, and none of view_particles_shared and after where it is absent).
struct OpenReply {
  std::uint64_t session = 0;
  std::uint8_t shared_memory = 0;
  const char* server_version = nullptr;
};
template <class A, Of<OpenReply> S>
void fields(A& a, S& s) {
  a(s.session, s.shared_memory, s.server_version);
}

// A struct of type T read from a message (struct_size set to this build's size).
template <class T>
T read(wire::Reader& in) {
  T value{};
  if constexpr (requires { value.struct_size; }) value.struct_size = sizeof(T);
  fields(in, value);
  return value;
}

// A value of any kind the messages carry: a number, a text, or a struct with a field list.
template <class T>
T read_value(wire::Reader& in) {
  if constexpr (std::is_arithmetic_v<T>)
    return in.get<T>();
  else if constexpr (std::is_same_v<T, std::string>)
    return in.text();
  else
    return read<T>(in);
}
template <class... T>
void write_values(wire::Writer& out, const T&... values) {
  [[maybe_unused]] const auto one = [&out](const auto& value) {
    if constexpr (requires { fields(out, value); })
      fields(out, value);
    else
      out(value);
  };
  (one(values), ...);
}

// Bytes of one value of a QUARRY_DTYPE_* (0 for an unknown one).
inline std::size_t dtype_bytes(std::uint32_t dtype) {
  switch (dtype) {
    case QUARRY_DTYPE_FLOAT64:
    case QUARRY_DTYPE_UINT64:
      return 8;
    case QUARRY_DTYPE_UINT32:
      return 4;
    case QUARRY_DTYPE_UINT16:
      return 2;
    default:
      return 0;
  }
}

}  // namespace quarry::api::protocol
