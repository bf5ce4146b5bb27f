// SimulationSpec: everything a simulation is built from, as plain data. The deck parser
// (io/deck) produces it from YAML keeping each value's source location; sim/world builds a
// World from it; the C ABI and tests can fill it directly without any deck. SI units.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/structure_spec.h"
#include "core/fluid_spec.h"
#include "core/vec3.h"

namespace quarry {

enum class Integrator { velocity_verlet, symplectic_euler };
enum class NormalModel { hertz_mindlin, linear };
enum class RollingModel { none, constant_torque, epsd };
enum class CohesionModel { sjkr, jkr };

struct SimulationSettings {
  Located<double> end_time{0.0};              // s
  // Time step: either fixed (s) or a fraction of the Rayleigh time step (default 0.2).
  std::optional<Located<double>> fixed_time_step;  // s
  Located<double> rayleigh_fraction{0.2};     // 1
  // Expected impact speed for the Hertz contact-time check (m/s); if absent, estimated from
  // the factories' initial speed and free fall over the domain height.
  std::optional<Located<double>> impact_speed;
  Located<Vec3> gravity{Vec3{0.0, 0.0, -9.81}};  // m/s²
  Located<Aabb> domain;                       // m; particles leaving it are removed and counted
  // Axes x, y, z along which the domain is periodic (issue #20): its min/max there are the
  // period; particles leaving through such a face re-enter at the other (core/periodic_box.h).
  Located<std::array<bool, 3>> periodic{std::array<bool, 3>{false, false, false}};
  Located<Integrator> integrator{Integrator::velocity_verlet};
  Located<int> threads{0};                    // 0 = OpenMP default
  Located<double> skin{-1.0};                 // m; < 0 (unset or `auto`): chosen at every list build
  Located<int> sort_interval{1000};           // steps between spatial re-sorts (0 = never)
  Located<double> max_overlap_fraction{0.1};  // guard: overlap / smaller radius
  std::uint64_t seed = 12345;                 // random seed for factories
};

struct MaterialSpec {
  Located<std::string> name;
  Located<double> density{0.0};        // kg/m³
  Located<double> youngs_modulus{0.0}; // Pa
  Located<double> poisson_ratio{0.0};  // 1
  // Infinitely stiff (surfaces only): no Young's modulus or Poisson ratio; a particle on it has
  // E* = Ep/(1−νp²) (contact/effective_properties.h).
  Located<bool> rigid{false};
};

// Interaction between two materials (order-independent).
struct InteractionSpec {
  Located<std::string> material_a, material_b;
  Located<double> restitution{0.5};             // 1, in (0, 1]
  Located<double> static_friction{0.5};         // 1
  Located<double> rolling_friction{0.0};        // 1
  Located<RollingModel> rolling_model{RollingModel::constant_torque};
  Located<double> cohesion_energy_density{0.0}; // J/m³ (SJKR)
  Located<CohesionModel> cohesion_model{CohesionModel::sjkr};
  Located<double> surface_energy{0.0};          // J/m², γ (JKR: energy per unit contact area)
  Located<NormalModel> normal_model{NormalModel::hertz_mindlin};
  // Linear spring-dashpot: normal stiffness (N/m); tangential = ratio × normal.
  Located<double> linear_stiffness{0.0};
  Located<double> linear_tangential_ratio{2.0 / 7.0};
  Located<bool> clip_attraction{false};         // clip total normal force at zero
};

enum class SizeDistributionKind { fixed, uniform, normal, log_normal, discrete };

struct SizeDistributionSpec {
  Located<SizeDistributionKind> kind{SizeDistributionKind::fixed};
  Located<double> radius{0.0};             // fixed (m)
  Located<double> min_radius{0.0}, max_radius{0.0};  // uniform; also clip bounds for normal/log-normal
  Located<double> mean_radius{0.0}, std_radius{0.0};  // normal (m)
  Located<double> log_mean{0.0}, log_std{0.0};        // log-normal: ln(R/1 m) mean and std
  std::vector<Located<double>> discrete_radii;          // m
  std::vector<Located<double>> discrete_mass_fractions; // sum to 1
};

struct ParticleTypeSpec {
  Located<std::string> name;
  Located<std::string> material;
  SizeDistributionSpec size;
  // Particles that do not move (rough walls, obstacles): infinite mass and moment of inertia
  // (inv_mass 0), velocity zero; they exert contact forces but are not integrated.
  Located<bool> fixed{false};
};

enum class MotionKind { none, translation, rotation, vibration };

struct MotionSpec {
  Located<MotionKind> kind{MotionKind::none};
  Located<Vec3> velocity;              // translation (m/s)
  Located<Vec3> axis_point, axis_direction{Vec3{0, 0, 1}};  // rotation axis
  Located<double> angular_velocity{0.0};  // rad/s about axis_direction (right hand)
  Located<Vec3> amplitude;             // vibration displacement amplitude (m)
  Located<double> frequency{0.0};      // Hz; x(t) = x0 + A sin(2π f t)
  Located<double> start_time{0.0}, stop_time{1e300};  // s
};

enum class SurfaceKind { stl, plane, box, cylinder, mesh };

struct SurfaceSpec {
  Located<std::string> name;
  Located<SurfaceKind> kind{SurfaceKind::stl};
  Located<std::string> file;            // stl: path relative to the deck
  Located<double> scale{1.0};           // stl: coordinates × scale (e.g. 0.001 for mm files)
  Located<Vec3> offset;                 // stl: added after scaling (m)
  // plane: point + normal, finite extent given by size (m) as a square centred at point.
  Located<Vec3> point, normal{Vec3{0, 0, 1}};
  Located<double> size{1.0};
  // box: closed box [min, max] with inward-facing walls; cylinder: axis from base along
  // axis_direction, radius, length, optional caps.
  Located<Vec3> min, max;
  Located<Vec3> base, axis{Vec3{0, 0, 1}};
  Located<double> radius{0.0}, length{0.0};
  Located<bool> capped{false};
  Located<int> resolution{32};           // cylinder: segments around
  // mesh: an inline mesh, vertices (m) and elements of 0-based indices into them; the parser
  // checks that every index is in range and that no element repeats a vertex.
  std::vector<Vec3> mesh_vertices;
  std::vector<std::array<std::uint32_t, 3>> mesh_triangles;
  std::vector<std::array<std::uint32_t, 4>> mesh_quads;  // corners in order around the edge
  SourceLocation mesh_where;             // mesh: the vertices: list, for later messages
  Located<std::string> material;
  MotionSpec motion;
  Located<Vec3> conveyor_velocity;      // tangential surface velocity (m/s), no geometric motion
  Located<bool> export_loads{false};    // flagged for FEM load export (issue 4)
  // The vertices are set from outside by a coupling partner; a surface has one driver, so
  // the parser rejects coupled together with motion.
  Located<bool> coupled{false};
};

enum class RegionKind { box, cylinder, point };

struct RegionSpec {
  Located<RegionKind> kind{RegionKind::box};
  Located<Vec3> min, max;               // box (m)
  Located<Vec3> base, axis{Vec3{0, 0, 1}};  // cylinder
  Located<double> radius{0.0}, length{0.0};
  Located<Vec3> position;               // point (m): every particle is placed with its centre here
};

struct FactorySpec {
  Located<std::string> name;
  Located<std::string> particle_type;
  RegionSpec region;
  std::optional<Located<std::int64_t>> target_count;  // particles
  std::optional<Located<double>> target_mass;         // kg
  std::optional<Located<double>> mass_rate;           // kg/s; absent = all at start_time
  Located<double> start_time{0.0}, stop_time{1e300};  // s
  Located<Vec3> initial_velocity;                     // m/s
  Located<Vec3> initial_angular_velocity;             // rad/s
  Located<int> max_attempts{50};                      // placement tries per particle
};

// ---- Initial particles (`particles:` section, issue #20): a run may start from particles read
// from files (a CSV table, or a particle frame of an earlier run) or given one by one. ----
struct ParticleSourceSpec {
  SourceLocation where;        // the list entry, for messages
  Located<std::string> file;   // CSV or VTU, absolute path; empty: one particle given inline
  // One inline particle: its type's name, centre (m), radius (m; absent: drawn from the type),
  // velocity (m/s), angular velocity (rad/s).
  Located<std::string> type;
  Located<Vec3> position, velocity, angular_velocity;
  std::optional<Located<double>> radius;
  // Overlaps of this entry's particles (with any particle or surface) are accepted, not errors.
  Located<bool> allow_overlap{false};
};

// One particle the run starts with, as the deck parser read it from its source.
struct InitialParticle {
  std::uint16_t type = 0;      // particle-type index
  Vec3 position;               // m
  Vec3 velocity;               // m/s
  Vec3 angular_velocity;       // rad/s
  double radius = 0.0;         // m; ≤ 0: drawn from the type's size distribution
  std::uint64_t id = 0;        // the file's id, kept; 0: a new one
  std::uint32_t source = 0;    // index into SimulationSpec::particle_sources
  std::uint32_t line = 0;      // CSV line (1-based); 0: the source entry is the location
};

// What a monitor measures (docs/deck.md "## monitors", sim/monitor_sensors.h). A monitor without
// `type:` is a region's mass (the form before there were types).
enum class MonitorKind { mass, particle, mass_flow, stress, velocity_profile };
enum class Axis { x, y, z };

struct MonitorSpec {
  Located<std::string> name;
  Located<MonitorKind> kind{MonitorKind::mass};
  // mass: the mass inside this region (none: no column); stress, velocity_profile: a box.
  std::optional<RegionSpec> region;
  Located<std::int64_t> particle_id{0};  // particle: its id (≥ 1)
  Located<Vec3> point, normal;           // mass_flow: a point of the plane (m), its normal
  Located<Axis> axis{Axis::z};           // velocity_profile: the binned direction
  Located<int> bins{10};                 // velocity_profile: equal bins along the axis
};

struct OutputSpec {
  Located<std::string> directory{std::string("out")};
  Located<double> interval{0.0};        // s between VTU frames (0 = only final)
  Located<double> monitor_interval{0.0};  // s between CSV monitor rows (0 = every output)
  Located<double> checkpoint_interval{0.0};  // s (0 = none, except on SIGINT/SIGTERM)
  Located<bool> plots{true};            // PNG plots of the monitors at the end
  Located<double> progress_interval{2.0};  // wall-clock s between progress lines
  Located<bool> contacts{false};        // a contacts_NNNNNN.vtu (force network) with each frame
};

// ---- FEM load export (issue 4): the `export:` section applies to every surface flagged
// `export: true`; written by src/export while the run goes. ----
enum class ExportFormat { med, calculix, vtu, csv };
enum class CalculixAnalysis { static_step, dynamic };
// SupportSpec (structure_spec.h): the CalculiX model's supports, as a Gmsh structure's.

// The structural model of the exported surface for the CalculiX deck: shells of one
// thickness and one linear elastic material, and the supports.
struct CalculixSpec {
  Located<double> thickness{0.0};         // m
  Located<double> youngs_modulus{0.0};    // Pa
  Located<double> poisson_ratio{0.3};     // 1
  Located<double> density{0.0};           // kg/m³ (needed by the dynamic analysis)
  Located<CalculixAnalysis> analysis{CalculixAnalysis::static_step};
  // Static step: loads of the export interval containing this time (s); absent = last one.
  std::optional<Located<double>> static_time;
  std::vector<SupportSpec> supports;
};

struct ExportSpec {
  bool enabled = false;                   // the deck has an export: section
  Located<double> interval{0.0};          // s, averaging window of each exported time
  Located<std::string> directory{std::string("fem_export")};  // relative to output.directory
  std::vector<Located<ExportFormat>> formats;  // empty = all formats
  std::optional<CalculixSpec> calculix;   // required when calculix is among the formats
  SourceLocation where;                   // the export: section, for messages
};

struct SimulationSpec {
  std::string deck_path;                // for messages; empty when built in code
  SimulationSettings simulation;
  std::vector<MaterialSpec> materials;
  std::vector<InteractionSpec> interactions;
  std::vector<ParticleTypeSpec> particle_types;
  std::vector<SurfaceSpec> surfaces;
  std::vector<FactorySpec> factories;
  std::vector<ParticleSourceSpec> particle_sources;   // `particles:` section
  // The particles those sources hold, read by the parser (files are not read again at a
  // restart: the checkpoint holds the particles); the deck writer writes the sources only.
  std::vector<InitialParticle> initial_particles;
  std::vector<MonitorSpec> monitors;
  OutputSpec output;
  ExportSpec fem_export;                // `export:` section (export is a C++ keyword)
  std::vector<StructureSpec> structures;  // `structures:` section (two-way shell coupling)
  std::optional<FluidSpec> fluid;       // `fluid:` section (CFD-DEM, issue #18)
};

}  // namespace quarry
