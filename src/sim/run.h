// The run loop: steps the world to the end time, writes ParaView frames, monitor CSV rows,
// plots and checkpoints when due, prints progress with an ETA, stops cleanly on SIGINT/SIGTERM
// (writing a checkpoint), and ends with a per-stage time table.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

#include "sim/world.h"

namespace quarry::sim {

struct RunOptions {
  std::string output_directory;      // overrides output.directory when not empty
  std::optional<double> end_time;    // s, overrides simulation.end_time
  bool quiet = false;                // no progress lines
  std::ostream* log = nullptr;       // progress/summary stream (default std::cerr)
};

struct RunSummary {
  std::uint64_t steps = 0;           // steps taken in this call
  std::uint64_t steps_opened_ahead = 0;  // of those, steps whose force stage also opened the next
  double simulated_time = 0.0;       // s, world time at the end
  double wall_seconds = 0.0;         // s
  std::size_t particles = 0;
  bool interrupted = false;          // stopped by a signal (checkpoint written)
  std::string checkpoint;            // last checkpoint written, if any
  std::uint64_t final_state_hash = 0;  // state_hash() at the end (determinism checks)
};

// Runs a freshly built world from its current time.
RunSummary run(World& world, const RunOptions& options);
// Loads a checkpoint written by run() (the deck it names is parsed again) and continues.
RunSummary restart(const std::string& checkpoint_path, const RunOptions& options);

// Checkpoints (checkpoint.cpp): the whole dynamic state, so a restart continues bit-identically.
void write_checkpoint(const World& world, const std::string& path, std::uint64_t frame_index);
// Restores the dynamic state into a world built from the same deck; returns the frame index.
std::uint64_t read_checkpoint(World& world, const std::string& path);
// Reads only the deck path stored in a checkpoint.
std::string checkpoint_deck_path(const std::string& path);

// A hash of the particle state (ids, positions, velocities, angular velocities) and of the
// surfaces' per-element and per-node loads, for the determinism tests: equal hashes mean
// bit-identical states.
std::uint64_t state_hash(const World& world);

}  // namespace quarry::sim
