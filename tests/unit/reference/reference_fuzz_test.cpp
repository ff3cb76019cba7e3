// Seeded mutation fuzzing of the CSV, meta.json and NPZ readers: every mutated input must either
// parse or raise a one-line InputError; anything else (another exception, a crash, a sanitizer
// report, a hang) is a failure. Bounded by iterations and by time so it stays ~2 s in all builds.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <random>

#include "formats/reference/npz_file.hpp"
#include "formats/reference/reference_csv.hpp"
#include "formats/reference/reference_meta.hpp"
#include "formats/reference/reference_npz.hpp"
#include "formats/reference/zip_archive.hpp"
#include "reference_test_util.hpp"

namespace rt {
namespace {

using Clock = std::chrono::steady_clock;

struct FuzzStats {
  int runs = 0;
  int accepted = 0;
  int rejected = 0;
};

// Applies 1-4 random byte-level mutations. `alphabet` biases inserted/overwritten bytes towards
// the characters the format is made of.
std::string mutate(std::string s, std::mt19937& rng, const std::string& alphabet) {
  std::uniform_int_distribution<int> count(1, 4), kind(0, 6), byte(0, 255);
  auto pick_pos = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n)(rng); };
  auto pick_char = [&] {
    return rng() % 2 && !alphabet.empty() ? alphabet[rng() % alphabet.size()] : static_cast<char>(byte(rng));
  };
  for (int m = count(rng); m > 0; --m) {
    if (s.empty()) {
      s.push_back(pick_char());
      continue;
    }
    const std::size_t p = pick_pos(s.size() - 1);
    switch (kind(rng)) {
      case 0: s[p] = static_cast<char>(s[p] ^ (1 << (rng() % 8))); break;           // bit flip
      case 1: s[p] = pick_char(); break;                                             // overwrite
      case 2: s.insert(s.begin() + static_cast<std::ptrdiff_t>(p), pick_char()); break;  // insert
      case 3: s.erase(p, std::min<std::size_t>(1 + rng() % 8, s.size() - p)); break;     // delete
      case 4: s.resize(p); break;                                                    // truncate
      case 5: {                                                                      // duplicate a chunk
        const std::size_t n = std::min<std::size_t>(1 + rng() % 32, s.size() - p);
        s.insert(pick_pos(s.size()), s.substr(p, n));
        break;
      }
      default: {  // interesting integers (little-endian) for binary formats
        static const std::uint32_t kValues[] = {0, 1, 0x7F, 0xFF, 0xFFFF, 0x7FFFFFFF, 0xFFFFFFFF, 0x80000000};
        const std::uint32_t v = kValues[rng() % 8];
        for (std::size_t i = 0; i < 4 && p + i < s.size(); ++i) s[p + i] = static_cast<char>((v >> (8 * i)) & 0xFF);
      }
    }
  }
  return s;
}

// Counts show in --gtest_output=xml reports (how deep a time-bounded run got).
void record(const FuzzStats& s) {
  ::testing::Test::RecordProperty("runs", s.runs);
  ::testing::Test::RecordProperty("accepted", s.accepted);
  ::testing::Test::RecordProperty("rejected", s.rejected);
}

// RT_FUZZ_SCALE=<n> multiplies iterations and time budgets for a longer manual run (e.g. under
// the sanitizers, which slow each iteration down ~50x); default 1.
int fuzz_scale() {
  const char* s = std::getenv("RT_FUZZ_SCALE");
  const int n = s ? std::atoi(s) : 1;
  return n >= 1 && n <= 10000 ? n : 1;
}

// Runs `parse` on mutated inputs until `iterations` or `budget` is reached.
template <typename Parse, typename Make>
FuzzStats fuzz(unsigned seed, int iterations, std::chrono::milliseconds budget, Make make_input, Parse parse) {
  std::mt19937 rng(seed);
  FuzzStats stats;
  iterations *= fuzz_scale();
  const auto deadline = Clock::now() + budget * fuzz_scale();
  for (int i = 0; i < iterations && Clock::now() < deadline; ++i) {
    const std::string input = make_input(rng);
    ++stats.runs;
    try {
      parse(input);
      ++stats.accepted;
    } catch (const InputError& e) {
      const std::string what = e.what();
      if (what.find('\n') != std::string::npos || e.location().empty()) {
        ADD_FAILURE() << "iteration " << i << ": error is not one located line: " << what;
        return stats;
      }
      ++stats.rejected;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "iteration " << i << " (seed " << seed << "): unexpected exception: " << e.what();
      return stats;
    }
  }
  return stats;
}

TEST(ReferenceFuzz, CsvReader) {
  const Reference r = test::make_reference(12, {"hip", "knee"}, 99, false);
  const std::string base = format_reference_csv(r);
  CsvReadOptions o;
  o.joint_names = r.joint_names;
  const FuzzStats s = fuzz(
      1234, 50000, std::chrono::milliseconds(500),
      [&](std::mt19937& rng) { return mutate(base, rng, ",,,\n\r .-+e0123456789nafiNI"); },
      [&](const std::string& text) { parse_reference_csv(text, "fuzz.csv", o); });
  EXPECT_GT(s.runs, 100);
  EXPECT_GT(s.rejected, 0);
  EXPECT_GT(s.accepted, 0);  // digit changes keep the file valid now and then
  record(s);
}

TEST(ReferenceFuzz, MetaReader) {
  const Reference r = test::make_reference(6, {"hip", "knee"}, 98);
  const std::string base = format_reference_meta(r, {"f.csv"});
  const FuzzStats s = fuzz(
      4321, 20000, std::chrono::milliseconds(400),
      [&](std::mt19937& rng) { return mutate(base, rng, "{}[],:\"0123456789.-e"); },
      [&](const std::string& text) {
        ReferenceMeta m = parse_reference_meta(text, "fuzz.meta.json");
        Reference back = r;
        apply_reference_meta(std::move(m), "fuzz.meta.json", "f.csv", MetaMerge::Fill, back);
      });
  EXPECT_GT(s.runs, 50);
  EXPECT_GT(s.rejected, 0);
  record(s);
}

TEST(ReferenceFuzz, NpzReader) {
  const Reference r = test::make_reference(8, {"hip", "knee"}, 97);
  const std::string deflated = encode_reference_npz(r);
  ReferenceNpzWriteOptions stored_options;
  stored_options.compress = false;
  const std::string stored = encode_reference_npz(r, nullptr, stored_options);
  const std::vector<zip::Entry> entries = zip::read_archive(stored, "base.npz");
  const FuzzStats s = fuzz(
      5678, 40000, std::chrono::milliseconds(1000),
      [&](std::mt19937& rng) {
        switch (rng() % 3) {
          case 0: return mutate(deflated, rng, "");  // archive level: mostly CRC / structure errors
          case 1: return mutate(stored, rng, "");
          default: {
            // Entry level: mutate one .npy (its header mostly) and re-zip with valid CRCs, so the
            // npy and reference checks are reached too.
            std::vector<zip::Entry> e = entries;
            zip::Entry& victim = e[rng() % e.size()];
            const std::string head = victim.data.substr(0, 128);
            victim.data = rng() % 2 ? mutate(head, rng, "'(),: 0123456789<fiUb|TrueFalse") + victim.data.substr(head.size())
                                    : mutate(victim.data, rng, "");
            return zip::write_archive(e, rng() % 2 ? zip::Method::Deflate : zip::Method::Stored);
          }
        }
      },
      [&](const std::string& bytes) { decode_reference_npz(bytes, "fuzz.npz"); });
  EXPECT_GT(s.runs, 100);
  EXPECT_GT(s.rejected, 0);
  EXPECT_GT(s.accepted, 0);  // mutated values inside re-zipped arrays still parse
  record(s);
}

}  // namespace
}  // namespace rt
