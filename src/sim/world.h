// World: everything a running simulation owns — particles, surfaces, materials, factories,
// neighbour lists with contact history, time. Built from a SimulationSpec (no deck needed);
// advanced by sim::step (step.h). Plain data with a few helpers; no virtual dispatch.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "contact/contact_law.h"
#include "contact/hertz_mindlin_batch.h"
#include "core/particle_store.h"
#include "core/simulation_spec.h"
#include "core/stage_timer.h"
#include "core/threading.h"
#include "core/worker_thread.h"
#include "geometry/load_window.h"
#include "geometry/mesh_topology.h"
#include "geometry/surface.h"
#include "geometry/surface_contact.h"
#include "geometry/surface_grid.h"
#include "insert/factory.h"
#include "insert/random.h"
#include "insert/size_distribution.h"
#include "neighbor/pair_list.h"
#include "sim/time_step_choice.h"

namespace quarry {

// Interaction parameters for every ordered pair of materials (symmetric).
struct MaterialTable {
  std::vector<std::string> names;
  std::vector<MaterialProperties> properties;
  std::vector<InteractionParameters> pairs;  // count × count
  std::size_t count() const { return names.size(); }
  const InteractionParameters& between(std::size_t a, std::size_t b) const {
    return pairs[a * names.size() + b];
  }
};

// One particle–surface contact of the current step. The contacts are kept sorted by particle
// index (then detection order); the next step finds a particle's previous contacts by binary
// search, so tangential history follows a contact while it slides from triangle to triangle.
// Only particles near a surface have any: memory is per contact, not per particle.
struct WallContact {
  std::uint32_t particle = 0;  // index
  std::uint16_t surface = 0;
  std::uint32_t triangle = 0;
  Vec3 normal;  // unit, surface → particle
  ContactHistory history;
  // This step's result, gathered onto the surface's triangles in a fixed order.
  std::array<double, 3> weights{};
  Vec3 point;              // m
  Vec3 force_on_particle;  // N
};

// Candidate triangles for particle–surface contacts, rebuilt with the pair list (triangles
// whose bounding box comes within skin of the particle). CSR over the particles that have
// any (most of a bed has none).
struct SurfaceCandidates {
  std::vector<std::uint32_t> particles;  // ascending particle indices
  std::vector<std::uint32_t> offsets;    // particles.size()+1
  std::vector<std::uint16_t> surface;    // per entry
  std::vector<std::uint32_t> triangle;   // per entry
};

// What moves a surface's vertices (DESIGN §5): nothing, the deck's prescribed motion, or a
// coupling partner.
enum class SurfaceDriverKind : std::uint8_t { fixed, prescribed, coupled };

struct SurfaceDriver {
  SurfaceDriverKind kind = SurfaceDriverKind::fixed;
  MotionSpec motion;  // prescribed
  // coupled: the vertex positions (m) and velocities (m/s) the partner set at set_time (s). Until
  // the next set the surface moves on with those velocities: x(t) = x + v (t − set_time), the
  // motion an explicit structural solver's central-difference step assumes over a sync period.
  std::vector<Vec3> set_positions, set_velocities;
  double set_time = 0.0;
};

// One surface of the world: its mesh and loads, everything derived from the mesh for the
// contact search, its driver, and its load windows.
struct WorldSurface {
  Surface mesh;                         // vertices now, this step's loads
  MeshTopology topology;                // edges and incidences (face/edge/vertex contacts)
  SurfaceGrid grid;                     // search grid over vertices_at_build
  std::vector<Vec3> vertices_at_build;  // m: the vertices the grid and the candidates were made for
  SurfaceDriver driver;
  // Elements as the partner or the deck numbered them: a quad of the input is two triangles of
  // one element (LoadWindow::element_of_triangle); empty when element = triangle.
  std::vector<std::uint32_t> element_of_triangle;
  std::size_t element_count = 0;
  // Time means of the loads: for the output frames (sized while a run writes frames) and for
  // the coupling partner (sized once a partner asks; restarted at each read).
  LoadWindow output_window, coupling_window;

  bool moving() const { return driver.kind != SurfaceDriverKind::fixed; }
};

// What a step's opening pass saw of the new state, over all particles (kick_drift_scan): the
// NaN guard, the domain check and the neighbour stage take it instead of a pass of their own.
// The last two hold only if the pass compared with the pair list (built for these particles).
struct OpeningTally {
  bool non_finite = false;   // some x, v or ω is not finite
  bool any_outside = false;  // some particle is outside the domain
  bool ids_changed = false;  // some id differs from the pair list's at its build
  bool fast = false;         // some particle moved more than half its radius in this drift
  double largest_displacement_squared = 0.0;  // m², max |xi − xi(build)|² over finite particles
  void merge(const OpeningTally& o) {
    non_finite |= o.non_finite, any_outside |= o.any_outside, ids_changed |= o.ids_changed;
    fast |= o.fast;
    largest_displacement_squared = o.largest_displacement_squared > largest_displacement_squared
                                       ? o.largest_displacement_squared
                                       : largest_displacement_squared;
  }
};

// Scratch of the force stage, kept between steps so that it does not allocate.
struct ForceWorkspace {
  // A pair whose partner belongs to a later thread's particle range: its result, computed
  // before the ranges are summed (sim/forces.cpp explains the fixed summation order).
  struct CrossingPair {
    std::uint32_t partner = 0;
    Vec3 force, torque_i, torque_j;  // N on i (partner: −force), N·m
  };
  // How the pair loop is split between threads, for one pair list and thread count: remade
  // when the list is rebuilt (or restored) or the thread count changes, not every step.
  struct PairPlan {
    std::uint64_t builds = ~std::uint64_t{0};  // PairList::builds it was made for
    std::size_t rows = 0, pairs = 0;
    int threads = 0;
    std::vector<std::uint32_t> range_start;  // threads + 1: first row of each range, then n
    // The crossing pairs of all ranges, by range, row and pair (ascending): row i, pair k.
    std::vector<std::uint32_t> crossing_row, crossing_pair;
    std::vector<std::uint32_t> crossing_begin;  // threads + 1: range t's are [begin[t], begin[t+1])
    std::vector<double> share;  // threads: the fraction of rows + pairs in each range
  };
  PairPlan plan;
  // Balance of the ranges, learnt from the time each thread spent on its rows: the fraction of
  // rows + pairs the next plan gives each thread (the split changes only speed: the sums are
  // the same for any split); a plan is made at each list build, or as soon as the shares move
  // by more than 1 % of the work. range_time: seconds per thread in the last step.
  std::vector<double> range_share, range_time;
  std::vector<CrossingPair> crossing;      // results, aligned with plan.crossing_pair
  std::vector<HertzMindlinBatch> batches;  // per thread (batched contact kernel)
  // The pair law of the batched kernel this step (the particles' one material), else null.
  const InteractionParameters* batch_law = nullptr;
  // Per particle: what the drift velocities lack to be those of the force's time, h F/m and
  // h τ/I of the previous forces (m/s, rad/s; set_velocity_leads). Derived each step from the
  // state, so not checkpointed.
  std::vector<Vec3> velocity_lead, angular_velocity_lead;
  double lead_time = 0.0;  // s, the h of those leads (ContactKinematics::lead_time)
  // Per surface: the fastest point's speed this step (m/s, vertices and belt), which bounds the
  // reach of a dashpot window against it (contact/dashpot_window.h).
  std::vector<double> surface_speed;
  // Surface contacts are found in chunks of candidates that any thread may take (the filler
  // that evens out the threads' pair ranges): each chunk's contacts, then gathered in order.
  std::vector<std::vector<WallContact>> wall_chunks;
  std::vector<int> chunk_taken;  // per chunk: the thread that took it + 1 (0: not taken yet)
  std::vector<std::size_t> wall_chunk_start;  // chunks + 1: first contact of each chunk, then total
  // A particle's surface contacts' force and torque on it, found before its pair sum was final
  // (another thread was still on its rows): added after the team's next barrier.
  struct WallSum {
    std::uint32_t particle = 0;
    Vec3 force, torque;  // N, N·m
  };
  std::vector<std::vector<WallSum>> wall_deferred;  // per thread
  // The chunks' reactions onto the surfaces are added in chunk order by whichever thread
  // finishes the next chunk in that order (sim/forces.cpp, add_ready_reactions): chunk_found
  // (per chunk, 1 once its contacts are found), reactions_next (the first chunk whose reactions
  // are not added yet) and reactions_busy (1 while a thread adds them).
  std::vector<int> chunk_found;
  std::size_t reactions_next = 0;
  int reactions_busy = 0;
  std::vector<int> rows_done;  // per thread: 1 once its pair rows are summed
};

// A mass-flow monitor's memory from one monitor row to the next (sim/monitor_sensors.cpp): the
// side of its plane each particle was on at the last row (a monitor with a window: at the last
// step), and the mass counted so far. Part of the checkpoint, so that a restarted run counts the
// crossings of the interrupted interval.
struct PlaneCrossingState {
  std::vector<std::int8_t> side_by_id;  // index: particle id; +1 / −1 at the last row, 0 unseen
  double last_time = 0.0;               // s: time of the last row
  double crossed_mass = 0.0;            // kg: net mass crossed along the normal since the start
  double pending_mass = 0.0;            // kg: a window's crossings since the last row
  bool started = false;                 // a first row was taken
};

struct World;

// Where in the step a hook runs (sim/step.cpp; like LAMMPS's fix stages).
enum class HookStage : std::uint8_t {
  // After the contact and body forces of the new configuration, before velocity Verlet's
  // closing half kick: forces that depend on the particles' velocities (fluid drag) are added
  // to particles.force here. Positions are x(t + dt); velocities are the half-step ones,
  // v(t + dt/2) (symplectic Euler: v(t + dt)), as LAMMPS's post_force sees them.
  post_force,
  // Alongside the step's stages, from when its clock has advanced (world.time is the step's
  // end time) to just before the end_of_step hooks: on a thread of its own (World::alongside)
  // when the world's team has one to spare, the stages then running on the others; else in
  // turn, just before the end_of_step hooks. Either way the same results: such a hook reads
  // only world.time, world.dt and world.alongside_threading (its team) of the world and writes
  // nothing the stages read (a coupled structure between its synchronisations).
  alongside,
  // After the step is complete (time advanced, velocities final, loads accumulated): read the
  // state, set the next step's loads or vertices.
  end_of_step,
  // Once, when sim::run or sim::restart ends (also when stopped by a signal), before the
  // output's last frame and files: a hook's own last rows and plots, with the folder still open.
  end_of_run,
};

struct StepHook {
  HookStage stage = HookStage::end_of_step;
  std::string name;                 // for messages and the stage table
  std::function<void(World&)> run;  // may throw UserError/PhysicsError: the step stops there
};

class BinaryWriter;  // sim/binary_stream.h
class BinaryReader;

// A part of the checkpoint owned by something attached to the world (a CFD-DEM run's fluid, its
// fluid frames and monitors), which sim writes and reads back without knowing what it holds.
// Whoever adds hooks that keep state from step to step registers one (names unique); a
// checkpoint writes each after the world's own state (sim/checkpoint.cpp), and a restart, once
// the same attachments are made again on the restored world, hands each its bytes back
// (sim::restore_sections).
struct CheckpointSection {
  std::string name;  // unique in the world; in messages
  // Writes the owner's state. Called whenever a checkpoint is taken; it may also bring the
  // owner's files up to date (a restart reads them back).
  std::function<void(const World&, BinaryWriter&)> save;
  // Reads all of what save wrote into the owner, attached to a world whose own state is restored
  // already. Throws std::runtime_error or std::invalid_argument saying what is wrong with
  // content it cannot take (a size that is not the deck's, a value that is not finite); the
  // restart then stops with a "cannot restore checkpoint" error.
  std::function<void(World&, BinaryReader&)> load;
};

namespace sim {
class Output;  // sim/output.h: frames, monitors, export and checkpoints of a run
}

// Owns a T that belongs to one world only: a copy of the world starts without one (a copied
// world writes no output of the original's). T may be incomplete where this is declared.
template <class T>
class NotCopied {
 public:
  NotCopied() = default;
  NotCopied(const NotCopied&) {}
  NotCopied& operator=(const NotCopied&) {
    owned_.reset();
    return *this;
  }
  NotCopied(NotCopied&&) noexcept = default;
  NotCopied& operator=(NotCopied&&) noexcept = default;
  ~NotCopied() = default;
  NotCopied& operator=(std::unique_ptr<T> p) {
    owned_ = std::move(p);
    return *this;
  }
  T* operator->() const { return owned_.get(); }
  T& operator*() const { return *owned_; }
  explicit operator bool() const { return owned_ != nullptr; }
  void reset() { owned_.reset(); }

 private:
  std::unique_ptr<T> owned_;
};

struct World {
  World();
  ~World();
  World(const World&);
  World& operator=(const World&);
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;

  SimulationSpec spec;
  ParticleStore particles;
  std::vector<WorldSurface> surfaces;
  MaterialTable materials;
  std::vector<ParticleTypeInfo> types;
  std::vector<std::string> type_names;
  std::vector<Factory> factories;
  // Sizes of particles added from outside without a radius (sim::add_particles): drawn from
  // their type's distribution with a random stream of their own (both checkpointed).
  std::vector<SizeSampler> size_samplers;  // per particle type
  Random size_random{0};

  PairList pairs;
  SurfaceCandidates candidates;
  std::vector<WallContact> wall_contacts;  // this step's, ascending particle index
  ForceWorkspace force_workspace;

  double time = 0.0;  // s
  std::uint64_t step_count = 0;
  double dt = 0.0;          // s
  double skin = 0.0;        // m, of the lists being built (the last build's: pairs.skin)
  // Unless the deck fixes it (spec.simulation.skin ≥ 0): chosen at every list build from the
  // fastest particle (sim/world_update.cpp, automatic_skin), between these bounds (m).
  struct SkinChoice {
    bool automatic = false;
    double smallest_diameter = 0.0;  // m
    double floor = 0.0, ceiling = 0.0;  // m
  } skin_choice;
  double max_radius = 0.0;  // m, largest particle radius that can exist
  // The fastest vertex of the prescribed surface motions (add_surface): it adds to the expected
  // impact speed (choose_time_step) that `check` and the overlap guard judge impacts by.
  FastestSurface fastest_surface;
  ParticleId next_id = 1;
  std::uint64_t removed_outside = 0;  // particles that left the domain
  std::uint64_t steps_since_sort = 0;
  int insertion_interval_steps = 1;
  std::uint64_t rebuilds = 0;
  bool initialized = false;           // sim::initialize has run: forces belong to the state
  bool excessive_overlap = false;     // set by the force stage for the overlap guard
  bool lists_stale = true;            // particles were added/removed: rebuild before forces
  std::vector<std::string> warnings;  // reported once (e.g. factory shortfall)
  // One per mass_flow monitor of the spec, in deck order (sized by the output stage).
  std::vector<PlaneCrossingState> plane_crossings;

  Threading threading;
  // Non-zero (a signal number) asks long phases — a factory placing many particles — to end
  // early; the run loop then stops with a checkpoint. Set by sim::run; null: never asked.
  const std::atomic<int>* stop_request = nullptr;
  std::vector<StepHook> hooks;
  std::vector<CheckpointSection> checkpoint_sections;  // registered with the hooks that own them
  NotCopied<sim::Output> output;  // null: the step writes nothing
  StageTimers timers;
  // The alongside hooks' thread (made at its first use), the team they may use while they run
  // (one thread on their own, the world's team in turn), and their time on their own thread,
  // which overlaps the stages' (not in `timers`, whose stages add up to the wall time; there,
  // "hook NAME (waited)" is the time the step waited for them).
  NotCopied<WorkerThread> alongside;
  Threading alongside_threading;
  StageTimers alongside_timers;

  bool has_moving_surfaces() const;
  std::size_t pair_contact_count() const;  // listed pairs with overlap > 0 now
  std::size_t wall_contact_count() const;
};

// Builds s.grid over s.vertices_at_build: cells of one particle diameter plus skin, clipped to
// the domain grown by one cell (particles leave the domain when their centre does, so no query
// reaches beyond it; geometry outside costs nothing).
void build_search_grid(const World& world, WorldSurface& s);

// Builds the world: material table, surfaces (STL or primitives), factories, time step.
// `meshes`, if not empty, are the surfaces' meshes as they were built before (one per
// spec.surfaces entry, reference vertices and triangles): files are then not read again (a
// checkpoint restores this way). Throws UserError (with the deck locations) for problems only
// visible now, e.g. a time step too large for the Hertz contact time. The world holds no
// particles' forces yet: sim::initialize comes next.
World build_world(const SimulationSpec& spec, const std::vector<Surface>& meshes = {});

// Adds world.spec.initial_particles (the deck's `particles:`) to a world being built (build_world
// calls it, after the surfaces): file ids kept, radii drawn where none is given. Throws UserError
// at the particle's file line or deck entry for a radius outside its type's size range, a centre
// outside the domain, an id two files share, and an overlap with another particle or a surface
// above 1 % of the smaller radius (contacts of a settled bed are below; unless the entry has
// allow_overlap: true). Cost: O(n) with the neighbour grid.
void place_initial_particles(World& world);

// Appends a surface to a built world (and its spec): mesh from `mesh` if given, else built from
// the spec entry; driver from the entry (prescribed motion, coupled, or fixed). The lists are
// rebuilt before the next force stage. Returns its index. Throws UserError for an unknown
// material. Cost: the mesh's topology and search grid, O(triangles log triangles).
std::size_t add_surface(World& world, const SurfaceSpec& surface, const Surface* mesh = nullptr);

// After the particles were reordered (new index k holds old index order[k]) or some removed
// (keep_old[i] == 0), moves the wall contacts' particle indices along; contacts of removed
// particles are dropped. The pair list needs nothing: it remaps by particle id at its rebuild.
void reindex_wall_contacts(World& world, const std::vector<std::size_t>& order);
void drop_wall_contacts_of_removed(World& world, const std::vector<char>& removed);

// The particle types' info for factories and estimates.
std::vector<ParticleTypeInfo> particle_type_infos(const SimulationSpec& spec);

// The force stage's split of the particles between its threads (ForceWorkspace::PairPlan): the
// step's per-particle passes take the same ranges (core/threading.h, thread_block).
inline std::span<const std::uint32_t> particle_ranges(const World& world) {
  return world.force_workspace.plan.range_start;
}

}  // namespace quarry
