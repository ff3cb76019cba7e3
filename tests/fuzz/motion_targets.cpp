// Fuzz targets for the motion inputs: BVH, C3D, ASF/AMC, BVH skeleton profiles and C3D marker
// maps, each read and converted to HumanMotion as `retarget convert` does.

#include <cmath>
#include <fstream>

#include "formats/asf/asf_amc.hpp"
#include "formats/bvh/bvh_reader.hpp"
#include "formats/c3d/c3d_reader.hpp"
#include "fuzz_target.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/asf/asf_motion.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"
#include "retarget/motion/c3d/c3d_motion.hpp"
#include "unit/bvh/bvh_test_clips.hpp"
#include "unit/c3d/synthetic_walker.hpp"

namespace rt::fuzz {
namespace {

// A converted motion must be usable: frames, and finite positions wherever a landmark is present.
void check_motion(const HumanMotion& m) {
  check(m.num_frames > 0, "a motion without frames was returned");
  for (const LandmarkTrack& t : m.landmarks) {
    if (!t.present) continue;
    check(t.p_W.cols() == m.num_frames, "landmark track length differs from the frame count");
    check(t.p_W.allFinite(), "non-finite landmark position returned");
  }
}

// The hierarchy and the first `rows` motion rows of a BVH, with `Frames:` set to match (a short
// seed keeps each run fast; the structure is all there).
std::string head_of_bvh(const std::string& text, int rows) {
  const auto frames = text.find("Frames:");
  const auto time = text.find("Frame Time:");
  if (frames == std::string::npos || time == std::string::npos || time < frames) return text.substr(0, 64 * 1024);
  std::size_t end = text.find('\n', time);
  for (int r = 0; r < rows && end != std::string::npos; ++r) end = text.find('\n', end + 1);
  std::string out = text.substr(0, end == std::string::npos ? text.size() : end + 1);
  const auto eol = out.find_first_of("\r\n", frames);
  out.replace(frames, eol - frames, "Frames: " + std::to_string(rows));
  return out;
}

std::vector<Seed> bvh_seeds(const SeedDirs& d) {
  std::vector<Seed> s = {{"generated:tiny", test::kTinyBvh}};
  test::HumanoidClip c;
  c.frames = 12;
  c.tpose_frames = 1;
  s.push_back({"generated:humanoid", test::make_humanoid_bvh(c)});
  c.up = 'z';
  c.metres_per_unit = 0.0254;
  c.prefix = "mixamorig:";
  s.push_back({"generated:humanoid-z-inch", test::make_humanoid_bvh(c)});
  for (const std::string& dir : {d.source + "/examples/clips", d.shared.empty() ? std::string() : d.shared + "/bvh"})
    for (Seed f : seed_files(dir, {".bvh"}, 4 << 20)) s.push_back({f.name, head_of_bvh(f.bytes, 16)});
  for (Seed& f : seed_files(d.source + "/tests/data/bvh/bad", {".bvh"}, 64 * 1024)) s.push_back(std::move(f));
  return s;
}

const std::vector<std::string> kBvhWords = {
    "HIERARCHY", "ROOT", "JOINT", "End Site", "OFFSET", "CHANNELS", "MOTION", "Frames:", "Frame Time:", "{", "}",
    "Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation", "Hips", "Head", "LeftFoot",
    "RightToeBase", "mixamorig:", "6", "3", "0", "\t", "\r\n", "\xff\xfe"};

Target bvh_target() {
  Target t;
  t.name = "bvh";
  t.seeds = bvh_seeds;
  t.dictionary = kBvhWords;
  t.run = [](std::string_view in) {
    Diagnostics d;
    const BvhFile f = parse_bvh(in, "fuzz.bvh", &d);
    check_motion(bvh_to_human_motion(f));
  };
  return t;
}
RT_FUZZ_TARGET(bvh_target);

// ---- C3D ----------------------------------------------------------------------------------------

std::vector<Seed> c3d_seeds(const SeedDirs& d) {
  std::vector<Seed> out;
  test::Walker walker;
  walker.frames = 40;
  walker.absent_leading = 3;
  for (auto [p, flt] : {std::pair{c3d::Processor::Intel, true}, std::pair{c3d::Processor::Dec, true},
                        std::pair{c3d::Processor::Mips, false}, std::pair{c3d::Processor::Intel, false}}) {
    test::C3dSpec s = walker.spec([](const std::string& n, int f) { return n == "LKNE" && f > 10 && f < 20; });
    s.processor = p;
    s.float_storage = flt;
    s.int_scale = 0.5;
    s.analog_channels = 2;
    s.analog_samples_per_frame = 3;
    s.events = {{"Foot Strike", 0.2}};
    s.labels_per_parameter = 20;
    out.push_back({"generated:walker", test::write_c3d(s).bytes});
  }
  for (Seed& f : seed_files(d.source + "/tests/data/c3d", {".c3d"})) out.push_back(std::move(f));
  // Real files cut to their first 96 KB: the reader takes the complete frames of a short data
  // section (with a warning), so a cut file keeps its header, parameters and some frames.
  if (!d.shared.empty()) {
    for (const std::string& dir : {d.shared + "/c3d", d.shared + "/c3d/btkdata"})
      for (Seed& f : seed_files(dir, {".c3d", ".C3D"}, 96 * 1024)) out.push_back(std::move(f));
  }
  return out;
}

Target c3d_target() {
  Target t;
  t.name = "c3d";
  t.binary = true;
  t.seeds = c3d_seeds;
  t.run = [](std::string_view in) {
    Diagnostics diag;
    const c3d::C3dFile f = c3d::parse_c3d(in, "fuzz.c3d", &diag);
    check_motion(c3d_to_motion(f, MotionLoadOptions{}, diag));
  };
  // Most of the structure is in the header and the parameter blocks: mutate there more often.
  t.mutate = [](std::string& b, Rng& rng) {
    if (b.size() < 16) return false;
    const std::size_t head = std::min<std::size_t>(b.size(), 4096);
    for (int k = 1 + static_cast<int>(rng() % 3); k > 0; --k) {
      const std::size_t at = rng() % head;
      switch (rng() % 3) {
        case 0: b[at] = static_cast<char>(b[at] ^ (1u << (rng() % 8))); break;
        case 1: b[at] = static_cast<char>(rng()); break;
        default: {
          static const std::uint16_t v[] = {0, 1, 2, 0x50, 0x7f, 0x80, 0xff, 0x100, 0x7fff, 0x8000, 0xffff};
          const std::uint16_t x = v[rng() % std::size(v)];
          b[at] = static_cast<char>(x & 0xff);
          if (at + 1 < b.size()) b[at + 1] = static_cast<char>(x >> 8);
        }
      }
    }
    return true;
  };
  return t;
}
RT_FUZZ_TARGET(c3d_target);

// ---- ASF/AMC: one input holds both files, split at kSplit (no split: the good AMC) ------------

const char kSplit[] = "\n#==== amc ====\n";

std::vector<Seed> asf_seeds(const SeedDirs& d) {
  const std::string dir = d.source + "/tests/data/asf/bad";
  const std::string good_asf = read_or_empty(dir + "/good.asf"), good_amc = read_or_empty(dir + "/good.amc");
  std::vector<Seed> out = {{"good", good_asf + kSplit + good_amc}};
  for (const Seed& f : seed_files(dir, {".asf"}, 64 * 1024)) out.push_back({f.name, f.bytes + kSplit + good_amc});
  for (const Seed& f : seed_files(dir, {".amc"}, 64 * 1024)) out.push_back({f.name, good_asf + kSplit + f.bytes});
  if (!d.shared.empty()) {
    const std::string cmu = d.shared + "/bvh/cmu_asf_amc";
    std::string amc = read_or_empty(cmu + "/01_01.amc");
    // The header and about 10 frames of the CMU take (frames start at a line holding only the number).
    std::size_t cut = amc.find("\n11\n");
    if (cut != std::string::npos) amc.resize(cut + 1);
    const std::string asf = read_or_empty(cmu + "/01.asf");
    if (!asf.empty() && !amc.empty()) out.push_back({cmu, asf + kSplit + amc});
  }
  return out;
}

Target asf_target() {
  Target t;
  t.name = "asf_amc";
  t.seeds = asf_seeds;
  t.dictionary = {":version", ":name", ":units", ":documentation", ":root", ":bonedata", ":hierarchy", "begin", "end",
                  "id", "name", "direction", "length", "axis", "dof", "limits", "XYZ", "ZYX", "rx", "ry", "rz", "tx",
                  "ty", "tz", "root", "lfemur", "rtibia", "lowerback", "mass", "angle", "deg", "rad", ":FULLY-SPECIFIED",
                  ":DEGREES", ":RADIANS", "(-180.0 180.0)", "1", "2", kSplit};
  t.run = [](std::string_view in) {
    const std::string_view split(kSplit);
    const std::size_t at = in.find(split);
    const std::string asf(in.substr(0, at));
    const std::string amc(at == std::string_view::npos ? std::string_view() : in.substr(at + split.size()));
    const AsfSkeleton skeleton = parse_asf(asf, "fuzz.asf");
    const AmcMotion motion = parse_amc(amc, "fuzz.amc", skeleton);
    const BvhFile bvh = asf_amc_to_bvh(skeleton, motion, 1.0 / 120, "fuzz.amc");
    check_motion(bvh_to_human_motion(bvh));
  };
  return t;
}
RT_FUZZ_TARGET(asf_target);

// ---- profiles and marker maps, read from a file as the batch workers read them -----------------

std::string g_scratch;

void write_scratch(const std::string& path, std::string_view bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

const std::vector<std::string> kYamlWords = {"name:", "base:", "landmarks:", "joint:", "point:", "end_site", "midpoint",
                                             "auto", "none", "mixamo", "null", "[", "]", "{", "}", "- ", ": ", "&a",
                                             "*a", "!!str", "'", "\"", "#", "pelvis", "left_knee", "right_toe", "head"};

Target skeleton_profile_target() {
  Target t;
  t.name = "skeleton_profile";
  t.dictionary = kYamlWords;
  for (const char* w : {"Hips", "LeftLeg", "RightFoot", "LeftToeBase", "Bone07", "joint", "left_ankle", "right_hip"})
    t.dictionary.push_back(w);
  t.seeds = [](const SeedDirs&) {
    return std::vector<Seed>{
        {"generated:explicit",
         "name: explicit\nlandmarks:\n  pelvis: Hips\n  head: Head\n  left_hip: LeftUpLeg\n  right_hip: RightUpLeg\n"
         "  left_knee: LeftLeg\n  right_knee: RightLeg\n  left_ankle: LeftFoot\n  right_ankle: RightFoot\n"
         "  left_toe: {joint: LeftToeBase, point: end_site}\n  right_toe: {joint: RightToeBase, point: end_site}\n"
         "  left_shoulder: LeftArm\n  right_shoulder: RightArm\n  left_elbow: LeftForeArm\n  right_elbow: RightForeArm\n"
         "  left_wrist: LeftHand\n  right_wrist: RightHand\n"},
        {"generated:based",
         "name: my_rig\nbase: mixamo\nlandmarks:\n  left_knee: LeftLeg\n  right_knee: [NoSuchJoint, {joint: RightLeg, "
         "point: joint}]\n  head: {joint: Head, point: midpoint}\n  left_hand: null\n  spine: Spine1\n"}};
  };
  t.setup = [](const std::string& scratch) { g_scratch = scratch; };
  t.run = [](std::string_view in) {
    static const BvhFile clip = [] {
      test::HumanoidClip c;
      c.frames = 4;
      return parse_bvh(test::make_humanoid_bvh(c), "clip.bvh");
    }();
    const std::string path = g_scratch + "/fuzz.profile.yaml";
    write_scratch(path, in);
    MotionLoadOptions o;
    o.profile_path = path;
    check_motion(bvh_to_human_motion(clip, o));
  };
  return t;
}
RT_FUZZ_TARGET(skeleton_profile_target);

Target marker_map_target() {
  Target t;
  t.name = "marker_map";
  t.dictionary = kYamlWords;
  for (const char* w : {"LASI", "RASI", "LPSI", "RPSI", "LKNE", "RANK", "LTOE", "LFHD", "'#1'", "'#99999'", "'#0'",
                        "'#-1'", "left_ankle"})
    t.dictionary.push_back(w);
  t.seeds = [](const SeedDirs&) {
    return std::vector<Seed>{
        {"generated:numbers", "name: lab\nlandmarks:\n  pelvis: ['#1', '#2', '#3', '#4']\n  left_ankle: ['#9', '#10']\n"
                              "  right_ankle: ['#11', '#12']\n  left_toe: '#13'\n  head: ['#20', '#21']\n"},
        {"generated:names", "name: lab\nlandmarks:\n  pelvis: [Matt:LASI, Matt:RASI, Matt:LPSI, Matt:RPSI]\n"
                            "  left_ankle: [Matt:LANK]\n  right_ankle: Matt:RANK\n"},
        {"generated:auto", "base: auto\nlandmarks:\n  left_knee: Matt:LKNE\n"}};
  };
  t.setup = [](const std::string& scratch) { g_scratch = scratch; };
  t.run = [](std::string_view in) {
    static const c3d::C3dFile clip = [] {
      test::Walker w;
      w.frames = 30;
      w.absent_leading = 2;
      return c3d::parse_c3d(test::write_c3d(w.spec()).bytes, "clip.c3d");
    }();
    const std::string path = g_scratch + "/fuzz.map.yaml";
    write_scratch(path, in);
    MotionLoadOptions o;
    o.profile_path = path;
    check_motion(c3d_to_motion(clip, o));
  };
  return t;
}
RT_FUZZ_TARGET(marker_map_target);

}  // namespace
}  // namespace rt::fuzz
