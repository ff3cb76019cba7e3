#include "retarget/sim/violations.hpp"

#include <algorithm>

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
  }
  return "?";
}

bool violation_kind_from_name(const std::string& name, ViolationKind& kind) {
  for (ViolationKind k : {ViolationKind::Fall, ViolationKind::CopNearEdge, ViolationKind::ContactNotAchieved,
                          ViolationKind::LiftOffNotAchieved, ViolationKind::FootSlip, ViolationKind::TorqueSaturation,
                          ViolationKind::JointLimit, ViolationKind::HeavyCorrection,
                          ViolationKind::StanceOffFloor})
    if (name == violation_name(k)) {
      kind = k;
      return true;
    }
  return false;
}

bool violation_fails_check(ViolationKind kind) {
  return kind == ViolationKind::Fall || kind == ViolationKind::ContactNotAchieved ||
         kind == ViolationKind::LiftOffNotAchieved || kind == ViolationKind::HeavyCorrection ||
         kind == ViolationKind::StanceOffFloor;
}

ViolationTracker::ViolationTracker(ViolationKind kind, std::string unit, double min_duration_s)
    : kind_(kind), unit_(std::move(unit)), min_duration_s_(min_duration_s) {}

void ViolationTracker::update(double t, bool active, double magnitude, const std::string& detail,
                              std::vector<Violation>& out) {
  if (active) {
    if (!active_) {
      active_ = true;
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
  if (std::max(t, last_) - start_ + 1e-12 >= min_duration_s_)
    out.push_back({kind_, start_, std::max(last_, start_), worst_, unit_, detail_});
}

}  // namespace rt
