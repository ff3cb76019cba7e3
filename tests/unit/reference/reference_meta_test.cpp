#include "formats/reference/reference_meta.hpp"

#include <gtest/gtest.h>

#include "formats/reference/reference_csv.hpp"
#include "reference_test_util.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/reference/reference_io.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

TEST(ContactIntervals, RoundTrip) {
  const std::vector<std::uint8_t> flags = {1, 1, 0, 0, 1, 0, 1, 1, 1};
  const auto iv = contact_intervals(flags);
  ASSERT_EQ(iv.size(), 3u);
  EXPECT_EQ(iv[0], (FrameInterval{0, 2}));
  EXPECT_EQ(iv[1], (FrameInterval{4, 5}));
  EXPECT_EQ(iv[2], (FrameInterval{6, 9}));
  EXPECT_EQ(contact_flags(iv, 9), flags);
  EXPECT_TRUE(contact_intervals({0, 0}).empty());
  EXPECT_THROW(contact_flags({{3, 2}}, 9), InternalError);
}

TEST(ReferenceMeta, WritesTheDocumentedSchema) {
  const Reference r = test::make_reference(12, {"hip", "knee"}, 3);
  const std::string text = format_reference_meta(r, {"walk.csv", "walk.npz"});
  for (const char* needle :
       {"\"format\": \"retarget-reference\"", "\"format_version\": 1", "\"robot\": \"g1\"", "\"fps\": 30.0",
        "\"num_frames\": 12", "\"files\": [\"walk.csv\",\"walk.npz\"]", "\"joint_names\": [\"hip\",\"knee\"]",
        "\"quaternion_order\": \"xyzw\"", "\"npz_quaternion_order\": \"wxyz\"", "\"number_format\": \"%.9g\"",
        "\"columns\": 9", "\"left\": [[0,7]]", "\"right\": [[0,5],[10,12]]", "\"urdf_sha256\": \"0123abcd\""})
    EXPECT_NE(text.find(needle), std::string::npos) << needle << "\n" << text;
  // Keys in schema order, extra keys after the ones the writer owns.
  EXPECT_LT(text.find("\"format\""), text.find("\"fps\""));
  EXPECT_LT(text.find("\"cop_ref_w\""), text.find("\"urdf_sha256\""));
  EXPECT_LT(text.find("\"urdf_sha256\""), text.find("\"provenance\""));
}

TEST(ReferenceMeta, ThePlannedZmpIsReadUnderEitherName) {
  const Reference r = test::make_reference(12, {"hip", "knee"}, 3);
  ASSERT_GT(r.cop_W.cols(), 0);
  const std::string text = format_reference_meta(r, {"walk.csv"});
  EXPECT_NE(text.find("\"zmp_w\""), std::string::npos);
  EXPECT_NE(text.find("\"cop_ref_w\""), std::string::npos);
  // Another tool's file with only zmp_w; one with both where they differ: zmp_w wins.
  const std::string only_zmp = R"({"fps": 30, "joint_names": ["hip"], "zmp_w": [[0.5, -0.25], [0.75, 1.0]]})";
  const ReferenceMeta a = parse_reference_meta(only_zmp, "a.meta.json");
  ASSERT_EQ(a.cop_W.cols(), 2);
  EXPECT_EQ(a.cop_W(1, 0), -0.25);
  for (const char* both : {R"({"fps": 30, "joint_names": ["hip"], "cop_ref_w": [[9, 9]], "zmp_w": [[1, 2]]})",
                           R"({"fps": 30, "joint_names": ["hip"], "zmp_w": [[1, 2]], "cop_ref_w": [[9, 9]]})"}) {
    const ReferenceMeta b = parse_reference_meta(both, "b.meta.json");
    ASSERT_EQ(b.cop_W.cols(), 1) << both;
    EXPECT_EQ(b.cop_W(0, 0), 1.0) << both;
  }
}

TEST(ReferenceMeta, RoundTripIsExactAndKeepsUnknownKeys) {
  const Reference r = test::make_reference(40, {"hip", "knee", "ankle"}, 11);
  const std::string text = format_reference_meta(r, {"walk.csv"});
  ReferenceMeta m = parse_reference_meta(text, "walk.meta.json");
  EXPECT_EQ(m.robot_name, "g1");
  EXPECT_EQ(m.fps, 30);
  EXPECT_EQ(m.num_frames, 40);
  EXPECT_EQ(m.joint_names, r.joint_names);
  EXPECT_EQ(m.com_W, r.com_W);  // bit-exact: shortest round-trip decimals
  EXPECT_EQ(m.cop_W, r.cop_W);
  Reference back;
  back.root_pos_W = r.root_pos_W;
  back.root_quat_W = r.root_quat_W;
  back.joint_pos = r.joint_pos;
  apply_reference_meta(std::move(m), "walk.meta.json", "walk.csv", MetaMerge::Fill, back);
  EXPECT_EQ(back.contact[0], r.contact[0]);
  EXPECT_EQ(back.contact[1], r.contact[1]);
  EXPECT_EQ(back.com_W, r.com_W);
  EXPECT_EQ(back.extra_meta_json, r.extra_meta_json);  // same keys, same order, same numbers
  // And the whole meta is a fixed point of read -> write.
  EXPECT_EQ(format_reference_meta(back, {"walk.csv"}), text);
}

TEST(ReferenceMeta, ReadsHandWrittenMetaWithTimeStampsAndWxyz) {
  // tests/data/reference/stand_wxyz: a hand-written CSV + meta (wxyz quaternion columns,
  // time stamps, a third-party key).
  ReferenceReadOptions o;
  const Reference r = read_reference(test::source_path("tests/data/reference/stand_wxyz.csv"), o);
  EXPECT_EQ(r.num_frames(), 4);
  EXPECT_EQ(r.fps, 50);
  EXPECT_EQ(r.robot_name, "humanoid25");
  EXPECT_EQ(r.joint_names, (std::vector<std::string>{"l_knee", "r_knee"}));
  EXPECT_DOUBLE_EQ(r.root_quat_W[0].w(), 1.0);
  EXPECT_DOUBLE_EQ(r.root_quat_W[3].z(), 0.6);  // file row: w=0.8 x=0 y=0 z=0.6
  EXPECT_DOUBLE_EQ(r.root_quat_W[3].w(), 0.8);
  EXPECT_EQ(r.contact[0], (std::vector<std::uint8_t>{1, 1, 1, 1}));
  EXPECT_EQ(r.contact[1], (std::vector<std::uint8_t>{1, 0, 0, 1}));
  EXPECT_EQ(r.extra_meta_json, R"({"recorded_by":"hand","notes":{"why":"reader test"}})");
}

TEST(ReferenceMeta, BadMetaIsOneLineErrorWithKeyLocation) {
  auto parse = [](const std::string& text) { return [text] { parse_reference_meta(text, "m.meta.json"); }; };
  test::expect_input_error(parse("{\"fps\": 30,\n \"joint_names\": [\"a\",]}"), {"m.meta.json:2:", "invalid JSON"});
  test::expect_input_error(parse("[1,2]"), {"m.meta.json:1:1", "must be a JSON object"});
  test::expect_input_error(parse(R"({"joint_names":["a"]})"), {"m.meta.json", "'fps'"});
  test::expect_input_error(parse(R"({"fps":30})"), {"m.meta.json", "'joint_names'"});
  test::expect_input_error(parse(R"({"fps":-3,"joint_names":["a"]})"), {"m.meta.json [fps]", "not between 1 and 10000 Hz"});
  // Issue 18 item 2: 0.001 fps made validate run for minutes; a second "fps" overrode the first.
  test::expect_input_error(parse(R"({"fps":0.001,"joint_names":["a"]})"), {"m.meta.json [fps]", "0.001 Hz, not between"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a"],"fps":0.001})"), {"m.meta.json:1:31", "fps: duplicate key (first at line 1)"});
  test::expect_input_error(parse(R"({"fps":"30","joint_names":["a"]})"), {"[fps]", "expected a number"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a","a"]})"), {"[joint_names[1]]", "duplicate"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a"],"format_version":2})"), {"[format_version]", "newer"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a"],"units":{"length":"cm"}})"), {"[units.length]", "'cm'"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a"],"quaternion_order":"zyxw"})"), {"[quaternion_order]"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a","b"],"csv":{"columns":8}})"),
                           {"[csv.columns]", "7 root + 2 joints = 9"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a"],"contacts":{"left":[[0,2]]}})"), {"[contacts.right]"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a"],"contacts":{"left":[[0,2.5]],"right":[]}})"),
                           {"[contacts.left[0]]", "integer"});
  test::expect_input_error(parse(R"({"fps":30,"joint_names":["a"],"com_pos_w":[[0,0]]})"), {"[com_pos_w[0]]", "3 numbers"});
  test::expect_input_error(parse(std::string(200, '[') + std::string(200, ']')), {"m.meta.json"});
  std::string deep = R"({"fps":30,"joint_names":["a"],"x":)" + std::string(100, '[') + std::string(100, ']') + "}";
  test::expect_input_error(parse(deep), {"m.meta.json", "nests deeper"});
}

TEST(ReferenceMeta, ChecksAgainstTheClip) {
  const std::string base = R"({"fps":30,"joint_names":["a"],)";
  auto apply = [&](const std::string& rest) {
    return [text = base + rest] {
      Reference r;
      r.root_pos_W = Mat3X::Zero(3, 10);
      r.root_quat_W.assign(10, Quat::Identity());
      r.joint_pos = MatX::Zero(1, 10);
      r.joint_names = {"a"};
      apply_reference_meta(parse_reference_meta(text, "m.meta.json"), "m.meta.json", "m.csv", MetaMerge::Fill, r);
    };
  };
  test::expect_input_error(apply(R"("num_frames":11})"), {"[num_frames]", "11 frames but m.csv has 10"});
  test::expect_input_error(apply(R"("contacts":{"left":[[0,11]],"right":[]}})"), {"[contacts.left[0]]", "ends after"});
  test::expect_input_error(apply(R"("contacts":{"left":[[4,4]],"right":[]}})"), {"[contacts.left[0]]", "empty or reversed"});
  test::expect_input_error(apply(R"("contacts":{"left":[],"right":[[0,5],[3,8]]}})"), {"[contacts.right[1]]", "overlaps"});
  test::expect_input_error(apply(R"("com_pos_w":[[0,0,0]]})"), {"[com_pos_w]", "1 rows for 10 frames"});
  test::expect_input_error(apply(R"("time_s":[0,0.1]})"), {"[time_s]", "2 time stamps for 10 frames"});
  std::string t = "[";
  for (int k = 0; k < 10; ++k) t += (k ? "," : "") + std::to_string(k == 6 ? 0.1 : k / 30.0);
  test::expect_input_error(apply(R"("time_s":)" + t + "]}"), {"[time_s]", "not increasing at index 6"});
  t = "[";
  for (int k = 0; k < 10; ++k) t += (k ? "," : "") + std::to_string(k < 5 ? k / 30.0 : k / 25.0);
  test::expect_input_error(apply(R"("time_s":)" + t + "]}"), {"[time_s]", "non-uniform time step at index 5"});
}

}  // namespace
}  // namespace rt
