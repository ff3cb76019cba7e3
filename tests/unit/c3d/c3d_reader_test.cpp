// C3D reader: the shared real files, and synthetic files written by the in-test writer for every
// processor type and storage.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "c3d_test_writer.hpp"
#include "formats/c3d/c3d_reader.hpp"
#include "retarget/core/diagnostics.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

using c3d::C3dFile;
using c3d::Processor;

struct Expected {
  const char* file;
  Processor processor;
  bool float_storage;
  int points;
  int markers;
  int frames;
  int first_frame;
  double rate;
  int analog_channels;
  double analog_rate;
  std::size_t events;
  const char* first_label;
};

// The table of ../shared/data/README.md section 2.
const Expected kShared[] = {
    {"c3d/c3dorg_sample01_Eb015pi_intel_int.c3d", Processor::Intel, false, 26, 26, 450, 1, 50, 16, 200, 3, "RFT1"},
    {"c3d/c3dorg_sample01_Eb015vr_dec_real.c3d", Processor::Dec, true, 26, 26, 450, 1, 50, 16, 200, 3, "RFT1"},
    {"c3d/c3dorg_sample01_Eb015si_sgi_int.c3d", Processor::Mips, false, 26, 26, 450, 1, 50, 16, 200, 3, "RFT1"},
    {"c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d", Processor::Intel, true, 193, 113, 255, 342, 100, 38, 1000, 8,
     "LFHD"},
    {"c3d/btk_mocap36_optitrack_fullbody.c3d", Processor::Intel, true, 36, 36, 1380, 1, 100, 0, 0, 0, "Skeleton_Hip2"},
    {"c3d/c3dorg_sample20_phasespace_noparams.c3d", Processor::Intel, true, 40, 40, 701, 1, 30, 0, 0, 0, ""},
    {"c3d/opensim_walking2_gait_forceplates.c3d", Processor::Intel, true, 44, 44, 1249, 1, 250, 12, 2000, 0, "RTH1"},
    {"c3d/ezc3d_Qualisys_fullbody_forceplates.c3d", Processor::Intel, true, 55, 55, 340, 705, 200, 69, 2000, 7, "L_IAS"},
};

TEST(C3dReader, EverySharedFileDecodes) {
  int found = 0;
  for (const Expected& e : kShared) {
    const std::string path = test::shared_data(e.file);
    if (path.empty()) continue;
    ++found;
    SCOPED_TRACE(e.file);
    Diagnostics diag;
    const C3dFile f = c3d::read_c3d(path, &diag);
    EXPECT_EQ(f.processor, e.processor);
    EXPECT_EQ(f.float_storage, e.float_storage);
    EXPECT_EQ(f.points.num_points, e.points);
    EXPECT_EQ(f.marker_count(), e.markers);
    EXPECT_EQ(f.points.num_frames, e.frames);
    EXPECT_EQ(f.first_frame, e.first_frame);
    EXPECT_DOUBLE_EQ(f.point_rate, e.rate);
    EXPECT_EQ(f.analog_channels, e.analog_channels);
    EXPECT_DOUBLE_EQ(f.analog_rate, e.analog_rate);
    EXPECT_EQ(f.events.size(), e.events);
    ASSERT_EQ(f.point_labels.size(), static_cast<std::size_t>(e.points));
    EXPECT_EQ(f.point_labels[0], e.first_label);
    EXPECT_EQ(f.points.xyz.size(), static_cast<std::size_t>(e.points) * e.frames * 3);
    // The data section must end inside the file, on the frame count the file states.
    EXPECT_LE(f.data_offset + f.frame_bytes * static_cast<std::size_t>(e.frames), f.file_size);
    // Units: mm everywhere except the PhaseSpace sample, which has no parameters at all.
    EXPECT_EQ(f.point_units, e.points == 40 ? "" : "mm");
    // No NaN ever reaches the samples; invalid samples are flagged by a negative residual.
    for (float v : f.points.xyz) ASSERT_TRUE(std::isfinite(v));
    for (float r : f.points.residual) ASSERT_TRUE(r >= 0 || r == -1.0f);
    for (const auto& d : diag.items()) EXPECT_EQ(d.severity, Diagnostic::Severity::Note) << d.to_string();
  }
  if (found == 0) GTEST_SKIP() << "shared C3D data not found under " << test::shared_data_dir();
}

TEST(C3dReader, SharedFileDetails) {
  RT_REQUIRE_SHARED(pig, "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d");
  const C3dFile f = c3d::read_c3d(pig);
  // Model outputs are told apart from markers by POINT:ANGLES/FORCES/MOMENTS/POWERS.
  auto kind_of = [&](const std::string& label) {
    const auto it = std::find(f.point_labels.begin(), f.point_labels.end(), label);
    return f.point_kinds[static_cast<std::size_t>(it - f.point_labels.begin())];
  };
  EXPECT_EQ(kind_of("LASI"), c3d::PointKind::Marker);
  EXPECT_EQ(kind_of("LKneeAngles"), c3d::PointKind::Angle);
  EXPECT_EQ(kind_of("LHipForce"), c3d::PointKind::Force);
  EXPECT_EQ(kind_of("LHipMoment"), c3d::PointKind::Moment);
  EXPECT_EQ(kind_of("LHipPower"), c3d::PointKind::Power);
  // EVENT group: label, context, time (minutes + seconds).
  ASSERT_EQ(f.events.size(), 8u);
  EXPECT_EQ(f.events[0].label, "Foot Strike");
  EXPECT_EQ(f.events[0].context, "Left");
  EXPECT_NEAR(f.events[0].time_s, 4.72, 1e-5);
  EXPECT_FALSE(f.events[0].from_header);
  const c3d::Parameter* start = f.find("TRIAL", "ACTUAL_START_FIELD");
  ASSERT_NE(start, nullptr);
  EXPECT_EQ(start->numbers[0], 342);

  RT_REQUIRE_SHARED(eb, "c3d/c3dorg_sample01_Eb015pi_intel_int.c3d");
  const C3dFile e = c3d::read_c3d(eb);
  ASSERT_EQ(e.events.size(), 3u);  // header event block, 4-character labels
  EXPECT_TRUE(e.events[0].from_header);
  EXPECT_EQ(e.events[1].label, "RHS");
  EXPECT_NEAR(e.events[1].time_s, 5.4, 1e-5);
  // First sample of RFT1, checked against an independent decode.
  EXPECT_NEAR(e.points.at(0, 0)[0], 249.0, 1.0);
  EXPECT_NEAR(e.points.at(0, 0)[1], 227.0, 1.0);
  EXPECT_NEAR(e.points.at(0, 0)[2], 37.0, 1.0);
  EXPECT_FALSE(e.points.valid(0, 3));  // LFT1 is occluded in frame 1

  RT_REQUIRE_SHARED(opti, "c3d/btk_mocap36_optitrack_fullbody.c3d");
  Diagnostics diag;
  const C3dFile o = c3d::read_c3d(opti, &diag);
  // POINT:LABELS lacks its description-length byte; its next-record offset is what counts.
  EXPECT_EQ(o.point_labels[35], "Skeleton_RFoot2");
  const c3d::Parameter* desc = o.find("POINT", "DESCRIPTIONS");
  ASSERT_NE(desc, nullptr);
  // The subject leaves the volume: every marker is invalid in the last 229 frames.
  for (int i = 0; i < 36; ++i) {
    EXPECT_TRUE(o.points.valid(1150, i));
    EXPECT_FALSE(o.points.valid(1151, i));
    EXPECT_FALSE(o.points.valid(1379, i));
  }
}

// The three Eb015 files hold the same trial as Intel int16, DEC float and MIPS int16.
TEST(C3dReader, Eb015ProcessorsAgree) {
  RT_REQUIRE_SHARED(intel, "c3d/c3dorg_sample01_Eb015pi_intel_int.c3d");
  RT_REQUIRE_SHARED(dec, "c3d/c3dorg_sample01_Eb015vr_dec_real.c3d");
  RT_REQUIRE_SHARED(sgi, "c3d/c3dorg_sample01_Eb015si_sgi_int.c3d");
  const C3dFile a = c3d::read_c3d(intel), b = c3d::read_c3d(dec), c = c3d::read_c3d(sgi);
  ASSERT_EQ(a.points.residual.size(), b.points.residual.size());
  ASSERT_EQ(a.points.residual.size(), c.points.residual.size());
  double max_diff_m = 0;
  int valid = 0;
  for (int f = 0; f < a.points.num_frames; ++f)
    for (int i = 0; i < a.points.num_points; ++i) {
      ASSERT_EQ(a.points.valid(f, i), b.points.valid(f, i)) << "frame " << f << " point " << i;
      ASSERT_EQ(a.points.valid(f, i), c.points.valid(f, i)) << "frame " << f << " point " << i;
      if (!a.points.valid(f, i)) continue;
      ++valid;
      for (int k = 0; k < 3; ++k) {
        max_diff_m = std::max(max_diff_m, 0.001 * std::abs(a.points.at(f, i)[k] - b.points.at(f, i)[k]));
        max_diff_m = std::max(max_diff_m, 0.001 * std::abs(a.points.at(f, i)[k] - c.points.at(f, i)[k]));
      }
    }
  EXPECT_EQ(valid, 11474);
  EXPECT_LT(max_diff_m, 0.001);
  EXPECT_LT(max_diff_m, 1e-6) << "the files agree far better than the 1 mm requirement";
  RecordProperty("eb015_max_disagreement_m", format("%.3g", max_diff_m));
}

// ---- synthetic files ------------------------------------------------------------------------------

test::C3dSpec small_spec(Processor p, bool float_storage, int points = 3, int frames = 5) {
  test::C3dSpec s;
  s.processor = p;
  s.float_storage = float_storage;
  s.int_scale = 0.1;
  s.rate = 120;
  s.first_frame = 7;
  for (int i = 0; i < points; ++i) s.labels.push_back("Sub:M" + std::to_string(i));
  for (int f = 0; f < frames; ++f) {
    std::vector<std::array<float, 4>> row;
    for (int i = 0; i < points; ++i)
      row.push_back({100.0f * i + f, -50.5f + i, 1000.0f - 3.5f * f, (f + i) % 4 == 3 ? -1.0f : 1.0f});
    s.samples.push_back(row);
  }
  return s;
}

class C3dRoundTrip : public ::testing::TestWithParam<std::tuple<Processor, bool>> {};

TEST_P(C3dRoundTrip, DecodesWhatWasWritten) {
  const auto [processor, float_storage] = GetParam();
  test::C3dSpec spec = small_spec(processor, float_storage);
  spec.analog_channels = 3;
  spec.analog_samples_per_frame = 4;
  spec.events = {{"Foot Strike", 0.5}, {"Foot Off", 61.25}};
  const test::C3dBytes bytes = test::write_c3d(spec);
  Diagnostics diag;
  const C3dFile f = c3d::parse_c3d(bytes.bytes, "synthetic.c3d", &diag);
  EXPECT_TRUE(diag.empty()) << diag.items().front().to_string();
  EXPECT_EQ(f.processor, processor);
  EXPECT_EQ(f.float_storage, float_storage);
  EXPECT_EQ(f.points.num_points, 3);
  EXPECT_EQ(f.points.num_frames, 5);
  EXPECT_EQ(f.first_frame, 7);
  EXPECT_DOUBLE_EQ(f.point_rate, 120);
  EXPECT_EQ(f.point_units, "mm");
  EXPECT_EQ(f.point_labels[2], "Sub:M2");
  EXPECT_EQ(f.analog_channels, 3);
  EXPECT_EQ(f.analog_samples_per_frame, 4);
  ASSERT_EQ(f.events.size(), 2u);
  EXPECT_EQ(f.events[1].label, "Foot Off");
  EXPECT_NEAR(f.events[1].time_s, 61.25, 1e-4);
  const double tol = float_storage ? 1e-4 : 0.051;  // int16 storage quantises to the scale
  for (int fr = 0; fr < 5; ++fr)
    for (int i = 0; i < 3; ++i) {
      const auto& s = spec.samples[static_cast<std::size_t>(fr)][static_cast<std::size_t>(i)];
      ASSERT_EQ(f.points.valid(fr, i), s[3] >= 0);
      if (s[3] < 0) {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(f.points.at(fr, i)[k], 0.0f);
        continue;
      }
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(f.points.at(fr, i)[k], s[static_cast<std::size_t>(k)], tol);
    }
}

INSTANTIATE_TEST_SUITE_P(AllProcessors, C3dRoundTrip,
                         ::testing::Combine(::testing::Values(Processor::Intel, Processor::Dec, Processor::Mips),
                                            ::testing::Bool()));

TEST(C3dReader, LabelsContinueInLabels2) {
  test::C3dSpec spec = small_spec(Processor::Intel, true, 7, 2);
  spec.labels_per_parameter = 3;  // LABELS, LABELS2, LABELS3
  const C3dFile f = c3d::parse_c3d(test::write_c3d(spec).bytes, "labels.c3d");
  ASSERT_EQ(f.point_labels.size(), 7u);
  EXPECT_EQ(f.point_labels[3], "Sub:M3");
  EXPECT_EQ(f.point_labels[6], "Sub:M6");
  EXPECT_NE(f.find("POINT", "LABELS3"), nullptr);
}

TEST(C3dReader, DataStartZeroFallsBackToTheHeader) {
  test::C3dSpec spec = small_spec(Processor::Intel, false);
  spec.data_start_param_zero = true;
  Diagnostics diag;
  const C3dFile f = c3d::parse_c3d(test::write_c3d(spec).bytes, "ds0.c3d", &diag);
  EXPECT_NEAR(f.points.at(1, 1)[0], 101.0, 0.051);
  ASSERT_FALSE(diag.empty());
  EXPECT_NE(diag.items()[0].to_string().find("[POINT:DATA_START]"), std::string::npos);
}

TEST(C3dReader, TrialFieldsCarry32BitFrameNumbers) {
  test::C3dSpec spec = small_spec(Processor::Intel, true);
  spec.first_frame = 70000;  // beyond the 16-bit header words
  spec.trial_fields = true;
  const C3dFile f = c3d::parse_c3d(test::write_c3d(spec).bytes, "long.c3d");
  EXPECT_EQ(f.first_frame, 70000);
  EXPECT_EQ(f.points.num_frames, 5);
}

TEST(C3dReader, EmptyParameterSectionUsesTheHeader) {
  test::C3dSpec spec = small_spec(Processor::Mips, true);
  spec.write_parameters = false;
  Diagnostics diag;
  const C3dFile f = c3d::parse_c3d(test::write_c3d(spec).bytes, "noparams.c3d", &diag);
  EXPECT_TRUE(f.parameters.empty());
  EXPECT_EQ(f.points.num_points, 3);
  EXPECT_EQ(f.point_labels[0], "");
  EXPECT_DOUBLE_EQ(f.point_rate, 120);
  EXPECT_NEAR(f.points.at(4, 2)[2], 1000 - 14, 1e-4);
}

TEST(C3dReader, MissingDescriptionByteAndGarbageLastOffsetAreTolerated) {
  test::C3dSpec spec = small_spec(Processor::Intel, true);
  spec.extra.push_back({"ZZZ", "LAST", c3d::DataType::Int16, {}, {5}, {}});  // the last record
  test::C3dBytes b = test::write_c3d(spec);
  const test::C3dWriter w(Processor::Intel);
  // OptiTrack-style: POINT:LABELS' next offset stops before its description-length byte.
  const std::size_t link = b.link_offset.at("POINT:LABELS");
  const int next = static_cast<unsigned char>(b.bytes[link]) | static_cast<unsigned char>(b.bytes[link + 1]) << 8;
  // Remove the description byte and shift the rest of the section left by one.
  const std::size_t desc = link + static_cast<std::size_t>(next) - 1;
  b.bytes.erase(desc, 1);
  b.bytes.insert(b.parameter_end - 1, 1, '\0');
  w.set_i16(b.bytes, link, next - 1);
  // A garbage next offset in the last record (pointing far past the section).
  std::size_t last_link = b.link_offset.at("ZZZ:LAST");
  if (last_link > desc) --last_link;
  w.set_i16(b.bytes, last_link, 30000);
  Diagnostics diag;
  const C3dFile f = c3d::parse_c3d(b.bytes, "tolerant.c3d", &diag);
  EXPECT_EQ(f.point_labels[1], "Sub:M1");
  ASSERT_NE(f.find("ZZZ", "LAST"), nullptr);
  bool noted = false;
  for (const auto& d : diag.items()) noted = noted || d.to_string().find("[ZZZ:LAST]") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(C3dReader, ModelOutputKindsFromTypeGroups) {
  test::C3dSpec spec = small_spec(Processor::Intel, true, 4, 2);
  spec.labels = {"LASI", "LKneeAngles", "LHipReaction", "RASI"};
  spec.extra.push_back({"POINT", "ANGLES", c3d::DataType::Char, {16, 1}, {}, {"LKneeAngles"}});
  spec.extra.push_back({"POINT", "REACTIONS", c3d::DataType::Char, {16, 1}, {}, {"LHipReaction"}});
  spec.extra.push_back({"POINT", "TYPE_GROUPS", c3d::DataType::Char, {10, 2, 2}, {}, {"ANGLES", "ANGLE", "REACTIONS", "REACTION"}});
  const C3dFile f = c3d::parse_c3d(test::write_c3d(spec).bytes, "kinds.c3d");
  EXPECT_EQ(f.point_kinds[0], c3d::PointKind::Marker);
  EXPECT_EQ(f.point_kinds[1], c3d::PointKind::Angle);
  EXPECT_EQ(f.point_kinds[2], c3d::PointKind::Other);
  EXPECT_EQ(f.marker_count(), 2);
}

TEST(C3dReader, LocationFormat) {
  EXPECT_EQ(c3d::c3d_location("walk.c3d", 0x48d, "POINT:LABELS"), "walk.c3d@0x048d [POINT:LABELS]");
  EXPECT_EQ(c3d::c3d_location("walk.c3d", 0x12345), "walk.c3d@0x12345");
}

// Issue 18 item 13: files of BTK's corpus that BTK reads (README of ../shared/data: c3d/btkdata),
// with the values BTK's reader test asserts.
TEST(C3dReader, BtkCorpusParameterSectionsAndEvents) {
  {  // the parameter header declares 3 blocks; the parameters run on to the data start (block 8)
    RT_REQUIRE_SHARED(path, "c3d/btkdata/c3dorg_sample13_golfswing.c3d");
    Diagnostics d;
    const c3d::C3dFile f = c3d::read_c3d(path, &d);
    EXPECT_NEAR(f.point_rate, 107.53, 0.01);
    EXPECT_EQ(f.points.num_points, 29);
    EXPECT_EQ(f.points.num_frames, 514);
    EXPECT_GE(d.warning_count(), 1u);  // says the section ran past its declared end
  }
  {  // same trap; POINT:UNITS 'mete' (read as metres by the motion layer)
    RT_REQUIRE_SHARED(path, "c3d/btkdata/c3dorg_sample15_FP1.c3d");
    const c3d::C3dFile f = c3d::read_c3d(path);
    EXPECT_EQ(f.point_units, "mete");
    EXPECT_GT(f.points.num_frames, 0);
  }
  {  // parameters past the declared 46 blocks up to the data start (51): ANALYSIS:VALUES is read
    RT_REQUIRE_SHARED(path, "c3d/btkdata/others_parameterOverflow.c3d");
    const c3d::C3dFile f = c3d::read_c3d(path);
    const c3d::Parameter* v = f.find("ANALYSIS", "VALUES");
    ASSERT_NE(v, nullptr);
    EXPECT_FALSE(v->numbers.empty());
  }
  {  // an unused ANALOG:UNITS whose data overrun its record: kept empty, the rest is read
    RT_REQUIRE_SHARED(path, "c3d/btkdata/others_badParameterOffset.c3d");
    Diagnostics d;
    const c3d::C3dFile f = c3d::read_c3d(path, &d);
    EXPECT_EQ(f.points.num_points, 41);
    EXPECT_EQ(f.first_frame, 1);
    EXPECT_EQ(f.points.num_frames, 111);
    EXPECT_DOUBLE_EQ(f.point_rate, 250);
    EXPECT_GE(d.warning_count(), 1u);
  }
  {  // integer data, header scale and POINT:SCALE disagree: the header's gives a body's size
    RT_REQUIRE_SHARED(path, "c3d/btkdata/c3dorg_sample06_MACsample.c3d");
    Diagnostics d;
    const c3d::C3dFile f = c3d::read_c3d(path, &d);
    EXPECT_NEAR(f.point_scale, f.header.scale, 1e-7);
    EXPECT_GE(d.warning_count(), 1u);
  }
  {  // events in an EVENTS (plural) group
    RT_REQUIRE_SHARED(path, "c3d/btkdata/c3dorg_sample22_BKINtechnologies.c3d");
    const c3d::C3dFile f = c3d::read_c3d(path);
    ASSERT_EQ(f.events.size(), 2u);
    EXPECT_EQ(f.events[0].label, "STAY_CENTRE");
    EXPECT_EQ(f.events[1].label, "TARGET_ON");
  }
}

}  // namespace
}  // namespace rt
