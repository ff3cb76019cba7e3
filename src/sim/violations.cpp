#include "retarget/sim/violations.hpp"

#include <algorithm>

#include "retarget/core/strings.hpp"

namespace rt {

const char* violation_name(ViolationKind kind) {
  switch (kind) {
    case ViolationKind::Fall: return "fall";
    case ViolationKind::CopNearEdge: return "cop-near-edge";
    case ViolationKind::ContactNotAchieved: return "contact-not-achieved";
    case ViolationKind::LiftOffNotAchieved: return "lift-off-not-achieved";
    case ViolationKind::FootSlip: return "foot-slip";
    case ViolationKind::TorqueSaturation: return "torque-saturation";
    case ViolationKind::JointLimit: return "joint-limit";
    case ViolationKind::HeavyCorrection: return "heavy-correction";
    case ViolationKind::StanceOffFloor: return "stance-off-floor";
    case ViolationKind::StanceFootMoved: return "stance-foot-moved";
    case ViolationKind::JointVelocity: return "joint-velocity";
    case ViolationKind::ReferenceTorque: return "reference-torque";
  }
  return "?";
}

bool violation_kind_from_name(const std::string& name, ViolationKind& kind) {
  for (ViolationKind k : {ViolationKind::Fall, ViolationKind::CopNearEdge, ViolationKind::ContactNotAchieved,
                          ViolationKind::LiftOffNotAchieved, ViolationKind::FootSlip, ViolationKind::TorqueSaturation,
                          ViolationKind::JointLimit, ViolationKind::HeavyCorrection,
                          ViolationKind::StanceOffFloor, ViolationKind::StanceFootMoved,
                          ViolationKind::JointVelocity, ViolationKind::ReferenceTorque})
    if (name == violation_name(k)) {
      kind = k;
      return true;
    }
  return false;
}

bool violation_fails_check(ViolationKind kind) {
  return kind == ViolationKind::Fall || kind == ViolationKind::ContactNotAchieved ||
         kind == ViolationKind::LiftOffNotAchieved || kind == ViolationKind::HeavyCorrection ||
         kind == ViolationKind::StanceOffFloor || kind == ViolationKind::StanceFootMoved ||
         kind == ViolationKind::JointVelocity;
}

void explain_fall(std::vector<Violation>& violations, double window_s) {
  const auto fall = std::find_if(violations.begin(), violations.end(), [](const Violation& v) { return v.kind == ViolationKind::Fall; });
  if (fall == violations.end()) return;
  const double t1 = fall->start_s, t0 = t1 - window_s;
  std::string why;
  for (ViolationKind kind : {ViolationKind::CopNearEdge, ViolationKind::FootSlip, ViolationKind::StanceFootMoved,
                             ViolationKind::TorqueSaturation, ViolationKind::ReferenceTorque, ViolationKind::JointLimit}) {
    double overlap = 0;
    const Violation* worst = nullptr;
    for (const Violation& v : violations) {
      if (v.kind != kind || v.end_s < t0 || v.start_s > t1) continue;
      overlap += std::min(v.end_s, t1) - std::max(v.start_s, t0);
      if (!worst || v.magnitude > worst->magnitude) worst = &v;
    }
    if (!worst) continue;
    why += format("; %s %.2f s", kind == ViolationKind::CopNearEdge ? "COP at the support's edge" : violation_name(kind), overlap);
    if (kind != ViolationKind::CopNearEdge) why += " (" + worst->detail + ")";
  }
  if (!why.empty()) fall->detail += format("; in the %g s before:", window_s) + why.substr(1);
}

ViolationTracker::ViolationTracker(ViolationKind kind, std::string unit, double min_duration_s)
    : kind_(kind), unit_(std::move(unit)), min_duration_s_(min_duration_s) {}

void ViolationTracker::update(double t, bool active, double magnitude, const std::string& detail,
                              std::vector<Violation>& out) {
  if (active) {
    if (!active_) {
      active_ = true;
      span_min_duration_s_ = min_duration_s_;
      start_ = t;
      worst_ = magnitude;
      detail_ = detail;
    } else if (magnitude > worst_) {
      worst_ = magnitude;
      detail_ = detail;
    }
    last_ = t;
    return;
  }
  if (active_) finish(t, out);
}

void ViolationTracker::finish(double t, std::vector<Violation>& out) {
  if (!active_) return;
  active_ = false;
  if (std::max(t, last_) - start_ + 1e-12 >= span_min_duration_s_)
    out.push_back({kind_, start_, std::max(last_, start_), worst_, unit_, detail_});
}

}  // namespace rt
