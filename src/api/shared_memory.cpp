// The shared-memory segment of a remote session (api/shared_memory.h): shm_open + mmap, grown
// with posix_fallocate so the space exists before either side touches it.
#include "api/shared_memory.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <random>
#include <stdexcept>

namespace quarry::api {

namespace {

constexpr const char* kPrefix = "/quarry-";
constexpr std::uint64_t kPage = 4096;     // bytes; sizes are whole pages
constexpr std::uint64_t kAlignment = 64;  // bytes: a cache line, and every element type's

std::runtime_error system_error(const std::string& what, int error) {
  return std::runtime_error(fmt::format("{}: {}", what, std::strerror(error)));
}

std::uint64_t round_up(std::uint64_t value, std::uint64_t to) {
  return (value + to - 1) / to * to;
}

}  // namespace

std::unique_ptr<SharedSegment> SharedSegment::create(std::uint64_t bytes) {
  static std::atomic<unsigned> counter{0};
  std::unique_ptr<SharedSegment> segment(new SharedSegment);
  segment->name_ =
      fmt::format("{}{}-{}-{:08x}", kPrefix, ::getpid(), counter++, std::random_device{}());
  segment->fd_ = ::shm_open(segment->name_.c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
  if (segment->fd_ < 0) throw system_error("shm_open " + segment->name_, errno);
  segment->named_ = true;
  segment->map(round_up(bytes, kPage));
  return segment;
}

std::unique_ptr<SharedSegment> SharedSegment::attach(const std::string& name) {
  if (name.rfind(kPrefix, 0) != 0 || name.size() > 200 || name.find('/', 1) != std::string::npos)
    throw std::runtime_error(
        fmt::format("'{}' is not the name of a Quarry client's segment ({}...)", name, kPrefix));
  std::unique_ptr<SharedSegment> segment(new SharedSegment);
  segment->name_ = name;
  segment->fd_ = ::shm_open(name.c_str(), O_RDWR, 0);
  if (segment->fd_ < 0) throw system_error("shm_open " + name, errno);
  ::shm_unlink(name.c_str());  // from now on only the two mappings hold it
  struct stat status {};
  if (::fstat(segment->fd_, &status) != 0) throw system_error("fstat " + name, errno);
  segment->data_ = nullptr;
  if (status.st_size > 0) {
    void* data =
        ::mmap(nullptr, status.st_size, PROT_READ | PROT_WRITE, MAP_SHARED, segment->fd_, 0);
    if (data == MAP_FAILED) throw system_error("mmap " + name, errno);
    segment->data_ = static_cast<std::byte*>(data);
    segment->size_ = static_cast<std::uint64_t>(status.st_size);
  }
  segment->view_ = wire::SegmentView{segment->data_, segment->size_,
                                     &SharedSegment::remap_to_file_size, segment.get()};
  return segment;
}

SharedSegment::~SharedSegment() {
  release_retired();
  if (data_) ::munmap(data_, size_);
  if (fd_ >= 0) ::close(fd_);
  unlink();
}

void SharedSegment::release_retired() {
  for (const auto& [data, size] : retired_) ::munmap(data, size);
  retired_.clear();
}

void SharedSegment::unlink() {
  if (named_) ::shm_unlink(name_.c_str());
  named_ = false;
}

void SharedSegment::map(std::uint64_t bytes) {
  // posix_fallocate returns the error (it does not set errno).
  if (const int error = ::posix_fallocate(fd_, 0, static_cast<off_t>(bytes)); error != 0)
    throw system_error(
        fmt::format("reserving {} bytes of shared memory for {} (is /dev/shm full?)", bytes, name_),
        error);
  void* data = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
  if (data == MAP_FAILED) throw system_error("mmap " + name_, errno);
  if (data_) ::munmap(data_, size_);
  data_ = static_cast<std::byte*>(data);
  size_ = bytes;
}

std::uint64_t SharedSegment::allocate(std::uint64_t bytes) {
  const std::uint64_t offset = round_up(next_, kAlignment);
  if (bytes > size_ || offset > size_ - bytes)
    map(round_up(std::max(offset + bytes, 2 * size_), kPage));
  next_ = offset + bytes;
  return offset;
}

bool SharedSegment::remap_to_file_size(void* self, std::uint64_t needed, wire::SegmentView& view) {
  auto& segment = *static_cast<SharedSegment*>(self);
  struct stat status {};
  if (::fstat(segment.fd_, &status) != 0 || static_cast<std::uint64_t>(status.st_size) < needed)
    return false;
  void* data = ::mmap(nullptr, status.st_size, PROT_READ | PROT_WRITE, MAP_SHARED, segment.fd_, 0);
  if (data == MAP_FAILED) return false;
  if (segment.data_) segment.retired_.emplace_back(segment.data_, segment.size_);
  segment.data_ = static_cast<std::byte*>(data);
  segment.size_ = static_cast<std::uint64_t>(status.st_size);
  view.data = segment.data_;
  view.size = segment.size_;
  return true;
}

}  // namespace quarry::api
