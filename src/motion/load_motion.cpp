#include "retarget/motion/load_motion.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"
#include "retarget/motion/c3d/c3d_motion.hpp"

namespace rt {

namespace {

enum class Kind { Bvh, C3d, Unknown };

// By content first (a C3D header has 0x50 in its second byte; a BVH starts with HIERARCHY), so a
// misnamed file is still read correctly; then by extension.
Kind sniff(const std::string& path) {
  require_regular_file(path);  // a FIFO would block the open below; /dev/zero is no clip
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  char head[64] = {};
  in.read(head, sizeof head);
  const std::size_t n = static_cast<std::size_t>(in.gcount());
  std::string_view text(head, n);
  if (n >= 3 && static_cast<unsigned char>(head[0]) == 0xEF && static_cast<unsigned char>(head[1]) == 0xBB &&
      static_cast<unsigned char>(head[2]) == 0xBF)
    text.remove_prefix(3);  // UTF-8 byte-order mark
  if (starts_with(trim(text), "HIERARCHY")) return Kind::Bvh;
  if (n >= 2 && static_cast<unsigned char>(head[1]) == 0x50) return Kind::C3d;
  const std::string lower = to_lower(path);
  if (ends_with(lower, ".bvh")) return Kind::Bvh;
  if (ends_with(lower, ".c3d")) return Kind::C3d;
  return Kind::Unknown;
}

}  // namespace

HumanMotion load_motion(const std::string& path, const MotionLoadOptions& options) {
  switch (sniff(path)) {
    case Kind::Bvh: return load_bvh_motion(path, options);
    case Kind::C3d: return load_c3d_motion(path, options);
    case Kind::Unknown: break;
  }
  throw InputError(path, "unsupported motion file: expected a BVH (starts with HIERARCHY) or a C3D file");
}

}  // namespace rt
