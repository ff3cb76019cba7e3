#pragma once
/// The paper's controller behind the check's controller interface (`--controller paper`): LQR
/// pendulum balance with an observer (eq. 1), the tracking controller (eq. 2–19), trunk mapping on
/// new contacts (eq. 20–24) and online dynamic mapping by COM re-planning (eq. 25–34). It targets
/// quasi-static motion (foot lift, slow weight shifts); the paper's Fig. 7 ablation runs on it.

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "retarget/balance/balance_controller.hpp"
#include "retarget/balance/com_replanner.hpp"
#include "retarget/control/trunk_mapping.hpp"
#include "retarget/sim/check_controller.hpp"
#include "retarget/sim/dynamics_check.hpp"

namespace rt {

class PaperController final : public CheckController {
 public:
  /// `signal` and `options` must outlive the controller. `start_com_W`: the plant's initial COM.
  PaperController(const RobotModel& model, const ReferenceSignal& signal, const DynamicsCheckOptions& options,
                  const Vec2& start_com_W);
  ~PaperController() override;

  void control(const ControlInput& in, ControlOutput& out) override;
  bool planner_active() const override { return !replans_.empty(); }
  void finish(DynamicsCheckResult& result) const override;

 private:
  struct Memos;  // memoised reference COPs and support frames (paper_controller.cpp)

  double clip_time(double t_sim) const;
  Vec2 original_com(double t_sim) const;
  BalanceReference balance_reference(double t_sim) const;
  Vec2 reference_cop(double t_sim);
  Vec2 delta_at(double t_sim) const;

  const RobotModel* model_;
  const ReferenceSignal* signal_;
  const DynamicsCheckOptions* o_;
  double dt_sim_ = 0, dt_plan_ = 0, omega_sq_ = 0, total_s_ = 0;
  int N_ = 0, K_ = 0;
  BalanceController balance_;
  TrackingController tracking_;
  ComReplanner planner_;
  BalanceState bstate_;
  TrunkTransform map_;
  Eigen::Matrix2Xd com_delta_;   ///< re-planner's COM corrections on its grid (sim time)
  Eigen::Matrix2Xd y_offset_;    ///< reference COP over the planner's window
  std::array<Mat3, 2> R_L_sole_;
  std::array<std::optional<Iso3>, 2> stance_pose_;
  std::array<bool, 2> prev_contact_{};
  bool contact_change_pending_ = false;
  int stance_pose_changes_ = 0;
  std::array<int, 7> support_inputs_{};
  double next_plan_ = 0;
  std::unique_ptr<Memos> memos_;
  TrackingProblem problem_;
  TrackingWorkspace workspace_;
  // Statistics.
  std::vector<ReplanRecord> replans_;
  int trunk_mapping_updates_ = 0;
  double planner_wall_s_ = 0;
};

}  // namespace rt
