// Checkpoints: the complete dynamic state of a World in one binary file, written atomically.
// Everything that influences later steps is saved — particles with their forces (the first
// half kick after a restart needs them), the neighbour list exactly as built (so that the
// restarted run sums contact forces in the same order), contact history, wall contacts,
// surface positions and load windows, factory random streams — so a restart is bit-identical.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

#include "io/atomic_file.h"
#include "sim/binary_stream.h"
#include "sim/run.h"

namespace quarry::sim {

namespace {

constexpr std::uint64_t kMagic = 0x32304B4359525551ull;  // "QURYCK02"

// An open checkpoint file and its length, read piece by piece by BinaryReader.
struct CheckpointFile {
  std::ifstream stream;
  std::uint64_t size = 0;  // bytes
};

CheckpointFile open_checkpoint(const std::string& path) {
  CheckpointFile file;
  std::error_code error;
  file.size = std::filesystem::file_size(path, error);
  file.stream.open(path, std::ios::binary);
  if (error || !file.stream)
    throw UserError(SourceLocation{path, 0, 0}, "cannot open checkpoint file",
                    "give the path of a checkpoint.qck written by 'quarry run'");
  return file;
}

template <class Stream, class F>
void each_particle_array(Stream& s, ParticleStore& p, F&& f) {
  f(s, p.position); f(s, p.velocity); f(s, p.angular_velocity); f(s, p.force); f(s, p.torque);
  f(s, p.radius); f(s, p.inv_mass); f(s, p.material); f(s, p.id);
  f(s, p.type); f(s, p.creation_time); f(s, p.external_force); f(s, p.external_torque);
}

template <class Stream, class F>
void each_pair_array(Stream& s, PairList& l, F&& f) {
  f(s, l.offsets); f(s, l.partner); f(s, l.tangential_displacement); f(s, l.rolling_torque);
  f(s, l.reference_positions); f(s, l.ids_at_build);
}

template <class Stream, class F>
void each_surface_array(Stream& s, Surface& surface, F&& f) {
  f(s, surface.vertices); f(s, surface.vertex_velocities); f(s, surface.triangle_normals);
  f(s, surface.triangle_areas); f(s, surface.triangle_force); f(s, surface.vertex_force);
  f(s, surface.window_force_impulse); f(s, surface.window_normal_impulse);
  f(s, surface.window_shear_impulse);
}

// The deck as it is now ("" if it is gone): stored in checkpoints, compared on restart.
std::string read_deck_text(const std::string& deck_path) { return read_file(deck_path).value_or(""); }

}  // namespace

void write_checkpoint(const World& const_world, const std::string& path, std::uint64_t frame_index) {
  // A checkpoint holds final velocities only: a restart could not know of a pending kick.
  if (const_world.next_opened)
    throw std::logic_error("write_checkpoint: the next step is already opened (StepEnd::next_opened); step on first");
  if (const_world.pending_kick != 0.0)
    throw std::logic_error("write_checkpoint: the last step is not complete (call complete_step first)");
  World& world = const_cast<World&>(const_world);  // the visitors take non-const arrays
  BinaryWriter w;
  const auto put = [](BinaryWriter& s, auto& v) { s.vector(v); };
  w.value(kMagic);
  w.string(world.spec.deck_path);
  w.string(read_deck_text(world.spec.deck_path));
  w.value(world.time);
  w.value(world.step_count);
  w.value(world.dt);
  w.value(world.next_id);
  w.value(world.removed_outside);
  w.value(world.steps_since_sort);
  w.value(world.rebuilds);
  w.value(static_cast<std::uint8_t>(world.lists_stale));
  w.value(frame_index);
  w.value(static_cast<std::uint8_t>(world.particles.external_loads_enabled));
  each_particle_array(w, world.particles, put);
  w.value<std::uint64_t>(world.particles.custom_names.size());
  for (std::size_t k = 0; k < world.particles.custom_names.size(); ++k) {
    w.string(world.particles.custom_names[k]);
    w.vector(world.particles.custom_values[k]);
  }
  each_pair_array(w, world.pairs, put);
  w.value(world.pairs.skin);
  w.value<std::uint64_t>(world.pairs.builds);
  w.vector(world.candidates.particles);
  w.vector(world.candidates.offsets);
  w.vector(world.candidates.surface);
  w.vector(world.candidates.triangle);
  w.value<std::uint64_t>(world.candidates.vertices_at_build.size());
  for (const auto& v : world.candidates.vertices_at_build) w.vector(v);
  w.vector(world.wall_contacts);
  w.value<std::uint64_t>(world.surfaces.size());
  for (auto& surface : world.surfaces) {
    each_surface_array(w, surface, put);
    w.value(surface.window_time);
    w.value(surface.total_force);
    w.value(surface.total_torque);
  }
  w.value<std::uint64_t>(world.factories.size());
  for (const auto& f : world.factories) w.vector(f.save_state());
  write_file_atomically(path, w.bytes());
}

std::string checkpoint_deck_path(const std::string& path) {
  CheckpointFile file = open_checkpoint(path);
  BinaryReader r(file.stream, file.size);
  if (file.size < 8 || r.value<std::uint64_t>() != kMagic)
    throw UserError(SourceLocation{path, 0, 0}, "not a Quarry checkpoint (wrong magic number)",
                    "give the path of a checkpoint.qck written by 'quarry run'");
  return r.string();
}

std::uint64_t read_checkpoint(World& world, const std::string& path) {
  CheckpointFile file = open_checkpoint(path);
  BinaryReader r(file.stream, file.size);
  try {
    if (r.value<std::uint64_t>() != kMagic) throw std::runtime_error("wrong magic number");
    const std::string deck_path = r.string();
    const std::string deck_text = r.string();
    if (read_deck_text(deck_path) != deck_text)
      throw UserError(SourceLocation{deck_path, 0, 0},
                      "the deck changed since the checkpoint was written",
                      "a restart continues the same simulation: restore the deck, or start a new run "
                      "(use --end-time to run a restart longer)");
    const auto get = [](BinaryReader& s, auto& v) { s.vector(v); };
    world.time = r.value<double>();
    world.step_count = r.value<std::uint64_t>();
    world.dt = r.value<double>();
    world.next_id = r.value<ParticleId>();
    world.removed_outside = r.value<std::uint64_t>();
    world.steps_since_sort = r.value<std::uint64_t>();
    world.rebuilds = r.value<std::uint64_t>();
    world.lists_stale = r.value<std::uint8_t>() != 0;
    const auto frame_index = r.value<std::uint64_t>();
    world.particles.external_loads_enabled = r.value<std::uint8_t>() != 0;
    each_particle_array(r, world.particles, get);
    const auto customs = r.value<std::uint64_t>();
    world.particles.custom_names.assign(customs, {});
    world.particles.custom_values.assign(customs, {});
    for (std::size_t k = 0; k < customs; ++k) {
      world.particles.custom_names[k] = r.string();
      r.vector(world.particles.custom_values[k]);
    }
    each_pair_array(r, world.pairs, get);
    world.pairs.skin = r.value<double>();
    world.pairs.builds = r.value<std::uint64_t>();
    world.force_workspace.plan = {};  // made for the list this one replaces
    r.vector(world.candidates.particles);
    r.vector(world.candidates.offsets);
    r.vector(world.candidates.surface);
    r.vector(world.candidates.triangle);
    const auto surfaces_at_build = r.value<std::uint64_t>();
    if (surfaces_at_build != world.surfaces.size()) throw std::runtime_error("surface count differs");
    for (auto& v : world.candidates.vertices_at_build) r.vector(v);
    r.vector(world.wall_contacts);
    if (r.value<std::uint64_t>() != world.surfaces.size()) throw std::runtime_error("surface count differs");
    for (auto& surface : world.surfaces) {
      each_surface_array(r, surface, get);
      surface.window_time = r.value<double>();
      surface.total_force = r.value<Vec3>();
      surface.total_torque = r.value<Vec3>();
    }
    if (r.value<std::uint64_t>() != world.factories.size()) throw std::runtime_error("factory count differs");
    for (auto& f : world.factories) {
      std::vector<std::uint64_t> state;
      r.vector(state);
      f.load_state(state);
    }
    if (!r.at_end()) throw std::runtime_error("trailing bytes");
    // Moving surfaces: their search grids are those of the last list build.
    for (std::size_t s = 0; s < world.surfaces.size(); ++s) {
      if (world.motions[s].kind.value == MotionKind::none) continue;
      Surface at_build = world.surfaces[s];
      at_build.vertices = world.candidates.vertices_at_build[s];
      world.grids[s].build(at_build, 2.0 * world.max_radius + world.skin);
    }
    return frame_index;
  } catch (const UserError&) {
    throw;
  } catch (const std::exception& e) {
    throw UserError(SourceLocation{path, 0, 0}, fmt::format("cannot read checkpoint: {}", e.what()),
                    "the file is damaged or from another Quarry version; rerun from the deck");
  }
}

std::uint64_t state_hash(const World& world) {
  // FNV-1a over the raw bytes of the dynamic particle state.
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) h = (h ^ b[k]) * 1099511628211ull;
  };
  const ParticleStore& p = world.particles;
  mix(p.id.data(), p.id.size() * sizeof(ParticleId));
  mix(p.position.data(), p.position.size() * sizeof(Vec3));
  mix(p.velocity.data(), p.velocity.size() * sizeof(Vec3));
  mix(p.angular_velocity.data(), p.angular_velocity.size() * sizeof(Vec3));
  // Surface loads per element and node: their numbering and sums must not depend on threads.
  for (const Surface& s : world.surfaces) {
    mix(s.triangle_force.data(), s.triangle_force.size() * sizeof(Vec3));
    mix(s.vertex_force.data(), s.vertex_force.size() * sizeof(Vec3));
  }
  return h;
}

}  // namespace quarry::sim
