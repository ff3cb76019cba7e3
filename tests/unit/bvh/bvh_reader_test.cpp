// BVH reader on small inline texts: structure, channel orders, tolerated syntax, row-count rules.

#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "bvh_test_clips.hpp"
#include "formats/bvh/bvh_reader.hpp"
#include "retarget/core/error.hpp"

namespace rt {
namespace {

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

// Runs the parser and returns the InputError (fails the test if there is none).
InputError parse_error(const std::string& text, const std::string& name = "t.bvh") {
  try {
    parse_bvh(text, name);
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "multi-line message: " << e.what();
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError("", "");
}

TEST(BvhReader, ReadsStructureAndValues) {
  Diagnostics d;
  const BvhFile f = parse_bvh(test::kTinyBvh, "tiny.bvh", &d);
  EXPECT_TRUE(d.empty());
  EXPECT_EQ(f.name, "tiny.bvh");
  ASSERT_EQ(f.joints.size(), 2u);
  EXPECT_EQ(f.joints[0].name, "Hips");
  EXPECT_EQ(f.joints[0].parent, -1);
  EXPECT_EQ(f.joints[0].line, 2);
  EXPECT_EQ(f.joints[1].name, "Chest");
  EXPECT_EQ(f.joints[1].parent, 0);
  EXPECT_EQ(f.joints[1].offset, Vec3(0, 10, 0));
  ASSERT_EQ(f.joints[0].channels.size(), 6u);
  EXPECT_EQ(f.joints[0].channels[3], BvhChannel::Zrotation);
  EXPECT_EQ(f.joints[0].channels[4], BvhChannel::Xrotation);
  EXPECT_EQ(f.joints[0].channels[5], BvhChannel::Yrotation);
  EXPECT_EQ(f.joints[1].first_column, 6);
  ASSERT_EQ(f.end_sites.size(), 1u);
  EXPECT_EQ(f.end_sites[0].parent, 1);
  EXPECT_EQ(f.end_sites[0].offset, Vec3(0, 5, 0));
  EXPECT_EQ(f.end_sites[0].line, 10);
  EXPECT_EQ(f.num_channels, 9);
  EXPECT_EQ(f.num_frames, 3);
  EXPECT_EQ(f.declared_frames, 3);
  EXPECT_DOUBLE_EQ(f.frame_time_s, 0.033333);
  EXPECT_EQ(f.frames_line, 17);
  EXPECT_EQ(f.frame_time_line, 18);
  EXPECT_EQ(f.first_row_line, 19);
  ASSERT_EQ(f.values.size(), 27u);
  EXPECT_DOUBLE_EQ(f.value(1, 3), 10);
  EXPECT_DOUBLE_EQ(f.value(2, 6), 10);
  EXPECT_EQ(f.find_joint("Chest"), 1);
  EXPECT_EQ(f.find_joint("chest"), -1);
  EXPECT_EQ(f.joint_of_column(5), 0);
  EXPECT_EQ(f.joint_of_column(6), 1);
  EXPECT_EQ(f.joint_of_column(9), -1);
}

TEST(BvhReader, ChannelOrdersDifferPerJointAndSixChannelChildren) {
  const std::string text = R"(HIERARCHY
ROOT R
{
  OFFSET 0 0 0
  CHANNELS 6 Zposition Xposition Yposition Yrotation Xrotation Zrotation
  JOINT A
  {
    OFFSET 1 0 0
    CHANNELS 6 Xrotation Yposition Zrotation Xposition Yrotation Zposition
    JOINT B
    {
      OFFSET 0 0 0
      CHANNELS 2 Yrotation Xrotation
      JOINT C
      {
        OFFSET 0 1 0
        CHANNELS 0
        End Site
        {
          OFFSET 0 1 0
        }
      }
    }
  }
}
MOTION
Frames: 1
Frame Time: 0.01
1 2 3 4 5 6 7 8 9 10 11 12 13 14
)";
  const BvhFile f = parse_bvh(text, "orders.bvh");
  ASSERT_EQ(f.joints.size(), 4u);
  using C = BvhChannel;
  EXPECT_EQ(f.joints[0].channels, (std::vector<C>{C::Zposition, C::Xposition, C::Yposition, C::Yrotation, C::Xrotation, C::Zrotation}));
  EXPECT_EQ(f.joints[1].channels, (std::vector<C>{C::Xrotation, C::Yposition, C::Zrotation, C::Xposition, C::Yrotation, C::Zposition}));
  EXPECT_EQ(f.joints[2].channels, (std::vector<C>{C::Yrotation, C::Xrotation}));
  EXPECT_TRUE(f.joints[3].channels.empty());
  EXPECT_EQ(f.joints[1].first_column, 6);
  EXPECT_EQ(f.joints[2].first_column, 12);
  EXPECT_EQ(f.joints[3].first_column, 14);
  EXPECT_EQ(f.joints[2].offset, Vec3::Zero());  // zero-length joint
  EXPECT_EQ(f.num_channels, 14);
  EXPECT_DOUBLE_EQ(f.value(0, 13), 14);
  EXPECT_EQ(bvh_channel_name(C::Yposition), "Yposition");
  EXPECT_EQ(bvh_channel_axis(C::Zrotation), 2);
  EXPECT_TRUE(bvh_is_rotation(C::Xrotation));
  EXPECT_FALSE(bvh_is_rotation(C::Zposition));
}

TEST(BvhReader, ToleratesLineEndsTabsBomSignsAndScientificNotation) {
  // CRLF in the hierarchy, LF and a lone CR in the motion, tabs, a BOM, trailing spaces, '+'
  // signs, exponents, braces on the keyword line, lower-case keywords and no final newline.
  std::string text = std::string("\xEF\xBB\xBF") + "HIERARCHY\r\nROOT Hips {\r\n\tOFFSET\t0 0 0 \r\n"
                     "\tchannels 3 Xposition Yposition Zposition\r\n\tEnd Site{OFFSET 0 1 0}\r\n}\r\n"
                     "MOTION\nFrames:\t2\nFrame Time:\t.0083333   \n"
                     "\t1.5e+01 -2E-2 +3.25   \r4 5 6";
  const BvhFile f = parse_bvh(text, "mixed.bvh");
  ASSERT_EQ(f.num_frames, 2);
  EXPECT_DOUBLE_EQ(f.frame_time_s, 0.0083333);
  EXPECT_DOUBLE_EQ(f.value(0, 0), 15.0);
  EXPECT_DOUBLE_EQ(f.value(0, 1), -0.02);
  EXPECT_DOUBLE_EQ(f.value(0, 2), 3.25);
  EXPECT_DOUBLE_EQ(f.value(1, 2), 6);
  EXPECT_EQ(f.frames_line, 8);
  EXPECT_EQ(f.first_row_line, 10);
  EXPECT_EQ(f.end_sites.size(), 1u);

  // The same with LF only, CRLF only and CR only gives the same values.
  const std::string lf = replace_all(replace_all(text, "\r\n", "\n"), "\r", "\n");
  for (const std::string& variant : {lf, replace_all(lf, "\n", "\r\n"), replace_all(lf, "\n", "\r")}) {
    const BvhFile g = parse_bvh(variant, "variant.bvh");
    EXPECT_EQ(g.values, f.values);
    EXPECT_EQ(g.first_row_line, 10);
  }
}

TEST(BvhReader, SubnormalAndUnderflowingValuesAreAccepted) {
  const std::string text = replace_all(test::kTinyBvh, "0 90 0 0 0 0 0 0 0", "0 90 0 1e-320 -1e-400 0 0 0 0");
  const BvhFile f = parse_bvh(text, "tiny.bvh");
  EXPECT_NEAR(f.value(0, 3), 1e-320, 1e-322);
  EXPECT_EQ(f.value(0, 4), 0.0);
}

TEST(BvhReader, NamesWithSpacesColonsAndSeveralRoots) {
  const std::string text = R"(HIERARCHY
ROOT mixamorig:Hips
{
 OFFSET 0 0 0
 CHANNELS 3 Xposition Yposition Zposition
 JOINT Left Upper Arm
 {
  OFFSET 1 0 0
  CHANNELS 1 Zrotation
  End Site
  {
   OFFSET 1 0 0
  }
 }
}
ROOT Prop
{
 OFFSET 5 0 0
 CHANNELS 1 Yrotation
}
MOTION
Frames: 1
Frame Time: 0.1
0 0 0 45 90
)";
  const BvhFile f = parse_bvh(text, "names.bvh");
  ASSERT_EQ(f.joints.size(), 3u);
  EXPECT_EQ(f.joints[0].name, "mixamorig:Hips");
  EXPECT_EQ(f.joints[1].name, "Left Upper Arm");
  EXPECT_EQ(f.joints[2].name, "Prop");
  EXPECT_EQ(f.joints[2].parent, -1);
  EXPECT_EQ(f.num_channels, 5);
}

TEST(BvhReader, DuplicateJointNamesWarn) {
  const std::string text = replace_all(test::kTinyBvh, "JOINT Chest", "JOINT Hips");
  Diagnostics d;
  const BvhFile f = parse_bvh(text, "dup.bvh", &d);
  ASSERT_EQ(d.warning_count(), 1u);
  EXPECT_NE(d.items()[0].message.find("repeats the joint at line 2"), std::string::npos) << d.items()[0].message;
  EXPECT_EQ(d.items()[0].location, "dup.bvh:6:2");
  EXPECT_EQ(f.find_joint("Hips"), 0);
}

TEST(BvhReader, ExtraRowsWarnAndAreIgnoredOrKept) {
  const std::string text = replace_all(test::kTinyBvh, "Frames: 3", "Frames: 2") + "\n\n3 90 0 0 0 0 0 0 0\n";
  Diagnostics d;
  const BvhFile f = parse_bvh(text, "extra.bvh", &d);
  EXPECT_EQ(f.num_frames, 2);
  EXPECT_EQ(f.values.size(), 18u);
  ASSERT_EQ(d.warning_count(), 1u);
  EXPECT_EQ(d.items()[0].location, "extra.bvh:21");
  EXPECT_NE(d.items()[0].message.find("2 motion rows after the 2 frames declared by 'Frames:' at line 17 ignored"),
            std::string::npos)
      << d.items()[0].message;

  BvhReadOptions keep;
  keep.keep_extra_rows = true;
  Diagnostics d2;
  const BvhFile g = parse_bvh(text, "extra.bvh", &d2, keep);
  EXPECT_EQ(g.num_frames, 4);
  EXPECT_EQ(g.declared_frames, 2);
  EXPECT_DOUBLE_EQ(g.value(3, 0), 3);
  ASSERT_EQ(d2.warning_count(), 1u);
  EXPECT_NE(d2.items()[0].message.find("kept"), std::string::npos);
}

TEST(BvhReader, FewerRowsIsAnErrorAtTheEndOfTheFile) {
  const InputError e = parse_error(replace_all(test::kTinyBvh, "Frames: 3", "Frames: 4"), "few.bvh");
  EXPECT_EQ(e.location(), "few.bvh:22:1");
  EXPECT_EQ(e.message(), "the file ends after 3 frames but 'Frames:' at line 17 declares 4");
  const InputError cut = parse_error(std::string(test::kTinyBvh).substr(0, std::string(test::kTinyBvh).size() - 21), "cut.bvh");
  EXPECT_EQ(cut.location(), "cut.bvh:21:1");
  EXPECT_EQ(cut.message(), "the file ends after 2 frames but 'Frames:' at line 17 declares 3");
}

TEST(BvhReader, RowsMustHoldExactlyOneValuePerChannel) {
  // A short row is not completed from the next line (assimp's flat token stream would do that).
  std::string text = replace_all(test::kTinyBvh, "1 90 0 10 0 0 5 0 0", "1 90 0 10 0 0 5 0");
  text = replace_all(text, "2 90 0 20 0 0 10 0 0", "0 2 90 0 20 0 0 10 0 0");
  const InputError e = parse_error(text);
  EXPECT_EQ(e.location(), "t.bvh:20:18");
  EXPECT_EQ(e.message(), "frame 1 has 8 values, expected 9 (one per channel)");
}

TEST(BvhReader, ZeroFramesAndBlankLinesAreFine) {
  const std::string text = replace_all(test::kTinyBvh, "Frames: 3", "Frames: 0");
  Diagnostics d;
  const BvhFile f = parse_bvh(text, "zero.bvh", &d);
  EXPECT_EQ(f.num_frames, 0);
  EXPECT_EQ(d.warning_count(), 1u);  // the three rows are extra

  const std::string blank = replace_all(test::kTinyBvh, "0.033333\n", "0.033333\n\n  \t\n") + "\n\n   \n";
  EXPECT_EQ(parse_bvh(blank, "blank.bvh").num_frames, 3);
}

TEST(BvhReader, AbsurdFrameCountsNeitherAllocateNorHang) {
  const auto t0 = std::chrono::steady_clock::now();
  for (const char* count : {"2147483647", "2000000000", "99999999999999999999999"}) {
    try {
      parse_bvh(replace_all(test::kTinyBvh, "Frames: 3", std::string("Frames: ") + count), "absurd.bvh");
      ADD_FAILURE() << "accepted Frames: " << count;
    } catch (const InputError& e) {
      EXPECT_TRUE(e.message().find("more than a file of this size can hold") != std::string::npos ||
                  e.message().find("absurd") != std::string::npos)
          << e.what();
    }
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
}

TEST(BvhReader, ErrorsNameTheColumnAndChannel) {
  InputError e = parse_error(replace_all(test::kTinyBvh, "2 90 0 20 0 0 10 0 0", "2 90 0 20 0 0 10 0 inf"));
  EXPECT_EQ(e.location(), "t.bvh:21:20");
  EXPECT_EQ(e.message(), "value 'inf' is not a finite number in frame 2 (column 9, Chest Yrotation)");
  e = parse_error(replace_all(test::kTinyBvh, "0 90 0 0 0 0 0 0 0", "0 90 0 0 0 0 0 0 --1"));
  EXPECT_EQ(e.location(), "t.bvh:19:18");
  EXPECT_EQ(e.message(), "invalid number '--1' in frame 0 (column 9, Chest Yrotation)");
  e = parse_error(replace_all(test::kTinyBvh, "0 90 0 0 0 0 0 0 0", "0 90 0 0 0 0 0 0 +-1"));
  EXPECT_EQ(e.location(), "t.bvh:19:18");
}

TEST(BvhReader, MessagesShowUnprintableBytesEscaped) {
  const InputError e = parse_error(std::string("\x01\x02\xff rest"), "bin.bvh");
  EXPECT_EQ(e.location(), "bin.bvh:1:1");
  EXPECT_EQ(e.message(), "not a BVH file: expected 'HIERARCHY' at the start, found '\\x01\\x02\\xFF'");
}

TEST(BvhReader, RecognisesBvhTextByContent) {
  EXPECT_TRUE(is_bvh_text(test::kTinyBvh));
  EXPECT_TRUE(is_bvh_text("\xEF\xBB\xBF\r\n  hierarchy\r\nROOT"));
  EXPECT_TRUE(is_bvh_text("HIERARCHY"));
  EXPECT_FALSE(is_bvh_text("HIERARCHYX"));
  EXPECT_FALSE(is_bvh_text("HIERAR"));
  EXPECT_FALSE(is_bvh_text(""));
  EXPECT_FALSE(is_bvh_text(std::string("\x02\x50\x1a\x00", 4)));
}

TEST(BvhReader, ReadBvhReportsUnreadableFiles) {
  try {
    read_bvh("/nonexistent/clip.bvh");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), "/nonexistent/clip.bvh");
  }
  BvhReadOptions tiny;
  tiny.max_file_bytes = 10;
  try {
    parse_bvh(test::kTinyBvh, "big.bvh", nullptr, tiny);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("too large"), std::string::npos);
  }
}

}  // namespace
}  // namespace rt
