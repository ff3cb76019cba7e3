// The smooth correction's whole-body ZMP rows (issue 14; src/refine/smooth_correction.hpp) on a
// synthetic single support: G1 stands on its left foot for 1 s with its right foot lifted and its
// COM held 10 cm outside the left sole. The correction must bring the multibody ZMP (the metric's
// definition, centroidal.hpp) into the sole while the stance sole stays where it is; without ZMP
// rows the same problem leaves the motion as it was (negative control).

#include <gtest/gtest.h>

#include <cmath>

#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/centroidal.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/stance_support.hpp"
#include "src/refine/smooth_correction.hpp"
#include "support/test_paths.hpp"

namespace rt::refine {
namespace {

struct SingleSupport {
  MatX q;                       // nq x T, every frame the same pose
  FootPlan plan;                // left foot held, right foot on its (lifted) pose
  SupportPolygon sole;          // the left sole
  Vec3 p_W_left_sole = Vec3::Zero();
};

// The pose: left sole flat where the standing pose has it, right foot 5 cm up, the COM 10 cm to the
// left of the left sole's outer edge (IK from the standing pose).
SingleSupport make_single_support(const RobotModel& model, int T) {
  RobotData data(model);
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  VecX q = model.standing_q();
  update_kinematics(model, data, q);
  std::array<IkTarget, 2> feet;
  for (std::size_t k = 0; k < 2; ++k) {
    const Sole& s = model.soles()[k];
    const Iso3 X = link_pose(model, data, s.link);
    feet[k].link = s.link;
    feet[k].p_L = s.p_L_center;
    feet[k].p_W = X * s.p_L_center;
    feet[k].R_L_frame = R_L_sole[k];
    feet[k].R_W = Quat(X.linear() * R_L_sole[k]);
    feet[k].weight = 1e4;
    feet[k].orientation_weight = 1e4;
  }
  feet[1].p_W.z() += 0.05;
  const double sole_half_width = 0.5 * model.soles()[0].size_m.y();
  IkComTarget com;
  com.p_W << feet[0].p_W.x(), feet[0].p_W.y() + sole_half_width + 0.10, 0;
  com.weight = 1e3;
  IkOptions o;
  o.max_iterations = 300;
  o.regularization = 1e-4;
  const LandmarkIk ik(model, o);
  ik.solve(data, {feet[0], feet[1]}, q, q, com);

  SingleSupport out;
  out.q = q.replicate(1, T);
  update_kinematics(model, data, q);
  for (std::size_t k = 0; k < 2; ++k) {
    const Iso3 X = link_pose(model, data, model.soles()[k].link);
    out.plan.feet[k].resize(static_cast<std::size_t>(T));
    for (FootTarget& t : out.plan.feet[k]) {
      t.mode = k == 0 ? FootMode::Stance : FootMode::Swing;
      t.pose.p_W = X * model.soles()[k].p_L_center;
      t.pose.R_W = X.linear() * R_L_sole[k];
    }
  }
  out.p_W_left_sole = out.plan.feet[0][0].pose.p_W;
  out.sole = stance_support_polygon(model, data, {{true, false}});
  return out;
}

CorrectionOptions options_for(const RobotModel& model, const SingleSupport& s, double fps, bool zmp_rows) {
  CorrectionOptions co;
  co.stance_weight = 1e8;  // as com-plan's whole-body stage: the ZMP rows' gains are large
  co.swing_weight = 1e4;
  co.q_lower = model.q_lower().array() + 1e-4;
  co.q_upper = model.q_upper().array() - 1e-4;
  co.lambda = 1e3;
  co.stiffness = legs_first_stiffness(model);
  RobotData data(model);
  co.R_L_sole = sole_frames_in_links(model, data);
  co.iterations = 30;
  co.fps = fps;
  if (zmp_rows) co.zmp_support.assign(static_cast<std::size_t>(s.q.cols()), s.sole.half_planes(0.01));
  return co;
}

TEST(ZmpCorrection, BringsAComHeldOutsideTheSoleBackOverIt) {
  RT_REQUIRE_SHARED(robots, "robots");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  const double fps = 30;
  const int T = 31;  // 1 s
  const SingleSupport s = make_single_support(*model, T);
  RobotData data(*model);
  const MultibodyZmp before = multibody_zmp(*model, data, s.q, fps);
  // The setup: the ZMP (a standing pose: the COM's projection) is 10 cm outside the sole.
  ASSERT_NEAR(s.sole.signed_distance(before.zmp_W.col(T / 2)), 0.10, 0.01);

  CorrectionReport report;
  const MatX q = solve_smooth_correction(*model, data, s.q, s.q, s.plan, options_for(*model, s, fps, true), &report);
  const MultibodyZmp after = multibody_zmp(*model, data, q, fps);
  for (int f = 1; f + 1 < T; ++f) EXPECT_LE(s.sole.signed_distance(after.zmp_W.col(f)), 0.0) << "frame " << f;
  for (int f = 0; f < T; ++f) {
    update_kinematics(*model, data, q.col(f));
    const Sole& sole = model->soles()[0];
    EXPECT_LT((link_point(*model, data, sole.link, sole.p_L_center) - s.p_W_left_sole).norm(), 1e-3) << "frame " << f;
  }
  // The rows are penalties: what is left of the 1 cm margin is small.
  EXPECT_LT(report.zmp_excess_max, 0.005) << report.zmp_rows << " rows";

  // Negative control: the same problem without ZMP rows has nothing to correct.
  const MatX q0 = solve_smooth_correction(*model, data, s.q, s.q, s.plan, options_for(*model, s, fps, false));
  EXPECT_LT((q0 - s.q).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace rt::refine
