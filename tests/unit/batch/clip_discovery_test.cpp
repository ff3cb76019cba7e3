#include <gtest/gtest.h>

#include <filesystem>

#include "batch_test_util.hpp"
#include "retarget/batch/clip_discovery.hpp"
#include "retarget/core/error.hpp"
#include "support/text_mutation.hpp"

namespace rt {
namespace {

namespace fs = std::filesystem;
using test::scratch_dir;
using test::write_text;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::vector<std::string> names(const std::vector<BatchClip>& clips) {
  std::vector<std::string> out;
  for (const BatchClip& c : clips) out.push_back(c.output_name);
  return out;
}

TEST(ClipDiscovery, FolderIsRecursiveCaseInsensitiveAndSorted) {
  const std::string dir = scratch_dir();
  write_text(dir + "/mocap/b.bvh", "x");
  write_text(dir + "/mocap/A.BVH", "xx");
  write_text(dir + "/mocap/walks/w1.c3d", "xyz");
  write_text(dir + "/mocap/walks/deeper/w2.C3D", "");
  write_text(dir + "/mocap/notes.txt", "not a clip");
  write_text(dir + "/mocap/walks/w1.csv", "an output, not a clip");
  write_text(dir + "/mocap/.hidden/h.bvh", "skipped");
  write_text(dir + "/mocap/.h.bvh", "skipped");
  const auto clips = discover_clips(dir + "/mocap");
  EXPECT_EQ(names(clips), (std::vector<std::string>{"A", "b", "walks/deeper/w2", "walks/w1"}));
  EXPECT_EQ(clips[0].input_bytes, 2u);
  EXPECT_EQ(clips[3].input_bytes, 3u);
  EXPECT_TRUE(fs::path(clips[0].input).is_absolute());
  EXPECT_EQ(fs::path(clips[2].input).filename(), "w2.C3D");
}

TEST(ClipDiscovery, FolderErrors) {
  const std::string dir = scratch_dir();
  write_text(dir + "/empty/readme.txt", "");
  EXPECT_NE(error_of([&] { discover_clips(dir + "/empty"); }).find("no .bvh, .c3d or .amc files"), std::string::npos);
  EXPECT_NE(error_of([&] { discover_clips(dir + "/missing"); }).find("no such file or folder"), std::string::npos);
  write_text(dir + "/one.bvh", "");
  EXPECT_NE(error_of([&] { discover_clips(dir + "/one.bvh"); }).find("retarget convert"), std::string::npos);
  // Same output name from two files.
  write_text(dir + "/dup/walk.bvh", "");
  write_text(dir + "/dup/walk.c3d", "");
  const std::string e = error_of([&] { discover_clips(dir + "/dup"); });
  EXPECT_NE(e.find("output name 'walk'"), std::string::npos) << e;
  EXPECT_NE(e.find("already used"), std::string::npos) << e;
}

TEST(ClipDiscovery, FolderSymlinkOutsideIsRejectedUnlessAllowed) {
  const std::string dir = scratch_dir();
  write_text(dir + "/elsewhere/far.bvh", "x");
  write_text(dir + "/mocap/near.bvh", "x");
  fs::create_symlink(dir + "/elsewhere/far.bvh", dir + "/mocap/link.bvh");
  const std::string e = error_of([&] { discover_clips(dir + "/mocap"); });
  EXPECT_NE(e.find("outside the input folder"), std::string::npos) << e;
  EXPECT_NE(e.find("--allow-outside"), std::string::npos) << e;
  const auto clips = discover_clips(dir + "/mocap", {true});
  EXPECT_EQ(names(clips), (std::vector<std::string>{"link", "near"}));
}

TEST(ClipDiscovery, YamlManifestWithOverridesAndRelativePaths) {
  const std::string dir = scratch_dir();
  write_text(dir + "/lib/walks/w1.bvh", "12345");
  write_text(dir + "/lib/profiles/studio.yaml", "x: 1\n");
  write_text(dir + "/lib/manifest.yaml", R"(# test manifest
clips:
  - walks/w1.bvh
  - path: walks/w1.bvh
    output: w1_slow
    source_units: cm
    source_fps: 60
    time_scale: 1.5
    up_axis: -y
    profile: profiles/studio.yaml
  - path: missing.c3d
)");
  const auto clips = discover_clips(dir + "/lib/manifest.yaml");
  ASSERT_EQ(clips.size(), 3u);
  EXPECT_EQ(names(clips), (std::vector<std::string>{"walks/w1", "w1_slow", "missing"}));
  EXPECT_EQ(clips[0].input, (fs::absolute(dir) / "lib/walks/w1.bvh").lexically_normal().string());
  EXPECT_EQ(clips[0].input_bytes, 5u);
  EXPECT_TRUE(clips[0].overrides.empty());
  const ClipOverrides& o = clips[1].overrides;
  EXPECT_EQ(*o.source_units, "cm");
  EXPECT_DOUBLE_EQ(*o.source_fps, 60);
  EXPECT_DOUBLE_EQ(*o.time_scale, 1.5);
  EXPECT_EQ(*o.up_axis, "-y");
  EXPECT_EQ(*o.profile, (fs::absolute(dir) / "lib/profiles/studio.yaml").lexically_normal().string());
  EXPECT_NE(clips[1].origin.find("manifest.yaml:4"), std::string::npos) << clips[1].origin;
  EXPECT_EQ(clips[2].input_bytes, 0u);  // missing: the worker reports it
}

TEST(ClipDiscovery, YamlManifestErrorsNameLineAndKey) {
  const std::string dir = scratch_dir();
  const std::string m = dir + "/m.yaml";
  auto err = [&](const std::string& text) {
    write_text(m, text);
    return error_of([&] { discover_clips(m); });
  };
  std::string e = err("clips:\n  - path: a.bvh\n    sorce_fps: 60\n");
  EXPECT_NE(e.find("m.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
  e = err("clips:\n  - path: a.bvh\n    source_fps: -5\n");
  EXPECT_NE(e.find("m.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("clips[0].source_fps"), std::string::npos) << e;
  e = err("clips:\n  - path: a.bvh\n    source_units: furlongs\n");
  EXPECT_NE(e.find("clips[0].source_units"), std::string::npos) << e;
  e = err("clips:\n  - path: a.bvh\n    time_scale: 100\n");
  EXPECT_NE(e.find("time_scale"), std::string::npos) << e;
  e = err("clips:\n  - output: x\n");
  EXPECT_NE(e.find("path"), std::string::npos) << e;
  e = err("clipz: []\n");
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
  e = err("clips: []\n");
  EXPECT_NE(e.find("lists no clips"), std::string::npos) << e;
  e = err("clips:\n  - a.bvh\n  - path: b.bvh\n    output: a\n");
  EXPECT_NE(e.find("output name 'a'"), std::string::npos) << e;
  EXPECT_NE(e.find("m.yaml:3"), std::string::npos) << e;
  e = err("clips:\n  - path: a.bvh\n    profile: nope.yaml\n");
  EXPECT_NE(e.find("profile 'nope.yaml' not found"), std::string::npos) << e;
  e = err("clips: [a.bvh\n");
  EXPECT_NE(e.find("YAML syntax error"), std::string::npos) << e;
}

TEST(ClipDiscovery, CsvManifest) {
  const std::string dir = scratch_dir();
  write_text(dir + "/lib/a.bvh", "1");
  write_text(dir + "/lib/sub/b, c.c3d", "22");
  write_text(dir + "/lib/m.csv",
             "\xEF\xBB\xBFpath,output,source_fps,up_axis,source_units,time_scale\r\n"
             "# comment\r\n"
             "a.bvh,,,,,\r\n"
             "\r\n"
             "\"sub/b, c.c3d\",\"b \"\"quoted\"\"\",120,z,mm,0.5\r\n");
  const auto clips = discover_clips(dir + "/lib/m.csv");
  ASSERT_EQ(clips.size(), 2u);
  EXPECT_EQ(clips[0].output_name, "a");
  EXPECT_TRUE(clips[0].overrides.empty());
  EXPECT_EQ(clips[1].output_name, "b \"quoted\"");
  EXPECT_EQ(fs::path(clips[1].input).filename(), "b, c.c3d");
  EXPECT_EQ(clips[1].input_bytes, 2u);
  EXPECT_DOUBLE_EQ(*clips[1].overrides.source_fps, 120);
  EXPECT_EQ(*clips[1].overrides.up_axis, "z");
  EXPECT_EQ(*clips[1].overrides.source_units, "mm");
  EXPECT_DOUBLE_EQ(*clips[1].overrides.time_scale, 0.5);
  EXPECT_EQ(clips[1].origin, dir + "/lib/m.csv:5");
}

TEST(ClipDiscovery, CsvManifestErrors) {
  const std::string dir = scratch_dir();
  const std::string m = dir + "/m.csv";
  auto err = [&](const std::string& text) {
    write_text(m, text);
    return error_of([&] { discover_clips(m); });
  };
  std::string e = err("path,fps\na.bvh,30\n");
  EXPECT_NE(e.find("m.csv:1"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown column 'fps'"), std::string::npos) << e;
  e = err("output\nx\n");
  EXPECT_NE(e.find("no 'path' column"), std::string::npos) << e;
  e = err("path,source_fps\na.bvh,fast\n");
  EXPECT_NE(e.find("m.csv:2"), std::string::npos) << e;
  EXPECT_NE(e.find("column source_fps"), std::string::npos) << e;
  e = err("path,output\na.bvh\n");
  EXPECT_NE(e.find("expected 2 fields"), std::string::npos) << e;
  e = err("path\n\"a.bvh\n");
  EXPECT_NE(e.find("unterminated"), std::string::npos) << e;
  e = err("path,up_axis\na.bvh,w\n");
  EXPECT_NE(e.find("column up_axis"), std::string::npos) << e;
  e = err("");
  EXPECT_NE(e.find("empty manifest"), std::string::npos) << e;
  e = err("path\n");
  EXPECT_NE(e.find("lists no clips"), std::string::npos) << e;
}

TEST(ClipDiscovery, ManifestPathsEscapingTheRootAreRejected) {
  const std::string dir = scratch_dir();
  write_text(dir + "/outside.bvh", "x");
  write_text(dir + "/lib/in.bvh", "x");
  fs::create_symlink(dir + "/outside.bvh", dir + "/lib/sneaky.bvh");
  for (const std::string& path : {std::string("../outside.bvh"), dir + "/outside.bvh", std::string("sub/../../outside.bvh"),
                                  std::string("sneaky.bvh")}) {
    write_text(dir + "/lib/m.yaml", "clips:\n  - in.bvh\n  - " + path + "\n");
    const std::string e = error_of([&] { discover_clips(dir + "/lib/m.yaml"); });
    EXPECT_NE(e.find("m.yaml:3"), std::string::npos) << path << ": " << e;
    EXPECT_NE(e.find("outside the manifest's folder"), std::string::npos) << path << ": " << e;
    const auto clips = discover_clips(dir + "/lib/m.yaml", {true});
    EXPECT_EQ(clips.size(), 2u) << path;
  }
  // Outside the root, the default output name is the file name.
  write_text(dir + "/lib/m.yaml", "clips:\n  - ../outside.bvh\n");
  EXPECT_EQ(discover_clips(dir + "/lib/m.yaml", {true})[0].output_name, "outside");
  // A path inside the root through '..' is fine.
  write_text(dir + "/lib/m.yaml", "clips:\n  - sub/../in.bvh\n");
  EXPECT_EQ(discover_clips(dir + "/lib/m.yaml")[0].output_name, "in");
}

// Issue 18 item 9: a manifest's per-clip profile is under the same outside-root rule as its clips
// (an absolute path to any readable file was opened and its first line echoed in the error).
TEST(ClipDiscovery, ManifestProfilesEscapingTheRootAreRejected) {
  const std::string dir = scratch_dir();
  write_text(dir + "/secret.yaml", "name: secret\n");
  write_text(dir + "/lib/in.bvh", "x");
  write_text(dir + "/lib/own.yaml", "name: own\n");
  for (const std::string& prof : {dir + "/secret.yaml", std::string("../secret.yaml")}) {
    write_text(dir + "/lib/m.yaml", "clips:\n  - {path: in.bvh, profile: '" + prof + "'}\n");
    const std::string e = error_of([&] { discover_clips(dir + "/lib/m.yaml"); });
    EXPECT_NE(e.find("m.yaml:2"), std::string::npos) << prof << ": " << e;
    EXPECT_NE(e.find("outside the manifest's folder"), std::string::npos) << prof << ": " << e;
    EXPECT_EQ(discover_clips(dir + "/lib/m.yaml", {true}).size(), 1u) << prof;
  }
  write_text(dir + "/lib/m.yaml", "clips:\n  - {path: in.bvh, profile: own.yaml}\n");
  EXPECT_EQ(*discover_clips(dir + "/lib/m.yaml")[0].overrides.profile,
            (fs::absolute(dir) / "lib/own.yaml").lexically_normal().string());
}

TEST(ClipDiscovery, OutputNamesAreChecked) {
  for (const std::string& bad : {std::string(""), std::string("/abs"), std::string("a/../../b"), std::string("a//b"),
                                 std::string("a/"), std::string("./a"), std::string("a\\b"), std::string("a\tb"),
                                 std::string("summary"), std::string("summary-shard-1-of-2")}) {
    const std::string e = error_of([&] { check_output_name(bad, "here"); });
    EXPECT_NE(e.find("here: output name"), std::string::npos) << "'" << bad << "': " << e;
  }
  for (const char* good : {"walk", "walks/walk 01", "a.b.c", "summary2", "sub/summary"})
    EXPECT_NO_THROW(check_output_name(good, "here")) << good;
  const std::string dir = scratch_dir();
  write_text(dir + "/m.yaml", "clips:\n  - {path: a.bvh, output: ../up}\n");
  EXPECT_NE(error_of([&] { discover_clips(dir + "/m.yaml"); }).find("'.' or '..'"), std::string::npos);
}

TEST(ClipDiscovery, ExampleManifestsAgree) {
  const std::string yaml = test::source_path("examples/manifests/example.yaml");
  const std::string csv = test::source_path("examples/manifests/example.csv");
  // They point into ../clips: outside their folder.
  EXPECT_NE(error_of([&] { discover_clips(yaml); }).find("--allow-outside"), std::string::npos);
  EXPECT_NE(error_of([&] { discover_clips(csv); }).find("--allow-outside"), std::string::npos);
  const auto a = discover_clips(yaml, {true});
  const auto b = discover_clips(csv, {true});
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].input, b[i].input);
    EXPECT_TRUE(fs::exists(a[i].input)) << a[i].input;
    EXPECT_EQ(a[i].output_name, b[i].output_name);
    EXPECT_EQ(a[i].overrides.time_scale, b[i].overrides.time_scale);
    EXPECT_EQ(a[i].overrides.source_units, b[i].overrides.source_units);
    EXPECT_EQ(a[i].overrides.source_fps, b[i].overrides.source_fps);
    EXPECT_EQ(a[i].overrides.up_axis, b[i].overrides.up_axis);
  }
  EXPECT_EQ(names(a), (std::vector<std::string>{"stand", "foot_lift_slow", "slow_steps"}));
}

// Issue 18: seeded mutants of YAML and CSV manifests parse or raise one one-line InputError.
TEST(ClipDiscovery, MutatedManifestsAreLocatedErrorsOrParse) {
  const std::string dir = scratch_dir();
  write_text(dir + "/a.bvh", "x");
  write_text(dir + "/b.c3d", "x");
  write_text(dir + "/p.yaml", "name: p\n");
  const std::string yaml = "clips:\n  - a.bvh\n  - path: b.c3d\n    output: walks/b\n    time_scale: 1.5\n"
                           "    source_fps: 60\n    up_axis: y\n    profile: p.yaml\n";
  const std::string csv = "path,output,time_scale,source_units,source_fps,up_axis\na.bvh,a,1,cm,120,y\nb.c3d,,,,,\n";
  int rejected = test::fuzz_text(yaml, ":{}[],- \n#'\"0123456789.", 181, 800, std::chrono::milliseconds(1500),
                                 [&](const std::string& t) { parse_manifest(t, dir + "/m.yaml", false, {}); });
  rejected += test::fuzz_text(csv, ",\n\"0123456789.", 182, 800, std::chrono::milliseconds(1500),
                              [&](const std::string& t) { parse_manifest(t, dir + "/m.csv", true, {}); });
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace rt
