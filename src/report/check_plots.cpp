#include "retarget/report/check_plots.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "replan_bursts.hpp"

namespace rt {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegPerRad = 57.29577951308232;

// Palette (matplotlib's tab10, which reads well on white and for common colour blindness).
constexpr const char* kBlue = "#1f77b4";
constexpr const char* kOrange = "#ff7f0e";
constexpr const char* kGreen = "#2ca02c";
constexpr const char* kRed = "#d62728";
constexpr const char* kPurple = "#9467bd";
constexpr const char* kBrown = "#8c564b";
constexpr const char* kGrey = "#7f7f7f";
constexpr const char* kBlack = "#000000";

std::string figure_title(const ReportInfo& info, const std::string& what) {
  std::string who = info.robot.empty() ? std::string("robot") : info.robot;
  if (!info.reference_path.empty()) who += " \u2190 " + base_name(info.reference_path);
  return who + ": " + what;
}

std::string verdict(const DynamicsCheckResult& r) {
  std::string v = r.passed ? "passed" : "FAILED";
  if (r.fell) v += format(", fell at %.3f s", r.fall_time_s);
  return v;
}

std::string mapping_note(const ReportInfo& info) {
  return std::string("dynamic mapping ") + (info.dynamic_mapping ? "on" : "off") + ", trunk mapping " +
         (info.trunk_mapping ? "on" : "off");
}

// Time axis shared by every panel: the clip, even when the run stopped early.
svg::Axis time_axis(const DynamicsCheckResult& r) {
  const double end = std::max({r.clip_duration_s, r.trace.t_s.empty() ? 0.0 : r.trace.t_s.back(), 1e-3});
  return {"time", "s", 0.0, end};
}

svg::Series series(std::string name, const std::vector<double>& t, std::vector<double> y, const char* color,
                   svg::LineStyle style = svg::LineStyle::Solid, double width_px = 1.5) {
  svg::Series s;
  s.name = std::move(name);
  s.x = t;
  s.y = std::move(y);
  s.color = color;
  s.style = style;
  s.width_px = width_px;
  return s;
}

template <class V>
std::vector<double> component(const std::vector<V>& v, int axis) {
  std::vector<double> out;
  out.reserve(v.size());
  for (const V& p : v) out.push_back(p[axis]);
  return out;
}

// Length-checked column of the trace: a trace whose columns differ in length is a bug upstream.
template <class V>
const std::vector<V>& column(const DynamicsTrace& tr, const std::vector<V>& c, const char* name) {
  RT_DEMAND(c.size() == tr.t_s.size(), std::string("DynamicsTrace::") + name + " and t_s differ in length");
  return c;
}

void add_violation_spans(svg::Panel& p, const DynamicsCheckResult& r, ViolationKind kind, const char* color) {
  for (const Violation& v : r.violations) {
    if (v.kind != kind) continue;
    svg::Span s;
    s.x0 = v.start_s;
    s.x1 = v.end_s;
    s.color = color;
    s.opacity = 0.15;
    s.legend = violation_name(kind);
    s.tooltip = format("%s %.3f-%.3f s, %.4g %s: ", violation_name(kind), v.start_s, v.end_s, v.magnitude, v.unit.c_str()) + v.detail;
    p.spans.push_back(std::move(s));
  }
}

void add_fall_marker(svg::Panel& p, const DynamicsCheckResult& r) {
  if (!r.fell) return;
  svg::Marker m;
  m.x = r.fall_time_s;
  m.color = kBlack;
  m.style = svg::LineStyle::Solid;
  m.legend = "fall";
  for (const Violation& v : r.violations)
    if (v.kind == ViolationKind::Fall) m.tooltip = format("fall at %.3f s: ", v.start_s) + v.detail;
  p.markers.push_back(std::move(m));
}

// One marker per burst of activations (at its first one), and a light span over bursts that
// last; a lone activation's tooltip gives its prediction along this axis.
void add_replan_markers(svg::Panel& p, const DynamicsCheckResult& r, int axis) {
  const char* axis_name = axis == 0 ? "x" : "y";
  for (const report_detail::ReplanBurst& b : report_detail::replan_bursts(r.replans)) {
    svg::Marker m;
    m.x = b.start_s;
    m.color = kPurple;
    m.style = svg::LineStyle::Dashed;
    m.legend = "COM re-plan";
    if (b.count == 1) {
      for (const ReplanRecord& rec : r.replans) {
        if (rec.t_s != b.start_s) continue;
        const ReplanEvent& e = rec.event;
        m.tooltip = format("COM re-plan at %.3f s (case %d, %d steps ahead): predicted COP %s %.4f m, target %.4f m, "
                           "after %.4f m; COM reference shifted up to %.4f m",
                           rec.t_s, e.kind, e.n, axis_name, e.y_predicted[axis], e.y_ref[axis], e.y_after[axis], e.max_shift_m);
        break;
      }
    } else {
      m.tooltip = format("%d COM re-plans %.3f-%.3f s; COM reference shifted up to %.4f m", b.count, b.start_s, b.end_s,
                         b.max_shift_m);
      svg::Span s;
      s.x0 = b.start_s;
      s.x1 = b.end_s;
      s.color = kPurple;
      s.opacity = 0.07;
      s.legend = "re-planning active";
      s.tooltip = m.tooltip;
      p.spans.push_back(std::move(s));
    }
    p.markers.push_back(std::move(m));
  }
}

}  // namespace

svg::Figure com_cop_figure(const DynamicsCheckResult& r, const ReportInfo& info, int axis) {
  RT_DEMAND(axis == 0 || axis == 1, "com_cop_figure axis must be 0 (x) or 1 (y)");
  const DynamicsTrace& tr = r.trace;
  const std::vector<double>& t = tr.t_s;
  svg::Figure fig;
  // World axes: "forward" and "sideways, + left" hold for a robot facing +x (the usual start).
  fig.title = figure_title(info, axis == 0 ? "COM and COP along world x (forward when facing +x)"
                                           : "COM and COP along world y (sideways, + left when facing +x)");
  svg::Panel p;
  p.title = verdict(r) + "; " + mapping_note(info) + format("; %zu COM re-plan(s)", r.replans.size());
  p.x = time_axis(r);
  p.y = {axis == 0 ? "x" : "y", "m"};
  p.height_px = 440;

  svg::Band support;
  support.name = "support polygon (extent)";
  support.x = t;
  support.lo = component(column(tr, tr.support_min_W, "support_min_W"), axis);
  support.hi = component(column(tr, tr.support_max_W, "support_max_W"), axis);
  support.color = kGreen;
  support.opacity = 0.22;
  p.bands.push_back(std::move(support));
  add_violation_spans(p, r, ViolationKind::CopNearEdge, kRed);

  p.series.push_back(series("COM", t, component(column(tr, tr.com_W, "com_W"), axis), kBlue, svg::LineStyle::Solid, 2.0));
  p.series.push_back(series("reference COM (re-planned)", t, component(column(tr, tr.com_ref_W, "com_ref_W"), axis), kBlack,
                            svg::LineStyle::Dashed));
  p.series.push_back(series("reference COM (original)", t,
                            component(column(tr, tr.com_ref_original_W, "com_ref_original_W"), axis), kGrey,
                            svg::LineStyle::Dotted, 1.8));
  p.series.push_back(series("COP (measured)", t, component(column(tr, tr.cop_W, "cop_W"), axis), kRed, svg::LineStyle::Solid, 1.2));
  p.series.push_back(series("COP (desired)", t, component(column(tr, tr.cop_desired_W, "cop_desired_W"), axis), kOrange,
                            svg::LineStyle::Dashed, 1.2));
  add_replan_markers(p, r, axis);
  add_fall_marker(p, r);
  fig.panels.push_back(std::move(p));
  return fig;
}

svg::Figure contacts_figure(const DynamicsCheckResult& r, const ReportInfo& info) {
  const DynamicsTrace& tr = r.trace;
  const std::vector<double>& t = tr.t_s;
  const auto& ref = column(tr, tr.contact_ref, "contact_ref");
  const auto& act = column(tr, tr.contact_actual, "contact_actual");
  const auto& force = column(tr, tr.foot_force_n, "foot_force_n");
  svg::Figure fig;
  fig.title = figure_title(info, "contacts, reference vs actual");

  svg::Panel timeline;
  timeline.title = verdict(r) + "; bars: foot in contact (reference) or carrying load (actual)";
  timeline.x = time_axis(r);
  timeline.height_px = 240;
  const char* foot[2] = {"left", "right"};
  const char* color[2] = {kBlue, kOrange};
  for (int f = 0; f < 2; ++f) {
    for (int actual = 0; actual < 2; ++actual) {
      svg::TimelineRow row;
      row.label = std::string(foot[f]) + (actual ? " actual" : " reference");
      row.t = t;
      for (std::size_t i = 0; i < t.size(); ++i)
        row.on.push_back(actual ? act[i][static_cast<std::size_t>(f)] : ref[i][static_cast<std::size_t>(f)]);
      row.color = color[f];
      row.opacity = actual ? 1.0 : 0.4;
      timeline.rows.push_back(std::move(row));
    }
  }
  add_violation_spans(timeline, r, ViolationKind::ContactNotAchieved, kRed);
  add_violation_spans(timeline, r, ViolationKind::LiftOffNotAchieved, kPurple);
  add_violation_spans(timeline, r, ViolationKind::FootSlip, kBrown);
  add_fall_marker(timeline, r);

  svg::Panel forces;
  forces.title = "normal force per foot";
  forces.x = time_axis(r);
  forces.y = {"normal force", "N", 0, 0, /*include_zero=*/true};
  forces.height_px = 260;
  for (int f = 0; f < 2; ++f) {
    std::vector<double> fn;
    fn.reserve(t.size());
    for (const auto& v : force) fn.push_back(v[static_cast<std::size_t>(f)]);
    forces.series.push_back(series(std::string(foot[f]) + " foot", t, std::move(fn), color[f]));
  }
  add_fall_marker(forces, r);
  fig.panels.push_back(std::move(timeline));
  fig.panels.push_back(std::move(forces));
  return fig;
}

svg::Figure tracking_figure(const DynamicsCheckResult& r, const ReportInfo& info) {
  const DynamicsTrace& tr = r.trace;
  const std::vector<double>& t = tr.t_s;
  const auto& err = column(tr, tr.tracking_error_rad, "tracking_error_rad");
  svg::Figure fig;
  fig.title = figure_title(info, "tracking errors");

  svg::Panel joints;
  joints.title = verdict(r) + format("; joint RMS error over the clip %.2f deg", r.joint_rms_error_rad * kDegPerRad);
  joints.x = time_axis(r);
  joints.y = {"RMS joint error", "deg", 0, 0, /*include_zero=*/true};
  joints.height_px = 320;
  add_violation_spans(joints, r, ViolationKind::TorqueSaturation, kRed);
  add_violation_spans(joints, r, ViolationKind::JointLimit, kPurple);
  const char* group[4] = {"legs", "torso", "arms", "all joints"};
  const char* color[4] = {kBlue, kGreen, kOrange, kBlack};
  for (std::size_t g = 0; g < 4; ++g) {
    std::vector<double> deg;
    deg.reserve(t.size());
    for (const auto& e : err) deg.push_back(e[g] * kDegPerRad);
    joints.series.push_back(series(group[g], t, std::move(deg), color[g], svg::LineStyle::Solid, g == 3 ? 2.0 : 1.3));
  }
  add_fall_marker(joints, r);

  svg::Panel balance;
  balance.title = format("COM error (RMS %.1f mm, max %.1f mm) and COP error (RMS %.1f mm)", r.com_rms_error_m * 1e3,
                         r.com_max_error_m * 1e3, r.cop_rms_error_m * 1e3);
  balance.x = time_axis(r);
  balance.y = {"horizontal error", "mm", 0, 0, /*include_zero=*/true};
  balance.height_px = 280;
  const auto& com = column(tr, tr.com_W, "com_W");
  const auto& com_ref = column(tr, tr.com_ref_W, "com_ref_W");
  const auto& cop = column(tr, tr.cop_W, "cop_W");
  const auto& cop_des = column(tr, tr.cop_desired_W, "cop_desired_W");
  std::vector<double> com_err, cop_err;
  for (std::size_t i = 0; i < t.size(); ++i) {
    com_err.push_back((com[i].head<2>() - com_ref[i]).norm() * 1e3);
    const double e = (cop[i] - cop_des[i]).norm() * 1e3;  // NaN while nothing touches: a gap
    cop_err.push_back(std::isfinite(e) ? e : kNaN);
  }
  balance.series.push_back(series("COM vs reference", t, std::move(com_err), kBlue, svg::LineStyle::Solid, 1.5));
  balance.series.push_back(series("COP vs desired", t, std::move(cop_err), kRed, svg::LineStyle::Solid, 1.0));
  add_fall_marker(balance, r);
  fig.panels.push_back(std::move(joints));
  fig.panels.push_back(std::move(balance));
  return fig;
}

}  // namespace rt
