#include "retarget/core/file_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "retarget/core/error.hpp"

namespace rt {

namespace {

// "a FIFO", "a character device", ... for a file type that is not a regular file.
const char* file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

[[noreturn]] void throw_not_regular(const std::string& path, mode_t mode) {
  if (S_ISDIR(mode)) throw InputError(path, "is a folder, expected a file");
  throw InputError(path, std::string("is ") + file_kind(mode) + ", expected a regular file");
}

thread_local const PathConfinement* active_confinement = nullptr;

// The real path of an open descriptor (Linux /proc); "" when unknown.
std::string fd_real_path(int fd) {
  char buf[4096];
  const std::string link = "/proc/self/fd/" + std::to_string(fd);
  const ssize_t n = ::readlink(link.c_str(), buf, sizeof buf - 1);
  return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
}

// Canonical form of a root (symlinks resolved where it exists).
std::string canonical_root(const std::string& root) {
  if (root.empty()) return root;
  std::error_code ec;
  const std::filesystem::path r = std::filesystem::weakly_canonical(std::filesystem::absolute(root, ec), ec);
  return ec ? root : r.string();
}

bool inside(const std::string& root, const std::string& real) {
  if (real.empty()) return false;
  const std::filesystem::path rel = std::filesystem::path(real).lexically_relative(root);
  return !rel.empty() && rel.begin()->string() != ".." && !rel.is_absolute();
}

// Applies the read confinement to an opened file.
void check_read_fd(const std::string& path, int fd) {
  const PathConfinement* c = active_confinement;
  if (!c || c->read_root.empty()) return;
  if (std::find(c->confined_reads.begin(), c->confined_reads.end(), path) == c->confined_reads.end()) return;
  const std::string real = fd_real_path(fd);
  if (!inside(c->read_root, real))
    throw InputError(path, "resolves outside the input root " + c->read_root + " (to " + (real.empty() ? "an unknown path" : real) +
                               ", through a symlink); pass --allow-outside to accept it");
}

// Opens a file for reading with read_file's checks; returns the descriptor and its size.
int open_for_reading(const std::string& path, std::uint64_t& size) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; fstat then refuses anything but a
  // regular file (FIFO, device, folder), so a reader never blocks or reads /dev/zero forever.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  try {
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw_not_regular(path, st.st_mode);
    check_read_fd(path, fd);
    size = static_cast<std::uint64_t>(st.st_size);
  } catch (...) {
    ::close(fd);
    throw;
  }
  return fd;
}

struct Closer {
  int fd;
  ~Closer() { ::close(fd); }
};

}  // namespace

ScopedPathConfinement::ScopedPathConfinement(PathConfinement confinement)
    : previous_(active_confinement), confinement_(std::move(confinement)) {
  confinement_.read_root = canonical_root(confinement_.read_root);
  confinement_.write_root = canonical_root(confinement_.write_root);
  active_confinement = &confinement_;
}

ScopedPathConfinement::~ScopedPathConfinement() { active_confinement = previous_; }

std::string read_file_prefix(const std::string& path, std::size_t max_bytes) {
  std::uint64_t size = 0;
  const int fd = open_for_reading(path, size);
  Closer closer{fd};
  std::string data(static_cast<std::size_t>(std::min<std::uint64_t>(size, max_bytes)), '\0');
  std::size_t got = 0;
  while (got < data.size()) {
    const ssize_t n = ::read(fd, data.data() + got, data.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(path, std::string("cannot read: ") + std::strerror(errno));
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  data.resize(got);
  return data;
}

void require_regular_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw_not_regular(path, st.st_mode);
}

std::string read_file(const std::string& path, std::uint64_t max_bytes) {
  std::uint64_t size = 0;
  const int fd = open_for_reading(path, size);
  Closer closer{fd};
  if (size > max_bytes)
    throw InputError(path, "file is too large (" + std::to_string(size) + " bytes, limit " +
                               std::to_string(max_bytes) + ")");
  std::string data(static_cast<std::size_t>(size), '\0');
  std::size_t got = 0;
  while (got < data.size()) {
    const ssize_t n = ::read(fd, data.data() + got, data.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(path, std::string("cannot read: ") + std::strerror(errno));
    if (n == 0) break;  // the file shrank while we read it
    got += static_cast<std::size_t>(n);
  }
  data.resize(got);
  return data;
}

void write_file_atomic(const std::string& path, const std::string& content) {
  // The temporary and the rename go through a descriptor of the folder, so the folder checked
  // against the write confinement is the one written into even if a path component is swapped
  // for a symlink meanwhile; O_NOFOLLOW | O_EXCL: the temporary is never a planted symlink.
  const std::size_t slash = path.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const int dfd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
  Closer folder_closer{dfd};
  if (const PathConfinement* c = active_confinement; c && !c->write_root.empty()) {
    const std::string real = fd_real_path(dfd);
    if (!inside(c->write_root, real) && real != c->write_root)
      throw InputError(path, "the output path leads outside the output folder " + c->write_root + " (to " +
                                 (real.empty() ? "an unknown folder" : real) + ", through a symlink)");
  }
  // Unique temporary name in the same folder so that rename() is atomic on the same filesystem.
  std::random_device rd;
  const std::string tmp = name + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(rd());
  const int fd = ::openat(dfd, tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::close(fd);
      ::unlinkat(dfd, tmp.c_str(), 0);
      throw InputError(path, "cannot write: " + why);
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string why = std::strerror(errno);
    ::unlinkat(dfd, tmp.c_str(), 0);
    throw InputError(path, "cannot write: " + why);
  }
  if (::renameat(dfd, tmp.c_str(), dfd, name.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlinkat(dfd, tmp.c_str(), 0);
    throw InputError(path, "cannot write: " + why);
  }
}

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace rt
