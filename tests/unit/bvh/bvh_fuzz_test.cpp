// Seeded mutation fuzzing of the BVH reader and the BVH -> HumanMotion conversion: mutants of
// small inline clips and of the first rows of every real clip must either load or throw
// rt::InputError with a located one-line message; anything else (another exception type, a crash,
// a sanitizer report, a hang) fails. Deterministic: fixed seed and mutant count (override with
// RT_FUZZ_MUTANTS); a wall-clock cap keeps slow (sanitizer) builds bounded.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <typeinfo>

#include "bvh_test_clips.hpp"
#include "formats/bvh/bvh_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

// The hierarchy and the first `rows` motion rows of a clip, with `Frames:` set to match.
std::string head_of_clip(const std::string& text, int rows) {
  const auto frames = text.find("Frames:");
  const auto time = text.find("Frame Time:");
  if (frames == std::string::npos || time == std::string::npos) return text;
  std::size_t end = text.find('\n', time);
  for (int r = 0; r < rows && end != std::string::npos; ++r) end = text.find('\n', end + 1);
  std::string out = text.substr(0, end == std::string::npos ? text.size() : end + 1);
  const auto eol = out.find_first_of("\r\n", frames);
  out.replace(frames, eol - frames, "Frames: " + std::to_string(rows));
  return out;
}

std::vector<std::string> seeds() {
  std::vector<std::string> s = {test::kTinyBvh};
  test::HumanoidClip c;
  c.frames = 12;
  c.tpose_frames = 1;
  s.push_back(test::make_humanoid_bvh(c));
  c.up = 'z';
  c.metres_per_unit = 0.0254;
  c.prefix = "mixamorig:";
  s.push_back(test::make_humanoid_bvh(c));
  const std::string dir = test::shared_data("bvh");
  if (!dir.empty())
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".bvh") s.push_back(head_of_clip(read_file(e.path().string()), 24));
  return s;
}

const char* kTokens[] = {"nan",   "inf",      "-1e999",  "1e308",  "",          "{",         "}",
                         "JOINT", "End",      "Site",    "OFFSET", "CHANNELS",  "MOTION",    "Frames:",
                         "ROOT",  "99999999999", "-0",  "1.2.3",  "0x10",      "Xrotation", "Zposition",
                         "6",     "0",        "2147483647", "-7", "+",         "e5",        "1e-400",
                         "\t",    "\r",       "\r\n",    "Frame Time:", "HIERARCHY", "\xff\xfe", "Hips"};

std::string mutate(std::string s, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) { return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng() % n); };
  const int rounds = rng() % 3 == 0 ? 2 + static_cast<int>(rng() % 3) : 1;  // mostly single mutations
  for (int r = 0; r < rounds; ++r) {
    if (s.empty()) s = "HIERARCHY";
    const std::size_t at = pick(s.size());
    switch (rng() % 10) {
      case 0: s[at] = static_cast<char>(rng()); break;                      // random byte
      case 1: s[at] = static_cast<char>(s[at] ^ (1 << (rng() % 8))); break;  // bit flip
      case 2: s.erase(at, 1 + pick(64)); break;                              // deletion
      case 3: s.insert(at, s.substr(pick(s.size()), 1 + pick(256))); break;  // duplication
      case 4: s.resize(at); break;                                           // truncation
      case 5: {                                                              // token replacement
        const std::size_t b = s.find_first_not_of(" \t\r\n", at);
        if (b == std::string::npos) break;
        const std::size_t e = std::min(s.find_first_of(" \t\r\n", b), s.size());
        s.replace(b, e - b, kTokens[pick(std::size(kTokens))]);
        break;
      }
      case 6: s.insert(at, 1, "\n\r\t {}"[pick(6)]); break;  // structure characters
      case 7: {                                             // swap two lines
        const std::size_t a = s.rfind('\n', at), b2 = s.find('\n', pick(s.size()));
        if (a == std::string::npos || b2 == std::string::npos || a == b2) break;
        const std::size_t lo = std::min(a, b2), hi = std::max(a, b2);
        const std::size_t lo_end = s.find('\n', lo + 1), hi_end = std::min(s.find('\n', hi + 1), s.size());
        if (lo_end == std::string::npos || lo_end >= hi) break;
        const std::string first = s.substr(lo, lo_end - lo), second = s.substr(hi, hi_end - hi);
        s.replace(hi, hi_end - hi, first);
        s.replace(lo, lo_end - lo, second);
        break;
      }
      case 8: {  // another frame count
        const std::size_t f = s.find("Frames:");
        if (f == std::string::npos) break;
        const std::size_t eol = std::min(s.find_first_of("\r\n", f), s.size());
        const unsigned long long counts[] = {0, 1, 2, 25, 1000, 4294967296ull, 10000000000ull, rng() % 100000};
        s.replace(f, eol - f, "Frames: " + std::to_string(counts[pick(std::size(counts))]));
        break;
      }
      default: s.insert(at, kTokens[pick(std::size(kTokens))]); break;
    }
  }
  return s;
}

TEST(BvhFuzz, MutantsLoadOrThrowLocatedInputErrors) {
  const std::vector<std::string> corpus = seeds();
  const char* env = std::getenv("RT_FUZZ_MUTANTS");
  const int mutants = env ? std::atoi(env) : 40000;  // ~2 s in Release
  const double cap_s = env ? 1e9 : 20;                 // sanitizer builds are ~15x slower
  std::mt19937_64 rng(0x5eed'b7b0'2026ull);
  int parsed = 0, converted = 0, rejected = 0, done = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (; done < mutants; ++done) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > cap_s) break;
    const std::string& seed = corpus[static_cast<std::size_t>(rng() % corpus.size())];
    const std::string text = mutate(seed, rng);
    try {
      Diagnostics d;
      const BvhFile f = parse_bvh(text, "fuzz.bvh", &d);
      ++parsed;
      try {
        const HumanMotion m = bvh_to_human_motion(f);
        EXPECT_GT(m.num_frames, 0);
        for (const LandmarkTrack& t : m.landmarks) {
          if (t.present) {
            EXPECT_TRUE(t.p_W.allFinite() && t.p_W.cols() == m.num_frames) << "mutant " << done;
          }
        }
        ++converted;
      } catch (const InputError& e) {
        EXPECT_FALSE(e.location().empty() && e.message().find("fuzz.bvh") == std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      }
    } catch (const InputError& e) {
      ++rejected;
      EXPECT_EQ(e.location().rfind("fuzz.bvh:", 0), 0u) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    } catch (const std::exception& e) {
      const std::string path = test::scratch_dir() + "/mutant.bvh";
      std::ofstream(path, std::ios::binary) << text;
      FAIL() << "mutant " << done << " threw " << typeid(e).name() << ": " << e.what() << " (saved to " << path << ")";
    }
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ fuzz ] %d mutants of %zu seeds in %.2f s: %d rejected, %d parsed, %d converted\n", done, corpus.size(),
              elapsed, rejected, parsed, converted);
  // The mutants must exercise both outcomes.
  EXPECT_GT(rejected, done / 10);
  EXPECT_GT(converted, done / 20);
}

}  // namespace
}  // namespace rt
