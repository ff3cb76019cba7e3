#include "retarget/reference/reference_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "formats/reference/reference_csv.hpp"
#include "reference_test_util.hpp"
#include "retarget/core/file_io.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

std::vector<std::string> folder_entries(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ReferenceIo, ParsesFormatLists) {
  EXPECT_EQ(parse_reference_formats("csv"), (std::vector<ReferenceFormat>{ReferenceFormat::Csv}));
  EXPECT_EQ(parse_reference_formats(" NPZ , csv,npz"), (std::vector<ReferenceFormat>{ReferenceFormat::Npz, ReferenceFormat::Csv}));
  test::expect_input_error([] { parse_reference_formats("csv,json"); }, {"--format", "'json'"});
  test::expect_input_error([] { parse_reference_formats(" , "); }, {"--format"});
}

TEST(ReferenceIo, MetaPath) {
  EXPECT_EQ(meta_path_for("out/walk.csv"), "out/walk.meta.json");
  EXPECT_EQ(meta_path_for("out.d/walk.npz"), "out.d/walk.meta.json");
  EXPECT_EQ(meta_path_for("out.d/walk"), "out.d/walk.meta.json");
}

TEST(ReferenceIo, WritesAllFormatsAtomicallyAndReadsThemBack) {
  const std::string dir = test::scratch_dir();
  const Reference r = test::make_reference(45, test::g1_joint_names(), 17);
  const auto written = write_reference(dir + "/walk", r, {ReferenceFormat::Csv, ReferenceFormat::Npz, ReferenceFormat::Csv});
  EXPECT_EQ(written, (std::vector<std::string>{dir + "/walk.csv", dir + "/walk.npz", dir + "/walk.meta.json"}));
  // No temporaries left behind.
  EXPECT_EQ(folder_entries(dir), (std::vector<std::string>{"walk.csv", "walk.meta.json", "walk.npz"}));
  EXPECT_NE(read_file(dir + "/walk.meta.json").find("\"files\": [\"walk.csv\",\"walk.npz\"]"), std::string::npos);

  ReferenceReadOptions o;
  o.robot_name = "g1";
  o.joint_names = test::g1_joint_names();
  const Reference from_csv = read_reference(dir + "/walk.csv", o);
  const Reference from_npz = read_reference(dir + "/walk.npz", o);
  for (const Reference* back : {&from_csv, &from_npz}) {
    EXPECT_EQ(back->robot_name, "g1");
    EXPECT_EQ(back->fps, 30);
    EXPECT_EQ(back->joint_names, r.joint_names);
    EXPECT_EQ(back->contact[0], r.contact[0]);
    EXPECT_EQ(back->contact[1], r.contact[1]);
    EXPECT_EQ(back->com_W, r.com_W);
    EXPECT_EQ(back->cop_W, r.cop_W);
    EXPECT_EQ(back->extra_meta_json, r.extra_meta_json);
  }
  EXPECT_EQ(from_npz.joint_pos, r.joint_pos);  // f8: exact
  EXPECT_LT((from_csv.joint_pos - r.joint_pos).cwiseAbs().maxCoeff(), 1e-8);

  // Writing what was read reproduces every file byte for byte.
  const std::string csv1 = read_file(dir + "/walk.csv"), meta1 = read_file(dir + "/walk.meta.json");
  write_reference(dir + "/walk", from_csv, {ReferenceFormat::Csv, ReferenceFormat::Npz});
  EXPECT_EQ(read_file(dir + "/walk.csv"), csv1);
  EXPECT_EQ(read_file(dir + "/walk.meta.json"), meta1);
  const Reference again = read_reference(dir + "/walk.npz", o);
  EXPECT_EQ(again.joint_pos, from_csv.joint_pos);
}

TEST(ReferenceIo, InvalidReferenceLeavesExistingFilesUntouched) {
  const std::string dir = test::scratch_dir();
  const Reference r = test::make_reference(10, {"a", "b"}, 1);
  write_reference(dir + "/x", r, {ReferenceFormat::Csv, ReferenceFormat::Npz});
  const std::string csv = read_file(dir + "/x.csv");
  Reference broken = r;
  broken.joint_pos(1, 4) = std::nan("");
  test::expect_input_error([&] { write_reference(dir + "/x", broken, {ReferenceFormat::Csv, ReferenceFormat::Npz}); },
                           {"reference frame 4 joint b", "non-finite"});
  EXPECT_EQ(read_file(dir + "/x.csv"), csv);
  EXPECT_EQ(folder_entries(dir), (std::vector<std::string>{"x.csv", "x.meta.json", "x.npz"}));
  // Bad body arrays are a programming error: caught before anything is written.
  NpzBodyArrays b;
  b.body_names = {"pelvis"};
  EXPECT_THROW(write_reference(dir + "/x", r, {ReferenceFormat::Npz}, &b), InternalError);
  EXPECT_EQ(folder_entries(dir), (std::vector<std::string>{"x.csv", "x.meta.json", "x.npz"}));
  test::expect_input_error([&] { write_reference(dir + "/no/such/folder/x", r, {ReferenceFormat::Csv}); }, {"cannot write"});
  test::expect_input_error([&] { write_reference(dir + "/x", r, {}); }, {"no output format"});
}

TEST(ReferenceIo, DispatcherErrors) {
  const std::string dir = test::scratch_dir();
  write_file_atomic(dir + "/plain.csv", "0,0,0.8,0,0,0,1,0.1,0.2\n0,0,0.8,0,0,0,1,0.1,0.2\n");
  test::expect_input_error([&] { read_reference(dir + "/plain.csv"); }, {"plain.csv", "plain.meta.json", "--fps", "--robot"});
  ReferenceReadOptions o;
  o.joint_names = {"a", "b"};
  o.fps = 25;
  o.robot_name = "toy";
  const Reference r = read_reference(dir + "/plain.csv", o);
  EXPECT_EQ(r.fps, 25);
  EXPECT_EQ(r.robot_name, "toy");
  test::expect_input_error([&] { read_reference(dir + "/clip.bvh", o); }, {"clip.bvh", "'.bvh'", ".csv or .npz"});
  test::expect_input_error([&] { read_reference(dir + "/missing.npz", o); }, {"missing.npz", "cannot open"});

  // With a meta: the robot, joints and rate must agree with what the caller expects.
  Reference ours = test::make_reference(5, {"a", "b"}, 3);
  write_reference(dir + "/ours", ours, {ReferenceFormat::Csv, ReferenceFormat::Npz});
  for (const char* file : {"/ours.csv", "/ours.npz"}) {
    SCOPED_TRACE(file);
    ReferenceReadOptions other = o;
    test::expect_input_error([&] { read_reference(dir + file, other); }, {"ours.", "robot 'g1', not 'toy'"});
    other.robot_name = "g1";
    test::expect_input_error([&] { read_reference(dir + file, other); }, {"ours.", "the file says 30 fps but --fps 25"});
    other.fps = 0;
    other.joint_names = {"a", "b", "c"};
    test::expect_input_error([&] { read_reference(dir + file, other); }, {"reference has 2 joints but robot g1 has 3 (first missing: c)"});
    other.joint_names = {"a", "z"};
    test::expect_input_error([&] { read_reference(dir + file, other); }, {"joint 'b' is not a joint of robot g1"});
    other.joint_names = {"b", "a"};  // same set, other order: fine, the caller maps by name
    EXPECT_EQ(read_reference(dir + file, other).joint_names, (std::vector<std::string>{"a", "b"}));
  }

  // A meta whose joint count disagrees with the CSV.
  std::string meta = read_file(dir + "/ours.meta.json");
  const std::string names = "\"joint_names\": [\"a\",\"b\"]";
  ASSERT_NE(meta.find(names), std::string::npos);
  std::string meta3 = meta;
  meta3.replace(meta3.find(names), names.size(), "\"joint_names\": [\"a\",\"b\",\"c\"]");
  meta3.replace(meta3.find("\"columns\": 9"), 12, "\"columns\": 10");
  write_file_atomic(dir + "/ours.meta.json", meta3);
  test::expect_input_error([&] { read_reference(dir + "/ours.csv"); },
                           {"ours.csv:1", "expected 10 columns (7 root + 3 joints in ours.meta.json), got 9"});
  test::expect_input_error([&] { read_reference(dir + "/ours.npz"); }, {"ours.meta.json [joint_names]", "differ"});
  // A meta with fewer frames than the CSV.
  std::string meta_t = meta;
  meta_t.replace(meta_t.find("\"num_frames\": 5"), 15, "\"num_frames\": 6");
  write_file_atomic(dir + "/ours.meta.json", meta_t);
  test::expect_input_error([&] { read_reference(dir + "/ours.csv"); }, {"ours.meta.json [num_frames]", "6 frames but ours.csv has 5"});
  // Non-monotonic time stamps in the meta.
  std::string meta_time = meta;
  meta_time.replace(meta_time.find("\"num_frames\": 5"), 15, "\"num_frames\": 5, \"time_s\": [0, 0.0333333333333, 0.02, 0.1, 0.133333333333]");
  write_file_atomic(dir + "/ours.meta.json", meta_time);
  test::expect_input_error([&] { read_reference(dir + "/ours.csv"); }, {"ours.meta.json [time_s]", "not increasing at index 2"});
}

TEST(ReferenceIo, CheckReference) {
  Reference r = test::make_reference(4, {"a"}, 1);
  check_reference(r, "r");
  r.fps = 0;
  test::expect_input_error([&] { check_reference(r, "r"); }, {"r", "frame rate"});
  r = test::make_reference(4, {"a", "a"}, 1);
  test::expect_input_error([&] { check_reference(r, "r"); }, {"duplicate joint name 'a'"});
  r = test::make_reference(4, {"a"}, 1);
  r.root_quat_W[2].coeffs() *= 2;
  test::expect_input_error([&] { check_reference(r, "r"); }, {"r frame 2 root orientation"});
  r = test::make_reference(4, {"a"}, 1);
  r.com_W(1, 3) = INFINITY;
  test::expect_input_error([&] { check_reference(r, "r"); }, {"r frame 3 COM"});
  r = test::make_reference(4, {"a"}, 1);
  r.contact[1].pop_back();
  EXPECT_THROW(check_reference(r, "r"), InternalError);
}

}  // namespace
}  // namespace rt
