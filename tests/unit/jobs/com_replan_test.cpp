// The com-replan pass (issue 6, paper eq. 25-34 offline): the feed-forward preview reproduces a
// reference COM whose ZMP stays inside the support exactly, re-plans one whose ZMP leaves it, and
// the COM-following IK makes the exported motion's own COM follow the re-planned COM within 5 mm
// with the feet held and the velocity limits kept, on the project's slow-steps example.

#include <gtest/gtest.h>

#include <cmath>

#include "retarget/jobs/convert_job.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/com_replan.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

SupportFrame square_support(double half_m) {
  SupportFrame s;
  s.polygon = SupportPolygon::convex_hull({{-half_m, -half_m}, {half_m, -half_m}, {half_m, half_m}, {-half_m, half_m}});
  return s;
}

// COM along x: smooth start from rest, constant speed, smooth stop (period 5 ms).
Eigen::Matrix2Xd com_ramp(double distance_m, double duration_s, double period_s) {
  const int K = static_cast<int>(std::lround(duration_s / period_s)) + 1;
  Eigen::Matrix2Xd c = Eigen::Matrix2Xd::Zero(2, K);
  for (int k = 0; k < K; ++k) {
    const double s = static_cast<double>(k) / (K - 1);
    c(0, k) = distance_m * (s - std::sin(2 * M_PI * s) / (2 * M_PI));  // zero velocity at both ends
  }
  return c;
}

TEST(ComReplanPlan, FeedForwardTracksAReferenceInsideTheSupportExactly) {
  const BalanceController balance(PendulumModel{0.8, 9.81});
  const ComReplanOptions o;
  const SupportFrame wide = square_support(1.0);
  const Eigen::Matrix2Xd com = com_ramp(0.15, 1.5, o.period_s);
  const ComReplanPlan plan = plan_com(balance, o, com, [&](int) -> const SupportFrame& { return wide; });
  EXPECT_TRUE(plan.events.empty());
  EXPECT_LT((plan.com_predicted_W - com).cwiseAbs().maxCoeff(), 1e-9);

  // The paper's regulator (no feed-forward) lags the same moving reference by centimetres.
  ComPreviewOptions paper;
  paper.feedforward = false;
  const ComReplanPlan lagging = plan_com(balance, o, com, [&](int) -> const SupportFrame& { return wide; }, paper);
  EXPECT_GT((lagging.com_predicted_W - com).cwiseAbs().maxCoeff(), 0.01);
}

TEST(ComReplanPlan, RePlansWhenTheReferenceZmpLeavesTheSupport) {
  const BalanceController balance(PendulumModel{0.8, 9.81});
  const ComReplanOptions o;
  // A 0.15 m shift in 0.4 s (centred on the support) needs a ZMP several centimetres beyond the
  // COM: outside a 4 cm half-width support. The clip then holds its last sample for a second.
  Eigen::Matrix2Xd ramp = com_ramp(0.15, 0.4, o.period_s);
  ramp.row(0).array() -= 0.075;
  const int K = static_cast<int>(ramp.cols());
  Eigen::Matrix2Xd com(2, K + 200);
  com.leftCols(K) = ramp;
  for (int k = K; k < K + 200; ++k) com.col(k) = ramp.col(K - 1);
  const SupportFrame tight = square_support(0.04), wide = square_support(1.0);
  const ComReplanPlan free = plan_com(balance, o, com, [&](int) -> const SupportFrame& { return wide; });
  ASSERT_TRUE(free.events.empty());
  const double zmp_excursion = free.cop_predicted_W.row(0).cwiseAbs().maxCoeff();
  ASSERT_GT(zmp_excursion, 0.04);  // the reference's own ZMP leaves the tight support
  const ComReplanPlan plan = plan_com(balance, o, com, [&](int) -> const SupportFrame& { return tight; });
  ASSERT_FALSE(plan.events.empty());
  EXPECT_LT(plan.cop_predicted_W.row(0).cwiseAbs().maxCoeff(), zmp_excursion);
  EXPECT_GT((plan.com_predicted_W - com).cwiseAbs().maxCoeff(), 1e-3);  // the COM was re-planned
}

TEST(ComReplanPass, ExportedComFollowsTheReplannedCom) {
  const std::unique_ptr<RobotModel> model = RobotModel::load(test::source_path("robots/humanoid25"));
  ConvertRequest request;
  request.clip_path = test::source_path("examples/clips/slow_steps.bvh");
  request.write_outputs = false;
  request.enabled_passes = {"com-replan"};
  const ConvertResult r = run_convert(request, *model);
  const PassRecord* pass = nullptr;
  for (const PassRecord& p : r.passes)
    if (p.name == "com-replan") pass = &p;
  ASSERT_NE(pass, nullptr);
  EXPECT_GT(pass->statistics.get("activations"), 0);
  EXPECT_GT(pass->statistics.get("adjusted-frames"), 0);
  EXPECT_GT(pass->statistics.get("max-com-shift"), 0.002);

  // The exported motion's own COM against the exported re-planned COM, every source frame.
  const Clip& clip = r.clip;
  ASSERT_EQ(clip.com_replanned_W.cols(), clip.motion.num_frames());
  RobotData data(*model);
  double worst = 0;
  for (int f = 0; f < clip.motion.num_frames(); ++f) {
    update_kinematics(*model, data, clip.motion.q.col(f));
    worst = std::max(worst, (com_position(*model, data) - clip.com_replanned_W.col(f)).head<2>().norm());
  }
  EXPECT_LE(worst, 0.005);
  EXPECT_EQ(r.quality.velocity_limit_violations, 0);
  EXPECT_LE(r.quality.foot_skating_p95_m, 0.01);
  EXPECT_LE(r.quality.penetration_max_m, 0.002);
  // The reference carries the re-planned COM and the predicted COP.
  EXPECT_EQ(r.clip.reference.com_W.cols(), r.clip.reference.num_frames());
  EXPECT_EQ(r.clip.reference.cop_W.cols(), r.clip.reference.num_frames());
}

TEST(ComReplanPass, IsOptIn) {
  const std::unique_ptr<RobotModel> model = RobotModel::load(test::source_path("robots/humanoid25"));
  ConvertRequest request;
  request.clip_path = test::source_path("examples/clips/stand.bvh");
  request.write_outputs = false;
  const ConvertResult r = run_convert(request, *model);
  EXPECT_EQ(r.pipeline.find("com-replan"), std::string::npos);
  // The default pipeline plans the COM with com-plan instead: the planned COM is com-plan's.
  EXPECT_NE(r.pipeline.find("com-plan"), std::string::npos);
}

}  // namespace
}  // namespace rt
