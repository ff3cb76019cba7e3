// Fuzz targets for the reference inputs of `retarget validate`: CSV, meta.json (applied to the CSV
// it describes) and NPZ (zip + npy + reference checks).

#include "formats/reference/reference_csv.hpp"
#include "formats/reference/reference_meta.hpp"
#include "formats/reference/reference_npz.hpp"
#include "formats/reference/zip_archive.hpp"
#include "fuzz_target.hpp"
#include "mutator.hpp"
#include "retarget/core/error.hpp"

namespace rt::fuzz {
namespace {

const std::vector<std::string> kJoints = {"l_knee", "r_knee"};

// The repository's stand_wxyz.csv with its meta.json applied: 4 frames, fps, contacts.
const Reference& sample(const std::string& source) {
  static const Reference r = [&] {
    const std::string dir = source + "/tests/data/reference/";
    CsvReadOptions o;
    o.joint_names = kJoints;
    o.quat_wxyz = true;
    Reference ref = parse_reference_csv(read_or_empty(dir + "stand_wxyz.csv"), "stand_wxyz.csv", o);
    apply_reference_meta(parse_reference_meta(read_or_empty(dir + "stand_wxyz.meta.json"), "stand_wxyz.meta.json"),
                         "stand_wxyz.meta.json", "stand_wxyz.csv", MetaMerge::Fill, ref);
    return ref;
  }();
  return r;
}

std::string g_source;

Target csv_target() {
  Target t;
  t.name = "reference_csv";
  t.dictionary = {",", ",,", "\n", "\r\n", "nan", "inf", "1e999", "-", "+", "e", ".", " ", "\t", "\"", "#", "\xef\xbb\xbf"};
  t.seeds = [](const SeedDirs& d) {
    std::vector<Seed> s = {{"generated:xyzw", format_reference_csv(sample(d.source))}};
    s.push_back({"stand_wxyz.csv", read_or_empty(d.source + "/tests/data/reference/stand_wxyz.csv")});
    return s;
  };
  t.run = [](std::string_view in) {
    CsvReadOptions o;
    o.joint_names = kJoints;
    o.joints_source = "of the fuzz robot";
    parse_reference_csv(in, "fuzz.csv", o);
  };
  return t;
}
RT_FUZZ_TARGET(csv_target);

Target meta_target() {
  Target t;
  t.name = "meta_json";
  t.dictionary = {"{", "}", "[", "]", ",", ":", "\"", "\"fps\"", "\"num_frames\"", "\"joint_names\"", "\"contacts\"",
                  "\"time_s\"", "\"left\"", "\"right\"", "\"quaternion_order\"", "\"wxyz\"", "\"com_pos_w\"", "\"robot\"",
                  "null", "true", "false", "\\u0000", "\\ud800", "1e400", "-0.0", "[[0, 4]]", "[[5, 1]]"};
  t.seeds = [](const SeedDirs& d) {
    g_source = d.source;
    return std::vector<Seed>{{"generated", format_reference_meta(sample(d.source), {"fuzz.csv"})},
                             {"stand_wxyz.meta.json", read_or_empty(d.source + "/tests/data/reference/stand_wxyz.meta.json")}};
  };
  t.run = [](std::string_view in) {
    ReferenceMeta m = parse_reference_meta(in, "fuzz.meta.json");
    Reference r = sample(g_source);
    apply_reference_meta(std::move(m), "fuzz.meta.json", "fuzz.csv", MetaMerge::Fill, r);
  };
  return t;
}
RT_FUZZ_TARGET(meta_target);

// Mutants of the archive bytes mostly fail the CRC; this mutation edits one entry (its .npy
// header half of the time) and re-zips it with valid CRCs, so the npy and reference checks run.
bool mutate_npz_entry(std::string& bytes, Rng& rng) {
  std::vector<zip::Entry> entries;
  try {
    entries = zip::read_archive(bytes, "seed.npz");
  } catch (const InputError&) {
    return false;
  }
  if (entries.empty()) return false;
  static Target npy = [] {
    Target t;
    t.dictionary = {"'descr'", "'<f8'", "'<f4'", "'|b1'", "'<i8'", "'>f8'", "'fortran_order'", "True", "False",
                    "'shape'", "()", "(0,)", "(4, 2)", "(99999999999, 1)", "{", "}", ":", ",", "\x93NUMPY"};
    return t;
  }();
  static const std::vector<Seed> none = {{"", ""}};
  zip::Entry& victim = entries[rng() % entries.size()];
  if (rng() % 2) {
    std::string head = victim.data.substr(0, 128);
    const std::string tail = victim.data.substr(head.size());
    mutate(head, rng, npy, none);
    victim.data = head + tail;
  } else {
    npy.binary = true;
    mutate(victim.data, rng, npy, none);
    npy.binary = false;
  }
  if (rng() % 8 == 0) entries.erase(entries.begin() + static_cast<std::ptrdiff_t>(rng() % entries.size()));
  bytes = zip::write_archive(entries, rng() % 2 ? zip::Method::Deflate : zip::Method::Stored);
  return true;
}

Target npz_target() {
  Target t;
  t.name = "npz";
  t.binary = true;
  t.max_len = 256 * 1024;  // deflate expands at most ~1000x: bounded well under the allocation cap
  t.seeds = [](const SeedDirs& d) {
    const Reference& r = sample(d.source);
    ReferenceNpzWriteOptions stored;
    stored.compress = false;
    return std::vector<Seed>{{"generated:deflate", encode_reference_npz(r)},
                             {"generated:stored", encode_reference_npz(r, nullptr, stored)},
                             {"numpy_fixture.npz", read_or_empty(d.source + "/tests/data/reference/numpy_fixture.npz")}};
  };
  t.mutate = mutate_npz_entry;
  t.run = [](std::string_view in) { decode_reference_npz(in, "fuzz.npz"); };
  return t;
}
RT_FUZZ_TARGET(npz_target);

}  // namespace
}  // namespace rt::fuzz
