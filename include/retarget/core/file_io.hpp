#pragma once
/// File helpers shared by readers and writers.

#include <cstdint>
#include <string>
#include <vector>

namespace rt {

/// Reads a whole file. Throws InputError("<path>: cannot open: <errno text>") when it cannot be
/// read, when it is not a regular file (a folder, FIFO or device: refused without blocking) and
/// when it is larger than `max_bytes` (protects against absurd inputs).
std::string read_file(const std::string& path, std::uint64_t max_bytes = (1ull << 32));

/// The first `max_bytes` bytes of a file (content sniffing), with read_file's checks.
std::string read_file_prefix(const std::string& path, std::size_t max_bytes);

/// Throws the same InputError as read_file unless `path` names an existing regular file; for
/// readers that open the file themselves (a FIFO would block them on open).
void require_regular_file(const std::string& path);

/// Writes `content` to `path` atomically: a temporary file in the same folder is written, flushed
/// to disk and renamed over `path`, so a crash never leaves a half-written file under `path`.
/// Throws InputError when the folder is not writable.
void write_file_atomic(const std::string& path, const std::string& content);

/// Where a batch worker may read and write, checked where files are opened (a symlink created
/// or changed after the batch checked its paths must not lead outside): while a
/// ScopedPathConfinement lives on this thread, read_file()/read_file_prefix() of a path listed in
/// `confined_reads` fail unless the opened file's real path (its descriptor's /proc link) is
/// inside `read_root`, and write_file_atomic() fails unless the real folder it writes into is
/// inside `write_root`. Empty roots check nothing.
struct PathConfinement {
  std::string read_root;
  std::vector<std::string> confined_reads;  ///< exact paths as they will be opened
  std::string write_root;
};

class ScopedPathConfinement {
 public:
  explicit ScopedPathConfinement(PathConfinement confinement);
  ~ScopedPathConfinement();
  ScopedPathConfinement(const ScopedPathConfinement&) = delete;
  ScopedPathConfinement& operator=(const ScopedPathConfinement&) = delete;

 private:
  const PathConfinement* previous_;
  PathConfinement confinement_;
};

/// The file name without folders ("a/b/walk.bvh" -> "walk.bvh"), used in diagnostics.
std::string base_name(const std::string& path);

}  // namespace rt
