// The C ABI (include/quarry/quarry.h): handles as {slot, generation} values checked against a
// registry (a closed or forged handle is refused, never dereferenced), one recursive mutex per
// handle (calls from any thread are serialised; a step hook may call back into its handle), the
// checks every backend needs (NULL pointers, struct sizes), and every exception turned into a
// status code and the handle's last-error text: nothing escapes the boundary.
#include <fmt/format.h>

#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "api/backend.h"
#include "api/local_backend.h"
#include "api/remote.h"
#include "api/struct_versions.h"

namespace quarry::api {
namespace {

struct Slot {
  std::uint32_t generation = 1;
  std::unique_ptr<Backend> backend;
  std::recursive_mutex mutex;  // held by each call on the handle
  std::mutex error_mutex;      // guards last_error (read from any thread)
  std::string last_error;
};

class Registry {
 public:
  quarry_sim add(std::unique_ptr<Backend> backend) {
    std::lock_guard lock(mutex_);
    std::size_t index;
    if (!free_.empty()) {
      index = free_.back();
      free_.pop_back();
    } else {
      index = slots_.size();
      slots_.push_back(std::make_unique<Slot>());
    }
    Slot& slot = *slots_[index];
    std::lock_guard slot_lock(slot.mutex);
    slot.backend = std::move(backend);
    return quarry_sim{(static_cast<std::uint64_t>(slot.generation) << 32) | (index + 1)};
  }
  // The slot a handle names if it is open (the slot itself lives for the process).
  Slot* find(quarry_sim sim) {
    std::lock_guard lock(mutex_);
    const std::uint64_t index = (sim.id & 0xffffffffu);
    if (index == 0 || index > slots_.size()) return nullptr;
    Slot* slot = slots_[index - 1].get();
    return generation_of(sim) == slot->generation ? slot : nullptr;
  }
  void release(quarry_sim sim, Slot& slot) {
    std::lock_guard lock(mutex_);
    slot.generation += 1;  // every copy of the handle is now stale
    free_.push_back((sim.id & 0xffffffffu) - 1);
  }
  static std::uint32_t generation_of(quarry_sim sim) { return static_cast<std::uint32_t>(sim.id >> 32); }

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<Slot>> slots_;
  std::vector<std::size_t> free_;
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: handles may be closed during exit
  return *r;
}

thread_local std::string t_last_error;  // errors of calls without a valid handle

quarry_status thread_error(quarry_status status, const std::string& text) {
  t_last_error = text;
  return status;
}

void set_error(Slot& slot, const std::string& text) {
  std::lock_guard lock(slot.error_mutex);
  slot.last_error = text;
}

// Runs f(backend) on the handle's backend: the status of its outcome, and the error text.
template <class F>
quarry_status call(quarry_sim sim, const char* name, F&& f) {
  Slot* slot = registry().find(sim);
  if (!slot)
    return thread_error(QUARRY_ERROR_INVALID_HANDLE,
                        fmt::format("{}: handle {:#x} is not an open simulation (never opened, or closed)", name, sim.id));
  std::lock_guard lock(slot->mutex);
  if (Registry::generation_of(sim) != slot->generation || !slot->backend)
    return thread_error(QUARRY_ERROR_INVALID_HANDLE, fmt::format("{}: handle {:#x} was closed", name, sim.id));
  try {
    f(*slot->backend);
    set_error(*slot, "");
    return QUARRY_OK;
  } catch (...) {
    const Failure failure = current_failure(name);
    set_error(*slot, failure.text);
    return failure.status;
  }
}

// A required pointer argument.
#define QUARRY_REQUIRE(pointer)                                                                       \
  do {                                                                                                \
    if (!(pointer)) throw ApiError(QUARRY_ERROR_NULL_POINTER, #pointer " is NULL");                      \
  } while (0)

// A struct whose struct_size covers at least the fields the struct had when it was first
// published (ABI 1.0): a caller built against an older quarry.h is served. A struct that has
// grown since is read through its own reader, bounded by the caller's size (struct_versions.h).
template <class T>
void require_struct(const T* s, const char* function, const char* what) {
  if (!s) throw ApiError(QUARRY_ERROR_NULL_POINTER, fmt::format("{}: {} is NULL", function, what));
  if (s->struct_size < kFirstPublishedSize<T>)
    throw ApiError(QUARRY_ERROR_BAD_VALUE,
                   fmt::format("{}: {}->struct_size is {}, less than any version of the struct ({} bytes in ABI 1.0, "
                               "{} in this library's {}.{}); set struct_size = sizeof the struct",
                               function, what, s->struct_size, kFirstPublishedSize<T>, sizeof(T), QUARRY_ABI_MAJOR,
                               QUARRY_ABI_MINOR));
}

// Copies `text` into a caller's buffer of `size` bytes, NUL-terminated and truncated.
void copy_text(const std::string& text, char* buffer, std::size_t size) {
  if (!buffer || size == 0) return;
  const std::size_t n = std::min(text.size(), size - 1);
  std::memcpy(buffer, text.data(), n);
  buffer[n] = '\0';
}

// An output struct: the fields the caller's struct_size holds.
template <class T>
void copy_out(const T& value, T* out) {
  const std::uint32_t size = out->struct_size;
  std::memcpy(reinterpret_cast<char*>(out) + sizeof(std::uint32_t), reinterpret_cast<const char*>(&value) + sizeof(std::uint32_t),
              std::min<std::size_t>(size, sizeof(T)) - sizeof(std::uint32_t));
}

}  // namespace
}  // namespace quarry::api

using namespace quarry;
using namespace quarry::api;

extern "C" {

QUARRY_API uint32_t quarry_abi_version(void) { return QUARRY_ABI_VERSION; }

QUARRY_API const char* quarry_version_string(void) { return kLibraryVersion; }

QUARRY_API const char* quarry_status_name(quarry_status status) {
  switch (status) {
    case QUARRY_OK: return "QUARRY_OK";
    case QUARRY_ERROR_INVALID_HANDLE: return "QUARRY_ERROR_INVALID_HANDLE";
    case QUARRY_ERROR_NULL_POINTER: return "QUARRY_ERROR_NULL_POINTER";
    case QUARRY_ERROR_BAD_LENGTH: return "QUARRY_ERROR_BAD_LENGTH";
    case QUARRY_ERROR_BAD_VALUE: return "QUARRY_ERROR_BAD_VALUE";
    case QUARRY_ERROR_WRONG_STATE: return "QUARRY_ERROR_WRONG_STATE";
    case QUARRY_ERROR_NOT_FOUND: return "QUARRY_ERROR_NOT_FOUND";
    case QUARRY_ERROR_INPUT: return "QUARRY_ERROR_INPUT";
    case QUARRY_ERROR_PHYSICS: return "QUARRY_ERROR_PHYSICS";
    case QUARRY_ERROR_IO: return "QUARRY_ERROR_IO";
    case QUARRY_ERROR_VERSION: return "QUARRY_ERROR_VERSION";
    case QUARRY_ERROR_TRANSPORT: return "QUARRY_ERROR_TRANSPORT";
    case QUARRY_ERROR_TIMEOUT: return "QUARRY_ERROR_TIMEOUT";
    case QUARRY_ERROR_UNSUPPORTED: return "QUARRY_ERROR_UNSUPPORTED";
    case QUARRY_ERROR_HOOK: return "QUARRY_ERROR_HOOK";
    case QUARRY_ERROR_INTERNAL: return "QUARRY_ERROR_INTERNAL";
    default: return "QUARRY_ERROR_UNKNOWN";
  }
}

QUARRY_API quarry_status quarry_last_error(quarry_sim sim, char* buffer, size_t size, size_t* length) {
  std::string text;
  if (sim.id == 0) {
    text = t_last_error;
  } else {
    Slot* slot = registry().find(sim);
    if (!slot) return thread_error(QUARRY_ERROR_INVALID_HANDLE, fmt::format("quarry_last_error: handle {:#x} is not open", sim.id));
    std::lock_guard lock(slot->error_mutex);
    text = slot->last_error;
  }
  copy_text(text, buffer, size);
  if (length) *length = text.size();
  return QUARRY_OK;
}

QUARRY_API quarry_status quarry_open(const quarry_open_info* info, quarry_sim* sim) {
  try {
    require_struct(info, "quarry_open", "info");
    QUARRY_REQUIRE(sim);
    *sim = QUARRY_NO_SIM;
    if ((info->abi_version >> 16) != QUARRY_ABI_MAJOR)
      return thread_error(QUARRY_ERROR_VERSION,
                          fmt::format("quarry_open: the caller was built for ABI {}.{}, this library is {}.{}; "
                                      "rebuild the caller against this quarry.h",
                                      info->abi_version >> 16, info->abi_version & 0xffff, QUARRY_ABI_MAJOR, QUARRY_ABI_MINOR));
    if (info->threads < 0) throw ApiError(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_open: threads = {} (≥ 0)", info->threads));
    if (info->timeout_ms < 0) throw ApiError(QUARRY_ERROR_BAD_VALUE, fmt::format("quarry_open: timeout_ms = {} (≥ 0)", info->timeout_ms));
    std::unique_ptr<Backend> backend;
    if (info->endpoint) backend = open_remote(*info);
    else backend = std::make_unique<LocalBackend>(*info);
    *sim = registry().add(std::move(backend));
    t_last_error.clear();
    return QUARRY_OK;
  } catch (...) {
    const Failure failure = current_failure("quarry_open");
    return thread_error(failure.status, failure.text);
  }
}

QUARRY_API quarry_status quarry_close(quarry_sim sim) {
  Slot* slot = registry().find(sim);
  if (!slot) return thread_error(QUARRY_ERROR_INVALID_HANDLE, fmt::format("quarry_close: handle {:#x} is not open", sim.id));
  std::unique_ptr<Backend> backend;
  quarry_status status = QUARRY_OK;
  {
    std::lock_guard lock(slot->mutex);
    if (Registry::generation_of(sim) != slot->generation || !slot->backend)
      return thread_error(QUARRY_ERROR_INVALID_HANDLE, fmt::format("quarry_close: handle {:#x} was closed", sim.id));
    status = call(sim, "quarry_close", [](Backend& b) { b.close(); });
    if (status != QUARRY_OK) {
      std::lock_guard error_lock(slot->error_mutex);
      t_last_error = slot->last_error;  // the handle is gone after this call: keep its last word
    }
    backend = std::move(slot->backend);
    registry().release(sim, *slot);
  }
  return status;  // the backend (and its simulation) is freed here, outside the lock
}

// quarry_default_settings returns its struct by value, into room the CALLER sized: a binary built
// against ABI 1.0 has 144 bytes there, and 1.1's 160 would overrun it. So the symbol has two
// versions (libquarry.map): @@QUARRY_1.1, the default that callers link to now and dlsym finds,
// and @QUARRY_1.0, 1.0's struct, which binaries linked before 1.1 (unversioned references) bind
// to. The names here are local; only the versioned quarry_default_settings is exported.
QUARRY_API quarry_settings default_settings_abi_1_1(void) { return default_settings(); }
__asm__(".symver default_settings_abi_1_1, quarry_default_settings@@QUARRY_1.1");

QUARRY_API abi_1_0::quarry_settings default_settings_abi_1_0(void) {
  const quarry_settings current = default_settings();
  abi_1_0::quarry_settings old;
  std::memcpy(&old, &current, sizeof old);  // 1.1 only appended: the same bytes up to seed
  old.struct_size = sizeof old;
  return old;
}
__asm__(".symver default_settings_abi_1_0, quarry_default_settings@QUARRY_1.0");

QUARRY_API quarry_status quarry_set_settings(quarry_sim sim, const quarry_settings* settings) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(settings, "quarry_set_settings", "settings");
    b.set_settings(read_settings(settings));  // a 1.0 caller's struct ends before periodic
  });
}

QUARRY_API quarry_status quarry_add_material(quarry_sim sim, const quarry_material* material, uint32_t* index) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(material, "quarry_add_material", "material");
    const std::uint32_t k = b.add_material(*material);
    if (index) *index = k;
  });
}

QUARRY_API quarry_status quarry_add_interaction(quarry_sim sim, const quarry_interaction* interaction) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(interaction, "quarry_add_interaction", "interaction");
    b.add_interaction(*interaction);
  });
}

QUARRY_API quarry_status quarry_add_particle_type(quarry_sim sim, const quarry_particle_type* type, uint32_t* index) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(type, "quarry_add_particle_type", "type");
    const std::uint32_t k = b.add_particle_type(*type);
    if (index) *index = k;
  });
}

QUARRY_API quarry_status quarry_start(quarry_sim sim) {
  return call(sim, __func__, [&](Backend& b) { b.start(); });
}

QUARRY_API quarry_status quarry_get_time(quarry_sim sim, double* time, double* time_step, uint64_t* steps) {
  return call(sim, __func__, [&](Backend& b) { b.get_time(time, time_step, steps); });
}

QUARRY_API quarry_status quarry_advance(quarry_sim sim, double duration, quarry_advance_result* result) {
  return call(sim, __func__, [&](Backend& b) {
    if (result) require_struct(result, "quarry_advance", "result");
    const quarry_advance_result r = b.advance(duration);
    if (result) copy_out(r, result);
  });
}

QUARRY_API quarry_status quarry_step(quarry_sim sim, uint64_t steps) {
  return call(sim, __func__, [&](Backend& b) { b.step(steps); });
}

QUARRY_API quarry_status quarry_save_checkpoint(quarry_sim sim, const char* path) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(path);
    b.save_checkpoint(path);
  });
}

QUARRY_API quarry_status quarry_save_state(quarry_sim sim, void* buffer, uint64_t size, uint64_t* needed) {
  return call(sim, __func__, [&](Backend& b) {
    const std::string bytes = b.save_state();
    if (needed) *needed = bytes.size();
    if (!buffer) return;
    if (size < bytes.size())
      throw ApiError(QUARRY_ERROR_BAD_LENGTH, fmt::format("quarry_save_state: {} bytes needed, the buffer holds {}", bytes.size(), size));
    std::memcpy(buffer, bytes.data(), bytes.size());
  });
}

QUARRY_API quarry_status quarry_restore_state(quarry_sim sim, const void* buffer, uint64_t size) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(buffer);
    b.restore_state(buffer, size);
  });
}

QUARRY_API quarry_status quarry_num_types(quarry_sim sim, uint32_t* count) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(count);
    *count = b.num_types();
  });
}

QUARRY_API quarry_status quarry_type_name(quarry_sim sim, uint32_t type, char* buffer, size_t size) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(buffer);
    copy_text(b.type_name(type), buffer, size);
  });
}

QUARRY_API quarry_status quarry_num_particles(quarry_sim sim, int32_t type, uint64_t* count) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(count);
    *count = b.num_particles(type);
  });
}

QUARRY_API quarry_status quarry_epoch(quarry_sim sim, uint64_t* epoch) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(epoch);
    *epoch = b.epoch();
  });
}

QUARRY_API quarry_status quarry_get_particles(quarry_sim sim, quarry_particle_data* data) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(data, "quarry_get_particles", "data");
    b.get_particles(*data);
  });
}

QUARRY_API quarry_status quarry_particle_index(quarry_sim sim, uint64_t id, uint64_t* index) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(index);
    *index = b.particle_index(id);
  });
}

QUARRY_API quarry_status quarry_view_particles(quarry_sim sim, int32_t field, quarry_view* view) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(view);
    *view = b.view_particles(field);
  });
}

QUARRY_API quarry_status quarry_view_next_step_loads(quarry_sim sim, int32_t field, quarry_view* view) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(view);
    *view = b.view_next_step_loads(field);
  });
}

QUARRY_API quarry_status quarry_add_particles(quarry_sim sim, const quarry_new_particles* particles) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(particles, "quarry_add_particles", "particles");
    b.add_particles(*particles);
  });
}

QUARRY_API quarry_status quarry_remove_particles(quarry_sim sim, const uint64_t* ids, uint64_t count) {
  return call(sim, __func__, [&](Backend& b) {
    if (count > 0) QUARRY_REQUIRE(ids);
    b.remove_particles(ids, count);
  });
}

QUARRY_API quarry_status quarry_set_external_loads(quarry_sim sim, const double* force, const double* torque,
                                                   uint64_t count, int32_t mode, int32_t hold) {
  return call(sim, __func__, [&](Backend& b) { b.set_external_loads(force, torque, count, mode, hold); });
}

QUARRY_API quarry_status quarry_set_external_loads_by_id(quarry_sim sim, const uint64_t* ids, uint64_t count,
                                                         const double* force, const double* torque, int32_t mode,
                                                         int32_t hold) {
  return call(sim, __func__, [&](Backend& b) {
    if (count > 0) QUARRY_REQUIRE(ids);
    b.set_external_loads_by_id(ids, count, force, torque, mode, hold);
  });
}

QUARRY_API quarry_status quarry_clear_external_loads(quarry_sim sim) {
  return call(sim, __func__, [&](Backend& b) { b.clear_external_loads(); });
}

QUARRY_API quarry_status quarry_register_property(quarry_sim sim, const char* name, uint32_t components,
                                                  const char* unit, double initial, uint32_t* index) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(name);
    const std::uint32_t k = b.register_property(name, components, unit ? unit : "", initial);
    if (index) *index = k;
  });
}

QUARRY_API quarry_status quarry_num_properties(quarry_sim sim, uint32_t* count) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(count);
    *count = b.num_properties();
  });
}

QUARRY_API quarry_status quarry_property_info(quarry_sim sim, uint32_t index, char* name, size_t name_size,
                                              uint32_t* components, char* unit, size_t unit_size) {
  return call(sim, __func__, [&](Backend& b) {
    std::string n, u;
    std::uint32_t c = 0;
    b.property_info(index, n, c, u);
    copy_text(n, name, name_size);
    copy_text(u, unit, unit_size);
    if (components) *components = c;
  });
}

QUARRY_API quarry_status quarry_get_property(quarry_sim sim, uint32_t index, double* values, uint64_t count) {
  return call(sim, __func__, [&](Backend& b) {
    if (count > 0) QUARRY_REQUIRE(values);
    b.get_property(index, values, count);
  });
}

QUARRY_API quarry_status quarry_set_property(quarry_sim sim, uint32_t index, const double* values, uint64_t count) {
  return call(sim, __func__, [&](Backend& b) {
    if (count > 0) QUARRY_REQUIRE(values);
    b.set_property(index, values, count);
  });
}

QUARRY_API quarry_status quarry_view_property(quarry_sim sim, uint32_t index, quarry_view* view) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(view);
    *view = b.view_property(index);
  });
}

QUARRY_API quarry_status quarry_sample_points(quarry_sim sim, uint32_t type, uint32_t points, uint64_t seed,
                                              double* unit_points) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(unit_points);
    b.sample_points(type, points, seed, unit_points);
  });
}

QUARRY_API quarry_status quarry_sample_point_positions(quarry_sim sim, uint32_t type, uint32_t points, uint64_t seed,
                                                       double* positions, uint64_t capacity, uint64_t* particles) {
  return call(sim, __func__, [&](Backend& b) {
    if (capacity > 0) QUARRY_REQUIRE(positions);
    const std::uint64_t count = b.sample_point_positions(type, points, seed, positions, capacity);
    if (particles) *particles = count;
  });
}

QUARRY_API quarry_status quarry_add_surface(quarry_sim sim, const quarry_surface_desc* surface, uint32_t* index) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(surface, "quarry_add_surface", "surface");
    const std::uint32_t k = b.add_surface(*surface);
    if (index) *index = k;
  });
}

QUARRY_API quarry_status quarry_num_surfaces(quarry_sim sim, uint32_t* count) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(count);
    *count = b.num_surfaces();
  });
}

QUARRY_API quarry_status quarry_find_surface(quarry_sim sim, const char* name, uint32_t* index) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(name);
    QUARRY_REQUIRE(index);
    *index = b.find_surface(name);
  });
}

QUARRY_API quarry_status quarry_get_surface_info(quarry_sim sim, uint32_t surface, quarry_surface_info* info) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(info, "quarry_get_surface_info", "info");
    copy_out(b.surface_info(surface), info);
  });
}

QUARRY_API quarry_status quarry_set_surface_driver(quarry_sim sim, uint32_t surface, int32_t driver) {
  return call(sim, __func__, [&](Backend& b) { b.set_surface_driver(surface, driver); });
}

QUARRY_API quarry_status quarry_set_surface_nodes(quarry_sim sim, uint32_t surface, const double* positions,
                                                  const double* velocities, uint64_t count) {
  return call(sim, __func__, [&](Backend& b) {
    QUARRY_REQUIRE(positions);
    b.set_surface_nodes(surface, positions, velocities, count);
  });
}

QUARRY_API quarry_status quarry_get_surface_nodes(quarry_sim sim, uint32_t surface, double* positions,
                                                  double* velocities, uint64_t count) {
  return call(sim, __func__, [&](Backend& b) { b.get_surface_nodes(surface, positions, velocities, count); });
}

QUARRY_API quarry_status quarry_get_surface_loads(quarry_sim sim, uint32_t surface, quarry_surface_loads* loads) {
  return call(sim, __func__, [&](Backend& b) {
    require_struct(loads, "quarry_get_surface_loads", "loads");
    b.get_surface_loads(surface, *loads);
  });
}

QUARRY_API quarry_status quarry_set_hook(quarry_sim sim, int32_t stage, quarry_hook_fn fn, void* user_data) {
  return call(sim, __func__, [&](Backend& b) { b.set_hook(sim, stage, fn, user_data); });
}

QUARRY_API quarry_status quarry_add_hook_forces(quarry_sim sim, const double* force, const double* torque,
                                                uint64_t count) {
  return call(sim, __func__, [&](Backend& b) { b.add_hook_forces(force, torque, count); });
}

}  // extern "C"
