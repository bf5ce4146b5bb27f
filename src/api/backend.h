// Backend: what one open simulation handle does, call by call — the C ABI (include/quarry/
// quarry.h) one to one, minus the handle. Two implementations: LocalBackend runs the simulation
// in this process; RemoteBackend forwards each call to a `quarry serve` process, where a
// LocalBackend answers it. The C functions (api.cpp) check the arguments every backend needs
// (null pointers, struct sizes) and turn exceptions into status codes and the last-error text;
// a backend returns a status or throws ApiError.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "quarry/quarry.h"

namespace quarry::api {

// quarry_version_string's text (also what `quarry serve` tells its clients).
inline constexpr const char* kLibraryVersion = "0.2.0";

// An error to report through the ABI: its status code and its text.
class ApiError : public std::runtime_error {
 public:
  ApiError(quarry_status status, const std::string& message) : std::runtime_error(message), status_(status) {}
  quarry_status status() const { return status_; }

 private:
  quarry_status status_;
};

// What a failed call reports: its status code and its text.
struct Failure {
  quarry_status status = QUARRY_ERROR_INTERNAL;
  std::string text;
};
// The failure of the exception being handled (call it inside a catch block): an ApiError's own
// status, UserError → INPUT with the deck's diagnostics, PhysicsError → PHYSICS, a malformed
// reply from a server → TRANSPORT, a filesystem error → IO, anything else → INTERNAL; each text begins with `call` ("quarry_step: ...") unless
// an ApiError's names its call already. Used by the C functions and by `quarry serve` alike.
Failure current_failure(const char* call);

class Backend {
 public:
  virtual ~Backend() = default;
  virtual bool remote() const = 0;

  virtual void close() = 0;
  virtual void set_settings(const quarry_settings& settings) = 0;
  virtual std::uint32_t add_material(const quarry_material& material) = 0;
  virtual void add_interaction(const quarry_interaction& interaction) = 0;
  virtual std::uint32_t add_particle_type(const quarry_particle_type& type) = 0;
  virtual void start() = 0;

  virtual void get_time(double* time, double* time_step, std::uint64_t* steps) = 0;
  virtual quarry_advance_result advance(double duration) = 0;
  virtual void step(std::uint64_t steps) = 0;

  virtual void save_checkpoint(const std::string& path) = 0;
  virtual std::string save_state() = 0;
  virtual void restore_state(const void* bytes, std::uint64_t size) = 0;

  virtual std::uint32_t num_types() = 0;
  virtual std::string type_name(std::uint32_t type) = 0;
  virtual std::uint64_t num_particles(std::int32_t type) = 0;
  virtual std::uint64_t epoch() = 0;
  virtual void get_particles(quarry_particle_data& data) = 0;
  virtual std::uint64_t particle_index(std::uint64_t id) = 0;
  virtual quarry_view view_particles(std::int32_t field) = 0;
  virtual quarry_view view_next_step_loads(std::int32_t field) = 0;
  virtual void add_particles(const quarry_new_particles& particles) = 0;
  virtual void remove_particles(const std::uint64_t* ids, std::uint64_t count) = 0;

  virtual void set_external_loads(const double* force, const double* torque, std::uint64_t count,
                                  std::int32_t mode, std::int32_t hold) = 0;
  virtual void set_external_loads_by_id(const std::uint64_t* ids, std::uint64_t count, const double* force,
                                        const double* torque, std::int32_t mode, std::int32_t hold) = 0;
  virtual void clear_external_loads() = 0;

  virtual std::uint32_t register_property(const std::string& name, std::uint32_t components,
                                          const std::string& unit, double initial) = 0;
  virtual std::uint32_t num_properties() = 0;
  virtual void property_info(std::uint32_t index, std::string& name, std::uint32_t& components,
                             std::string& unit) = 0;
  virtual void get_property(std::uint32_t index, double* values, std::uint64_t count) = 0;
  virtual void set_property(std::uint32_t index, const double* values, std::uint64_t count) = 0;
  virtual quarry_view view_property(std::uint32_t index) = 0;

  virtual void sample_points(std::uint32_t type, std::uint32_t points, std::uint64_t seed, double* unit_points) = 0;
  // Returns the particles of the type; writes positions if capacity suffices (else BAD_LENGTH).
  virtual std::uint64_t sample_point_positions(std::uint32_t type, std::uint32_t points, std::uint64_t seed,
                                               double* positions, std::uint64_t capacity) = 0;

  virtual std::uint32_t add_surface(const quarry_surface_desc& surface) = 0;
  virtual std::uint32_t num_surfaces() = 0;
  virtual std::uint32_t find_surface(const std::string& name) = 0;
  virtual quarry_surface_info surface_info(std::uint32_t surface) = 0;
  virtual void set_surface_driver(std::uint32_t surface, std::int32_t driver) = 0;
  virtual void set_surface_nodes(std::uint32_t surface, const double* positions, const double* velocities,
                                 std::uint64_t count) = 0;
  virtual void get_surface_nodes(std::uint32_t surface, double* positions, double* velocities,
                                 std::uint64_t count) = 0;
  virtual void get_surface_loads(std::uint32_t surface, quarry_surface_loads& loads) = 0;

  // In-process only (RemoteBackend throws UNSUPPORTED). `sim` is the handle to give the hook.
  virtual void set_hook(quarry_sim sim, std::int32_t stage, quarry_hook_fn fn, void* user_data) = 0;
  virtual void add_hook_forces(const double* force, const double* torque, std::uint64_t count) = 0;
};

}  // namespace quarry::api
