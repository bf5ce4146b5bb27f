// Atomic file replacement for every output Quarry writes (VTU, PVD, CSV, PNG, checkpoints):
// readers and crashes only ever see the old file or the complete new one, never a half file.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace quarry {

// Replaces `path` with exactly `bytes`.
// How: writes a uniquely named temporary file in the same folder, fsyncs it, renames it over
// the target (POSIX rename within one file system is atomic) and fsyncs the folder so the
// rename itself survives a power loss. Missing parent folders are created.
// Post: on success the file holds `bytes` and no temporary remains; on failure the target is
// untouched, the temporary is removed, and std::runtime_error names the path and strerror.
// Cost: one write of the bytes plus two fsyncs (milliseconds on disks; keep calls per output
// interval, not per step). Thread-safe for distinct paths.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// The whole content of `path` (binary), or nothing if it cannot be opened. Cost: one read.
std::optional<std::string> read_file(const std::filesystem::path& path);

}  // namespace quarry
