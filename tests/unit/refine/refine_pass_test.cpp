#include "retarget/passes/refine.hpp"

#include <gtest/gtest.h>

#include "refine_test_util.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/collision_hull.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/leg_ends.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {
namespace {

using test::PassRun;
using test::robot;

PassRun run_refine(Clip& clip, const RobotModel& model, const std::string& options = "") {
  return test::run_pass<RefinePass>(clip, model, options, "refine");
}

// Ground truth known: noisy per-frame "IK" with a velocity spike, both feet planted.
TEST(RefinePass, SyntheticClipRecoversASmoothFeasibleMotion) {
  const RobotModel& model = robot("humanoid25");
  MatX truth;
  Clip clip = test::synthetic_clip(model, &truth);
  RobotData data(model);
  const QualityMetrics before = compute_quality(model, data, clip);
  ASSERT_GT(before.velocity_limit_violations, 0);  // the injected jump

  const PassRun r = run_refine(clip, model);
  EXPECT_GT(r.statistics.get("velocity-violations-before"), 0);
  EXPECT_EQ(r.statistics.get("velocity-violations-after", -1), 0);
  EXPECT_EQ(r.statistics.get("frames-stance-not-held", -1), 0);
  const QualityMetrics q = compute_quality(model, data, clip);
  EXPECT_EQ(q.position_limit_violations, 0);
  EXPECT_EQ(q.velocity_limit_violations, 0);
  test::expect_stance_held(q);
  EXPECT_LT(q.penetration_max_m, 1e-3);
  EXPECT_LT(q.frame0_sole_tilt_deg, 0.1);
  EXPECT_LT(std::abs(q.frame0_sole_height_m), 1e-4);
  // The joint noise passes the 6 Hz smoother in part (the exact landmark targets of this synthetic
  // clip are not used by refine): about 1.3 % of the input's jitter is left.
  EXPECT_LT(q.jitter_rad_s3, 0.02 * before.jitter_rad_s3);
  // Closer to the exact targets than the noisy input, and to the ground truth.
  EXPECT_LT(q.landmark_error_median_m, 0.01);
  EXPECT_LT(q.landmark_error_median_m, before.landmark_error_median_m);
  EXPECT_LT(test::max_joint_error_rad(clip.motion.q, truth), 0.1);  // the 0.8 rad jump is gone
}

// A stance foot that slides and turns in the input is fixed in the output; the robot is kept above
// the floor where the input pushes a hand through it.
TEST(RefinePass, FixesSlidingTurningFeetAndLiftsWhatIsBelowTheFloor) {
  const RobotModel& model = robot("humanoid25");
  Clip clip = test::synthetic_clip(model, nullptr, 120, 60);
  const int T = clip.motion.num_frames();
  // The whole robot slides 4 cm and turns 10 deg over the clip, its feet with it.
  for (int f = 0; f < T; ++f) {
    const double s = static_cast<double>(f) / (T - 1);
    clip.motion.q(0, f) += 0.04 * s;
    const Quat turn(AngleAxis(0.17 * s, Vec3::UnitZ()));
    const Quat R = (turn * Quat(clip.motion.q(3, f), clip.motion.q(4, f), clip.motion.q(5, f), clip.motion.q(6, f))).normalized();
    clip.motion.q.block<4, 1>(3, f) << R.w(), R.x(), R.y(), R.z();
  }
  // A shoulder swung down so far that the hand goes under the floor in the middle frames.
  const int shoulder = model.joints()[static_cast<std::size_t>(model.joint_index("l_shoulder_roll"))].qpos_index;
  RobotData data(model);
  double lowest_before = INFINITY;
  for (int f = 40; f < 80; ++f) {
    clip.motion.q(shoulder, f) = model.q_upper()[shoulder - 7] - 0.01;
    clip.motion.q(2, f) -= 0.5;  // and the whole robot sunk (the IK of a kneel can do that)
    update_kinematics(model, data, clip.motion.q.col(f));
    lowest_before = std::min(lowest_before, lowest_collision_point(model, data).z_m);
  }
  ASSERT_LT(lowest_before, -0.1);
  const PassRun r = run_refine(clip, model);
  EXPECT_EQ(r.statistics.get("frames-stance-not-held", -1), 0);
  const QualityMetrics q = compute_quality(model, data, clip);
  test::expect_stance_held(q);
  EXPECT_EQ(q.velocity_limit_violations, 0);
}

TEST(RefinePass, SlowStepsExampleHoldsEveryStanceAndClearsEverySwing) {
  const RobotModel& model = robot("humanoid25");
  const test::Converted c = test::convert(model, test::source_path("examples/clips/slow_steps.bvh"), 0,
                                          "scale,label-contacts,ik,flat-contact,refine,ground,resample");
  test::expect_refine_acceptance(c);
  test::expect_stance_held(c.quality);
  EXPECT_EQ(c.quality.swing_frames_low, 0);
  EXPECT_GE(c.quality.swing_clearance_min_m, 0.015 - 1e-4);
  EXPECT_EQ(c.quality.frames_without_stance, 0);
  EXPECT_LT(c.quality.landmark_error_median_m, 0.05);
}

// The root height's limits (opt-in): on a real walk, where the per-frame IK drops the root by 4-5
// cm for the frames of each double support and pops it back at the lift-off (about 2 g), the root
// of the result accelerates within the limits in stance, and every stance is still held.
TEST(RefinePass, RootHeightLimitsSpreadTheDoubleSupportDips) {
  RT_REQUIRE_SHARED(bvh, "bvh/bandai2_walk-turn-left_normal_001.bvh");
  const RobotModel& model = robot("humanoid25");
  const std::string passes = "scale,label-contacts,ik,flat-contact,refine";
  auto largest_stance_accel = [](const test::Converted& c, double* up, double* down) {
    const MatX& q = c.clip.motion.q;
    const double fps = c.clip.motion.fps;
    *up = *down = 0;
    for (Eigen::Index f = 1; f + 1 < q.cols(); ++f) {
      const auto k = static_cast<std::size_t>(f);
      if (!c.clip.contacts.in_contact[0][k] && !c.clip.contacts.in_contact[1][k]) continue;
      const double a = (q(2, f - 1) - 2 * q(2, f) + q(2, f + 1)) * fps * fps;
      *up = std::max(*up, a);
      *down = std::max(*down, -a);
    }
  };
  const test::Converted plain = test::convert(model, bvh, 0, passes);
  const test::Converted limited = test::convert(model, bvh, 0, passes + "{root_rise_accel=3,root_fall_accel=2}");
  double up_plain = 0, down_plain = 0, up = 0, down = 0;
  largest_stance_accel(plain, &up_plain, &down_plain);
  largest_stance_accel(limited, &up, &down);
  EXPECT_GT(up_plain, 8.0);  // the dips are there without the limits
  // The limits are on the smoothed motion; the projection and the smooth correction that put the
  // feet back move the root by a millimetre here and there (4.6 m/s² at most here: the bound lets
  // the root move 6 cm horizontally to reach, the projection also lowers it a little).
  EXPECT_LT(up, 3.0 * 2);
  EXPECT_LT(down, 2.0 * 2);
  EXPECT_LT(up, 0.6 * up_plain);
  EXPECT_GT(limited.refine->get("root-height-bound-rows", -1), 0);
  test::expect_stance_held(limited.quality);
  EXPECT_EQ(limited.quality.velocity_limit_violations, 0);
}

// Each stance leg's hip-ankle distance over its straight length, largest over the stance frames of
// `c` (leg_ends.hpp).
double largest_stance_extension(const RobotModel& model, const test::Converted& c) {
  RobotData data(model);
  const std::array<LegEnds, 2> legs = leg_ends(model);
  double largest = 0;
  const MatX& q = c.clip.motion.q;
  for (Eigen::Index f = 0; f < q.cols(); ++f) {
    update_kinematics(model, data, q.col(f));
    for (std::size_t k = 0; k < 2; ++k)
      if (c.clip.contacts.in_contact[k][static_cast<std::size_t>(f)]) largest = std::max(largest, hip_ankle_distance_m(model, data, legs[k]) / legs[k].length_m);
  }
  return largest;
}

// Bent knees (opt-in): the slow-steps example stands on nearly straight legs; with
// max_leg_extension the root is lowered until every stance leg is within that fraction of its
// length, and the stances, swings and speed limits still hold.
TEST(RefinePass, MaxLegExtensionBendsTheStanceKnees) {
  const RobotModel& model = robot("humanoid25");
  const std::string clip = test::source_path("examples/clips/slow_steps.bvh");
  const std::string passes = "scale,label-contacts,ik,flat-contact,refine";
  const test::Converted plain = test::convert(model, clip, 0, passes);
  const test::Converted bent = test::convert(model, clip, 0, passes + "{max_leg_extension=0.9,root_max_drop=0.1}");
  const double straight = largest_stance_extension(model, plain), limited = largest_stance_extension(model, bent);
  EXPECT_GT(straight, 0.97);
  // The bound is on the smoothed motion and takes the root as free to move 6 cm horizontally
  // towards the soles (as the projection moves it, but not always as far): 0.915 here.
  EXPECT_LT(limited, 0.9 + 0.02);
  EXPECT_LT(limited, straight - 0.05);
  EXPECT_GT(bent.refine->get("root-height-bound-rows", -1), 0);
  test::expect_stance_held(bent.quality);
  EXPECT_EQ(bent.quality.velocity_limit_violations, 0);
  EXPECT_EQ(bent.quality.swing_frames_low, 0);
  // Negative control: at 1 (the default) nothing is bounded.
  EXPECT_EQ(plain.refine->get("root-height-bound-rows", -1), 0);
  std::printf("[ measured ] largest stance extension %.3f -> %.3f\n", straight, limited);
}

// A performer who turns on planted feet further than the robot's hips can (a pirouette): the whole
// input turns 270 deg over 2 s, feet with it, both feet labelled in stance. The soles are held at
// their anchors and the root's turn is held back to the hip yaw's range (humanoid25: +-0.8 rad,
// plus the projection's 0.5 rad slack) instead of the legs contorting to reach the anchors.
TEST(RefinePass, HoldsBackATurnOnPlantedFeetBeyondTheHipYaw) {
  const RobotModel& model = robot("humanoid25");
  auto pirouette = [&] {
    Clip clip = test::synthetic_clip(model, nullptr, 120, 60);
    const int T = clip.motion.num_frames();
    for (int f = 0; f < T; ++f) {
      const Quat turn(AngleAxis(1.5 * M_PI * f / (T - 1), Vec3::UnitZ()));
      const Quat R = (turn * Quat(clip.motion.q(3, f), clip.motion.q(4, f), clip.motion.q(5, f), clip.motion.q(6, f))).normalized();
      clip.motion.q.block<4, 1>(3, f) << R.w(), R.x(), R.y(), R.z();
    }
    return clip;
  };
  auto root_turn = [](const MatX& q) {  // the root's heading at the end relative to the start [rad]
    const auto heading = [&](Eigen::Index f) {
      const Mat3 R = Quat(q(3, f), q(4, f), q(5, f), q(6, f)).normalized().toRotationMatrix();
      return std::atan2(R(1, 0), R(0, 0));
    };
    double total = 0;
    for (Eigen::Index f = 1; f < q.cols(); ++f) total += std::remainder(heading(f) - heading(f - 1), 2 * M_PI);
    return total;
  };
  RobotData data(model);
  Clip held = pirouette();
  const double input_turn = root_turn(held.motion.q), input_lowest = held.motion.q.row(2).minCoeff();
  const PassRun r = run_refine(held, model);
  const QualityMetrics q = compute_quality(model, data, held);
  EXPECT_GT(r.statistics.get("turn-limited-max"), 45.0);  // [deg]
  EXPECT_EQ(r.statistics.get("frames-stance-not-held", -1), 0);
  test::expect_stance_held(q);
  EXPECT_EQ(q.velocity_limit_violations, 0);
  // From one end of the hip yaw's range (plus slack) to the other at most, not 270 deg; the root
  // as high as in the input.
  EXPECT_GT(input_turn, 4.7);
  EXPECT_LT(std::abs(root_turn(held.motion.q)), 2 * (0.8 + 0.5));
  EXPECT_GT(held.motion.q.row(2).minCoeff(), input_lowest - 0.01);
  // Without it the projection cannot hold the stances on the frames where the turn is beyond the
  // range (measured: 10 frames, 3.7 mm of drift, 4 frames x joints above their speed limit).
  Clip free = pirouette();
  const PassRun r_free = run_refine(free, model, "hold_turns=false");
  EXPECT_GT(r_free.statistics.get("frames-stance-not-held", -1), 0);
}

TEST(RefinePass, RejectsBadOptionsAndAMissingIk) {
  const RobotModel& model = robot("humanoid25");
  for (const char* bad : {"velocity_margin=1", "smoothing_hz=-1", "rounds=0", "max_iterations=0", "swing_clearance=-0.1", "turn_slack=5",
                          "stance_weight=0"}) {
    Clip clip = test::synthetic_clip(model, nullptr, 20);
    EXPECT_THROW(run_refine(clip, model, bad), InputError) << bad;
  }
  Clip empty;
  EXPECT_THROW(run_refine(empty, model), InputError);
}

}  // namespace
}  // namespace rt
