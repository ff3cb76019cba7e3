#include "retarget/passes/refine_ipopt.hpp"

#include <gtest/gtest.h>

#include "refine_test_util.hpp"
#include "retarget/core/error.hpp"

namespace rt {
namespace {

using test::PassRun;
using test::robot;

PassRun run_refine(Clip& clip, const RobotModel& model, const std::string& options = "") {
  return test::run_pass<RefineIpoptPass>(clip, model, options, "refine-ipopt");
}

// Ground truth known: noisy per-frame "IK" with a velocity spike, both feet planted.
TEST(RefineIpoptPass, SyntheticClipRecoversASmoothFeasibleMotion) {
  const RobotModel& model = robot("humanoid25");
  MatX truth;
  Clip clip = test::synthetic_clip(model, &truth);
  RobotData data(model);
  const QualityMetrics before = compute_quality(model, data, clip);
  ASSERT_GT(before.velocity_limit_violations, 0);  // the injected jump

  const PassRun r = run_refine(clip, model);
  EXPECT_EQ(r.statistics.get("failed-windows", -1), 0);
  EXPECT_GT(r.statistics.get("velocity-violations-before"), 0);
  EXPECT_EQ(r.statistics.get("velocity-violations-after", -1), 0);
  const QualityMetrics q = compute_quality(model, data, clip);
  EXPECT_EQ(q.position_limit_violations, 0);
  EXPECT_EQ(q.velocity_limit_violations, 0);
  EXPECT_LT(q.foot_skating_p95_m, 1e-3);
  EXPECT_LT(q.foot_skating_max_m, 2e-3);
  EXPECT_LT(q.penetration_max_m, 1e-3);
  EXPECT_LT(q.frame0_sole_tilt_deg, 0.1);
  EXPECT_LT(std::abs(q.frame0_sole_height_m), 1e-4);
  EXPECT_LT(q.jitter_rad_s3, 0.01 * before.jitter_rad_s3);
  EXPECT_LT(q.landmark_error_median_m, 0.01);
  // Tracks the exact targets better than the noisy input does, and stays near the ground truth.
  EXPECT_LT(q.landmark_error_median_m, before.landmark_error_median_m);
  EXPECT_LT(test::max_joint_error_rad(clip.motion.q, truth), 0.1);  // the 0.8 rad jump is gone
}

TEST(RefineIpoptPass, FailedWindowsFallBackWithoutThrowing) {
  const RobotModel& model = robot("humanoid25");
  Clip clip = test::synthetic_clip(model);
  const PassRun r = run_refine(clip, model, "max_iterations=1");
  EXPECT_GT(r.statistics.get("failed-windows"), 0);
  bool warned = false;
  for (const Diagnostic& d : r.diagnostics.items()) warned = warned || d.to_string().find("not solved") != std::string::npos;
  EXPECT_TRUE(warned);
  EXPECT_TRUE(clip.motion.q.allFinite());
  RobotData data(model);
  EXPECT_EQ(compute_quality(model, data, clip).position_limit_violations, 0);
}

TEST(RefineIpoptPass, WindowsOverlapAndHandOver) {
  const RobotModel& model = robot("humanoid25");
  Clip one = test::synthetic_clip(model), many = one;
  const PassRun a = run_refine(one, model);
  const PassRun b = run_refine(many, model, "window=20,overlap=6");
  EXPECT_EQ(a.statistics.get("windows"), 1);
  EXPECT_GE(b.statistics.get("windows"), 3);
  EXPECT_EQ(b.statistics.get("failed-windows", -1), 0);
  RobotData data(model);
  const QualityMetrics q = compute_quality(model, data, many);
  EXPECT_EQ(q.velocity_limit_violations, 0);
  EXPECT_LT(q.foot_skating_p95_m, 1e-3);
  // Jitter stays low across the junctions (the hand-over is C²).
  EXPECT_LT(q.jitter_rad_s3, 0.01 * q.jitter_per_frame_ik_rad_s3);
}

TEST(RefineIpoptPass, SkipsWhatItCannotRefine) {
  const RobotModel& model = robot("humanoid25");
  Clip short_clip = test::synthetic_clip(model, nullptr, 3);
  const MatX q_short = short_clip.motion.q;
  EXPECT_EQ(run_refine(short_clip, model).statistics.get("skipped"), 1);
  EXPECT_EQ(short_clip.motion.q, q_short);

  Clip upside_down = test::synthetic_clip(model, nullptr, 30);
  const Quat flip(AngleAxis(M_PI, Vec3::UnitX()));
  for (int f = 0; f < 30; ++f) upside_down.motion.q.block<4, 1>(3, f) << flip.w(), flip.x(), flip.y(), flip.z();
  const MatX q_flip = upside_down.motion.q;
  const PassRun r = run_refine(upside_down, model);
  EXPECT_EQ(r.statistics.get("skipped"), 1);
  EXPECT_EQ(r.diagnostics.items().size(), 1u);
  EXPECT_EQ(upside_down.motion.q, q_flip);
}

TEST(RefineIpoptPass, RejectsBadOptions) {
  const RobotModel& model = robot("humanoid25");
  for (const char* bad : {"window=4", "overlap=2", "overlap=96", "knot_fps=0", "velocity_margin=1", "max_iterations=0"}) {
    Clip clip = test::synthetic_clip(model, nullptr, 20);
    EXPECT_THROW(run_refine(clip, model, bad), InputError) << bad;
  }
  RefineIpoptPass pass;
  EXPECT_THROW(pass.options().set("no_such_option", "1", "refine-ipopt"), InputError);
}

// The project's own example clip (always available): every acceptance metric after refine + ground.
TEST(RefineIpoptPass, SlowStepsExampleMeetsTheAcceptanceMetrics) {
  const RobotModel& model = robot("humanoid25");
  const test::Converted c = test::convert(model, test::source_path("examples/clips/slow_steps.bvh"), 0,
                                          "scale,label-contacts,ik,flat-contact,refine-ipopt,ground");
  test::expect_issue4_acceptance(c);
  EXPECT_LT(c.quality.landmark_error_median_m, 0.05);
}

}  // namespace
}  // namespace rt
