#pragma once
/// Balance plan of a reference for the walking controller (issue 15): the whole-clip COM/ZMP plan
/// (balance/zmp_plan.hpp) of the reference's own kinematics, computed before the simulation as the
/// first stage of the controller's mapping. The controller then tracks the planned COM's divergent
/// component of motion with the planned ZMP as its feed-forward.
///
/// The plan is always made from the reference's joint trajectories, also when the file carries a
/// planned COM (meta.json `com_pos_w`): the check judges what the motion implies, not what the file
/// claims. For a reference already planned by `convert --com-plan` the plan then moves the COM by
/// millimetres; a third-party reference may need centimetres. How far it moved the COM (max and RMS)
/// is reported, and above `max_shift_m` the check fails with its own violation kind
/// (ViolationKind::HeavyCorrection): a reference that only passes after heavy correction is not
/// the motion the user exported.
///
/// The ZMP of the plan is the cart-table ZMP of the planned COM, optionally plus the multibody
/// offset of the reference (its whole-body ZMP minus its own cart-table ZMP: the angular-momentum
/// part):
///
///     p = c − h c̈ + Δp,   h = z_c / (g + z̈_c),   Δp = p_multibody(ref) − (c_ref − h c̈_ref)
///
/// By default Δp = 0 (`angular_offset`): the plan does not count on the reference's angular
/// momentum. The tracking controller does not reproduce it (its cost damps the moment about the
/// COM, and a G1's 35 N m waist saturates under a retargeted torso's swing), so a plan that leans on
/// it puts the COM where only that momentum would hold it: on the shared walks the offset was 9 cm
/// (median), the planned COM stayed between the feet in single support, and the robot's COM ran
/// off sideways with the COP clamped at the stance sole's inner edge.

#include "retarget/balance/zmp_plan.hpp"
#include "retarget/core/types.hpp"

namespace rt {

class RobotModel;
class RobotData;
class ReferenceSignal;

struct BalancePlanOptions {
  double period_s = 0.01;          ///< [s] plan grid
  double margin_m = 0.015;         ///< [m] the stance polygons are shrunk by this for the plan
  /// Each stance sole counts only where its ankle can hold the COP under the body's weight
  /// (ankle_reach.hpp), not as the whole sole.
  bool ankle_reach = true;
  /// Add the reference's angular-momentum ZMP offset Δp to the planned ZMP (see above; off by
  /// default, for ablation).
  bool angular_offset = false;
  /// [s] Gaussian smoothing of the multibody offset Δp (finite differences of a 30 fps reference
  /// amplify its noise) and its length cap [m] (a longer one is a glitch of the motion).
  double offset_smoothing_s = 0.03;
  double max_offset_m = 0.2;
  /// [m] largest COM shift the plan may make before the check reports HeavyCorrection.
  double max_shift_m = 0.08;
  /// [s] standing lead-in before the clip: the first frame held (the check's settle phase), so a
  /// clip that starts mid-step has time to bring its COM over the first stance foot.
  double lead_in_s = 0.5;
  /// Weights (period and rest are set here). The ZMP is pulled to the support's centroid with
  /// weight 100 [1/m²] (the COM's own weight is 1): the controller then has margin on every side to
  /// correct errors, and the weight moves onto the next stance foot in double support rather than
  /// after the lift-off. With weight 1 the plan ran its ZMP along the stance sole's edge: any
  /// tracking error at a lift-off was then beyond the COP's reach, and the G1 fell on the Bandai
  /// walk played 1.5x, 2x and 4x slower (it walks the 1.5x one with 100). Centring only moves the
  /// COM for margin: `heavy-correction` is judged on the plan without it.
  ZmpPlanOptions plan = [] {
    ZmpPlanOptions p;
    p.zmp_centre_weight = 100.0;
    return p;
  }();
};

/// The plan on a uniform grid of clip time t = start_s + k · period_s (W, unmapped by trunk
/// mapping); start_s = −lead-in.
struct BalancePlan {
  double period_s = 0.01;
  double start_s = 0;
  Eigen::Matrix2Xd com_W;          ///< [m] planned horizontal COM
  Eigen::Matrix2Xd com_velocity_W; ///< [m/s]
  Eigen::Matrix2Xd zmp_W;          ///< [m] planned ZMP (cart-table of the plan + offset)
  Eigen::Matrix2Xd offset_W;       ///< [m] Δp (zero without BalancePlanOptions::angular_offset)
  VecX com_height_m;               ///< [m] reference COM height (not re-planned)
  /// ‖planned − reference COM‖ over the clip for the plan without ZMP centring: how far the
  /// reference must be moved to be feasible (the centred plan moves it further, for margin). Not
  /// over the lead-in, nor over the clip's last sqrt(z_c/g) (≈ 0.25 s), where a clip cut mid-step
  /// leaves the free-end plan's COM running off towards the step the clip no longer shows.
  double max_shift_m = 0, rms_shift_m = 0;
  double max_shift_time_s = 0;
  double max_violation_m = 0;      ///< worst planned ZMP outside its shrunk polygon

  int size() const { return static_cast<int>(com_W.cols()); }
  /// Linear interpolation at clip time t (clamped to the grid).
  Vec2 com(double t_s) const { return sample(com_W, t_s); }
  Vec2 com_velocity(double t_s) const;
  Vec2 zmp(double t_s) const { return sample(zmp_W, t_s); }
  Vec2 offset(double t_s) const;
  double com_height(double t_s) const;

 private:
  Vec2 sample(const Eigen::Matrix2Xd& m, double t_s) const;
};

/// Plans on the reference held by `signal` (unmapped). `data` is scratch.
BalancePlan plan_reference_balance(const RobotModel& model, RobotData& data, const ReferenceSignal& signal,
                                   const BalancePlanOptions& options = {});

}  // namespace rt
