// Nodal-force history on disk: one record (time, 3 forces per node) appended per export
// interval, so that the CalculiX *AMPLITUDE curves can be written at the end of a run of any
// length with bounded memory. Little-endian float64; header "QNFHIST1" + node count (uint64).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <vector>

#include "core/vec3.h"

namespace quarry::fem_export {

class NodalHistoryWriter {
 public:
  // Fresh (resume_time empty): creates or replaces `path`. Resume: opens the existing file,
  // keeps the records with time ≤ *resume_time (s) and drops later ones (written after the
  // checkpoint a restarted run continues from); a missing file starts fresh.
  // Throws std::runtime_error naming the file on I/O errors or a node-count mismatch.
  NodalHistoryWriter(std::filesystem::path path, std::size_t node_count,
                     std::optional<double> resume_time);
  // Appends one record. Pre: nodal_force.size() == node_count. Cost: one write of 24·n bytes.
  void append(double time, std::span<const Vec3> nodal_force);
  void flush();
  std::size_t frame_count() const { return frames_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::size_t node_count_ = 0;
  std::size_t frames_ = 0;
  std::ofstream out_;
  std::vector<double> buffer_;
};

class NodalHistoryReader {
 public:
  // Opens a history; throws std::runtime_error naming the file if it is missing or malformed.
  explicit NodalHistoryReader(std::filesystem::path path);
  std::size_t node_count() const { return node_count_; }
  std::size_t frame_count() const { return frames_; }
  // Time (s) of every record. Cost: one 8-byte read per record.
  std::vector<double> times();
  // Nodal forces (N) of record `frame` (< frame_count()).
  void read_frame(std::size_t frame, std::vector<Vec3>& forces);
  // Forces of nodes [first, first+count) in every record, frame-major:
  // out[frame·count + k] = force on node first+k. Memory: 24·count·frames bytes.
  void read_nodes(std::size_t first, std::size_t count, std::vector<Vec3>& out);

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  std::size_t node_count_ = 0;
  std::size_t frames_ = 0;
};

}  // namespace quarry::fem_export
