// The POSIX shared-memory segment through which a remote client and `quarry serve` on one host
// pass bulk arrays (issue 16 §3): the client creates it per session and grows it in place; the
// server maps it at open and removes its name at once, so nothing outlives the two processes.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "api/wire.h"

namespace quarry::api {

class SharedSegment final : public wire::SegmentSpace {
 public:
  // The client's: a new segment "/quarry-<pid>-<n>-<random>" of `bytes` (mode 0600, the space
  // reserved so that a full /dev/shm is an error here and not a SIGBUS later). Throws
  // std::runtime_error naming the segment and the errno text.
  static std::unique_ptr<SharedSegment> create(std::uint64_t bytes);
  // The server's: maps the client's segment by name and removes the name (the memory stays
  // until both sides unmap it). Only names Quarry clients make are accepted.
  static std::unique_ptr<SharedSegment> attach(const std::string& name);
  ~SharedSegment() override;
  SharedSegment(const SharedSegment&) = delete;
  SharedSegment& operator=(const SharedSegment&) = delete;

  const std::string& name() const { return name_; }
  std::uint64_t size() const { return size_; }

  // Client: room for a request's arrays, 64-byte aligned, from the start of the segment after
  // each restart(); grows the segment (at least doubling it) when it must.
  std::uint64_t allocate(std::uint64_t bytes) override;
  std::byte* at(std::uint64_t offset) override { return data_ + offset; }
  void restart() { next_ = 0; }

  // Server: the view a wire::Reader resolves shared arrays in (re-mapped when the client grew
  // the segment). A re-map keeps the old mapping until release_retired(): the arrays of the
  // same request read before it still point there.
  wire::SegmentView& view() { return view_; }
  // Server, before each request: unmaps what re-maps left behind.
  void release_retired();

  // Removes the name now (no error if it is gone already).
  void unlink();

 private:
  SharedSegment() = default;
  void map(std::uint64_t bytes);
  static bool remap_to_file_size(void* self, std::uint64_t needed, wire::SegmentView& view);

  std::string name_;
  int fd_ = -1;
  std::byte* data_ = nullptr;
  std::uint64_t size_ = 0;
  std::uint64_t next_ = 0;
  bool named_ = false;
  wire::SegmentView view_;
  std::vector<std::pair<std::byte*, std::uint64_t>> retired_;  // old mappings (address, bytes)
};

}  // namespace quarry::api
