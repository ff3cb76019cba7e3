// Golden-file tests (design.md §1, issue 7): the whole `retarget convert` pipeline (and the
// dynamics check) on fixed inputs must reproduce stored outputs within stated tolerances.
//
// Every folder tests/golden/<case>/ with a case.yaml is one test, "Cases/Golden.Matches/<case>":
//
//   case.yaml        what to run (schema below)
//   tolerance.yaml   how close the outputs must be (schema below)
//   expected/        outcome.json (exit status, error line), reference.csv + reference.meta.json,
//                    report.json (its time series stripped) — written by the regeneration mode
//
// case.yaml:
//   description: one line
//   input: {project: examples/clips/foot_lift.bvh}   # or {shared: bvh/x.bvh} (skips when the
//                                                    # shared data is absent) or {case: input.bvh}
//   robot: humanoid25                                # as --robot
//   requires_shared: [robots/unitree_g1/g1_29dof_rev_1_0.urdf]   # optional: skip without these
//   convert_args: [--fps, "50"]                      # optional extra `retarget convert` flags
//   check: true                                      # run the dynamics check (--check --report)
//
// tolerance.yaml (every key optional; what is absent is not compared, except that the exit status,
// the frame count, the joint names and the check verdict are always compared exactly):
//   reference:
//     joint_rms_rad: 2.0e-3        # per joint: RMS over frames of actual - expected
//     joint_max_abs_rad: 8.0e-3    # per joint: largest |actual - expected| over frames
//     root_position_rms_m: 2.0e-3  # root position, RMS over frames of the distance
//     root_rotation_rms_rad: 2.0e-3  # root orientation, RMS over frames of the angle between
//     com_rms_m: 2.0e-3            # re-planned COM, RMS of the distance
//     contact_mismatch_fraction: 0.02  # frames x feet whose contact flag differs / all
//   quality:                       # meta.json "quality" metrics: |a - e| <= abs + rel * |e|
//     landmark_error_median_m: {abs: 1.0e-3, rel: 0.02}
//   check:
//     fall_time_s: {abs: 0.1}      # when both fell
//     failing_kinds: true          # the set of kinds of failing violations must match
//     metrics:                     # report.json "metrics"
//       joint_rms_error_rad: {abs: 5.0e-3, rel: 0.1}
//
// A case whose expected outcome is an error (exit status 2) compares the error line exactly; run
// it on an input inside the case folder, which the test passes by a relative path from there, so
// the message does not depend on where the project is checked out.
//
// Regeneration (after an intentional change; README "Golden files" says when that is
// legitimate): RT_GOLDEN_REGENERATE=1 makes each test write its expected/ files instead of
// comparing; tests/golden/regenerate.sh does that for all or named cases.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "retarget/batch/worker_process.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/core/yaml_view.hpp"
#include "retarget/reference/reference_io.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string golden_root() { return test::source_path("tests/golden"); }

std::vector<std::string> case_names() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(golden_root(), ec))
    if (fs::exists(e.path() / "case.yaml")) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

struct Bound {
  double abs = 0, rel = 0;
  bool holds(double actual, double expected) const {
    return std::fabs(actual - expected) <= abs + rel * std::fabs(expected) + 1e-12;
  }
};

struct Tolerance {
  std::map<std::string, double> reference;  // joint_rms_rad, ...
  std::map<std::string, Bound> quality;
  std::optional<Bound> fall_time;
  bool failing_kinds = false;
  std::map<std::string, Bound> check_metrics;
};

Bound parse_bound(const YamlView& v) {
  v.expect_map();
  v.check_keys({"abs", "rel"});
  Bound b{v.get("abs", 0.0), v.get("rel", 0.0)};
  if (b.abs < 0 || b.rel < 0) v.fail("bounds must be >= 0");
  return b;
}

Tolerance parse_tolerance(const std::string& path) {
  const YamlView root = YamlView::load_file(path);
  root.expect_map();
  root.check_keys({"reference", "quality", "check"});
  Tolerance t;
  if (auto r = root.find("reference")) {
    r->check_keys({"joint_rms_rad", "joint_max_abs_rad", "root_position_rms_m", "root_rotation_rms_rad", "com_rms_m",
                   "contact_mismatch_fraction"});
    for (const std::string& k : r->keys()) t.reference[k] = r->at(k).as_double();
  }
  if (auto q = root.find("quality"))
    for (const std::string& k : q->keys()) t.quality[k] = parse_bound(q->at(k));
  if (auto c = root.find("check")) {
    c->check_keys({"fall_time_s", "failing_kinds", "metrics"});
    if (auto f = c->find("fall_time_s")) t.fall_time = parse_bound(*f);
    t.failing_kinds = c->get("failing_kinds", false);
    if (auto m = c->find("metrics"))
      for (const std::string& k : m->keys()) t.check_metrics[k] = parse_bound(m->at(k));
  }
  return t;
}

struct GoldenCase {
  std::string name, dir;
  std::string input;            // path passed to convert
  std::string working_dir;      // where convert runs ("" = here)
  std::string skip_reason;      // non-empty: data missing
  std::string robot;
  std::vector<std::string> convert_args;
  bool check = false;
};

GoldenCase load_case(const std::string& name) {
  GoldenCase c;
  c.name = name;
  c.dir = golden_root() + "/" + name;
  const YamlView y = YamlView::load_file(c.dir + "/case.yaml");
  y.expect_map();
  y.check_keys({"description", "input", "robot", "requires_shared", "convert_args", "check"});
  const YamlView in = y.at("input");
  in.check_keys({"project", "shared", "case"});
  if (in.keys().size() != 1) in.fail("give exactly one of project, shared, case");
  const std::string kind = in.keys().front();
  const std::string rel = in.at(kind).as_string();
  if (kind == "project") {
    c.input = test::source_path(rel);
  } else if (kind == "shared") {
    c.input = test::shared_data(rel);
    if (c.input.empty()) c.skip_reason = "shared test data not found: " + test::shared_data_dir() + "/" + rel;
  } else {
    c.input = rel;  // relative to the case folder, where convert runs
    c.working_dir = c.dir;
  }
  if (auto req = y.find("requires_shared"))
    for (const std::string& r : req->as_strings())
      if (test::shared_data(r).empty() && c.skip_reason.empty())
        c.skip_reason = "shared test data not found: " + test::shared_data_dir() + "/" + r;
  c.robot = y.at("robot").as_string();
  if (auto a = y.find("convert_args")) c.convert_args = a->as_strings();
  c.check = y.get("check", false);
  return c;
}

struct CaseRun {
  int exit_code = -1;
  std::string log;
  std::string error_line;  // the last "error: ..." line
  std::string out_dir;
};

CaseRun run_case(const GoldenCase& c, const std::string& out_dir) {
  WorkerLaunch l;
  l.argv = {std::string(RT_BINARY_DIR) + "/retarget", "convert", c.input, "--robot", c.robot, "-o",
            out_dir + "/reference.csv"};
  l.argv.insert(l.argv.end(), c.convert_args.begin(), c.convert_args.end());
  if (c.check) l.argv.insert(l.argv.end(), {"--check", "--report", out_dir + "/report"});
  l.log_path = out_dir + "/convert.log";
  l.working_dir = c.working_dir;
  l.timeout_s = 600;
  const WorkerExit x = run_worker(l);
  CaseRun r;
  r.exit_code = x.exited ? x.exit_code : 128 + x.signal;
  r.log = read_file(l.log_path);
  r.out_dir = out_dir;
  for (const std::string& line : split(r.log, "\n"))
    if (starts_with(line, "error: ") || starts_with(line, "internal error: ")) r.error_line = line;
  return r;
}

Json read_json(const std::string& path) { return Json::parse(read_file(path)); }

// Machine-specific paths in a meta.json, replaced so expected files are the same on every checkout.
std::string portable(std::string text) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{fs::weakly_canonical(test::shared_data_dir()).string(), "<shared>"},
                                 {test::shared_data_dir(), "<shared>"},
                                 {test::source_dir(), "<project>"}}) {
    for (std::size_t at = text.find(from); !from.empty() && at != std::string::npos; at = text.find(from, at + to.size()))
      text.replace(at, from.size(), to);
  }
  return text;
}

// report.json without its long time series (the trace and the re-plan list).
Json stripped_report(Json report) {
  if (report.contains("trace")) report["trace"] = {{"stripped", true}};
  if (report.contains("replans")) {
    const std::size_t n = report["replans"].size();
    report["replans"] = {{"stripped", true}, {"count", n}};
  }
  return report;
}

void regenerate(const GoldenCase& c, const CaseRun& r) {
  const fs::path expected = fs::path(c.dir) / "expected";
  fs::remove_all(expected);
  fs::create_directories(expected);
  Json outcome = {{"exit_code", r.exit_code}};
  if (!r.error_line.empty()) outcome["error"] = r.error_line;
  write_file_atomic((expected / "outcome.json").string(), outcome.dump(1) + "\n");
  if (fs::exists(r.out_dir + "/reference.meta.json")) {
    fs::copy_file(r.out_dir + "/reference.csv", expected / "reference.csv");
    write_file_atomic((expected / "reference.meta.json").string(), portable(read_file(r.out_dir + "/reference.meta.json")));
  }
  if (fs::exists(r.out_dir + "/report/report.json"))
    write_file_atomic((expected / "report.json").string(),
                      portable(stripped_report(read_json(r.out_dir + "/report/report.json")).dump(1)) + "\n");
}

double number(const Json& j, const std::string& key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::nan("");
}

void compare_bound(const std::string& what, double actual, double expected, const Bound& b) {
  EXPECT_TRUE(b.holds(actual, expected)) << what << ": " << actual << ", expected " << expected << " +- (" << b.abs
                                         << " + " << b.rel << " * |expected|)";
}

void compare_reference(const GoldenCase& c, const CaseRun& r, const Tolerance& t) {
  const std::string exp_csv = c.dir + "/expected/reference.csv";
  ASSERT_TRUE(fs::exists(exp_csv)) << "no expected reference: regenerate";
  const Reference e = read_reference(exp_csv);
  const Reference a = read_reference(r.out_dir + "/reference.csv");
  ASSERT_EQ(a.joint_names, e.joint_names);
  ASSERT_EQ(a.num_frames(), e.num_frames()) << "frame count";
  EXPECT_DOUBLE_EQ(a.fps, e.fps);
  const int T = e.num_frames();
  auto tol = [&](const char* key) {
    const auto it = t.reference.find(key);
    return it == t.reference.end() ? -1.0 : it->second;
  };
  // Per joint: RMS and max over frames.
  for (int j = 0; j < static_cast<int>(e.joint_names.size()); ++j) {
    const Eigen::VectorXd d = a.joint_pos.row(j) - e.joint_pos.row(j);
    const double rms = std::sqrt(d.squaredNorm() / T), max_abs = d.cwiseAbs().maxCoeff();
    int worst = 0;
    d.cwiseAbs().maxCoeff(&worst);
    if (tol("joint_rms_rad") >= 0) {
      EXPECT_LE(rms, tol("joint_rms_rad")) << "joint " << e.joint_names[static_cast<std::size_t>(j)] << ": RMS difference "
                                           << rms << " rad";
    }
    if (tol("joint_max_abs_rad") >= 0) {
      EXPECT_LE(max_abs, tol("joint_max_abs_rad"))
          << "joint " << e.joint_names[static_cast<std::size_t>(j)] << ": difference " << max_abs << " rad ("
          << max_abs * 180 / M_PI << " deg) at frame " << worst;
    }
  }
  if (tol("root_position_rms_m") >= 0) {
    const double rms = std::sqrt((a.root_pos_W - e.root_pos_W).colwise().squaredNorm().sum() / T);
    EXPECT_LE(rms, tol("root_position_rms_m")) << "root position RMS difference [m]";
  }
  if (tol("root_rotation_rms_rad") >= 0) {
    double sum = 0;
    for (int k = 0; k < T; ++k) {
      const double angle = a.root_quat_W[static_cast<std::size_t>(k)].angularDistance(e.root_quat_W[static_cast<std::size_t>(k)]);
      sum += angle * angle;
    }
    EXPECT_LE(std::sqrt(sum / T), tol("root_rotation_rms_rad")) << "root orientation RMS difference [rad]";
  }
  if (tol("com_rms_m") >= 0) {
    ASSERT_EQ(a.com_W.cols(), e.com_W.cols()) << "COM present in one and not the other";
    if (e.com_W.cols() > 0) {
      EXPECT_LE(std::sqrt((a.com_W - e.com_W).colwise().squaredNorm().sum() / T), tol("com_rms_m")) << "COM RMS difference [m]";
    }
  }
  if (tol("contact_mismatch_fraction") >= 0) {
    ASSERT_EQ(a.has_contacts(), e.has_contacts());
    int differ = 0;
    for (int f = 0; f < 2; ++f)
      for (int k = 0; k < (e.has_contacts() ? T : 0); ++k)
        differ += a.contact[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)] !=
                  e.contact[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
    EXPECT_LE(differ, tol("contact_mismatch_fraction") * 2 * T) << differ << " contact flags differ";
  }
  // Quality metrics of meta.json.
  const Json em = read_json(c.dir + "/expected/reference.meta.json");
  const Json am = read_json(r.out_dir + "/reference.meta.json");
  EXPECT_EQ(am["source"]["sha256"], em["source"]["sha256"]) << "the input changed: regenerate the case";
  EXPECT_EQ(am["source"]["frames"], em["source"]["frames"]);
  for (const auto& [key, bound] : t.quality) {
    const double ev = number(em["quality"], key), av = number(am["quality"], key);
    ASSERT_FALSE(std::isnan(ev)) << "quality." << key << " is not in the expected meta.json";
    compare_bound("quality." + key, av, ev, bound);
  }
}

std::set<std::string> failing_kinds(const Json& report) {
  std::set<std::string> kinds;
  for (const Json& v : report["violations"])
    if (v.value("fails_check", false)) kinds.insert(v.value("kind", ""));
  return kinds;
}

void compare_report(const GoldenCase& c, const CaseRun& r, const Tolerance& t) {
  ASSERT_TRUE(fs::exists(c.dir + "/expected/report.json")) << "no expected report: regenerate";
  const Json e = read_json(c.dir + "/expected/report.json");
  const Json a = read_json(r.out_dir + "/report/report.json");
  EXPECT_EQ(a["passed"], e["passed"]) << "check verdict";
  EXPECT_EQ(a["fell"], e["fell"]) << "fall";
  if (t.fall_time && e["fell"] == true && a["fell"] == true)
    compare_bound("fall_time_s", number(a, "fall_time_s"), number(e, "fall_time_s"), *t.fall_time);
  if (t.failing_kinds) {
    std::set<std::string> ak = failing_kinds(a), ek = failing_kinds(e);
    EXPECT_EQ(ak, ek) << "kinds of failing violations";
  }
  for (const auto& [key, bound] : t.check_metrics) {
    const double ev = number(e["metrics"], key);
    ASSERT_FALSE(std::isnan(ev)) << "metrics." << key << " is not in the expected report.json";
    compare_bound("metrics." + key, number(a["metrics"], key), ev, bound);
  }
}

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, Matches) {
  const GoldenCase c = load_case(GetParam());
  if (!c.skip_reason.empty()) GTEST_SKIP() << c.skip_reason;
  const Tolerance t = parse_tolerance(c.dir + "/tolerance.yaml");
  const CaseRun r = run_case(c, test::scratch_dir());
  if (std::getenv("RT_GOLDEN_REGENERATE")) {
    regenerate(c, r);
    std::cout << "regenerated " << c.dir << "/expected (exit status " << r.exit_code << ")\n";
    return;
  }
  ASSERT_TRUE(fs::exists(c.dir + "/expected/outcome.json")) << "no expected outputs: run tests/golden/regenerate.sh " << c.name;
  const Json outcome = read_json(c.dir + "/expected/outcome.json");
  ASSERT_EQ(r.exit_code, outcome["exit_code"].get<int>()) << "exit status of retarget convert; its output:\n" << r.log;
  if (outcome.contains("error")) {
    EXPECT_EQ(r.error_line, outcome["error"].get<std::string>());
    EXPECT_FALSE(fs::exists(r.out_dir + "/reference.meta.json")) << "a rejected input must write no output";
    return;
  }
  compare_reference(c, r, t);
  if (c.check) compare_report(c, r, t);
}

INSTANTIATE_TEST_SUITE_P(Cases, Golden, ::testing::ValuesIn(case_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace rt
