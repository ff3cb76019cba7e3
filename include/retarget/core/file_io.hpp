#pragma once
/// File helpers shared by readers and writers.

#include <cstdint>
#include <string>

namespace rt {

/// Reads a whole file. Throws InputError("<path>: cannot open: <errno text>") when it cannot be
/// read, when it is not a regular file (a folder, FIFO or device: refused without blocking) and
/// when it is larger than `max_bytes` (protects against absurd inputs).
std::string read_file(const std::string& path, std::uint64_t max_bytes = (1ull << 32));

/// Throws the same InputError as read_file unless `path` names an existing regular file; for
/// readers that open the file themselves (a FIFO would block them on open).
void require_regular_file(const std::string& path);

/// Writes `content` to `path` atomically: a temporary file in the same folder is written, flushed
/// to disk and renamed over `path`, so a crash never leaves a half-written file under `path`.
/// Throws InputError when the folder is not writable.
void write_file_atomic(const std::string& path, const std::string& content);

/// The file name without folders ("a/b/walk.bvh" -> "walk.bvh"), used in diagnostics.
std::string base_name(const std::string& path);

}  // namespace rt
