// Streamed nodal-force history (see nodal_history.h): fixed-size records, so that any record
// or any node's column is found by offset arithmetic without an index.
#include "export/nodal_history.h"

#include <bit>
#include <cstring>
#include <stdexcept>

namespace quarry::fem_export {

namespace {

static_assert(std::endian::native == std::endian::little, "history files are little-endian");
constexpr char kMagic[8] = {'Q', 'N', 'F', 'H', 'I', 'S', 'T', '1'};
constexpr std::size_t kHeaderBytes = 16;

std::size_t record_bytes(std::size_t node_count) { return 8 * (1 + 3 * node_count); }

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw std::runtime_error("nodal force history " + path.string() + ": " + what);
}

// Reads the header; returns the node count and the number of complete records.
std::pair<std::size_t, std::size_t> read_header(std::ifstream& in,
                                                const std::filesystem::path& path) {
  char magic[8];
  std::uint64_t nodes = 0;
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&nodes), 8);
  if (!in || std::memcmp(magic, kMagic, 8) != 0) fail(path, "not a Quarry history file");
  const std::uintmax_t size = std::filesystem::file_size(path);
  return {static_cast<std::size_t>(nodes),
          static_cast<std::size_t>((size - kHeaderBytes) / record_bytes(nodes))};
}

}  // namespace

NodalHistoryWriter::NodalHistoryWriter(std::filesystem::path path, std::size_t node_count,
                                       std::optional<double> resume_time)
    : path_(std::move(path)), node_count_(node_count), buffer_(1 + 3 * node_count) {
  std::error_code ignored;
  if (resume_time && std::filesystem::exists(path_, ignored)) {
    NodalHistoryReader reader(path_);
    if (reader.node_count() != node_count_)
      fail(path_, "written for " + std::to_string(reader.node_count()) + " nodes, the mesh has " +
                      std::to_string(node_count_));
    const std::vector<double> times = reader.times();
    while (frames_ < times.size() && times[frames_] <= *resume_time) ++frames_;
    // Also cuts a partial record left by a crash.
    std::filesystem::resize_file(path_, kHeaderBytes + frames_ * record_bytes(node_count_));
    out_.open(path_, std::ios::binary | std::ios::app);
  } else {
    out_.open(path_, std::ios::binary | std::ios::trunc);
    const std::uint64_t nodes = node_count_;
    out_.write(kMagic, 8);
    out_.write(reinterpret_cast<const char*>(&nodes), 8);
  }
  if (!out_) fail(path_, "cannot open for writing");
}

void NodalHistoryWriter::append(double time, std::span<const Vec3> nodal_force) {
  if (nodal_force.size() != node_count_) fail(path_, "record with the wrong node count");
  buffer_[0] = time;
  for (std::size_t n = 0; n < node_count_; ++n) {
    buffer_[1 + 3 * n] = nodal_force[n].x;
    buffer_[2 + 3 * n] = nodal_force[n].y;
    buffer_[3 + 3 * n] = nodal_force[n].z;
  }
  out_.write(reinterpret_cast<const char*>(buffer_.data()),
             static_cast<std::streamsize>(buffer_.size() * 8));
  if (!out_) fail(path_, "write failed (disk full?)");
  ++frames_;
}

void NodalHistoryWriter::flush() {
  out_.flush();
  if (!out_) fail(path_, "write failed (disk full?)");
}

NodalHistoryReader::NodalHistoryReader(std::filesystem::path path)
    : path_(std::move(path)), in_(path_, std::ios::binary) {
  if (!in_) fail(path_, "cannot open");
  std::tie(node_count_, frames_) = read_header(in_, path_);
}

std::vector<double> NodalHistoryReader::times() {
  std::vector<double> times(frames_);
  for (std::size_t f = 0; f < frames_; ++f) {
    in_.seekg(static_cast<std::streamoff>(kHeaderBytes + f * record_bytes(node_count_)));
    in_.read(reinterpret_cast<char*>(&times[f]), 8);
  }
  if (!in_) fail(path_, "read failed");
  return times;
}

void NodalHistoryReader::read_frame(std::size_t frame, std::vector<Vec3>& forces) {
  if (frame >= frames_) fail(path_, "record out of range");
  forces.assign(node_count_, {});
  std::vector<double> values(3 * node_count_);
  in_.seekg(static_cast<std::streamoff>(kHeaderBytes + frame * record_bytes(node_count_) + 8));
  in_.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(values.size() * 8));
  if (!in_) fail(path_, "read failed");
  for (std::size_t n = 0; n < node_count_; ++n)
    forces[n] = {values[3 * n], values[3 * n + 1], values[3 * n + 2]};
}

void NodalHistoryReader::read_nodes(std::size_t first, std::size_t count, std::vector<Vec3>& out) {
  if (first + count > node_count_) fail(path_, "node range out of range");
  out.assign(frames_ * count, {});
  std::vector<double> values(3 * count);
  for (std::size_t f = 0; f < frames_; ++f) {
    in_.seekg(static_cast<std::streamoff>(kHeaderBytes + f * record_bytes(node_count_) + 8 +
                                          24 * first));
    in_.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(values.size() * 8));
    if (!in_) fail(path_, "read failed");
    for (std::size_t k = 0; k < count; ++k)
      out[f * count + k] = {values[3 * k], values[3 * k + 1], values[3 * k + 2]};
  }
}

}  // namespace quarry::fem_export
