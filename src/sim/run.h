// Run loop: initializes a world, steps it to the end time with the output stage attached
// (frames, monitors, export, checkpoints), prints progress with an ETA, stops cleanly when asked
// (writing a checkpoint), and ends with a per-stage time table. Checkpoints: the whole state of a
// world in one file, from which it restarts bit-identically without the deck's files.
#pragma once

#include <atomic>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "sim/estimate.h"  // AttachToWorld
#include "sim/world.h"

namespace quarry::sim {

struct RunOptions {
  std::string output_directory;      // overrides output.directory when not empty
  std::optional<double> end_time;    // s, overrides simulation.end_time
  bool quiet = false;                // no progress lines
  int threads = 0;                   // > 0: overrides the deck's simulation.threads
  bool overwrite = false;            // a folder with an earlier run's output: replace its files
  // Run a step on one thread instead of several while that is measured to be faster (another
  // process busy on the cores; sim/thread_governor.h). Results are the same either way.
  bool adapt_threads = true;
  std::ostream* log = nullptr;       // progress/summary stream (default std::cerr)
  // Read after every step: non-zero (a signal number) asks the run to stop with a checkpoint.
  // The CLI's SIGINT/SIGTERM handler sets it; null: the run is never asked.
  const std::atomic<int>* stop = nullptr;
};

struct RunSummary {
  std::uint64_t steps = 0;           // steps taken in this call
  double simulated_time = 0.0;       // s, world time at the end
  double wall_seconds = 0.0;         // s
  std::size_t particles = 0;
  int stop_signal = 0;               // the signal that stopped the run (checkpoint written); 0: none
  std::string checkpoint;            // last checkpoint written, if any
  std::uint64_t final_state_hash = 0;  // state_hash() at the end (determinism checks)
  std::uint64_t steps_on_one_thread = 0;  // of `steps`, run on one thread by the governor
  bool interrupted() const { return stop_signal != 0; }
};

// Initializes a freshly built world and runs it from its current time.
RunSummary run(World& world, const RunOptions& options);
// Restores a checkpoint written by run() and continues; outputs go to the checkpoint's folder
// unless options say otherwise. The deck's files are not needed (the checkpoint holds the
// effective deck and the meshes); if the deck or an STL file still exists and has changed, that
// is an error: a restart continues the same simulation. `attach` makes on the restored world
// what the run attached beyond build_world (the CLI: the fluid of a fluid: section and the
// structures of a structures: section, as `quarry run` does); its checkpoint sections then get their state back (restore_sections) before the
// first step. A checkpoint with a section nothing attached takes, or an attachment with no
// section in the checkpoint, is a UserError.
RunSummary restart(const std::string& checkpoint_path, const RunOptions& options,
                   const AttachToWorld& attach = {});

// ---- checkpoints (checkpoint.cpp) ----
// Writes the whole state atomically. `frame_index`: the output's next frame number.
void write_checkpoint(const World& world, const std::string& path, std::uint64_t frame_index);
// A checkpoint section as read from the file (World::checkpoint_sections wrote it).
struct SavedSection {
  std::string name;
  std::string bytes;  // what its save wrote
};
struct RestoredWorld {
  World world;
  std::uint64_t frame_index = 0;
  // The sections of what was attached to the world, in the order they were written: given to
  // the same attachments made again (restore_sections); nothing in `world` holds them yet.
  std::vector<SavedSection> sections;
};
// Rebuilds the world a checkpoint was written from and restores its state; the world is
// complete (initialized). Throws UserError naming the file and what is wrong for a damaged,
// truncated or foreign file, or a changed deck or mesh.
RestoredWorld read_checkpoint(const std::string& path);
// The same from checkpoint bytes in memory (`name` for messages).
RestoredWorld read_checkpoint_bytes(const std::string& bytes, const std::string& name);
// The checkpoint as bytes (what write_checkpoint writes).
std::string checkpoint_bytes(const World& world, std::uint64_t frame_index);
// Hands each saved section to the entry of world.checkpoint_sections of the same name (the world
// restored from the checkpoint, with the run's attachments made again). Throws UserError naming
// `file_name`: "cannot restore checkpoint: …" for a section no entry takes, an entry with no
// section, or content its load refuses or does not read to its end. Cost: the sections' loads.
void restore_sections(World& world, const std::vector<SavedSection>& sections, const std::string& file_name);

// A hash of the particle state (ids, positions, velocities, angular velocities) and of the
// surfaces' per-element and per-node loads, for the determinism tests: equal hashes mean
// bit-identical states.
std::uint64_t state_hash(const World& world);

}  // namespace quarry::sim
