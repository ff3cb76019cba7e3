#include "retarget/report/check_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string_view>
#include <system_error>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/json_document.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/report/check_plots.hpp"
#include "replan_bursts.hpp"

namespace rt {

namespace {

// ordered_json keeps key order, so the file reads like the schema in the header.
using Json = nlohmann::ordered_json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegPerRad = 57.29577951308232;
constexpr int kMaxJsonDepth = 32;
constexpr std::uint64_t kMaxReportBytes = 256ull << 20;
constexpr std::size_t kMaxListedViolations = 20;
constexpr std::size_t kMaxListedReplanBursts = 6;

const ViolationKind kAllKinds[] = {ViolationKind::Fall,          ViolationKind::CopNearEdge,
                                   ViolationKind::ContactNotAchieved, ViolationKind::LiftOffNotAchieved,
                                   ViolationKind::FootSlip,      ViolationKind::TorqueSaturation,
                                   ViolationKind::JointLimit,    ViolationKind::HeavyCorrection,
                                   ViolationKind::StanceOffFloor, ViolationKind::StanceFootMoved,
                                   ViolationKind::JointVelocity, ViolationKind::ReferenceTorque};

// ---- writing -----------------------------------------------------------------------------------

// A number rounded to 1/scale (fixed resolution: compact, and the same text for the same value);
// null when not finite.
Json rounded(double v, double scale = 1e6) {
  if (!std::isfinite(v)) return nullptr;
  if (std::abs(v) < 1e12) v = std::round(v * scale) / scale;
  return v + 0.0;  // no "-0.0"
}

template <class V>
Json vec(const V& v, double scale = 1e6) {
  bool any = false;
  Json a = Json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    any = any || std::isfinite(v[i]);
    a.push_back(rounded(v[i], scale));
  }
  return any ? a : Json(nullptr);
}

template <std::size_t N>
Json arr(const std::array<double, N>& v, double scale) {
  Json a = Json::array();
  for (double x : v) a.push_back(rounded(x, scale));
  return a;
}

Json flags(const std::array<bool, 2>& v) { return Json::array({v[0] ? 1 : 0, v[1] ? 1 : 0}); }

// One line, with a space after ',' and ':' (nlohmann's compact form has none).
std::string dump_compact(const Json& j) {
  if (!j.is_structured()) return j.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (j.empty()) return j.is_object() ? "{}" : "[]";
  std::string out = j.is_object() ? "{" : "[";
  bool first = true;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!first) out += ", ";
    first = false;
    if (j.is_object()) out += Json(it.key()).dump(-1, ' ', false, Json::error_handler_t::replace) + ": ";
    out += dump_compact(*it);
  }
  out += j.is_object() ? "}" : "]";
  return out;
}

constexpr std::size_t kLineWidth = 100;

// Small values on one line; objects that do not fit one key per line; arrays of short items
// (numbers, [x, y] pairs: the trace) filled into lines of kLineWidth; other arrays one item per line.
void dump_pretty(const Json& j, std::size_t indent, std::string& out) {
  const std::string compact = dump_compact(j);
  if (!j.is_structured() || j.empty() || (indent > 0 && compact.size() + indent <= kLineWidth)) {
    out += compact;
    return;
  }
  const std::string pad(indent + 2, ' ');
  if (j.is_array()) {
    std::vector<std::string> items;
    bool short_items = true;
    for (const Json& v : j) {
      items.push_back(dump_compact(v));
      short_items = short_items && items.back().size() <= 40;
    }
    if (short_items) {
      out += "[\n" + pad;
      std::size_t column = pad.size();
      for (std::size_t i = 0; i < items.size(); ++i) {
        const std::string item = items[i] + (i + 1 < items.size() ? "," : "");
        if (column > pad.size() && column + 1 + item.size() > kLineWidth) {
          out += "\n" + pad;
          column = pad.size();
        } else if (column > pad.size()) {
          out += ' ';
          ++column;
        }
        out += item;
        column += item.size();
      }
      out += "\n" + std::string(indent, ' ') + "]";
      return;
    }
  }
  const bool object = j.is_object();
  out += object ? "{\n" : "[\n";
  std::size_t i = 0;
  for (auto it = j.begin(); it != j.end(); ++it, ++i) {
    out += pad;
    if (object) out += dump_compact(Json(it.key())) + ": ";
    dump_pretty(*it, indent + 2, out);
    if (i + 1 < j.size()) out.push_back(',');
    out.push_back('\n');
  }
  out.append(indent, ' ');
  out.push_back(object ? '}' : ']');
}

void check_trace(const DynamicsTrace& tr) {
  const std::size_t n = tr.t_s.size();
  const std::size_t sizes[] = {tr.com_W.size(),         tr.com_ref_W.size(),    tr.com_ref_original_W.size(),
                               tr.cop_W.size(),         tr.cop_desired_W.size(), tr.support_min_W.size(),
                               tr.support_max_W.size(), tr.contact_ref.size(),   tr.contact_actual.size(),
                               tr.foot_force_n.size(),  tr.tracking_error_rad.size()};
  for (std::size_t s : sizes) RT_DEMAND(s == n, "DynamicsTrace columns differ in length");
}

// Indices of the trace samples written to report.json (the rule is documented in the header).
std::vector<std::size_t> trace_indices(std::size_t n, std::size_t& stride) {
  const auto max_samples = static_cast<std::size_t>(kMaxReportTraceSamples);
  stride = n <= max_samples ? 1 : (n + max_samples - 1) / max_samples;
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < n; i += stride) idx.push_back(i);
  if (n > 0 && idx.back() != n - 1) idx.push_back(n - 1);
  return idx;
}

Json trace_json(const DynamicsTrace& tr) {
  std::size_t stride = 1;
  const std::vector<std::size_t> idx = trace_indices(tr.t_s.size(), stride);
  Json t = Json::array(), com = Json::array(), com_ref = Json::array(), com_orig = Json::array(), cop = Json::array(),
       cop_des = Json::array(), smin = Json::array(), smax = Json::array(), cref = Json::array(), cact = Json::array(),
       force = Json::array(), err = Json::array();
  for (std::size_t i : idx) {
    t.push_back(rounded(tr.t_s[i]));
    com.push_back(vec(tr.com_W[i]));
    com_ref.push_back(vec(tr.com_ref_W[i]));
    com_orig.push_back(vec(tr.com_ref_original_W[i]));
    cop.push_back(vec(tr.cop_W[i]));
    cop_des.push_back(vec(tr.cop_desired_W[i]));
    smin.push_back(vec(tr.support_min_W[i]));
    smax.push_back(vec(tr.support_max_W[i]));
    cref.push_back(flags(tr.contact_ref[i]));
    cact.push_back(flags(tr.contact_actual[i]));
    force.push_back(arr(tr.foot_force_n[i], 1e3));
    err.push_back(arr(tr.tracking_error_rad[i], 1e6));
  }
  Json j;
  j["source_samples"] = tr.t_s.size();
  j["stride"] = stride;
  j["samples"] = idx.size();
  j["t_s"] = std::move(t);
  j["com_w"] = std::move(com);
  j["com_ref_w"] = std::move(com_ref);
  j["com_ref_original_w"] = std::move(com_orig);
  j["cop_w"] = std::move(cop);
  j["cop_desired_w"] = std::move(cop_des);
  j["support_min_w"] = std::move(smin);
  j["support_max_w"] = std::move(smax);
  j["contact_ref"] = std::move(cref);
  j["contact_actual"] = std::move(cact);
  j["foot_force_n"] = std::move(force);
  j["tracking_error_rad"] = std::move(err);
  return j;
}

int failing_count(const std::vector<Violation>& vs) {
  return static_cast<int>(std::count_if(vs.begin(), vs.end(), [](const Violation& v) { return violation_fails_check(v.kind); }));
}

std::string span_text(const Violation& v) {
  return v.end_s > v.start_s ? format("%.3f-%.3f s", v.start_s, v.end_s) : format("%.3f s", v.start_s);
}

// ---- reading -----------------------------------------------------------------------------------

// Typed access by key path, with `file [path]` in every error.
class Reader {
 public:
  explicit Reader(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw InputError(file_ + " [" + path + "]", what);
  }
  const Json& at(const Json& obj, const std::string& parent, const char* key) const {
    const std::string path = parent.empty() ? key : parent + "." + key;
    const auto it = obj.find(key);
    if (it == obj.end()) fail(path, "missing required key");
    return *it;
  }
  static std::string path(const std::string& parent, const char* key) { return parent.empty() ? key : parent + "." + key; }

  bool boolean(const Json& obj, const std::string& parent, const char* key) const {
    const Json& j = at(obj, parent, key);
    if (!j.is_boolean()) fail(path(parent, key), "expected a boolean, got " + json_type_phrase(j));
    return j.get<bool>();
  }
  /// null reads as NaN when `nullable`.
  double number(const Json& obj, const std::string& parent, const char* key, bool nullable = false) const {
    const Json& j = at(obj, parent, key);
    if (nullable && j.is_null()) return kNaN;
    if (!j.is_number()) fail(path(parent, key), "expected a number, got " + json_type_phrase(j));
    return j.get<double>();
  }
  int count(const Json& obj, const std::string& parent, const char* key) const {
    const Json& j = at(obj, parent, key);
    const bool ok = j.is_number_unsigned() ? j.get<std::uint64_t>() <= 2147483647u
                                           : j.is_number_integer() && j.get<long long>() >= 0 && j.get<long long>() <= 2147483647;
    if (!ok)
      fail(path(parent, key), "expected a non-negative integer, got " + dump_compact(j).substr(0, 40));
    return static_cast<int>(j.get<long long>());
  }
  std::string string(const Json& obj, const std::string& parent, const char* key) const {
    const Json& j = at(obj, parent, key);
    if (!j.is_string()) fail(path(parent, key), "expected a string, got " + json_type_phrase(j));
    return j.get<std::string>();
  }
  const Json& object(const Json& obj, const std::string& parent, const char* key) const {
    const Json& j = at(obj, parent, key);
    if (!j.is_object()) fail(path(parent, key), "expected an object, got " + json_type_phrase(j));
    return j;
  }
  const Json& array(const Json& obj, const std::string& parent, const char* key) const {
    const Json& j = at(obj, parent, key);
    if (!j.is_array()) fail(path(parent, key), "expected an array, got " + json_type_phrase(j));
    return j;
  }

 private:
  std::string file_;
};

}  // namespace

ReportInfo make_report_info(const std::string& robot, const std::string& reference_path, const DynamicsCheckOptions& o) {
  ReportInfo info;
  info.robot = robot;
  info.reference_path = reference_path;
  info.dynamic_mapping = o.dynamic_mapping;
  info.trunk_mapping = o.trunk_mapping;
  const std::string controller =
      o.controller == CheckControllerKind::Paper
          ? format("paper controller, re-planning N %d x %g ms, h_max %g, w %g", o.replan.horizon, o.replan.period_s * 1e3,
                   o.replan.h_max, o.replan.w)
          : format("walking controller, DCM gain %g /s, plan margin %g mm, COM-shift bound %g mm, foothold box %g mm, "
                   "foot kp %g, kd %g, friction margin %g",
                   o.walking.dcm_gain, o.walking.plan.margin_m * 1e3, o.walking.plan.max_shift_m * 1e3,
                   o.walking.foothold_box_m * 1e3, o.walking.foot_kp, o.walking.foot_kd, o.walking.friction_margin);
  info.options_summary =
      format("%s; control %g ms, kp %g, kd %g; COP margin %g mm, contact tolerance %g s (at most %g of a phase), slip %g m/s, settle %g s%s",
             controller.c_str(), o.control_period_s * 1e3, o.tracking.kp, o.tracking.kd, o.cop_margin_m * 1e3,
             o.contact_tolerance_s, o.contact_tolerance_fraction, o.slip_speed_mps, o.settle_s,
             o.mass_scale != 1 || o.floor_friction > 0
                 ? format("; simulated masses x%g, floor friction %s", o.mass_scale,
                          o.floor_friction > 0 ? format("%g", o.floor_friction).c_str() : "as robot.yaml")
                       .c_str()
                 : "");
  return info;
}

std::string format_check_summary(const DynamicsCheckResult& r, const ReportInfo& info) {
  std::string s;
  const std::string who = (info.robot.empty() ? std::string("robot") : info.robot) +
                          (info.reference_path.empty() ? std::string() : " <- " + info.reference_path);
  s += who + ": " + (r.passed ? "PASSED" : "FAILED");
  if (r.fell) s += format(" (fell at %.3f s; simulated %.3f s of %.3f s)\n", r.fall_time_s, r.simulated_s, r.clip_duration_s);
  else s += format(" (simulated %.3f s of %.3f s)\n", r.simulated_s, r.clip_duration_s);
  s += std::string("  options     dynamic mapping ") + (info.dynamic_mapping ? "on" : "off") + ", trunk mapping " +
       (info.trunk_mapping ? "on" : "off") + (info.options_summary.empty() ? "" : "; " + info.options_summary) + "\n";
  s += format("  tracking    joint RMS %.4f rad (%.2f deg); COM RMS %.1f mm, max %.1f mm; COP RMS %.1f mm\n",
              r.joint_rms_error_rad, r.joint_rms_error_rad * kDegPerRad, r.com_rms_error_m * 1e3, r.com_max_error_m * 1e3,
              r.cop_rms_error_m * 1e3);
  s += format("  control     %d saturated control cycle%s, %d trunk-mapping update%s, %zu COM re-plan%s\n",
              r.saturated_control_cycles, r.saturated_control_cycles == 1 ? "" : "s", r.trunk_mapping_updates,
              r.trunk_mapping_updates == 1 ? "" : "s", r.replans.size(), r.replans.size() == 1 ? "" : "s");
  if (r.walking.used) {
    const DynamicsCheckResult::WalkingStats& w = r.walking;
    s += format("  balance     plan moved the COM by up to %.1f mm (RMS %.1f mm, at %.2f s)%s; %d receding re-plan%s%s, "
                "%d foothold-adjusting cycle%s (largest %.1f mm), COP clamped in %.1f %% of cycles, DCM error max %.1f mm\n",
                w.plan_max_shift_m * 1e3, w.plan_rms_shift_m * 1e3, w.plan_max_shift_time_s,
                w.plan_max_violation_m < 0 ? ", no plan (solver failed)"
                : w.plan_max_violation_m > 1e-4 ? format(", its ZMP up to %.1f mm outside the shrunk support", w.plan_max_violation_m * 1e3).c_str()
                                                 : "",
                w.replans, w.replans == 1 ? "" : "s",
                w.replans_rejected > 0 ? format(" (%d more left the support: not kept)", w.replans_rejected).c_str() : "",
                w.foothold_adjustments, w.foothold_adjustments == 1 ? "" : "s",
                w.max_foothold_change_m * 1e3, w.cop_clamped_fraction * 100, w.max_dcm_error_m * 1e3);
    if (w.lead_in_foot >= 0)
      s += format("  lead-in     the clip starts with the %s foot %.0f mm in the air: it was put down%s and lifted into "
                  "the first frame over %.2f s before t = 0\n",
                  w.lead_in_foot == 0 ? "left" : "right", w.lead_in_foot_height_m * 1e3,
                  w.lead_in_root_drop_m > 5e-4 ? format(" (the root lowered %.0f mm for it)", w.lead_in_root_drop_m * 1e3).c_str() : "",
                  w.lead_in_s);
    else if (!w.lead_in_skipped.empty())
      s += format("  lead-in     none: %s; the clip starts on one foot\n", w.lead_in_skipped.c_str());
  }
  if (!r.replans.empty()) {
    const std::vector<report_detail::ReplanBurst> bursts = report_detail::replan_bursts(r.replans);
    std::string list;
    const std::size_t shown = std::min(bursts.size(), kMaxListedReplanBursts);
    for (std::size_t i = 0; i < shown; ++i) {
      const report_detail::ReplanBurst& b = bursts[i];
      const char* cases = b.case1 && b.case2 ? "cases 1, 2" : b.case2 ? "case 2" : "case 1";
      list += i ? ", " : "";
      list += b.count == 1 ? format("%.3f s (%s)", b.start_s, cases)
                           : format("%.3f-%.3f s (%d, %s)", b.start_s, b.end_s, b.count, cases);
    }
    if (bursts.size() > shown) list += format(", ... %zu more", bursts.size() - shown);
    double shift = 0;
    for (const report_detail::ReplanBurst& b : bursts) shift = std::max(shift, b.max_shift_m);
    s += format("  re-plans    %zu in %zu burst%s: %s; largest COM shift %.1f mm\n", r.replans.size(), bursts.size(),
                bursts.size() == 1 ? "" : "s", list.c_str(), shift * 1e3);
  }
  s += format("  speed       %.2f s wall, %.1fx real time\n", r.wall_s, r.real_time_factor);
  if (r.violations.empty()) {
    s += "  violations  none\n";
    return s;
  }
  const int failing = failing_count(r.violations);
  s += format("  violations  %zu (%d fail%s the check)\n", r.violations.size(), failing, failing == 1 ? "s" : "");
  for (ViolationKind k : kAllKinds) {
    int n = 0;
    double total = 0, worst = -INFINITY, first = INFINITY;
    std::string unit;
    for (const Violation& v : r.violations) {
      if (v.kind != k) continue;
      ++n;
      total += v.end_s - v.start_s;
      worst = std::max(worst, v.magnitude);
      first = std::min(first, v.start_s);
      unit = v.unit;
    }
    if (n == 0) continue;
    s += format("    %-22s %3d  first at %.3f s", violation_name(k), n, first);
    if (total > 0) s += format(", total %.3f s", total);
    if (!unit.empty()) s += format(", worst %.4g %s", worst, unit.c_str());
    s += "\n";
  }
  // Individual spans: failing ones first, each group in time order.
  std::vector<const Violation*> listed;
  for (int pass = 0; pass < 2; ++pass)
    for (const Violation& v : r.violations)
      if (violation_fails_check(v.kind) == (pass == 0)) listed.push_back(&v);
  const std::size_t shown = std::min(listed.size(), kMaxListedViolations);
  for (std::size_t i = 0; i < shown; ++i) {
    const Violation& v = *listed[i];
    s += format("  %s %-22s %-16s", violation_fails_check(v.kind) ? "FAIL" : "    ", violation_name(v.kind), span_text(v).c_str());
    s += v.unit.empty() ? std::string(17, ' ') : format(" %10.4g %-5s", v.magnitude, v.unit.c_str());
    s += " " + one_line(v.detail) + "\n";
  }
  if (listed.size() > shown) s += format("  ... and %zu more (report.json lists all)\n", listed.size() - shown);
  return s;
}

std::string check_report_json(const DynamicsCheckResult& r, const ReportInfo& info) {
  check_trace(r.trace);
  Json j;
  j["format"] = kCheckReportFormat;
  j["format_version"] = kCheckReportFormatVersion;
  j["tool_version"] = info.tool_version;
  j["robot"] = info.robot;
  j["reference"] = info.reference_path;
  j["options"] = Json{{"dynamic_mapping", info.dynamic_mapping}, {"trunk_mapping", info.trunk_mapping}, {"summary", info.options_summary}};
  j["passed"] = r.passed;
  j["fell"] = r.fell;
  j["fall_time_s"] = r.fell ? rounded(r.fall_time_s) : Json(nullptr);
  j["clip_duration_s"] = rounded(r.clip_duration_s);
  j["simulated_s"] = rounded(r.simulated_s);
  j["wall_s"] = rounded(r.wall_s, 1e3);
  j["real_time_factor"] = rounded(r.real_time_factor, 1e2);
  j["metrics"] = Json{{"joint_rms_error_rad", rounded(r.joint_rms_error_rad)},
                      {"com_rms_error_m", rounded(r.com_rms_error_m)},
                      {"com_max_error_m", rounded(r.com_max_error_m)},
                      {"cop_rms_error_m", rounded(r.cop_rms_error_m)},
                      {"saturated_control_cycles", r.saturated_control_cycles},
                      {"trunk_mapping_updates", r.trunk_mapping_updates},
                      {"replans", r.replans.size()},
                      {"violations", r.violations.size()},
                      {"failing_violations", failing_count(r.violations)}};
  Json vs = Json::array();
  for (const Violation& v : r.violations)
    vs.push_back(Json{{"kind", violation_name(v.kind)},
                      {"start_s", rounded(v.start_s)},
                      {"end_s", rounded(v.end_s)},
                      {"magnitude", rounded(v.magnitude)},
                      {"unit", v.unit},
                      {"detail", v.detail},
                      {"fails_check", violation_fails_check(v.kind)}});
  j["violations"] = std::move(vs);
  if (r.walking.used) {
    const DynamicsCheckResult::WalkingStats& w = r.walking;
    j["balance_plan"] = Json{{"max_com_shift_m", rounded(w.plan_max_shift_m)},
                             {"rms_com_shift_m", rounded(w.plan_rms_shift_m)},
                             {"max_com_shift_time_s", rounded(w.plan_max_shift_time_s)},
                             {"zmp_violation_max_m", rounded(w.plan_max_violation_m)},
                             {"receding_replans", w.replans},
                             {"receding_replans_rejected", w.replans_rejected},
                             {"receding_replan_max_violation_m", rounded(w.replan_max_violation_m)},
                             {"foothold_adjusting_cycles", w.foothold_adjustments},
                             {"max_foothold_change_m", rounded(w.max_foothold_change_m)},
                             {"cop_clamped_fraction", rounded(w.cop_clamped_fraction)},
                             {"early_touchdown_cycles", w.early_touchdown_cycles},
                             {"max_dcm_error_m", rounded(w.max_dcm_error_m)},
                             {"lead_in_s", rounded(w.lead_in_s)},
                             {"lead_in_foot", w.lead_in_foot < 0 ? Json(nullptr) : Json(w.lead_in_foot == 0 ? "left" : "right")},
                             {"lead_in_root_drop_m", rounded(w.lead_in_root_drop_m)},
                             {"lead_in_skipped", w.lead_in_skipped.empty() ? Json(nullptr) : Json(w.lead_in_skipped)}};
  }
  Json rp = Json::array();
  for (const ReplanRecord& p : r.replans)
    rp.push_back(Json{{"t_s", rounded(p.t_s)},
                      {"kind", p.event.kind},
                      {"n", p.event.n},
                      {"predicted_cop_w", vec(p.event.y_predicted)},
                      {"ref_cop_w", vec(p.event.y_ref)},
                      {"after_cop_w", vec(p.event.y_after)},
                      {"max_shift_m", rounded(p.event.max_shift_m)}});
  j["replans"] = std::move(rp);
  j["trace"] = trace_json(r.trace);
  std::string out;
  dump_pretty(j, 0, out);
  out.push_back('\n');
  return out;
}

std::vector<std::string> write_check_report(const std::string& folder, const DynamicsCheckResult& r, const ReportInfo& info) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec || !std::filesystem::is_directory(folder))
    throw InputError(folder, "cannot create the report folder" + (ec ? ": " + ec.message() : std::string()));
  // Render everything first, so a bug in one plot does not leave a half-updated folder.
  std::vector<std::pair<std::string, std::string>> files;
  files.emplace_back("report.json", check_report_json(r, info));
  files.emplace_back("report.txt", format_check_summary(r, info));
  files.emplace_back("com_cop_y.svg", svg::render(com_cop_figure(r, info, 1)));
  files.emplace_back("com_cop_x.svg", svg::render(com_cop_figure(r, info, 0)));
  files.emplace_back("contacts.svg", svg::render(contacts_figure(r, info)));
  files.emplace_back("tracking.svg", svg::render(tracking_figure(r, info)));
  std::vector<std::string> written;
  for (const auto& [name, content] : files) {
    const std::string path = (std::filesystem::path(folder) / name).string();
    write_file_atomic(path, content);
    written.push_back(path);
  }
  return written;
}

CheckReportSummary parse_check_report(const std::string& text, const std::string& file) {
  const Json j = parse_json_object(text, file, "a check report", kMaxJsonDepth);
  const Reader in(file);
  CheckReportSummary s;
  const std::string format_name = in.string(j, "", "format");
  if (format_name != kCheckReportFormat)
    in.fail("format", "expected \"" + std::string(kCheckReportFormat) + "\", got \"" + one_line(format_name).substr(0, 60) + "\"");
  s.format_version = in.count(j, "", "format_version");
  if (s.format_version < 1 || s.format_version > kCheckReportFormatVersion)
    in.fail("format_version", format("unsupported version %d (this tool reads 1 to %d)", s.format_version, kCheckReportFormatVersion));
  s.tool_version = in.string(j, "", "tool_version");
  s.robot = in.string(j, "", "robot");
  s.reference_path = in.string(j, "", "reference");
  const Json& options = in.object(j, "", "options");
  s.dynamic_mapping = in.boolean(options, "options", "dynamic_mapping");
  s.trunk_mapping = in.boolean(options, "options", "trunk_mapping");
  s.passed = in.boolean(j, "", "passed");
  s.fell = in.boolean(j, "", "fell");
  const double fall = in.number(j, "", "fall_time_s", /*nullable=*/true);
  if (s.fell && !std::isfinite(fall)) in.fail("fall_time_s", "expected the fall time (\"fell\" is true)");
  s.fall_time_s = s.fell ? fall : -1;
  s.clip_duration_s = in.number(j, "", "clip_duration_s");
  s.simulated_s = in.number(j, "", "simulated_s");
  s.wall_s = in.number(j, "", "wall_s");
  s.real_time_factor = in.number(j, "", "real_time_factor");

  const Json& m = in.object(j, "", "metrics");
  s.joint_rms_error_rad = in.number(m, "metrics", "joint_rms_error_rad");
  s.com_rms_error_m = in.number(m, "metrics", "com_rms_error_m");
  s.com_max_error_m = in.number(m, "metrics", "com_max_error_m");
  s.cop_rms_error_m = in.number(m, "metrics", "cop_rms_error_m");
  s.saturated_control_cycles = in.count(m, "metrics", "saturated_control_cycles");
  s.trunk_mapping_updates = in.count(m, "metrics", "trunk_mapping_updates");

  const Json& vs = in.array(j, "", "violations");
  for (std::size_t i = 0; i < vs.size(); ++i) {
    const std::string where = format("violations[%zu]", i);
    const Json& v = vs[i];
    if (!v.is_object()) in.fail(where, "expected an object, got " + json_type_phrase(v));
    Violation out;
    const std::string kind = in.string(v, where, "kind");
    if (!violation_kind_from_name(kind, out.kind)) in.fail(where + ".kind", "unknown violation kind \"" + one_line(kind).substr(0, 60) + "\"");
    out.start_s = in.number(v, where, "start_s");
    out.end_s = in.number(v, where, "end_s");
    if (out.end_s < out.start_s) in.fail(where + ".end_s", format("ends at %g s before it starts at %g s", out.end_s, out.start_s));
    out.magnitude = in.number(v, where, "magnitude", /*nullable=*/true);
    out.unit = in.string(v, where, "unit");
    out.detail = in.string(v, where, "detail");
    s.violations.push_back(std::move(out));
  }
  s.num_replans = static_cast<int>(in.array(j, "", "replans").size());
  const Json& trace = in.object(j, "", "trace");
  s.trace_samples = in.count(trace, "trace", "samples");
  const Json& t = in.array(trace, "trace", "t_s");
  if (static_cast<std::size_t>(s.trace_samples) != t.size())
    in.fail("trace.samples", format("says %d samples, trace.t_s has %zu", s.trace_samples, t.size()));
  return s;
}

CheckReportSummary read_check_report(const std::string& path) {
  return parse_check_report(read_file(path, kMaxReportBytes), path);
}

}  // namespace rt
