#pragma once
/// `com-replan` pass (paper §VI offline, design.md §3.4, issue 6; opt-in, see registry.cpp): the
/// balance controller's closed-loop model (eq. 25–26, in the feed-forward error coordinates of
/// balance_controller.hpp unless ComPreviewOptions::feedforward is off) is run forward along the whole
/// clip from its own predicted state; whenever the
/// predicted COP would leave the support polygon of a future frame, or a foot is about to land while
/// the COP is still inside the old polygon, the COM reference is re-planned in closed form (eq. 27–34).
/// The re-planned COM and the predicted COP are stored in the reference, and a COM-following IK
/// (feet held where they are, COM task, posture held) moves the joint trajectory so that the
/// exported motion's own COM follows the re-planned COM.
///
/// "Re-planned COM" is the COM the balance model predicts under the re-planned reference (state c of
/// eq. 25), not the re-planned reference input itself: eq. (31) changes the first samples of its
/// window most (W_ii = w·i² makes them cheap), so the input is spiky by design, and the balance
/// controller is what turns it into a smooth COM motion. Following the input would make the exported
/// pelvis jerk; following the predicted COM gives the motion the controller will produce.

#include "retarget/balance/balance_controller.hpp"
#include "retarget/balance/com_replanner.hpp"
#include "retarget/pipeline/pass.hpp"

namespace rt {

/// How the balance controller is previewed: as the dynamics check runs it by default
/// (DynamicsCheckOptions::balance_feedforward, com_smoothing_s), so that the offline plan and the
/// online re-planning agree.
struct ComPreviewOptions {
  bool feedforward = true;            ///< track the reference COM motion's pendulum state (else the paper's regulator)
  /// [s] Gaussian smoothing of the COM before it is differentiated: the ZMP of a retargeted clip's
  /// COM is dominated by IK and mocap noise above ~5 Hz (measured ±1 m on CMU 131_01 at 0.03 s)
  double com_smoothing_s = 0.06;
};

struct ComReplanPassOptions {
  ComReplanOptions replan;            ///< N, period, h_max, w (paper defaults)
  ComPreviewOptions preview;
  BalanceOptions balance;             ///< LQR weights of the balance model being previewed
  double com_weight = 1000.0;         ///< COM-following IK: weight of the horizontal COM target
  double foot_weight = 1e5;           ///< ... weight holding each foot's sole pose (>> com_weight: feet win)
  double posture_regularization = 1e-2;  ///< ... pull towards the frame's own configuration
  int ik_iterations = 50;
  double min_shift_m = 0.0005;        ///< frames whose COM moves less than this keep their pose
  double max_shift_m = 0.05;          ///< [m] planned COM shifts are clipped to this length
  double velocity_margin = 0.02;      ///< fraction of each URDF velocity limit the COM-following steps keep free
  double foot_tolerance_m = 0.001;    ///< [m] a held sole moving further makes the shift halve (twice), then drop
  double foot_tolerance_rad = 0.01;   ///< [rad] same for its orientation
};

/// Result of previewing the balance model along a COM trajectory (exposed for tests).
struct ComReplanPlan {
  double period_s = 0;
  Eigen::Matrix2Xd com_original_W;    ///< reference COM on the planner grid
  Eigen::Matrix2Xd com_replanned_W;   ///< the re-planned reference COM (reference + eq. 31's changes)
  Eigen::Matrix2Xd com_predicted_W;   ///< model COM under the re-planned input (state c)
  Eigen::Matrix2Xd cop_predicted_W;   ///< model COP on the planner grid
  std::vector<std::pair<double, ReplanEvent>> events;  ///< (time [s], event)
};

/// Runs the planner forward along `com_W` (2 x K on the planner grid) with `support(k)` giving the
/// support at grid step k (k may run past the end: clamp). With feed-forward the model starts on
/// the reference (exact tracking until re-planning changes it); without, at rest at the first sample.
ComReplanPlan plan_com(const BalanceController& balance, const ComReplanOptions& options, const Eigen::Matrix2Xd& com_W,
                       const std::function<const SupportFrame&(int)>& support, const ComPreviewOptions& preview = {});

class ComReplanPass final : public Pass {
 public:
  ComReplanPass();
  std::string name() const override { return "com-replan"; }
  std::string description() const override {
    return "preview the balance controller and re-plan the COM (paper eq. 25-34); COM-following IK with feet held";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  ComReplanPassOptions options_;
  OptionTable table_;
};

}  // namespace rt
