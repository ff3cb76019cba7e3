#include "retarget/report/check_report.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/report/check_plots.hpp"
#include "support/test_paths.hpp"
#include "xml_check.hpp"

namespace rt {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const Vec2 kNaN2(kNaN, kNaN);

// A 3 s run sampled at 10 ms that goes wrong in every way the plots show: the right foot lifts
// at 1 s (single support, support box shrinks to the left foot), the robot is airborne for 50 ms
// at 1.5 s (no support, no COP), the COP grazes the edge, the right foot fails to land at 2 s,
// torques saturate, the COM is re-planned three times (two of them 20 ms apart) and it falls at 2.5 s.
DynamicsCheckResult synthetic_result(int samples = 250, double dt = 0.01) {
  DynamicsCheckResult r;
  r.clip_duration_s = 3.0;
  r.fell = true;
  r.fall_time_s = 2.5;
  r.simulated_s = 2.5;
  r.passed = false;
  r.wall_s = 0.123456;
  r.real_time_factor = 24.3219;
  r.joint_rms_error_rad = 0.0123456789;
  r.com_rms_error_m = 0.004;
  r.com_max_error_m = 0.0111;
  r.cop_rms_error_m = 0.0065;
  r.saturated_control_cycles = 7;
  r.trunk_mapping_updates = 2;
  r.violations = {
      {ViolationKind::CopNearEdge, 0.8, 0.95, -0.004, "m", "COP 0.004 m inside the support polygon's edge"},
      {ViolationKind::ContactNotAchieved, 2.0, 2.4, 12.5, "N", "right foot carries 12 N <&> \"x\""},
      {ViolationKind::TorqueSaturation, 2.2, 2.3, 1.7, "ratio", "r_knee at 1.70x its effort limit"},
      {ViolationKind::Fall, 2.5, 2.5, 1.0, "", "link 'r_hand' touched the floor"},
  };
  ReplanEvent e;
  e.kind = 1;
  e.n = 37;
  e.y_predicted = Vec2(0.01, -0.02);
  e.y_ref = Vec2(0.01, 0.05);
  e.y_after = Vec2(0.01, 0.049);
  e.max_shift_m = 0.031;
  r.replans = {{0.5, e}, {0.52, e}, {1.9, e}};
  r.replans[2].event.kind = 2;
  DynamicsTrace& tr = r.trace;
  for (int i = 0; i < samples; ++i) {
    const double t = i * dt;
    const bool right_down = t < 1.0 || t >= 2.0;
    const bool airborne = t >= 1.5 && t < 1.55;
    tr.t_s.push_back(t);
    tr.com_W.push_back(Vec3(0.01 * t, 0.05 * std::sin(t), 0.8));
    tr.com_ref_W.push_back(Vec2(0.01 * t, 0.06 * std::sin(t)));
    tr.com_ref_original_W.push_back(Vec2(0.01 * t, 0.04 * std::sin(t)));
    tr.cop_W.push_back(airborne ? kNaN2 : Vec2(0.01 * t, 0.08 * std::sin(1.3 * t)));
    tr.cop_desired_W.push_back(Vec2(0.01 * t, 0.07 * std::sin(1.3 * t)));
    tr.support_min_W.push_back(airborne ? kNaN2 : Vec2(-0.1, right_down ? -0.15 : 0.05));
    tr.support_max_W.push_back(airborne ? kNaN2 : Vec2(0.12, 0.15));
    tr.contact_ref.push_back({true, t < 1.0 || t >= 2.0});
    tr.contact_actual.push_back({!airborne, !airborne && t < 1.0});
    tr.foot_force_n.push_back({airborne ? 0.0 : 300.0, !airborne && t < 1.0 ? 290.0 : 0.0});
    tr.tracking_error_rad.push_back({0.01, 0.02, 0.03 * t, 0.015});
  }
  return r;
}

ReportInfo synthetic_info() {
  ReportInfo info;
  info.robot = "humanoid25";
  info.reference_path = "out/step & <lift>.csv";
  info.dynamic_mapping = true;
  info.trunk_mapping = false;
  info.options_summary = "control 2 ms";
  info.tool_version = "9.9.9-test";
  return info;
}

std::size_t count_markers(const svg::Panel& p, const std::string& legend) {
  return static_cast<std::size_t>(std::count_if(p.markers.begin(), p.markers.end(), [&](const svg::Marker& m) { return m.legend == legend; }));
}

TEST(CheckReport, JsonRoundTripsThroughTheReader) {
  const DynamicsCheckResult r = synthetic_result();
  const std::string text = check_report_json(r, synthetic_info());
  const CheckReportSummary s = parse_check_report(text, "report.json");
  EXPECT_EQ(s.format_version, kCheckReportFormatVersion);
  EXPECT_EQ(s.tool_version, "9.9.9-test");
  EXPECT_EQ(s.robot, "humanoid25");
  EXPECT_EQ(s.reference_path, "out/step & <lift>.csv");
  EXPECT_TRUE(s.dynamic_mapping);
  EXPECT_FALSE(s.trunk_mapping);
  EXPECT_FALSE(s.passed);
  EXPECT_TRUE(s.fell);
  EXPECT_DOUBLE_EQ(s.fall_time_s, 2.5);
  EXPECT_DOUBLE_EQ(s.clip_duration_s, 3.0);
  EXPECT_DOUBLE_EQ(s.simulated_s, 2.5);
  EXPECT_DOUBLE_EQ(s.wall_s, 0.123);
  EXPECT_DOUBLE_EQ(s.real_time_factor, 24.32);
  EXPECT_DOUBLE_EQ(s.joint_rms_error_rad, 0.012346);  // rounded to 1e-6
  EXPECT_DOUBLE_EQ(s.com_rms_error_m, 0.004);
  EXPECT_DOUBLE_EQ(s.com_max_error_m, 0.0111);
  EXPECT_DOUBLE_EQ(s.cop_rms_error_m, 0.0065);
  EXPECT_EQ(s.saturated_control_cycles, 7);
  EXPECT_EQ(s.trunk_mapping_updates, 2);
  EXPECT_EQ(s.num_replans, 3);
  EXPECT_EQ(s.trace_samples, 250);
  ASSERT_EQ(s.violations.size(), r.violations.size());
  for (std::size_t i = 0; i < r.violations.size(); ++i) {
    const Violation &a = r.violations[i], &b = s.violations[i];
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_DOUBLE_EQ(a.start_s, b.start_s);
    EXPECT_DOUBLE_EQ(a.end_s, b.end_s);
    EXPECT_DOUBLE_EQ(a.magnitude, b.magnitude);
    EXPECT_EQ(a.unit, b.unit);
    EXPECT_EQ(a.detail, b.detail);
  }
  // Same result, same bytes; NaN samples are null, never "nan".
  EXPECT_EQ(text, check_report_json(r, synthetic_info()));
  EXPECT_EQ(text.find("nan"), std::string::npos);
  EXPECT_NE(text.find("\"cop_w\""), std::string::npos);
  EXPECT_NE(text.find("\"fails_check\": true"), std::string::npos);
}

TEST(CheckReport, PassingRunWithoutFallWritesNullFallTime) {
  DynamicsCheckResult r = synthetic_result();
  r.fell = false;
  r.fall_time_s = -1;
  r.passed = true;
  r.violations.clear();
  const std::string text = check_report_json(r, synthetic_info());
  EXPECT_NE(text.find("\"fall_time_s\": null"), std::string::npos);
  const CheckReportSummary s = parse_check_report(text, "report.json");
  EXPECT_TRUE(s.passed);
  EXPECT_FALSE(s.fell);
  EXPECT_EQ(s.fall_time_s, -1);
  EXPECT_TRUE(s.violations.empty());
}

TEST(CheckReport, LongTracesAreDownsampledByTheDocumentedRule) {
  const int n = 10001;  // 100 s at 10 ms
  const DynamicsCheckResult r = synthetic_result(n, 0.01);
  const std::string text = check_report_json(r, synthetic_info());
  const CheckReportSummary s = parse_check_report(text, "report.json");
  // stride = ceil(10001 / 4000) = 3: samples 0, 3, ..., 9999 (3334) plus the last one.
  EXPECT_EQ(s.trace_samples, 3335);
  EXPECT_NE(text.find("\"stride\": 3"), std::string::npos);
  EXPECT_NE(text.find("\"source_samples\": 10001"), std::string::npos);
  const std::size_t tail = text.find("\"t_s\"");
  ASSERT_NE(tail, std::string::npos);
  EXPECT_NE(text.find(" 100.0\n", tail), std::string::npos);  // the last sample (t = 100 s) is kept
  EXPECT_LT(text.size(), 2u << 20) << "report.json of a 100 s clip is " << text.size() << " bytes";
  std::cout << "report.json for a 100 s trace: " << text.size() << " bytes\n";
}

TEST(CheckReport, ReaderRejectsMalformedReportsWithLocations) {
  const std::string good = check_report_json(synthetic_result(), synthetic_info());
  auto error_of = [](const std::string& text) -> std::string {
    try {
      parse_check_report(text, "r.json");
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(error_of("{\n  \"format\": }").rfind("r.json:2:13: invalid JSON", 0), 0u) << error_of("{\n  \"format\": }");
  EXPECT_EQ(error_of("[1, 2]").rfind("r.json:1:1:", 0), 0u);
  EXPECT_EQ(error_of("{\"a\": " + std::string(100, '[') + std::string(100, ']') + "}"), "r.json: JSON nests deeper than 32 levels");

  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const std::size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? t : t.replace(at, from.size(), to);
  };
  EXPECT_NE(error_of(replaced("\"retarget-check-report\"", "\"something-else\"")).find("r.json [format]"), std::string::npos);
  EXPECT_NE(error_of(replaced("\"format_version\": 1", "\"format_version\": 2")).find("unsupported version 2"), std::string::npos);
  EXPECT_NE(error_of(replaced("\"com_rms_error_m\"", "\"com_rms\"")).find("r.json [metrics.com_rms_error_m]: missing required key"),
            std::string::npos);
  EXPECT_NE(error_of(replaced("\"passed\": false", "\"passed\": \"no\"")).find("r.json [passed]: expected a boolean, got a string"),
            std::string::npos);
  EXPECT_NE(error_of(replaced("\"kind\": \"torque-saturation\"", "\"kind\": \"wobble\"")).find("r.json [violations[2].kind]"),
            std::string::npos);
  EXPECT_NE(error_of(replaced("\"saturated_control_cycles\": 7", "\"saturated_control_cycles\": -7"))
                .find("[metrics.saturated_control_cycles]"),
            std::string::npos);
  EXPECT_NE(error_of(replaced("\"fall_time_s\": 2.5", "\"fall_time_s\": null")).find("[fall_time_s]"), std::string::npos);
  EXPECT_NE(error_of(replaced("\"samples\": 250", "\"samples\": 251")).find("[trace.samples]"), std::string::npos);
  EXPECT_NE(error_of(replaced("\"clip_duration_s\": 3.0", "\"clip_duration_s\": 1e999")).find("r.json"), std::string::npos);
  EXPECT_THROW(read_check_report(test::scratch_dir() + "/missing.json"), InputError);
}

TEST(CheckReport, SummaryListsVerdictMetricsAndViolationsFailingFirst) {
  const std::string s = format_check_summary(synthetic_result(), synthetic_info());
  EXPECT_EQ(s.rfind("humanoid25 <- out/step & <lift>.csv: FAILED (fell at 2.500 s; simulated 2.500 s of 3.000 s)\n", 0), 0u) << s;
  EXPECT_NE(s.find("dynamic mapping on, trunk mapping off; control 2 ms"), std::string::npos);
  EXPECT_NE(s.find("joint RMS 0.0123 rad (0.71 deg); COM RMS 4.0 mm, max 11.1 mm; COP RMS 6.5 mm"), std::string::npos);
  EXPECT_NE(s.find("7 saturated control cycles, 2 trunk-mapping updates, 3 COM re-plans"), std::string::npos);
  EXPECT_NE(s.find("re-plans    3 in 2 bursts: 0.500-0.520 s (2, case 1), 1.900 s (case 2); largest COM shift 31.0 mm"),
            std::string::npos);
  EXPECT_NE(s.find("violations  4 (2 fail the check)"), std::string::npos);
  const std::size_t fail_contact = s.find("FAIL contact-not-achieved");
  const std::size_t fail_fall = s.find("FAIL fall");
  const std::size_t cop = s.find("     cop-near-edge");
  ASSERT_NE(fail_contact, std::string::npos) << s;
  ASSERT_NE(fail_fall, std::string::npos) << s;
  ASSERT_NE(cop, std::string::npos) << s;
  EXPECT_LT(fail_contact, fail_fall);
  EXPECT_LT(fail_fall, cop);
  EXPECT_EQ(s.back(), '\n');

  DynamicsCheckResult many = synthetic_result();
  for (int i = 0; i < 30; ++i) many.violations.push_back({ViolationKind::FootSlip, 0.1 * i, 0.1 * i + 0.02, 0.2, "m/s", "left foot"});
  EXPECT_NE(format_check_summary(many, synthetic_info()).find("... and 14 more (report.json lists all)"), std::string::npos);
}

TEST(CheckReport, SyntheticRunPlotsShowSupportGapsReplansAndViolations) {
  const DynamicsCheckResult r = synthetic_result();
  const ReportInfo info = synthetic_info();

  const svg::Figure y = com_cop_figure(r, info, 1);
  ASSERT_EQ(y.panels.size(), 1u);
  const svg::Panel& p = y.panels[0];
  EXPECT_EQ(p.series.size(), 5u);
  ASSERT_EQ(p.bands.size(), 1u);
  EXPECT_DOUBLE_EQ(p.bands[0].lo[50], -0.15);  // double support
  EXPECT_DOUBLE_EQ(p.bands[0].lo[120], 0.05);  // left foot only
  EXPECT_TRUE(std::isnan(p.bands[0].lo[152])); // airborne
  EXPECT_EQ(count_markers(p, "COM re-plan"), 2u);  // 0.50 and 0.52 s share a marker
  EXPECT_EQ(count_markers(p, "fall"), 1u);
  ASSERT_EQ(p.spans.size(), 2u);
  EXPECT_EQ(p.spans[0].legend, "cop-near-edge");
  EXPECT_EQ(p.spans[1].legend, "re-planning active");  // the 0.50-0.52 s burst
  EXPECT_DOUBLE_EQ(p.spans[1].x0, 0.5);
  EXPECT_DOUBLE_EQ(p.spans[1].x1, 0.52);
  EXPECT_DOUBLE_EQ(p.x.min, 0);
  EXPECT_DOUBLE_EQ(p.x.max, 3.0);  // the whole clip, although it fell at 2.5 s
  EXPECT_NE(y.title.find("sideways"), std::string::npos);
  EXPECT_NE(com_cop_figure(r, info, 0).title.find("forward"), std::string::npos);
  EXPECT_DOUBLE_EQ(com_cop_figure(r, info, 0).panels[0].series[0].y[100], 0.01);
  EXPECT_THROW(com_cop_figure(r, info, 2), InternalError);

  const svg::Figure c = contacts_figure(r, info);
  ASSERT_EQ(c.panels.size(), 2u);
  ASSERT_EQ(c.panels[0].rows.size(), 4u);
  EXPECT_EQ(c.panels[0].rows[2].label, "right reference");
  EXPECT_TRUE(c.panels[0].rows[2].on[210]);    // right foot should be down again at 2.1 s ...
  EXPECT_FALSE(c.panels[0].rows[3].on[210]);   // ... and is not
  ASSERT_EQ(c.panels[0].spans.size(), 1u);
  EXPECT_EQ(c.panels[0].spans[0].legend, "contact-not-achieved");
  EXPECT_EQ(c.panels[1].series.size(), 2u);

  const svg::Figure t = tracking_figure(r, info);
  ASSERT_EQ(t.panels.size(), 2u);
  EXPECT_EQ(t.panels[0].series.size(), 4u);
  EXPECT_NEAR(t.panels[0].series[2].y[100], 0.03 * 1.0 * 57.29577951308232, 1e-9);  // arms, in degrees
  ASSERT_EQ(t.panels[0].spans.size(), 1u);
  EXPECT_EQ(t.panels[0].spans[0].legend, "torque-saturation");
  EXPECT_TRUE(std::isnan(t.panels[1].series[1].y[152]));  // no COP error while airborne

  // Rendered: well-formed, tooltips carry the (escaped) details.
  const std::string svg = svg::render(c);
  const test::XmlCheck x = test::check_xml(svg);
  ASSERT_TRUE(x.ok) << x.error;
  EXPECT_NE(svg.find("right foot carries 12 N &lt;&amp;&gt; &quot;x&quot;"), std::string::npos);
  EXPECT_NE(svg.find("step &amp; &lt;lift&gt;.csv"), std::string::npos);
}

TEST(CheckReport, WritesAllFilesIntoAFolder) {
  const std::string scratch = test::scratch_dir();
  const std::string dir = scratch + "/nested/report";
  const DynamicsCheckResult r = synthetic_result();
  const std::vector<std::string> files = write_check_report(dir, r, synthetic_info());
  ASSERT_EQ(files.size(), 6u);
  for (const char* name : {"report.json", "report.txt", "com_cop_y.svg", "com_cop_x.svg", "contacts.svg", "tracking.svg"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + name)) << name;
  for (const std::string& f : files)
    if (f.size() > 4 && f.compare(f.size() - 4, 4, ".svg") == 0) {
      const test::XmlCheck x = test::check_xml(read_file(f));
      EXPECT_TRUE(x.ok) << f << ": " << x.error;
    }
  EXPECT_EQ(read_file(dir + "/report.txt"), format_check_summary(r, synthetic_info()));
  EXPECT_FALSE(read_check_report(dir + "/report.json").passed);
  // No temporary files left behind.
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 6);
  // A folder that cannot be created is an input error.
  write_file_atomic(scratch + "/plain-file", "x");
  EXPECT_THROW(write_check_report(scratch + "/plain-file/sub", r, synthetic_info()), InputError);
}

TEST(CheckReport, EmptyTraceStillWritesAReport) {
  DynamicsCheckResult r;
  r.fell = true;
  r.fall_time_s = 0;
  r.clip_duration_s = 4;
  r.violations = {{ViolationKind::Fall, 0, 0, 1, "", "fell while settling"}};
  const std::vector<std::string> files = write_check_report(test::scratch_dir(), r, ReportInfo{});
  EXPECT_EQ(files.size(), 6u);
  EXPECT_EQ(read_check_report(files[0]).trace_samples, 0);
  EXPECT_TRUE(test::check_xml(read_file(files[2])).ok);
}

TEST(CheckReport, Humanoid25StandingRunProducesAPassingReport) {
  const auto model = RobotModel::load(test::source_path("robots/humanoid25"));
  const Reference ref = constant_reference(*model, model->standing_q(), 2.0, 30.0);
  const DynamicsCheckOptions options = default_check_options(*model);
  const DynamicsCheckResult r = run_dynamics_check(*model, ref, options);
  const ReportInfo info = make_report_info("humanoid25", "standing (constant_reference)", options);
  EXPECT_NE(info.options_summary.find("kp 36"), std::string::npos) << info.options_summary;

  const std::string dir = test::scratch_dir();
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<std::string> files = write_check_report(dir, r, info);
  const double write_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(files.size(), 6u);
  const CheckReportSummary s = read_check_report(dir + "/report.json");
  EXPECT_EQ(s.passed, r.passed);
  EXPECT_TRUE(s.passed);
  EXPECT_FALSE(s.fell);
  EXPECT_EQ(s.violations.size(), r.violations.size());
  EXPECT_NEAR(s.simulated_s, 2.0, 1e-6);
  EXPECT_EQ(static_cast<std::size_t>(s.trace_samples), r.trace.t_s.size());
  EXPECT_GE(s.trace_samples, 195);
  EXPECT_NEAR(s.cop_rms_error_m, r.cop_rms_error_m, 1e-6);
  for (std::size_t i = 2; i < files.size(); ++i) {
    const std::string svg = read_file(files[i]);
    const test::XmlCheck x = test::check_xml(svg);
    EXPECT_TRUE(x.ok) << files[i] << ": " << x.error;
    EXPECT_GE(x.count("path"), 2u) << files[i];
  }
  // Standing on both feet: the support band is drawn, and the COM lies inside it.
  const svg::Figure fig = com_cop_figure(r, info, 1);
  const svg::Band& support = fig.panels[0].bands[0];
  const svg::Series& com = fig.panels[0].series[0];
  for (std::size_t i = 0; i < com.y.size(); ++i) {
    ASSERT_TRUE(std::isfinite(support.lo[i])) << "no support at sample " << i;
    EXPECT_GT(com.y[i], support.lo[i]);
    EXPECT_LT(com.y[i], support.hi[i]);
  }
  EXPECT_NE(read_file(dir + "/com_cop_y.svg").find("support polygon"), std::string::npos);
  std::cout << "humanoid25 standing 2 s: report written in " << write_ms << " ms, report.json "
            << std::filesystem::file_size(dir + "/report.json") << " bytes\n"
            << read_file(dir + "/report.txt");
}

}  // namespace
}  // namespace rt
