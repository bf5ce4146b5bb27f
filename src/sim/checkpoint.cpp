// Checkpoints: the complete state of a World in one binary file, written atomically, from which
// it restarts bit-identically without the deck's files. Format 6: a header (magic, format,
// payload length, CRC-32 of the payload) and the payload: the effective deck as YAML text and
// every surface's mesh (so a world built through the C ABI restores too), then everything that
// influences later steps — particles with their forces (the first half kick after a restart
// needs them), the neighbour list exactly as built (so the restarted run sums contact forces in
// the same order), contact history, wall contacts, surface poses, drivers and load windows,
// factory random streams, the mass-flow monitors' plane sides — and last the named sections of
// what was attached to the world (World::checkpoint_sections: a CFD-DEM run's fluid), each as
// its name and bytes. Loading checks the checksum and then every length, index and value, so a
// damaged file is an error that says what is wrong, never a crash or a different state.
#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.h"
#include "io/deck.h"
#include "io/deck_writer.h"
#include "sim/binary_stream.h"
#include "sim/run.h"

namespace quarry::sim {

namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kMagic = 0x34304B4359525551ull;  // "QURYCK04"
// 5: the contacts' last normal force (implicit dashpots); 6: the attachments' named sections.
// 7: a mass-flow window's crossings since the last row.
constexpr std::uint32_t kFormat = 7;
constexpr std::uint64_t kMostSections = 1000;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 4 + 4;

struct Header {
  std::uint64_t magic = kMagic;
  std::uint32_t format = kFormat;
  std::uint32_t reserved = 0;
  std::uint64_t payload_bytes = 0;
  std::uint32_t crc = 0;
  std::uint32_t reserved2 = 0;
};

std::uint32_t crc32_of(const char* data, std::size_t n, std::uint32_t crc = 0) {
  // zlib's crc32 takes a uInt length: feed it in pieces.
  while (n > 0) {
    const auto piece = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
    crc = static_cast<std::uint32_t>(::crc32(crc, reinterpret_cast<const Bytef*>(data), piece));
    data += piece, n -= piece;
  }
  return crc;
}

// FNV-1a of a file's bytes (0 if it cannot be read): to tell whether an STL changed.
std::uint64_t file_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return 0;
  std::uint64_t h = 1469598103934665603ull;
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    for (std::streamsize k = 0; k < in.gcount(); ++k) h = (h ^ static_cast<unsigned char>(buffer[k])) * 1099511628211ull;
  }
  return h;
}

[[noreturn]] void bad(const std::string& what) { throw std::runtime_error(what); }

// The two directions of one visit: Save writes each field, Load reads it back in place, so the
// order of the fields is written once (transfer_state) and cannot differ between them.
struct Save {
  static constexpr bool loading = false;
  BinaryWriter& out;
  template <class T>
  void value(T& v) { out.value(v); }
  template <class T>
  void vector(std::vector<T>& v) { out.vector(v); }
  void string(std::string& s) { out.string(s); }
};

struct Load {
  static constexpr bool loading = true;
  BinaryReader& in;
  template <class T>
  void value(T& v) { v = in.value<T>(); }
  template <class T>
  void vector(std::vector<T>& v) { in.vector(v); }
  void string(std::string& s) { s = in.string(); }
};

void transfer_header(auto& io, Header& h) {
  io.value(h.magic);
  io.value(h.format);
  io.value(h.reserved);
  io.value(h.payload_bytes);
  io.value(h.crc);
  io.value(h.reserved2);
}

// A flag as one byte; a loaded byte other than 0 or 1 is damage.
void transfer_flag(auto& io, bool& flag) {
  auto byte = static_cast<std::uint8_t>(flag);
  io.value(byte);
  if (byte > 1) bad("a flag holds a value other than 0 or 1");
  flag = byte != 0;
}

void transfer_window(auto& io, LoadWindow& w) {
  io.vector(w.element_of_triangle);
  io.vector(w.force_impulse);
  io.vector(w.normal_impulse);
  io.vector(w.shear_impulse);
  io.vector(w.nodal_impulse);
  io.value(w.duration);
}

// Everything of a built world that later steps depend on (the world itself — materials, types,
// meshes — is rebuilt from the spec first). A count read from the file is bounded before use.
void transfer_state(auto& io, World& world, std::uint64_t& frame_index) {
  constexpr bool loading = std::remove_reference_t<decltype(io)>::loading;
  io.value(world.time);
  io.value(world.step_count);
  io.value(world.dt);
  io.value(world.next_id);
  io.value(world.removed_outside);
  io.value(world.steps_since_sort);
  io.value(world.rebuilds);
  transfer_flag(io, world.lists_stale);
  io.value(frame_index);
  ParticleStore& p = world.particles;
  transfer_flag(io, p.external_loads_enabled);
  for (auto* v : {&p.position, &p.velocity, &p.angular_velocity, &p.force, &p.torque}) io.vector(*v);
  io.vector(p.radius);
  io.vector(p.inv_mass);
  io.vector(p.material);
  io.vector(p.id);
  io.vector(p.type);
  io.vector(p.creation_time);
  for (auto* v : {&p.external_force, &p.external_torque, &p.external_force_once, &p.external_torque_once}) io.vector(*v);
  // Saved forces hold the one-step loads (checkpoint_bytes refuses them apart); zeros or not,
  // the end of the next step takes them out again.
  if constexpr (loading) {
    p.held_loads = p.once_loads = p.has_external_loads() ? ParticleStore::kForceLoads | ParticleStore::kTorqueLoads : 0;
    p.once_in_forces = true;
  }
  std::uint64_t customs = p.custom.size();
  io.value(customs);
  if constexpr (loading) {
    if (customs > 100000) bad("the custom property count is implausible");
    p.custom.assign(customs, {});
  }
  for (auto& c : p.custom) {
    io.string(c.name);
    io.string(c.unit);
    io.value(c.components);
    io.value(c.initial);
    io.vector(c.values);
  }
  io.value(p.layout_epoch);
  PairList& l = world.pairs;
  for (auto* v : {&l.tangential_displacement, &l.rolling_torque, &l.reference_positions}) io.vector(*v);
  io.vector(l.jkr_attached);
  io.vector(l.normal_force);
  io.vector(l.offsets);
  io.vector(l.partner);
  io.vector(l.ids_at_build);
  io.value(l.skin);
  io.value(l.builds);
  io.vector(world.candidates.particles);
  io.vector(world.candidates.offsets);
  io.vector(world.candidates.surface);
  io.vector(world.candidates.triangle);
  io.vector(world.wall_contacts);
  for (WorldSurface& s : world.surfaces) {
    Surface& m = s.mesh;
    for (auto* v : {&m.vertices, &m.vertex_velocities, &m.triangle_normals, &m.triangle_force, &m.vertex_force,
                    &s.vertices_at_build, &s.driver.set_positions, &s.driver.set_velocities})
      io.vector(*v);
    io.vector(m.triangle_areas);
    io.vector(s.element_of_triangle);
    io.value(m.total_force);
    io.value(m.total_torque);
    auto kind = static_cast<std::uint8_t>(s.driver.kind);
    io.value(kind);
    if constexpr (loading) {
      if (kind > static_cast<std::uint8_t>(SurfaceDriverKind::coupled)) bad("a surface has an unknown driver");
      s.driver.kind = static_cast<SurfaceDriverKind>(kind);
    }
    io.value(s.driver.set_time);
    io.value(s.element_count);
    transfer_window(io, s.output_window);
    transfer_window(io, s.coupling_window);
  }
  std::uint64_t factories = world.factories.size();
  io.value(factories);
  if (loading && factories != world.factories.size()) bad("the factory count differs from the deck's");
  for (auto& f : world.factories) {
    std::vector<std::uint64_t> state;
    if constexpr (!loading) state = f.save_state();
    io.vector(state);
    if constexpr (loading) f.load_state(state);
  }
  std::array<std::uint64_t, 4> random = world.size_random.state();
  for (auto& word : random) io.value(word);
  if constexpr (loading) {
    if (random == std::array<std::uint64_t, 4>{}) bad("the size stream's state is all zero");
    world.size_random.set_state(random);
  }
  for (SizeSampler& sampler : world.size_samplers) {
    std::vector<double> state = sampler.state();
    io.vector(state);
    if constexpr (loading) sampler.set_state(state);
  }
  std::uint64_t crossings = world.plane_crossings.size();
  io.value(crossings);
  if constexpr (loading) {
    std::size_t flow_monitors = 0;
    for (const MonitorSpec& m : world.spec.monitors) flow_monitors += m.kind.value == MonitorKind::mass_flow;
    if (crossings > flow_monitors) bad("more mass-flow monitor states than the deck has mass-flow monitors");
    world.plane_crossings.assign(crossings, {});
  }
  for (PlaneCrossingState& c : world.plane_crossings) {
    io.vector(c.side_by_id);
    io.value(c.last_time);
    io.value(c.crossed_mass);
    io.value(c.pending_mass);
    transfer_flag(io, c.started);
    if constexpr (loading) {
      if (c.side_by_id.size() > world.next_id) bad("a mass-flow monitor's state names particle ids never given");
      for (std::int8_t side : c.side_by_id)
        // ±1, or ±2 for a plane across a periodic axis (the quarter of the period:
        // monitor_sensors.cpp).
        if (side < -2 || side > 2)
          bad("a mass-flow monitor's state holds a side other than -2 to 2");
      if (!std::isfinite(c.last_time) || !std::isfinite(c.crossed_mass) || !std::isfinite(c.pending_mass))
        bad("a mass-flow monitor's state is not finite");
    }
  }
}

// ---- validation of a loaded state: every length, index and value the steps will trust ----

template <class T>
void expect_size(const std::vector<T>& v, std::size_t n, const char* what) {
  if (v.size() != n) bad(fmt::format("{} has {} entries, expected {}", what, v.size(), n));
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

template <class T>
void expect_finite(const std::vector<T>& v, const char* what) {
  for (std::size_t k = 0; k < v.size(); ++k) {
    bool ok;
    if constexpr (std::is_same_v<T, Vec3>) ok = finite(v[k]);
    else ok = std::isfinite(v[k]);
    if (!ok) bad(fmt::format("{} entry {} is not a finite number", what, k));
  }
}

void validate_window(const LoadWindow& w, const WorldSurface& s, const char* which) {
  if (!w.sized()) return;
  const std::string what = fmt::format("the {} load window of surface '{}'", which, s.mesh.name);
  if (!w.element_of_triangle.empty()) {
    expect_size(w.element_of_triangle, s.mesh.triangle_count(), what.c_str());
    for (std::uint32_t e : w.element_of_triangle)
      if (e >= w.force_impulse.size()) bad(what + " maps a triangle to an element that does not exist");
  } else {
    expect_size(w.force_impulse, s.mesh.triangle_count(), what.c_str());
  }
  expect_size(w.normal_impulse, w.force_impulse.size(), what.c_str());
  expect_size(w.shear_impulse, w.force_impulse.size(), what.c_str());
  expect_size(w.nodal_impulse, s.mesh.vertex_count(), what.c_str());
  if (!(w.duration >= 0.0) || !std::isfinite(w.duration)) bad(what + " has an invalid duration");
}

void validate(const World& world) {
  if (!(world.dt > 0.0) || !std::isfinite(world.dt)) bad(fmt::format("the time step {} s is not a positive number", world.dt));
  if (!std::isfinite(world.time) || world.time < 0.0) bad(fmt::format("the time {} s is invalid", world.time));
  const ParticleStore& p = world.particles;
  const std::size_t n = p.size();
  if (n >= 0xffffffffu) bad("too many particles");
  expect_size(p.velocity, n, "particle velocities"); expect_size(p.angular_velocity, n, "particle angular velocities");
  expect_size(p.force, n, "particle forces"); expect_size(p.torque, n, "particle torques");
  expect_size(p.radius, n, "particle radii"); expect_size(p.inv_mass, n, "particle masses");
  expect_size(p.material, n, "particle materials"); expect_size(p.id, n, "particle ids");
  expect_size(p.type, n, "particle types"); expect_size(p.creation_time, n, "particle creation times");
  const std::size_t loads = p.has_external_loads() ? n : 0;
  expect_size(p.external_force, loads, "external forces"); expect_size(p.external_torque, loads, "external torques");
  expect_size(p.external_force_once, loads, "one-step external forces");
  expect_size(p.external_torque_once, loads, "one-step external torques");
  expect_finite(p.position, "particle positions"); expect_finite(p.velocity, "particle velocities");
  expect_finite(p.angular_velocity, "particle angular velocities"); expect_finite(p.force, "particle forces");
  expect_finite(p.torque, "particle torques");
  for (std::size_t i = 0; i < n; ++i) {
    if (!(p.radius[i] > 0.0) || !std::isfinite(p.radius[i])) bad(fmt::format("particle {} has radius {}", i, p.radius[i]));
    if (!(p.inv_mass[i] >= 0.0) || !std::isfinite(p.inv_mass[i])) bad(fmt::format("particle {} has an invalid mass", i));
    if (p.material[i] >= world.materials.count()) bad(fmt::format("particle {} has material index {}", i, p.material[i]));
    if (p.type[i] >= world.types.size()) bad(fmt::format("particle {} has type index {}", i, p.type[i]));
    if (p.id[i] == 0 || p.id[i] >= world.next_id) bad(fmt::format("particle {} has id {} (next id {})", i, p.id[i], world.next_id));
  }
  for (const auto& c : p.custom) {
    if (c.components == 0) bad("custom property '" + c.name + "' has no components");
    expect_size(c.values, n * c.components, ("custom property " + c.name).c_str());
  }
  // The pair list as built for the particles of its last build (it maps their history to the
  // particles of the next build by id); when the lists are not stale that is these particles.
  const PairList& l = world.pairs;
  const std::size_t built = l.ids_at_build.size();
  expect_size(l.reference_positions, built, "the neighbour list's positions at build");
  if (!world.lists_stale && built != n) bad(fmt::format("the neighbour list was built for {} particles, not {}", built, n));
  if (!l.offsets.empty() || !l.partner.empty()) {
    expect_size(l.offsets, built + 1, "the neighbour list's row offsets");
    if (l.offsets[0] != 0 || l.offsets[built] != l.partner.size()) bad("the neighbour list's offsets do not span its pairs");
    for (std::size_t i = 0; i < built; ++i) {
      if (l.offsets[i + 1] < l.offsets[i]) bad(fmt::format("the neighbour list's row {} has a negative length", i));
      for (std::uint32_t k = l.offsets[i]; k < l.offsets[i + 1]; ++k)
        if (l.partner[k] <= i || l.partner[k] >= built) bad(fmt::format("neighbour pair {} names particle {}", k, l.partner[k]));
    }
  }
  expect_size(l.tangential_displacement, l.partner.size(), "the pairs' tangential history");
  if (!l.rolling_torque.empty()) expect_size(l.rolling_torque, l.partner.size(), "the pairs' rolling history");
  if (!l.jkr_attached.empty()) expect_size(l.jkr_attached, l.partner.size(), "the pairs' JKR adhesion");
  for (const std::uint8_t flag : l.jkr_attached)
    if (flag > 1) bad("a pair's JKR adhesion flag holds a value other than 0 or 1");
  expect_finite(l.tangential_displacement, "the pairs' tangential history");
  expect_size(l.normal_force, l.partner.size(), "the pairs' normal forces");
  expect_finite(l.normal_force, "the pairs' normal forces");
  const std::size_t surfaces = world.surfaces.size();
  const SurfaceCandidates& c = world.candidates;
  expect_size(c.offsets, c.particles.size() + 1, "the surface candidates' offsets");
  if (c.offsets[0] != 0 || c.offsets.back() != c.triangle.size()) bad("the surface candidates' offsets do not span them");
  expect_size(c.surface, c.triangle.size(), "the surface candidates' surfaces");
  for (std::size_t k = 0; k < c.particles.size(); ++k) {
    if (c.particles[k] >= n || (k > 0 && c.particles[k] <= c.particles[k - 1])) bad(fmt::format("surface candidate {} names particle {}", k, c.particles[k]));
    if (c.offsets[k + 1] < c.offsets[k]) bad(fmt::format("surface candidate {} has a negative length", k));
  }
  for (std::size_t k = 0; k < c.triangle.size(); ++k)
    if (c.surface[k] >= surfaces || c.triangle[k] >= world.surfaces[c.surface[k]].mesh.triangle_count())
      bad(fmt::format("surface candidate entry {} names surface {} triangle {}", k, c.surface[k], c.triangle[k]));
  for (std::size_t k = 0; k < world.wall_contacts.size(); ++k) {
    const WallContact& w = world.wall_contacts[k];
    if (w.particle >= n || w.surface >= surfaces || w.triangle >= world.surfaces[w.surface].mesh.triangle_count() ||
        (k > 0 && w.particle < world.wall_contacts[k - 1].particle))
      bad(fmt::format("wall contact {} names particle {}, surface {}, triangle {}", k, w.particle, w.surface, w.triangle));
  }
  for (const WorldSurface& s : world.surfaces) {
    const Surface& m = s.mesh;
    const std::size_t v = m.reference_vertices.size(), t = m.triangles.size();
    const std::string what = "surface '" + m.name + "'";
    expect_size(m.vertices, v, (what + " vertices").c_str());
    expect_size(m.vertex_velocities, v, (what + " vertex velocities").c_str());
    expect_size(m.vertex_force, v, (what + " vertex forces").c_str());
    expect_size(s.vertices_at_build, v, (what + " vertices at the list build").c_str());
    expect_size(m.triangle_normals, t, (what + " normals").c_str());
    expect_size(m.triangle_areas, t, (what + " areas").c_str());
    expect_size(m.triangle_force, t, (what + " triangle forces").c_str());
    expect_finite(m.vertices, (what + " vertices").c_str());
    expect_finite(m.vertex_velocities, (what + " vertex velocities").c_str());
    for (const auto& tri : m.triangles)
      for (std::uint32_t k : tri)
        if (k >= v) bad(what + " has a triangle with a vertex index out of range");
    if (s.driver.kind == SurfaceDriverKind::coupled && !s.driver.set_positions.empty()) {
      expect_size(s.driver.set_positions, v, (what + " coupled positions").c_str());
      expect_size(s.driver.set_velocities, v, (what + " coupled velocities").c_str());
      expect_finite(s.driver.set_positions, (what + " coupled positions").c_str());
      expect_finite(s.driver.set_velocities, (what + " coupled velocities").c_str());
    }
    if (!s.element_of_triangle.empty()) {
      expect_size(s.element_of_triangle, t, (what + " element map").c_str());
      for (std::uint32_t e : s.element_of_triangle)
        if (e >= s.element_count) bad(what + " maps a triangle to an element that does not exist");
    }
    validate_window(s.output_window, s, "output");
    validate_window(s.coupling_window, s, "coupling");
  }
}

// The world a checkpoint's spec and meshes describe (nothing read from the deck's files).
World rebuild_world(const std::string& spec_yaml, const std::string& deck_path, const std::vector<Surface>& meshes) {
  DeckParseOptions options;
  options.require_files = false;
  SimulationSpec spec = parse_deck_string(spec_yaml, deck_path.empty() ? "checkpoint" : deck_path, options);
  spec.deck_path = deck_path;
  return build_world(spec, meshes);
}

RestoredWorld read_payload(std::istream& in, std::uint64_t payload_bytes) {
  BinaryReader r(in, payload_bytes);
  const std::string deck_path = r.string();
  const std::string deck_text = r.string();
  const std::string spec_yaml = r.string();
  // The deck and its STL files, where they still exist, must be those the run was made from.
  if (!deck_text.empty()) {
    if (const std::optional<std::string> now = read_file(deck_path); now && *now != deck_text)
      throw UserError(SourceLocation{deck_path, 0, 0}, "the deck changed since the checkpoint was written",
                      "a restart continues the same simulation: restore the deck, or start a new run "
                      "(use --end-time to run a restart longer)");
  }
  const auto surface_count = r.value<std::uint64_t>();
  if (surface_count > 65535) bad("the surface count is implausible");
  std::vector<Surface> meshes(surface_count);
  std::vector<std::pair<std::string, std::uint64_t>> stl_hashes(surface_count);
  for (Surface& mesh : meshes) {
    r.vector(mesh.reference_vertices);
    r.vector(mesh.triangles);
  }
  for (auto& [file, hash] : stl_hashes) {
    file = r.string();
    hash = r.value<std::uint64_t>();
    if (!file.empty() && hash != 0 && fs::exists(file) && file_hash(file) != hash)
      throw UserError(SourceLocation{file, 0, 0}, "this mesh changed since the checkpoint was written",
                      "a restart continues the same simulation: restore the file, or start a new run");
  }
  for (const Surface& mesh : meshes)
    for (const auto& tri : mesh.triangles)
      for (std::uint32_t k : tri)
        if (k >= mesh.reference_vertices.size()) bad("a surface mesh has a vertex index out of range");
  RestoredWorld restored{rebuild_world(spec_yaml, deck_path, meshes), 0, {}};
  World& world = restored.world;
  if (world.surfaces.size() != surface_count) bad("the deck and the meshes disagree on the number of surfaces");
  Load load{r};
  transfer_state(load, world, restored.frame_index);
  // The attachments' sections: kept as bytes until the same attachments are made again.
  const auto sections = r.value<std::uint64_t>();
  if (sections > kMostSections) bad("the count of attached sections is implausible");
  restored.sections.resize(sections);
  std::set<std::string> names;
  for (SavedSection& section : restored.sections) {
    section.name = r.string();
    section.bytes = r.string();
    if (section.name.empty() || !names.insert(section.name).second)
      bad("an attached section has an empty or repeated name");
  }
  if (!r.at_end()) bad("bytes remain after the last section");
  validate(world);
  // The skin is the last build's (an automatic skin was chosen then; a fixed one is the deck's).
  if (world.pairs.builds > 0) world.skin = world.pairs.skin;
  // The triangles' bounds follow the restored vertices; the search grids of moving surfaces
  // are those of the last list build.
  for (WorldSurface& s : world.surfaces) {
    s.mesh.update_triangle_bounds();
    s.mesh.mark_step_loads();  // the last step's loads, cleared by the next contact stage
    if (s.moving()) build_search_grid(world, s);
  }
  world.initialized = true;
  return restored;
}

// A std::streambuf over bytes in memory (no copy).
struct MemoryBuffer : std::streambuf {
  MemoryBuffer(const char* data, std::size_t n) {
    char* begin = const_cast<char*>(data);
    setg(begin, begin, begin + n);
  }
};

UserError damaged(const std::string& name, const std::string& what) {
  return UserError(SourceLocation{name, 0, 0}, fmt::format("cannot restore checkpoint: {}", what),
                   "the file is damaged, truncated or not a Quarry checkpoint of this version; "
                   "restart from an earlier checkpoint or rerun from the deck");
}

Header parse_header(std::istream& in, std::uint64_t size, const std::string& name) {
  Header h;
  if (size < kHeaderBytes) throw damaged(name, fmt::format("the file has {} bytes, fewer than a header", size));
  BinaryReader r(in, kHeaderBytes);
  Load load{r};
  transfer_header(load, h);
  if (h.magic != kMagic) {
    if ((h.magic & 0x0000ffffffffffffull) == (kMagic & 0x0000ffffffffffffull))
      throw damaged(name, "it was written by another version of Quarry's checkpoint format");
    throw damaged(name, "it is not a Quarry checkpoint (wrong magic number)");
  }
  if (h.format != kFormat) throw damaged(name, fmt::format("format {} (this Quarry reads format {})", h.format, kFormat));
  if (h.reserved != 0 || h.reserved2 != 0) throw damaged(name, "the header's reserved fields are not zero");
  if (h.payload_bytes != size - kHeaderBytes)
    throw damaged(name, fmt::format("the header announces {} bytes of data but the file holds {} (truncated or extended)",
                                    h.payload_bytes, size - kHeaderBytes));
  return h;
}

RestoredWorld restore(std::istream& in, std::uint64_t size, const std::string& name,
                      const std::function<std::uint32_t()>& payload_crc) {
  const Header header = parse_header(in, size, name);
  if (payload_crc() != header.crc)
    throw damaged(name, "the checksum does not match the data (the file was changed or damaged)");
  try {
    return read_payload(in, header.payload_bytes);
  } catch (const UserError&) {
    throw;
  } catch (const std::exception& e) {
    throw damaged(name, e.what());
  }
}

}  // namespace

std::string checkpoint_bytes(const World& const_world, std::uint64_t frame_index) {
  if (!const_world.initialized)
    throw std::logic_error("checkpoint: the world is not initialized (sim::initialize first)");
  if (const_world.particles.apart_once_loads().any())
    throw std::logic_error("checkpoint: one-step loads are apart from the forces (sim::settle_once_loads first)");
  World& world = const_cast<World&>(const_world);  // the visit takes non-const fields
  BinaryWriter w;
  std::error_code ignored;
  const std::string deck_path =
      world.spec.deck_path.empty() ? std::string() : fs::absolute(world.spec.deck_path, ignored).string();
  w.string(deck_path);
  w.string(deck_path.empty() ? std::string() : read_file(deck_path).value_or(""));
  // A drag UDF's library path as the run resolved it, absolute: a restart may start elsewhere.
  SimulationSpec written = world.spec;
  if (written.fluid && written.fluid->drag_udf && !written.fluid->drag_udf->library.value.empty())
    written.fluid->drag_udf->library.value = fs::absolute(written.fluid->drag_udf->library.value, ignored).string();
  w.string(write_deck(written));
  w.value<std::uint64_t>(world.surfaces.size());
  for (const WorldSurface& s : world.surfaces) {
    w.vector(s.mesh.reference_vertices);
    w.vector(s.mesh.triangles);
  }
  for (std::size_t s = 0; s < world.surfaces.size(); ++s) {
    const SurfaceSpec& spec = world.spec.surfaces[s];
    const bool stl = spec.kind.value == SurfaceKind::stl;
    w.string(stl ? spec.file.value : std::string());
    w.value<std::uint64_t>(stl ? file_hash(spec.file.value) : 0);
  }
  Save save{w};
  transfer_state(save, world, frame_index);
  std::set<std::string> names;
  w.value<std::uint64_t>(world.checkpoint_sections.size());
  for (const CheckpointSection& section : world.checkpoint_sections) {
    if (section.name.empty() || !names.insert(section.name).second)
      throw std::logic_error("checkpoint: two sections named '" + section.name + "' (or one unnamed)");
    BinaryWriter part;
    section.save(world, part);
    w.string(section.name);
    w.string(part.bytes());
  }

  BinaryWriter file;
  Header header;
  header.payload_bytes = w.bytes().size();
  header.crc = crc32_of(w.bytes().data(), w.bytes().size());
  Save save_header{file};
  transfer_header(save_header, header);
  file.bytes() += w.bytes();
  return std::move(file.bytes());
}

void write_checkpoint(const World& world, const std::string& path, std::uint64_t frame_index) {
  write_file_atomically(path, checkpoint_bytes(world, frame_index));
}

RestoredWorld read_checkpoint(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error))
    throw UserError(SourceLocation{path, 0, 0}, "this is a folder, not a checkpoint file",
                    "give the path of a checkpoint.qck written by 'quarry run'");
  const std::uint64_t size = fs::file_size(path, error);
  std::ifstream in(path, std::ios::binary);
  if (error || !in)
    throw UserError(SourceLocation{path, 0, 0}, "cannot open checkpoint file",
                    "give the path of a checkpoint.qck written by 'quarry run'");
  // The checksum streams over the payload first (no copy of a file of gigabytes), then the
  // payload is read from its start.
  const auto payload_crc = [&] {
    std::ifstream again(path, std::ios::binary);
    again.seekg(static_cast<std::streamoff>(kHeaderBytes));
    std::vector<char> buffer(1 << 20);
    std::uint32_t crc = 0;
    while (again) {
      again.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      crc = crc32_of(buffer.data(), static_cast<std::size_t>(again.gcount()), crc);
    }
    return crc;
  };
  return restore(in, size, path, payload_crc);
}

RestoredWorld read_checkpoint_bytes(const std::string& bytes, const std::string& name) {
  MemoryBuffer buffer(bytes.data(), bytes.size());
  std::istream in(&buffer);
  const auto payload_crc = [&] {
    return bytes.size() < kHeaderBytes ? 0u : crc32_of(bytes.data() + kHeaderBytes, bytes.size() - kHeaderBytes);
  };
  return restore(in, bytes.size(), name, payload_crc);
}

void restore_sections(World& world, const std::vector<SavedSection>& sections, const std::string& file_name) {
  const auto saved = [&](const std::string& name) {
    return std::find_if(sections.begin(), sections.end(), [&](const SavedSection& s) { return s.name == name; });
  };
  for (const CheckpointSection& taker : world.checkpoint_sections)
    if (saved(taker.name) == sections.end())
      throw UserError(SourceLocation{file_name, 0, 0},
                      fmt::format("cannot restore checkpoint: it holds no '{}' state, which this restart needs",
                                  taker.name),
                      "the checkpoint was written by a run without it (another deck, or a program that did not "
                      "attach it): restart it the way it was run, or rerun from the deck");
  for (const SavedSection& section : sections) {
    const auto taker = std::find_if(world.checkpoint_sections.begin(), world.checkpoint_sections.end(),
                                    [&](const CheckpointSection& c) { return c.name == section.name; });
    if (taker == world.checkpoint_sections.end())
      throw UserError(SourceLocation{file_name, 0, 0},
                      fmt::format("cannot restore checkpoint: it holds '{}' state that nothing in this restart takes",
                                  section.name),
                      "restart it with 'quarry restart', which makes again what 'quarry run' attached (a deck's "
                      "fluid:); a program restoring it must attach the same before restore_sections");
    MemoryBuffer buffer(section.bytes.data(), section.bytes.size());
    std::istream in(&buffer);
    BinaryReader reader(in, section.bytes.size());
    try {
      taker->load(world, reader);
      if (!reader.at_end()) bad("bytes remain after its last field");
    } catch (const UserError&) {
      throw;
    } catch (const std::exception& e) {
      throw damaged(file_name, fmt::format("its '{}' section: {}", section.name, e.what()));
    }
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
  for (const WorldSurface& s : world.surfaces) {
    mix(s.mesh.triangle_force.data(), s.mesh.triangle_force.size() * sizeof(Vec3));
    mix(s.mesh.vertex_force.data(), s.mesh.vertex_force.size() * sizeof(Vec3));
  }
  return h;
}

}  // namespace quarry::sim
