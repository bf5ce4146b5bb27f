// What a coupled run leaves, written the same way by the built-in path (builtin_reference.cpp)
// and by the external partner (shell_partner.cpp), so that the test compares the two files
// byte for byte: every double as a hexadecimal float (%a: all 53 bits, no decimal rounding).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace quarry_partner {

struct Sync {
  double time = 0.0;                 // s, the DEM's time at the exchange
  std::array<double, 3> load{};      // N, Σ over nodes of the structure's loads for the next period
  std::uint64_t loads_hash = 0;      // FNV-1a of every node's load (all bits)
};

struct Particle {
  std::uint64_t id = 0;
  std::array<double, 3> position{}, velocity{};  // m, m/s
};

struct CouplingReport {
  std::vector<Sync> history;
  std::vector<std::array<double, 3>> node_position, node_velocity;  // m, m/s per solver node
  std::int64_t structure_steps = 0;
  std::vector<Particle> particles;  // sorted by id
};

inline std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t bytes) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < bytes; ++k) hash = (hash ^ b[k]) * 1099511628211ull;
  return hash;
}
constexpr std::uint64_t kFnvOffset = 1469598103934665603ull;

// Returns false if the file cannot be written.
inline bool write_report(const std::string& path, CouplingReport report) {
  std::sort(report.particles.begin(), report.particles.end(),
            [](const Particle& a, const Particle& b) { return a.id < b.id; });
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "syncs %zu nodes %zu structure_steps %lld particles %zu\n", report.history.size(),
               report.node_position.size(), static_cast<long long>(report.structure_steps), report.particles.size());
  for (const Sync& s : report.history)
    std::fprintf(f, "sync %a load %a %a %a hash %016llx\n", s.time, s.load[0], s.load[1], s.load[2],
                 static_cast<unsigned long long>(s.loads_hash));
  for (std::size_t n = 0; n < report.node_position.size(); ++n) {
    const auto& x = report.node_position[n];
    const auto& v = report.node_velocity[n];
    std::fprintf(f, "node %zu x %a %a %a v %a %a %a\n", n, x[0], x[1], x[2], v[0], v[1], v[2]);
  }
  for (const Particle& p : report.particles)
    std::fprintf(f, "particle %llu x %a %a %a v %a %a %a\n", static_cast<unsigned long long>(p.id), p.position[0],
                 p.position[1], p.position[2], p.velocity[0], p.velocity[1], p.velocity[2]);
  return std::fclose(f) == 0;
}

}  // namespace quarry_partner
