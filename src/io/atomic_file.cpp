// Atomic file replacement: temporary file + fsync + rename + folder fsync (POSIX).
#include "io/atomic_file.h"

#include "core/diagnostics.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace quarry {

namespace {

[[noreturn]] void throw_io_error(const std::string& what, const std::filesystem::path& path,
                                 int error_number) {
  throw FileError(fmt::format("cannot {} '{}': {}", what, path.string(), std::strerror(error_number)));
}

// Closes a file descriptor on every path out of a scope (errors from close on the success
// path are checked explicitly before this runs).
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  // Closes now and reports the errno of close (0 on success); NFS reports write errors here.
  int close_now() {
    const int result = ::close(fd_);
    fd_ = -1;
    return result == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

// Unique within this process (counter) and across processes (pid), so concurrent writers of
// different files in one folder never share a temporary.
std::filesystem::path temporary_path_for(const std::filesystem::path& target) {
  static std::atomic<unsigned long> counter{0};
  const unsigned long serial = counter.fetch_add(1, std::memory_order_relaxed);
  std::filesystem::path temporary = target;
  temporary += fmt::format(".tmp.{}.{}", static_cast<long>(::getpid()), serial);
  return temporary;
}

void write_all(int fd, std::string_view bytes, const std::filesystem::path& temporary) {
  const char* cursor = bytes.data();
  std::size_t remaining = bytes.size();
  while (remaining > 0) {
    const ssize_t written = ::write(fd, cursor, remaining);
    if (written < 0) {
      if (errno == EINTR) continue;
      throw_io_error("write", temporary, errno);
    }
    cursor += written;
    remaining -= static_cast<std::size_t>(written);
  }
}

void fsync_folder(const std::filesystem::path& folder, const std::filesystem::path& target) {
  const std::filesystem::path to_open = folder.empty() ? std::filesystem::path(".") : folder;
  FileDescriptor directory(::open(to_open.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (directory.get() < 0) throw_io_error("open the folder of", target, errno);
  // Some file systems (e.g. certain FUSE mounts) refuse fsync on a folder; the rename has
  // already happened, so only real I/O errors are reported.
  if (::fsync(directory.get()) != 0 && errno != EINVAL && errno != EROFS) {
    throw_io_error("fsync the folder of", target, errno);
  }
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
  if (path.empty() || !path.has_filename()) {
    throw FileError(fmt::format("cannot write '{}': not a file name", path.string()));
  }
  const std::filesystem::path folder = path.parent_path();
  if (!folder.empty()) {
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error) {
      throw FileError(fmt::format("cannot create the folder of '{}': {}", path.string(), error.message()));
    }
  }

  const std::filesystem::path temporary = temporary_path_for(path);
  FileDescriptor file(::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644));
  if (file.get() < 0) throw_io_error("create a temporary file for", path, errno);
  try {
    write_all(file.get(), bytes, temporary);
    if (::fsync(file.get()) != 0) throw_io_error("fsync", temporary, errno);
    if (const int close_error = file.close_now(); close_error != 0) {
      throw_io_error("close", temporary, close_error);
    }
    if (::rename(temporary.c_str(), path.c_str()) != 0) throw_io_error("replace", path, errno);
  } catch (...) {
    ::unlink(temporary.c_str());
    throw;
  }
  fsync_folder(folder, path);
}

std::optional<std::string> read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

}  // namespace quarry
