// libFuzzer entry point for the C3D reader and the C3D -> HumanMotion conversion (built only with
// clang; see CMakeLists.txt). Any exception other than rt::InputError aborts the run.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "formats/c3d/c3d_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/c3d/c3d_motion.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    rt::Diagnostics diag;
    const rt::c3d::C3dFile f =
        rt::c3d::parse_c3d(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.c3d", &diag);
    rt::c3d_to_motion(f, rt::MotionLoadOptions{}, diag);
  } catch (const rt::InputError&) {
  }
  return 0;
}
