// Malformed C3D input: every case must end in one rt::InputError whose one-line message carries a
// `file@0x<offset>` location (plus `[GROUP:PARAM]` when a parameter is at fault). Cases are built
// from the in-test writer's well-formed files; tests/data/c3d holds a few files that the writer
// cannot produce.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <regex>

#include "c3d_test_writer.hpp"
#include "formats/c3d/c3d_reader.hpp"
#include "retarget/core/diagnostics.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

using c3d::Processor;

test::C3dSpec base_spec(bool float_storage = true, Processor p = Processor::Intel) {
  test::C3dSpec s;
  s.processor = p;
  s.float_storage = float_storage;
  s.labels = {"LASI", "RASI", "LPSI"};
  s.analog_channels = 2;
  s.analog_samples_per_frame = 2;
  s.events = {{"Foot Strike", 0.1}};
  for (int f = 0; f < 12; ++f)
    s.samples.push_back({{{100.0f + f, 200, 900, 1}}, {{100, -200.0f - f, 900, 1}}, {{-50, 0, 950, f == 4 ? -1.0f : 1.0f}}});
  return s;
}

// Parses and returns the InputError message; fails the test when no InputError is thrown.
std::string error_of(const std::string& bytes, const std::string& name = "bad.c3d") {
  try {
    c3d::parse_c3d(bytes, name);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception type: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no error for " << name;
  return {};
}

// `name@0x<hex>` (optionally ` [GROUP:PARAM]`) then ": message", on one line.
void expect_location(const std::string& message, const std::string& parameter = {}) {
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  static const std::regex kLocation(R"(^[^@]+@0x[0-9a-f]{4,}( \[[A-Za-z0-9_ ]+:[A-Za-z0-9_ ]+\])?: .+)");
  EXPECT_TRUE(std::regex_match(message, kLocation)) << message;
  if (!parameter.empty()) {
    EXPECT_NE(message.find("[" + parameter + "]"), std::string::npos) << message;
  }
}

TEST(C3dBadInput, EmptyAndNotC3d) {
  std::string m = error_of("");
  expect_location(m);
  EXPECT_NE(m.find("empty file"), std::string::npos);
  m = error_of("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n}\n" + std::string(600, ' '), "text.c3d");
  expect_location(m);
  EXPECT_NE(m.find("not a C3D file"), std::string::npos);
  m = error_of(std::string("\x02\x50", 2) + std::string(100, '\0'));
  expect_location(m);
  EXPECT_NE(m.find("truncated inside the 512-byte header"), std::string::npos);
}

TEST(C3dBadInput, CorpusFilesInTestsData) {
  for (const char* f : {"empty.c3d", "text_file.c3d", "garbage.c3d", "header_only.c3d"}) {
    const std::string path = test::source_path(std::string("tests/data/c3d/") + f);
    SCOPED_TRACE(path);
    try {
      c3d::read_c3d(path);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      expect_location(e.what());
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos);
    }
  }
}

TEST(C3dBadInput, TruncatedAtEveryPoint) {
  for (bool float_storage : {true, false}) {
    const test::C3dBytes b = test::write_c3d(base_spec(float_storage));
    const c3d::C3dFile whole = c3d::parse_c3d(b.bytes, "whole.c3d");
    const std::size_t data_end = whole.data_offset + whole.frame_bytes * 12;
    // Up to the first complete frame: an error. Beyond: the complete frames, with a warning
    // (issue 18 item 13, as ezc3d reads them).
    for (std::size_t n = 0; n < whole.data_offset + whole.frame_bytes; ++n) {
      SCOPED_TRACE(n);
      expect_location(error_of(b.bytes.substr(0, n)));
    }
    for (std::size_t n = whole.data_offset + whole.frame_bytes; n < data_end; ++n) {
      SCOPED_TRACE(n);
      Diagnostics d;
      const c3d::C3dFile cut = c3d::parse_c3d(b.bytes.substr(0, n), "cut.c3d", &d);
      EXPECT_EQ(cut.points.num_frames, static_cast<int>((n - whole.data_offset) / whole.frame_bytes));
      ASSERT_EQ(d.warning_count(), 1u);
      EXPECT_NE(d.items()[0].to_string().find("data section truncated"), std::string::npos);
    }
    // Cutting only the block padding after the last frame is harmless.
    EXPECT_NO_THROW(c3d::parse_c3d(b.bytes.substr(0, data_end), "exact.c3d"));
  }
}

TEST(C3dBadInput, RealFilesTruncated) {
  RT_REQUIRE_SHARED(path, "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d");
  const std::string bytes = read_file(path);
  const c3d::C3dFile whole = c3d::parse_c3d(bytes, "pig.c3d");
  for (int k = 0; k < 64; ++k) {
    const std::size_t n = bytes.size() * static_cast<std::size_t>(k) / 64 + static_cast<std::size_t>(k);
    SCOPED_TRACE(n);
    if (n < whole.data_offset + whole.frame_bytes) {
      expect_location(error_of(bytes.substr(0, n), "pig_cut.c3d"));
    } else {  // the complete frames
      EXPECT_EQ(c3d::parse_c3d(bytes.substr(0, n), "pig_cut.c3d").points.num_frames,
                static_cast<int>((n - whole.data_offset) / whole.frame_bytes));
    }
  }
}

TEST(C3dBadInput, BadProcessorAndSectionPointers) {
  test::C3dBytes b = test::write_c3d(base_spec());
  std::string bad = b.bytes;
  bad[b.parameter_offset + 3] = 12;
  std::string m = error_of(bad);
  expect_location(m);
  EXPECT_NE(m.find("@0x0203"), std::string::npos) << m;
  EXPECT_NE(m.find("unknown processor type 12"), std::string::npos);

  bad = b.bytes;
  bad[0] = 0;  // parameter section at block 0
  expect_location(error_of(bad));
  bad[0] = static_cast<char>(200);  // past the end of the file
  m = error_of(bad);
  expect_location(m);
  EXPECT_NE(m.find("past the end of the file"), std::string::npos);

  bad = b.bytes;
  bad[b.parameter_offset + 2] = static_cast<char>(255);  // absurd parameter block count
  m = error_of(bad);
  expect_location(m);
  EXPECT_NE(m.find("extends past the end"), std::string::npos);
}

TEST(C3dBadInput, CyclicAndOutOfRangeParameterOffsets) {
  const test::C3dBytes b = test::write_c3d(base_spec());
  const test::C3dWriter w(Processor::Intel);
  const std::size_t link = b.link_offset.at("POINT:RATE");
  std::string bad = b.bytes;
  w.set_i16(bad, link, -40);  // points back to an earlier record
  std::string m = error_of(bad);
  expect_location(m, "POINT:RATE");
  EXPECT_NE(m.find("backwards"), std::string::npos);

  bad = b.bytes;
  w.set_i16(bad, link, 0x7000);  // far past the section, not the last record
  m = error_of(bad);
  expect_location(m, "POINT:RATE");
  EXPECT_NE(m.find("past the end of the parameter section"), std::string::npos);

  bad = b.bytes;
  w.set_i16(bad, link, 1);  // into its own link word
  expect_location(error_of(bad), "POINT:RATE");

  bad = b.bytes;
  w.set_i16(bad, link, 4);  // too short for the parameter's own data
  m = error_of(bad);
  expect_location(m, "POINT:RATE");
  EXPECT_NE(m.find("overruns"), std::string::npos);
}

TEST(C3dBadInput, CorruptParameterRecords) {
  const test::C3dBytes b = test::write_c3d(base_spec());
  const std::size_t rec = b.record_offset.at("POINT:SCALE");
  const std::size_t type_at = b.link_offset.at("POINT:SCALE") + 2;
  std::string bad = b.bytes;
  bad[type_at] = 3;
  std::string m = error_of(bad);
  expect_location(m, "POINT:SCALE");
  EXPECT_NE(m.find("unknown parameter type 3"), std::string::npos);

  bad = b.bytes;
  bad[type_at + 1] = 9;  // dimensions
  expect_location(error_of(bad), "POINT:SCALE");

  bad = b.bytes;
  bad[type_at + 1] = 7;  // 7 dimensions: the record has no room for them
  m = error_of(bad);
  expect_location(m, "POINT:SCALE");
  EXPECT_NE(m.find("dimensions run past the end of the record"), std::string::npos) << m;

  bad = b.bytes;  // 7 dimensions of 255 (7e16 elements) in a record with room for the dimensions
  const std::size_t labels_type = b.link_offset.at("POINT:LABELS") + 2;
  bad[labels_type + 1] = 7;
  for (int k = 0; k < 7; ++k) bad[labels_type + 2 + static_cast<std::size_t>(k)] = static_cast<char>(255);
  m = error_of(bad);
  expect_location(m, "POINT:LABELS");
  EXPECT_NE(m.find("overruns"), std::string::npos) << m;

  bad = b.bytes;
  bad[rec + 1] = 0;  // group id 0
  expect_location(error_of(bad));

  bad = b.bytes;
  bad[rec + 3] = '\x07';  // control character in the name
  m = error_of(bad);
  expect_location(m);
  EXPECT_NE(m.find("printable"), std::string::npos);
}

// Sets the first element of a numeric parameter in a written file.
void set_number(test::C3dBytes& b, const std::string& key, double v, c3d::DataType t) {
  const test::C3dWriter w(Processor::Intel);
  const std::size_t type_at = b.link_offset.at(key) + 2;
  const std::size_t ndims = static_cast<unsigned char>(b.bytes[type_at + 1]);
  const std::size_t at = type_at + 2 + ndims;
  if (t == c3d::DataType::Float) w.set_f32(b.bytes, at, static_cast<float>(v));
  else w.set_i16(b.bytes, at, static_cast<int>(v));
}

TEST(C3dBadInput, AbsurdCounts) {
  {  // 30000 points in a small file: the data section cannot hold them
    test::C3dBytes b = test::write_c3d(base_spec());
    set_number(b, "POINT:USED", 30000, c3d::DataType::Int16);
    const std::string m = error_of(b.bytes);
    expect_location(m);
    EXPECT_NE(m.find("data section truncated"), std::string::npos) << m;
  }
  // A frame count beyond the data section: its 12 complete frames are read, with a warning
  // (issue 18 item 13; nothing is sized from the claimed count).
  auto expect_complete_frames = [](const std::string& bytes) {
    Diagnostics d;
    const c3d::C3dFile f = c3d::parse_c3d(bytes, "claims.c3d", &d);
    EXPECT_EQ(f.points.num_frames, 12);
    EXPECT_EQ(f.points.xyz.size(), 12u * 3 * 3);
    EXPECT_EQ(d.warning_count(), 1u);
  };
  {  // 65000 header frames
    test::C3dSpec s = base_spec();
    s.header_frames_override = 65000;
    expect_complete_frames(test::write_c3d(s).bytes);
  }
  {  // 32-bit frame count of 2^31 - 1 via TRIAL
    test::C3dSpec s = base_spec();
    s.trial_fields = true;
    test::C3dBytes b = test::write_c3d(s);
    const test::C3dWriter w(Processor::Intel);
    const std::size_t at = b.link_offset.at("TRIAL:ACTUAL_END_FIELD") + 2 + 3;
    w.set_i16(b.bytes, at, -1);
    w.set_i16(b.bytes, at + 2, 0x7fff);
    expect_complete_frames(b.bytes);
  }
  {  // 65535 analog channels at a huge rate
    test::C3dBytes b = test::write_c3d(base_spec());
    set_number(b, "ANALOG:USED", -1, c3d::DataType::Int16);  // 65535 as unsigned
    set_number(b, "ANALOG:RATE", 1e9, c3d::DataType::Float);
    expect_location(error_of(b.bytes));
  }
  {  // last frame before the first
    test::C3dSpec s = base_spec();
    s.first_frame = 100;
    s.header_frames_override = -5;
    expect_location(error_of(test::write_c3d(s).bytes));
  }
  {  // data start beyond the end of the file
    test::C3dBytes b = test::write_c3d(base_spec());
    set_number(b, "POINT:DATA_START", 4000, c3d::DataType::Int16);
    const std::string m = error_of(b.bytes);
    expect_location(m, "POINT:DATA_START");
  }
}

// Issue 18 item 4: a count stored as a float (NaN, -1, 1e10, 1e8 with no frames) is a located
// error at the parameter, never an undefined conversion or a huge label table.
TEST(C3dBadInput, CountsStoredAsFloats) {
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), -1.0, 1e10, 2.5}) {
    test::C3dSpec s = base_spec();
    s.point_used_float = true;
    test::C3dBytes b = test::write_c3d(s);
    set_number(b, "POINT:USED", bad, c3d::DataType::Float);
    const std::string m = error_of(b.bytes);
    expect_location(m, "POINT:USED");
    EXPECT_NE(m.find("is not a count"), std::string::npos) << m;
  }
  {  // 1e8 points and no frames: nothing in the data section bounds the count
    test::C3dSpec s = base_spec();
    s.samples.clear();
    s.point_used_float = true;
    test::C3dBytes b = test::write_c3d(s);
    set_number(b, "POINT:USED", 1e8, c3d::DataType::Float);
    expect_location(error_of(b.bytes), "POINT:USED");
  }
  {  // a whole-number float count is read as the count
    test::C3dSpec s = base_spec();
    s.point_used_float = true;
    const c3d::C3dFile f = c3d::parse_c3d(test::write_c3d(s).bytes, "float_used.c3d");
    EXPECT_EQ(f.points.num_points, 3);
  }
  {  // ANALOG:USED and EVENT:USED too
    test::C3dBytes b = test::write_c3d(base_spec());
    set_number(b, "EVENT:USED", -3, c3d::DataType::Int16);  // 65533 as unsigned: a count, clipped to the times
    EXPECT_NO_THROW(c3d::parse_c3d(b.bytes, "events.c3d"));
  }
}

// Issue 18 item 4: the header scale and POINT:SCALE disagree in sign (float vs int16 storage);
// the data section's size decides, with a warning, and the values come out right either way.
TEST(C3dBadInput, StorageSignDisagreement) {
  for (const bool float_storage : {true, false}) {
    const test::C3dSpec s = base_spec(float_storage);
    const c3d::C3dFile good = c3d::parse_c3d(test::write_c3d(s).bytes, "good.c3d");
    test::C3dBytes b = test::write_c3d(s);
    // Flip POINT:SCALE's sign only (the header word 7 keeps the true storage).
    set_number(b, "POINT:SCALE", float_storage ? 0.1 : -0.1, c3d::DataType::Float);
    Diagnostics d;
    const c3d::C3dFile f = c3d::parse_c3d(b.bytes, "flipped.c3d", &d);
    EXPECT_EQ(f.float_storage, float_storage);
    EXPECT_GE(d.warning_count(), 1u);
    ASSERT_EQ(f.points.xyz.size(), good.points.xyz.size());
    for (std::size_t i = 0; i < f.points.xyz.size(); ++i) EXPECT_NEAR(f.points.xyz[i], good.points.xyz[i], 1e-3) << i;
  }
}

// Issue 18 item 13: integer data whose header scale and POINT:SCALE disagree (c3d.org MACsample
// came out 0.39x too small): the scale giving a body's extent wins, with a warning; when neither
// or both do, a located error rather than a silent conversion at the wrong scale.
TEST(C3dBadInput, IntegerScaleDisagreementPicksTheBodySizedOne) {
  test::C3dSpec s = base_spec(false);
  s.analog_channels = 0;
  s.samples.clear();
  for (int f = 0; f < 10; ++f)  // ankle, head, hand: 1.5 m tall at scale 0.1 (counts up to 16000)
    s.samples.push_back({{{0, 0, 100.0f + f, 1}}, {{0, 0, 1600, 1}}, {{300, 0, 900, 1}}});
  const c3d::C3dFile good = c3d::parse_c3d(test::write_c3d(s).bytes, "good.c3d");
  test::C3dBytes b = test::write_c3d(s);
  set_number(b, "POINT:SCALE", 0.01, c3d::DataType::Float);  // 0.15 m across: not a body
  Diagnostics d;
  const c3d::C3dFile f = c3d::parse_c3d(b.bytes, "mac.c3d", &d);
  EXPECT_NEAR(f.point_scale, 0.1, 1e-7);
  EXPECT_GE(d.warning_count(), 1u);
  ASSERT_EQ(f.points.xyz.size(), good.points.xyz.size());
  for (std::size_t i = 0; i < f.points.xyz.size(); ++i) EXPECT_NEAR(f.points.xyz[i], good.points.xyz[i], 1e-3) << i;
  set_number(b, "POINT:SCALE", 0.12, c3d::DataType::Float);  // 1.8 m: both plausible
  const std::string m = error_of(b.bytes);
  expect_location(m, "POINT:SCALE");
  EXPECT_NE(m.find("ambiguous"), std::string::npos) << m;
}

TEST(C3dBadInput, BadNumbers) {
  {  // NaN rate
    test::C3dBytes b = test::write_c3d(base_spec());
    set_number(b, "POINT:RATE", std::numeric_limits<double>::quiet_NaN(), c3d::DataType::Float);
    expect_location(error_of(b.bytes), "POINT:RATE");
  }
  {  // zero scale with integer storage
    test::C3dBytes b = test::write_c3d(base_spec(false));
    set_number(b, "POINT:SCALE", 0, c3d::DataType::Float);
    const std::string m = error_of(b.bytes);
    expect_location(m, "POINT:SCALE");
  }
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    test::C3dSpec s = base_spec();
    s.samples[3][1][1] = bad;  // a valid sample (residual 1)
    const std::string m = error_of(test::write_c3d(s).bytes);
    expect_location(m);
    EXPECT_NE(m.find("frame 3 (file frame 4), point 2 'RASI': non-finite coordinate"), std::string::npos) << m;
  }
  {  // NaN in an invalid sample is no error: the sample is flagged, its coordinates zeroed
    test::C3dSpec s = base_spec();
    s.samples[4][2][0] = std::numeric_limits<float>::quiet_NaN();
    const c3d::C3dFile f = c3d::parse_c3d(test::write_c3d(s).bytes, "nan_invalid.c3d");
    EXPECT_FALSE(f.points.valid(4, 2));
    EXPECT_EQ(f.points.at(4, 2)[0], 0.0f);
  }
}

}  // namespace
}  // namespace rt
