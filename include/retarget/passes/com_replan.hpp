#pragma once
/// `com-replan` pass (paper §VI offline, design.md §3.4, issue 6): the balance controller's closed-loop
/// model (eq. 25–26) is run forward along the whole clip from its own predicted state; whenever the
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

struct ComReplanPassOptions {
  ComReplanOptions replan;            ///< N, period, h_max, w (paper defaults)
  BalanceOptions balance;             ///< LQR weights of the balance model being previewed
  double com_weight = 1000.0;         ///< COM-following IK: weight of the horizontal COM target
  double foot_weight = 1000.0;        ///< ... weight holding each foot's sole pose
  double posture_regularization = 1e-2;  ///< ... pull towards the frame's own configuration
  int ik_iterations = 50;
  double min_shift_m = 0.0005;        ///< frames whose COM moves less than this keep their pose
};

/// Result of previewing the balance model along a COM trajectory (exposed for tests).
struct ComReplanPlan {
  double period_s = 0;
  Eigen::Matrix2Xd com_original_W;    ///< reference COM on the planner grid
  Eigen::Matrix2Xd com_replanned_W;   ///< the re-planned reference input (eq. 31's U')
  Eigen::Matrix2Xd com_predicted_W;   ///< model COM under the re-planned input (state c)
  Eigen::Matrix2Xd cop_predicted_W;   ///< model COP on the planner grid
  std::vector<std::pair<double, ReplanEvent>> events;  ///< (time [s], event)
};

/// Runs the planner forward along `com_W` (2 x K on the planner grid) with `support(k)` giving the
/// support at grid step k (k may run past the end: clamp).
ComReplanPlan plan_com(const BalanceController& balance, const ComReplanOptions& options, const Eigen::Matrix2Xd& com_W,
                       const std::function<const SupportFrame&(int)>& support);

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
