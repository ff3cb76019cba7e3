#include "retarget/motion/load_motion.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/asf/asf_motion.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"
#include "retarget/motion/c3d/c3d_motion.hpp"
#include "retarget/motion/source_checks.hpp"

namespace rt {

namespace {

enum class Kind { Bvh, C3d, Amc, Asf, Unknown };

// By content first (a C3D header has 0x50 in its second byte; a BVH starts with HIERARCHY), so a
// misnamed file is still read correctly; then by extension.
Kind sniff(const std::string& path) {
  // read_file's checks: a FIFO, device or folder is refused without blocking, and a batch
  // worker's clip must still resolve inside the input root (ScopedPathConfinement).
  const std::string prefix = read_file_prefix(path, 512);
  const char* head = prefix.data();
  const std::size_t n = prefix.size();
  std::string_view text(head, n);
  if (n >= 3 && static_cast<unsigned char>(head[0]) == 0xEF && static_cast<unsigned char>(head[1]) == 0xBB &&
      static_cast<unsigned char>(head[2]) == 0xBF)
    text.remove_prefix(3);  // UTF-8 byte-order mark
  if (starts_with(trim(text), "HIERARCHY")) return Kind::Bvh;
  // AMC and ASF start with '#' comments or their first keyword.
  const std::string lower_head = to_lower(std::string(text));
  if (lower_head.find(":fully-specified") != std::string::npos || lower_head.find(":degrees") != std::string::npos)
    return Kind::Amc;
  if (lower_head.find(":version") != std::string::npos || lower_head.find(":bonedata") != std::string::npos) return Kind::Asf;
  if (n >= 2 && static_cast<unsigned char>(head[1]) == 0x50) return Kind::C3d;
  const std::string lower = to_lower(path);
  if (ends_with(lower, ".bvh")) return Kind::Bvh;
  if (ends_with(lower, ".c3d")) return Kind::C3d;
  if (ends_with(lower, ".amc")) return Kind::Amc;
  if (ends_with(lower, ".asf")) return Kind::Asf;
  return Kind::Unknown;
}

}  // namespace

HumanMotion load_motion(const std::string& path, const MotionLoadOptions& options) {
  HumanMotion m;
  switch (sniff(path)) {
    case Kind::Bvh: m = load_bvh_motion(path, options); break;
    case Kind::C3d: m = load_c3d_motion(path, options); break;
    case Kind::Amc: m = load_asf_amc_motion(path, options); break;
    case Kind::Asf:
      throw InputError(path, "this is an ASF skeleton: give the AMC motion file (its ASF is found beside it, or with --asf)");
    case Kind::Unknown:
      throw InputError(path, "unsupported motion file: expected a BVH (starts with HIERARCHY), a C3D or an AMC file (FBX is not read)");
  }
  if (!options.allow_implausible_stature) check_stature(m);
  if (!options.source_fps) check_frame_rate_against_data(m);
  return m;
}

}  // namespace rt
