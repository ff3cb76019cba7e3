#pragma once
/// Balance violations reported by the dynamics check (design.md §3.5), each with a time span and a
/// magnitude.

#include <string>
#include <vector>

namespace rt {

enum class ViolationKind {
  Fall,                ///< non-sole geometry on the floor, COM below half its standing height, or trunk tilt > 45°
  CopNearEdge,         ///< measured COP within the margin of the support polygon's edge (or outside it)
  ContactNotAchieved,  ///< the reference puts a foot down, the robot's foot carries no load
  LiftOffNotAchieved,  ///< the reference lifts a foot, the robot's foot stays loaded
  FootSlip,            ///< a loaded stance foot slides
  TorqueSaturation,    ///< a commanded torque exceeded the joint's effort limit (clamped)
  JointLimit,          ///< a joint reached its position limit
  /// The walking controller's balance plan had to move the reference's COM by more than its bound
  /// (BalancePlanOptions::max_shift_m): the reference is not feasible as exported.
  HeavyCorrection,
  /// The reference labels a foot in contact while its sole is off the reference's own floor
  /// (reference_consistency.hpp): the motion is inconsistent before any controller runs.
  StanceOffFloor,
  /// A loaded stance foot moved over the floor from where it was planted by more than the bound
  /// (DynamicsCheckOptions::max_stance_foot_travel_m): the robot did not keep the reference's
  /// footstep, it slid away from it.
  StanceFootMoved,
  /// The reference moves a joint faster than its URDF velocity limit (reference_consistency.hpp):
  /// the simulated motors have no speed limit, a real one cannot follow.
  JointVelocity,
  /// The reference asks a joint with no foot below it for more torque than its effort limit
  /// (reference_consistency.hpp, inverse dynamics of its frames): that joint saturates whatever the
  /// controller does. Reported, and named in a fall's cause; the simulation decides the verdict.
  ReferenceTorque,
};

/// "fall", "cop-near-edge", ... (stable names used in report.json and summaries).
const char* violation_name(ViolationKind kind);
/// Inverse of violation_name: the kind named `name`; false when no kind has that name.
bool violation_kind_from_name(const std::string& name, ViolationKind& kind);
/// Whether this kind fails the check (exit status 1): falls, unmet contacts, heavy correction,
/// stance feet off the floor.
bool violation_fails_check(ViolationKind kind);

struct Violation {
  ViolationKind kind = ViolationKind::Fall;
  double start_s = 0;     ///< [s] clip time
  double end_s = 0;       ///< [s] clip time (= start for instantaneous events)
  double magnitude = 0;   ///< worst value during the span, in `unit`
  std::string unit;       ///< "m", "m/s", "N", "ratio", "deg", ...
  std::string detail;     ///< which foot / joint / link, and what was measured
};

/// What led to a fall: appends to the detail of the fall in `violations` the warnings (COP at the
/// support's edge, foot slip, a stance foot moved, torque saturation, the reference's own torque
/// demand, joint limits) that overlap the `window_s` before
/// it, each with its time within the window and its worst instance, e.g. "; in the 0.5 s before:
/// COP at the support's edge 0.42 s; foot-slip 0.10 s (right foot sole slides at 0.875 m/s)".
/// A fall has one cause the summary can name, instead of the last symptom (the trunk's tilt).
void explain_fall(std::vector<Violation>& violations, double window_s = 0.5);

/// Tracks one condition over time and emits a Violation for every span where it held at least
/// `min_duration_s`.
class ViolationTracker {
 public:
  ViolationTracker(ViolationKind kind, std::string unit, double min_duration_s);
  /// `active`: the condition at time t; `magnitude`: its size (the worst one is kept).
  void update(double t_s, bool active, double magnitude, const std::string& detail, std::vector<Violation>& out);
  /// Ends an open span at t (end of the run).
  void finish(double t_s, std::vector<Violation>& out);
  /// The shortest span that counts, for spans that start from now on (a span keeps the value it
  /// started with, so a phase's tolerance is not judged by the next phase's).
  void set_min_duration(double min_duration_s) { min_duration_s_ = min_duration_s; }

 private:
  ViolationKind kind_;
  std::string unit_;
  double min_duration_s_;
  double span_min_duration_s_ = 0;  ///< min_duration_s_ when the open span started
  bool active_ = false;
  double start_ = 0, worst_ = 0, last_ = 0;
  std::string detail_;
};

}  // namespace rt
