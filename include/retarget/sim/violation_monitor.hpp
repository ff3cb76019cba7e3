#pragma once
/// ViolationMonitor: the dynamics check's observer of the closed loop (issue 15 architecture). It
/// is told every control cycle what the plant did and what the controller aimed at, and turns that
/// into balance violations (sim/violations.hpp), tracking metrics, the feasibility statistics of
/// the commanded contact wrenches and the recorded time series. It does not depend on which
/// controller runs: the thresholds are DynamicsCheckOptions' and the reference is the controller's
/// mapped one.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "retarget/sim/check_controller.hpp"
#include "retarget/sim/dynamics_check.hpp"

namespace rt {

class ViolationMonitor {
 public:
  /// `contacts` and `fps`: the reference signal's contact schedule (ReferenceSignal::contacts()),
  /// whose phase lengths bound the contact-timing tolerance (DynamicsCheckOptions).
  ViolationMonitor(const RobotModel& model, const DynamicsCheckOptions& options,
                   const std::array<std::vector<std::uint8_t>, 2>& contacts, double fps);

  /// Per-foot load and floor contact from the plant's contacts (data current for the state).
  FootStates foot_states(const ContactState& contacts, const RobotData& data) const;
  /// The reason the robot fell at this state (empty if it did not): a non-sole link on the floor,
  /// the COM below its fall height, the trunk tilted past the limit, or an unstable simulation.
  std::string fall_reason(const VecX& q, const Vec3& com_W, const ContactState& contacts, bool unstable) const;
  /// One control cycle in clip time (not while settling).
  void observe(const ControlInput& in, const ControlOutput& out);
  /// Closes open spans at `t_end_s`, sorts the violations and fills the result's metrics.
  void finish(double t_end_s, DynamicsCheckResult& result);

  std::vector<Violation>& violations() { return result_.violations; }

 private:
  const RobotModel* model_;
  const DynamicsCheckOptions* o_;
  double load_threshold_n_ = 0, touch_threshold_n_ = 0, friction_ = 1, com_fall_z_ = 0;
  std::vector<int> group_;  ///< joint group per movable joint: 0 legs, 1 torso, 2 arms
  /// Per foot and reference frame: the lag allowed for a contact change in that frame's phase [s].
  std::array<std::vector<double>, 2> contact_tolerance_s_;
  double fps_ = 1;
  std::array<ViolationTracker, 2> not_achieved_, no_lift_off_, slip_, moved_;
  /// Per foot: where its sole was when it was first loaded in the current reference stance.
  std::array<std::optional<Iso3>, 2> planted_;
  ViolationTracker cop_edge_, saturation_, limit_;
  double joint_sq_ = 0, com_sq_ = 0, cop_sq_ = 0;
  long joint_n_ = 0, clip_ticks_ = 0, cop_n_ = 0;
  double next_record_ = 0;
  DynamicsCheckResult result_;  ///< violations, trace, force feasibility, saturated cycles, COM error max
};

}  // namespace rt
