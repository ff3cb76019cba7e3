// Seeded mutation fuzzing of the C3D reader and the C3D -> HumanMotion conversion: every mutant
// of the real files and of synthetic files must either load or fail with rt::InputError, never
// crash, hang, allocate absurdly or return non-finite landmarks. Deterministic seed; bounded by
// an iteration count and a wall-clock budget so that it stays a few seconds even under ASan.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <random>

#include "c3d_test_writer.hpp"
#include "formats/c3d/c3d_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/motion/c3d/c3d_motion.hpp"
#include "support/test_paths.hpp"
#include "synthetic_walker.hpp"

namespace rt {
namespace {

struct Seed {
  std::string name;
  std::string bytes;
};

std::vector<Seed> seeds() {
  std::vector<Seed> out;
  test::Walker walker;
  walker.frames = 60;
  walker.absent_leading = 5;
  for (auto [p, flt] : {std::pair{c3d::Processor::Intel, true}, std::pair{c3d::Processor::Dec, true},
                        std::pair{c3d::Processor::Mips, false}, std::pair{c3d::Processor::Intel, false}}) {
    test::C3dSpec s = walker.spec([](const std::string& n, int f) { return n == "LKNE" && f > 20 && f < 30; });
    s.processor = p;
    s.float_storage = flt;
    s.int_scale = 0.5;
    s.analog_channels = 2;
    s.analog_samples_per_frame = 3;
    s.events = {{"Foot Strike", 0.2}};
    s.labels_per_parameter = 20;
    out.push_back({"synthetic.c3d", test::write_c3d(s).bytes});
  }
  for (const char* f : {"c3d/c3dorg_sample01_Eb015pi_intel_int.c3d", "c3d/c3dorg_sample01_Eb015vr_dec_real.c3d",
                        "c3d/c3dorg_sample01_Eb015si_sgi_int.c3d", "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d",
                        "c3d/btk_mocap36_optitrack_fullbody.c3d", "c3d/c3dorg_sample20_phasespace_noparams.c3d",
                        "c3d/opensim_walking2_gait_forceplates.c3d", "c3d/ezc3d_Qualisys_fullbody_forceplates.c3d"}) {
    const std::string path = test::shared_data(f);
    if (!path.empty()) out.push_back({f, read_file(path)});
  }
  return out;
}

void mutate(std::string& b, std::mt19937_64& rng) {
  auto uniform = [&](std::size_t n) { return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng() % n); };
  // Most of the structure lives in the first blocks (header and parameters): mutate there more.
  auto where = [&]() {
    const std::size_t head = std::min<std::size_t>(b.size(), 4096);
    return (rng() % 4 != 0) ? uniform(head) : uniform(b.size());
  };
  static constexpr std::uint16_t kInteresting[] = {0, 1, 2, 3, 0x50, 0x7f, 0x80, 0xff, 0x100, 0x7fff, 0x8000, 0xffff, 12345};
  const int ops = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < ops && !b.empty(); ++k) {
    switch (rng() % 7) {
      case 0:  // flip bits
        b[where()] ^= static_cast<char>(1u << (rng() % 8));
        break;
      case 1:  // random byte
        b[where()] = static_cast<char>(rng());
        break;
      case 2: {  // interesting 16-bit word
        const std::size_t at = where();
        if (at + 1 < b.size()) {
          const std::uint16_t v = kInteresting[rng() % (sizeof kInteresting / sizeof kInteresting[0])];
          b[at] = static_cast<char>(v & 0xff);
          b[at + 1] = static_cast<char>(v >> 8);
        }
        break;
      }
      case 3:  // truncate
        b.resize(uniform(b.size()));
        break;
      case 4: {  // NaN / Inf / huge float somewhere in the data
        const std::size_t at = uniform(b.size()) & ~std::size_t{3};
        const float vals[] = {NAN, INFINITY, -INFINITY, 3e38f, -1.0f, 0.0f};
        const float v = vals[rng() % 6];
        if (at + 4 <= b.size()) std::memcpy(&b[at], &v, 4);
        break;
      }
      case 5: {  // delete a chunk
        const std::size_t at = where();
        b.erase(at, std::min<std::size_t>(1 + uniform(16), b.size() - at));
        break;
      }
      default: {  // duplicate a chunk
        const std::size_t at = where();
        const std::size_t n = std::min<std::size_t>(1 + uniform(16), b.size() - at);
        b.insert(at, b.substr(at, n));
        break;
      }
    }
  }
}

TEST(C3dFuzz, MutantsLoadOrFailWithInputError) {
  const std::vector<Seed> corpus = seeds();
  std::mt19937_64 rng(0xC3D5EED);
  const auto start = std::chrono::steady_clock::now();
#if defined(__SANITIZE_ADDRESS__)
  // Unoptimised sanitizer builds run Eigen ~50x slower: a longer budget, and real-file mutants
  // (1 MB each) only decoded, except one in four that is also converted to a motion.
  const auto budget = std::chrono::milliseconds(6000);
  const int convert_real_every = 4;
  const int min_iterations = 50;
#else
  const auto budget = std::chrono::milliseconds(2500);
  const int convert_real_every = 1;
  const int min_iterations = 500;
#endif
  int iterations = 0, decoded = 0, converted = 0, rejected = 0, real = 0;
  for (; iterations < 4000 && std::chrono::steady_clock::now() - start < budget; ++iterations) {
    // Synthetic seeds are small and fast; real files are visited one time in five.
    const std::size_t synthetic = 4;
    const std::size_t pick = (rng() % 5 == 0 && corpus.size() > synthetic) ? synthetic + rng() % (corpus.size() - synthetic)
                                                                             : rng() % synthetic;
    std::string bytes = corpus[pick].bytes;
    mutate(bytes, rng);
    const std::string name = "mutant" + std::to_string(iterations) + "_" + corpus[pick].name.substr(corpus[pick].name.rfind('/') + 1);
    try {
      Diagnostics diag;
      const c3d::C3dFile f = c3d::parse_c3d(bytes, name, &diag);
      ++decoded;
      if (pick >= synthetic && real++ % convert_real_every != 0) continue;
      const HumanMotion m = c3d_to_motion(f, MotionLoadOptions{}, diag);
      ++converted;
      for (Landmark l : all_landmarks()) {
        if (!m.has(l)) continue;
        ASSERT_TRUE(m[l].p_W.allFinite()) << name << " " << landmark_name(l);
        ASSERT_EQ(m[l].p_W.cols(), m.num_frames);
      }
    } catch (const InputError& e) {
      ++rejected;
      const std::string what = e.what();
      ASSERT_EQ(what.find('\n'), std::string::npos) << what;
    } catch (const std::exception& e) {
      FAIL() << name << " (seed " << corpus[pick].name << ", iteration " << iterations << "): " << typeid(e).name()
             << ": " << e.what();
    }
  }
  RecordProperty("iterations", iterations);
  RecordProperty("converted", converted);
  EXPECT_GE(iterations, min_iterations);
  EXPECT_GT(rejected, 0);
  EXPECT_GT(decoded, rejected / 10);  // the mutations are not all fatal: deep paths are reached
  std::printf("[ fuzz     ] %d mutants: %d decoded, %d converted to motion, %d rejected with InputError\n", iterations,
              decoded, converted, rejected);
}

}  // namespace
}  // namespace rt
