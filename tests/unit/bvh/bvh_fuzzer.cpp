// libFuzzer entry point for the BVH reader and the BVH -> HumanMotion conversion (clang only; see
// CMakeLists.txt). Any exception other than rt::InputError escapes and is reported as a crash.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "formats/bvh/bvh_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const rt::BvhFile file = rt::parse_bvh(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.bvh");
    (void)rt::bvh_to_human_motion(file);
  } catch (const rt::InputError&) {
  }
  return 0;
}
