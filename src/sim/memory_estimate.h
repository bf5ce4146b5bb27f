// The memory a deck will need, estimated from the deck alone before anything is allocated, and
// the refusal of a deck that cannot fit in this machine (issue 19: `count: 2000000000` passed
// `check`, then allocated until the kernel killed it; a cylinder of resolution 10000 needed
// 13 GB). The bytes per particle and per triangle are measured figures (docs/errors.md).
#pragma once

#include <cstdint>
#include <string>

#include "core/diagnostics.h"
#include "core/simulation_spec.h"

namespace quarry::sim {

// Measured peak resident memory of whole runs, per item (docs/errors.md, "Memory"): a
// two-million-particle fill 515 B/particle (vectors grown by doubling), a settled bed with its
// contacts 400 B/particle, plus a frame being written 148 B/particle; a drum of 1.27 M
// triangles in `check` 314 B/triangle (mesh, welded topology, search grid). Since then each
// listed pair keeps its last normal force (8 B; 6–8 pairs a particle in a bed): counted, not
// measured, as 60 B/particle more.
inline constexpr double kBytesPerParticle = 760.0;
inline constexpr double kBytesPerTriangle = 320.0;
// The program itself with nothing in it: `check` of a deck with 12,600 triangles peaked at
// 20.0 MB, 4 MB of them the triangles.
inline constexpr double kBaseBytes = 16e6;

struct MemoryEstimate {
  double particles = 0.0;  // expected at most (each factory's count, or its mass over the mean
                           // particle mass)
  double triangles = 0.0;  // of all surfaces (STL: from the file size)
  double bytes = 0.0;      // kBaseBytes + particles · kBytesPerParticle + triangles · kBytesPerTriangle
  // The single largest item (a factory or a surface), for the message and its location.
  std::string largest;
  SourceLocation largest_where;
  double largest_bytes = 0.0;
};

// Pre: the spec passed parse_deck. Cost: O(factories + surfaces) and one stat() per STL file.
MemoryEstimate estimate_memory(const SimulationSpec& spec);

// "420 MB", "1.42 GB": bytes as a person reads them (decimal units).
std::string format_bytes(double bytes);

// This machine's memory (bytes): physical memory, or the control group's limit when lower.
std::uint64_t machine_memory_bytes();

// Throws UserError (at the largest item's location, with the estimate, its parts and the
// machine's memory) when the estimate exceeds `available` bytes. Returns the estimate.
MemoryEstimate refuse_if_it_cannot_fit(const SimulationSpec& spec,
                                       std::uint64_t available = machine_memory_bytes());

}  // namespace quarry::sim
