// LocalBackend: a simulation in this process behind the C ABI — the World, its outputs, the type
// order and id index the ABI's arrays are in, and the hooks a partner set. Also what a
// `quarry serve` process runs for its remote partner.
#pragma once

#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>

#include "api/backend.h"
#include "api/built_in_solvers.h"
#include "sim/exchange.h"
#include "sim/world.h"

namespace quarry::api {

class LocalBackend final : public Backend {
 public:
  // Opens a deck, a checkpoint or an empty simulation (info's paths), in-process. Throws
  // ApiError / UserError / PhysicsError (api.cpp maps them to status codes).
  explicit LocalBackend(const quarry_open_info& info);
  ~LocalBackend() override;

  bool remote() const override { return false; }
  void close() override;
  void set_settings(const quarry_settings& settings) override;
  std::uint32_t add_material(const quarry_material& material) override;
  void add_interaction(const quarry_interaction& interaction) override;
  std::uint32_t add_particle_type(const quarry_particle_type& type) override;
  void start() override;

  void get_time(double* time, double* time_step, std::uint64_t* steps) override;
  quarry_advance_result advance(double duration) override;
  void step(std::uint64_t steps) override;

  void save_checkpoint(const std::string& path) override;
  std::string save_state() override;
  void restore_state(const void* bytes, std::uint64_t size) override;

  std::uint32_t num_types() override;
  std::string type_name(std::uint32_t type) override;
  std::uint64_t num_particles(std::int32_t type) override;
  std::uint64_t epoch() override;
  void get_particles(quarry_particle_data& data) override;
  std::uint64_t particle_index(std::uint64_t id) override;
  quarry_view view_particles(std::int32_t field) override;
  quarry_view view_next_step_loads(std::int32_t field) override;
  void add_particles(const quarry_new_particles& particles) override;
  void remove_particles(const std::uint64_t* ids, std::uint64_t count) override;

  void set_external_loads(const double* force, const double* torque, std::uint64_t count, std::int32_t mode,
                          std::int32_t hold) override;
  void set_external_loads_by_id(const std::uint64_t* ids, std::uint64_t count, const double* force,
                                const double* torque, std::int32_t mode, std::int32_t hold) override;
  void clear_external_loads() override;

  std::uint32_t register_property(const std::string& name, std::uint32_t components, const std::string& unit,
                                  double initial) override;
  std::uint32_t num_properties() override;
  void property_info(std::uint32_t index, std::string& name, std::uint32_t& components, std::string& unit) override;
  void get_property(std::uint32_t index, double* values, std::uint64_t count) override;
  void set_property(std::uint32_t index, const double* values, std::uint64_t count) override;
  quarry_view view_property(std::uint32_t index) override;

  void sample_points(std::uint32_t type, std::uint32_t points, std::uint64_t seed, double* unit_points) override;
  std::uint64_t sample_point_positions(std::uint32_t type, std::uint32_t points, std::uint64_t seed,
                                       double* positions, std::uint64_t capacity) override;

  std::uint32_t add_surface(const quarry_surface_desc& surface) override;
  std::uint32_t num_surfaces() override;
  std::uint32_t find_surface(const std::string& name) override;
  quarry_surface_info surface_info(std::uint32_t surface) override;
  void set_surface_driver(std::uint32_t surface, std::int32_t driver) override;
  void set_surface_nodes(std::uint32_t surface, const double* positions, const double* velocities,
                         std::uint64_t count) override;
  void get_surface_nodes(std::uint32_t surface, double* positions, double* velocities, std::uint64_t count) override;
  void get_surface_loads(std::uint32_t surface, quarry_surface_loads& loads) override;

  void set_hook(quarry_sim sim, std::int32_t stage, quarry_hook_fn fn, void* user_data) override;
  void add_hook_forces(const double* force, const double* torque, std::uint64_t count) override;

  // The world (started simulations only), for tests and the server.
  World& world();
  // `quarry serve`: once *stop is non-zero (a signal number), an advance or step ends between
  // two steps with TRANSPORT (the server is stopping), the state being that step's.
  void set_stop_flag(const std::atomic<int>* stop) { stop_ = stop; }

 private:
  void require_started(const char* call) const;
  void require_not_started(const char* call) const;
  void require_outside_hook(const char* call) const;
  void attach_output(std::optional<double> resume_time, std::uint64_t frame_index);
  void attach_built_in();
  // Type order and id index of the current particles (remade when the epoch changed).
  const sim::TypeOrder& order();
  std::size_t surface_index(std::uint32_t surface) const;
  void run_steps(std::uint64_t steps);

  bool started_ = false;
  SimulationSpec spec_;              // before start: the definition built by calls
  World world_;
  BuiltInSolvers built_in_;          // the deck's fluid and structures (their hooks refer to them)
  int threads_ = 0;
  std::optional<std::filesystem::path> output_directory_;
  sim::TypeOrder order_;
  sim::IdIndex ids_;
  int in_hook_ = 0;                  // the stage of the hook running now (0: none)
  struct Hook {
    quarry_hook_fn fn = nullptr;
    void* user_data = nullptr;
    quarry_sim sim{0};
  };
  Hook hooks_[2];                    // post_force, end_of_step
  const std::atomic<int>* stop_ = nullptr;
  // quarry_set_external_loads_by_id's engine indices, kept between calls.
  std::vector<std::uint32_t> load_indices_;
};

}  // namespace quarry::api
