// The com-plan pass (issue 14) end to end: on a real walk the exported motion's multibody ZMP
// (quality.hpp, the summary's definition) moves into the support on far more stance frames while
// the stance feet stay fixed and the limits hold; a standing clip is left where it was; the
// reference carries the planned COM and ZMP.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "retarget/jobs/convert_job.hpp"
#include "retarget/model/ankle_reach.hpp"
#include "retarget/model/centroidal.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"
#include "retarget/passes/stance_support.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

ConvertResult convert(const RobotModel& model, const std::string& clip, bool com_plan) {
  ConvertRequest request;
  request.clip_path = clip;
  request.write_outputs = false;
  if (!com_plan) request.disabled_passes = {"com-plan"};  // it runs by default
  return run_convert(request, model);
}

// The default pipeline with com-plan before resample, given options (`com-plan{<options>}`, and
// refine's `refine{<refine_options>}`).
ConvertResult convert_with_com_plan(const RobotModel& model, const std::string& clip, const std::string& options,
                                    const std::string& refine_options = "") {
  ConvertRequest request;
  request.clip_path = clip;
  request.write_outputs = false;
  request.passes = "retime,scale,label-contacts,ik,flat-contact,refine{" + refine_options + "},ground,com-plan{" + options + "},resample";
  return run_convert(request, model);
}

// Issue 14's bars on a walk: the default pipeline's ZMP mostly outside, com-plan's within 1 cm of
// the support on >= 98 % of the stance frames (>= 95 % in single support), the landmark median at
// most 2 cm worse, the stance soles fixed, no limit violated.
void expect_issue_bars(const QualityMetrics& before, const QualityMetrics& after) {
  EXPECT_LT(before.zmp_near_fraction, 0.5);
  EXPECT_GT(after.zmp_near_fraction, 0.98);
  EXPECT_GT(after.zmp_single_near_fraction, 0.95);
  EXPECT_LT(after.landmark_error_median_m, before.landmark_error_median_m + 0.02);
  EXPECT_LE(after.foot_skating_max_m, 0.003);
  EXPECT_EQ(after.position_limit_violations, 0);
  EXPECT_EQ(after.velocity_limit_violations, 0);
}

const PassRecord* find_pass(const ConvertResult& r, const std::string& name) {
  for (const PassRecord& p : r.passes)
    if (p.name == name) return &p;
  return nullptr;
}

TEST(ComPlanPass, LeavesAStandingClipWhereItWas) {
  const std::unique_ptr<RobotModel> model = RobotModel::load(test::source_path("robots/humanoid25"));
  const std::string clip = test::source_path("examples/clips/stand.bvh");
  const ConvertResult plain = convert(*model, clip, false), planned = convert(*model, clip, true);
  ASSERT_NE(find_pass(planned, "com-plan"), nullptr);
  EXPECT_EQ(find_pass(plain, "com-plan"), nullptr);  // --no-com-plan
  const Reference &a = plain.clip.reference, &b = planned.clip.reference;
  ASSERT_EQ(a.num_frames(), b.num_frames());
  RobotData data(*model);
  double com_moved = 0;
  for (int f = 0; f < planned.clip.motion.num_frames(); ++f) {
    update_kinematics(*model, data, plain.clip.motion.q.col(f));
    const Vec3 c0 = com_position(*model, data);
    update_kinematics(*model, data, planned.clip.motion.q.col(f));
    com_moved = std::max(com_moved, (com_position(*model, data) - c0).norm());
  }
  EXPECT_LT(com_moved, 1e-3);
  EXPECT_LT((a.root_pos_W - b.root_pos_W).cwiseAbs().maxCoeff(), 2e-3);
  EXPECT_DOUBLE_EQ(planned.quality.zmp_near_fraction, 1.0);
  EXPECT_EQ(b.com_W.cols(), b.num_frames());
  EXPECT_EQ(b.cop_W.cols(), b.num_frames());
}

// CMU 131_01 (G1): before the plan 33 % of stance frames have their ZMP within 1 cm of the support
// (2 % in single support); after the plan 100 % (100 %).
// The bars are the issue's (98 % / 95 %).
TEST(ComPlanPass, MovesTheZmpOfARealWalkIntoTheSupport) {
  RT_REQUIRE_SHARED(clip, "bvh/cmu_max_131_01_start_walk_stop.bvh");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  const ConvertResult plain = convert(*model, clip, false), planned = convert(*model, clip, true);
  const QualityMetrics &before = plain.quality, &after = planned.quality;
  ASSERT_GT(after.zmp_stance_frames, 200);
  expect_issue_bars(before, after);
  EXPECT_EQ(after.swing_frames_low, 0);
  EXPECT_GT(after.zmp_single_near_fraction, before.zmp_single_near_fraction + 0.4);
  EXPECT_LE(after.stance_height_max_m, 0.002);
  const PassRecord* pass = find_pass(planned, "com-plan");
  ASSERT_NE(pass, nullptr);
  EXPECT_LT(pass->statistics.get("zmp-outside-after"), pass->statistics.get("zmp-outside-before"));
  EXPECT_GT(pass->statistics.get("max-com-shift"), 0.01);
  // The whole-body stage ran on the export grid and left fewer frames outside than it found.
  EXPECT_LT(pass->statistics.get("whole-body-zmp", 1e9), 10);
}

// The pass plans the COM at rest at the clip's ends, and at rest the ZMP is the COM: the first frame
// must put it where the robot can hold it still, over the stance soles where the ankles' effort
// limits hold the COP (ankle_reach.hpp). PyMO's walk starts mid-step on one foot; the plan once put
// its first frame's COM 2 cm beyond the G1's stance toe (the moving motion's angular-momentum
// offset credited to the rested end, the whole sole counted although G1's ankle pitch only holds
// the COP 10 cm ahead of its axis), and the dynamics check's G1 fell over its toe 0.2 s into the
// clip. CMU 131_01 ends standing: its last frame too. PyMO's clip ends mid-stride: the pass adds a
// standing lead-out (clip_ends.hpp), whose last frame is checked the same way.
TEST(ComPlanPass, StartsAndEndsOnAComTheAnklesHold) {
  struct Case {
    const char* clip;
    bool check_end;
  };
  RT_REQUIRE_SHARED(robots, "robots");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  const std::array<SoleReach, 2> reach = ankle_reach(*model, model->total_mass_kg() * kGravity);
  for (const Case c : {Case{"bvh/pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh", true}, Case{"bvh/cmu_max_131_01_start_walk_stop.bvh", true}}) {
    RT_REQUIRE_SHARED(clip, c.clip);
    const ConvertResult planned = convert(*model, clip, true);
    const Reference& ref = planned.clip.reference;
    ASSERT_TRUE(ref.has_contacts());
    const ReferenceRobotMap map(*model, ref, "test");
    RobotData data(*model);
    std::vector<int> frames{0};
    if (c.check_end) frames.push_back(ref.num_frames() - 1);
    for (const int f : frames) {
      update_kinematics(*model, data, map.q(ref, f));
      const std::array<bool, 2> down{{ref.contact[0][static_cast<std::size_t>(f)] != 0, ref.contact[1][static_cast<std::size_t>(f)] != 0}};
      const SupportPolygon held = stance_support_polygon(*model, data, down, reach);
      ASSERT_FALSE(held.empty()) << c.clip << " frame " << f;
      const double outside = held.signed_distance(com_position(*model, data).head<2>());
      std::cout << "[ measured ] " << c.clip << " frame " << f << ": COM " << -outside << " m inside the ankles' reach\n";
      EXPECT_LT(outside, 0.0) << c.clip << " frame " << f << ": the COM is " << outside << " m beyond what the ankles hold";
    }
  }
}

// A gait captured mid-stride (BTK's Plug-in Gait trial: the subject walks through the volume, its
// COM at 0.75 m/s over the first 0.1 s and 0.56 m/s over the last) cannot be planned at rest on its
// own ends without bending its first and last steps: without the lead every stage that does it moves
// the landmark median by more than 2 cm and is dropped, and the gait is left at 13 % of the stance
// frames within 1 cm (3 % in single support; 61 % when a held sole could move 2 mm); with a 1 s
// standing lead-in and lead-out, in which the plan starts and stops the COM, 100 % (100 %) at a
// landmark median of 3.8 cm against 3.4 cm.
TEST(ComPlanPass, AddsAStandingLeadWhereAGaitStartsAndEndsMidStride) {
  RT_REQUIRE_SHARED(clip, "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  const ConvertResult plain = convert(*model, clip, false), planned = convert(*model, clip, true);
  const ConvertResult no_lead = convert_with_com_plan(*model, clip, "lead=0");
  EXPECT_EQ(no_lead.clip.lead_in_frames + no_lead.clip.lead_out_frames, 0);
  EXPECT_EQ(plain.clip.lead_in_frames + plain.clip.lead_out_frames, 0);

  // The pass works on the export grid: the motion it leaves is at the export rate.
  const Clip& c = planned.clip;
  EXPECT_DOUBLE_EQ(c.motion.fps, 30.0);
  const int lead = 30;  // 1 s
  EXPECT_EQ(c.lead_in_frames, lead);
  EXPECT_EQ(c.lead_out_frames, lead);
  EXPECT_EQ(c.motion.num_frames(), plain.clip.reference.num_frames() + 2 * lead);
  EXPECT_EQ(c.reference.num_frames(), c.motion.num_frames());
  const PassRecord* pass = find_pass(planned, "com-plan");
  ASSERT_NE(pass, nullptr);
  EXPECT_DOUBLE_EQ(pass->statistics.get("lead-in"), 1.0);

  // The issue's bars, on more frames than without the lead (fractions of different frame counts:
  // the frames outside are compared).
  const QualityMetrics &q = planned.quality, &q0 = no_lead.quality;
  expect_issue_bars(plain.quality, q);
  EXPECT_LT((1 - q.zmp_near_fraction) * q.zmp_stance_frames, (1 - q0.zmp_near_fraction) * q0.zmp_stance_frames - 5);

  // The exported reference starts and ends at rest; the source's own first frame moves.
  const Reference& ref = c.reference;
  const ReferenceRobotMap map(*model, ref, "test");
  RobotData data(*model);
  auto com_at = [&](const Reference& r, const ReferenceRobotMap& m, int f) {
    update_kinematics(*model, data, m.q(r, f));
    return Vec3(com_position(*model, data));
  };
  const int T = ref.num_frames();
  const double start_speed = (com_at(ref, map, 1) - com_at(ref, map, 0)).norm() * ref.fps;
  const double end_speed = (com_at(ref, map, T - 1) - com_at(ref, map, T - 2)).norm() * ref.fps;
  const ReferenceRobotMap plain_map(*model, plain.clip.reference, "test");
  const double source_speed = (com_at(plain.clip.reference, plain_map, 1) - com_at(plain.clip.reference, plain_map, 0)).norm() * ref.fps;
  std::cout << "[ measured ] COM speed: exported first frame " << start_speed << ", last " << end_speed
            << " m/s; the clip's own first frame " << source_speed << " m/s\n";
  EXPECT_GT(source_speed, 0.5);
  EXPECT_LT(start_speed, 0.02);
  EXPECT_LT(end_speed, 0.02);

  // The gait starts on its right foot; the lead-in stands on both: the left sole flat on the floor
  // (every corner within 1 mm of it), lifted into the clip's first pose in the lead's last frames,
  // with the right sole held and no swing frame low or below the floor.
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(*model, data);
  ASSERT_TRUE(ref.has_contacts());
  EXPECT_FALSE(plain.clip.reference.contact[0][0]);
  EXPECT_TRUE(ref.contact[0][0] && ref.contact[1][0]);
  update_kinematics(*model, data, map.q(ref, 0));
  for (int f = 0; f < 2; ++f)
    for (const Vec3& corner : sole_corners_W(sole_frame_W(*model, data, f, R_L_sole[static_cast<std::size_t>(f)]), model->soles()[static_cast<std::size_t>(f)]))
      EXPECT_NEAR(corner.z(), 0.0, 1e-3) << (f == 0 ? "left" : "right") << " sole corner at frame 0";
  int lift_off = 0;
  while (lift_off < T && ref.contact[0][static_cast<std::size_t>(lift_off)]) ++lift_off;
  std::cout << "[ measured ] left foot lifts off at frame " << lift_off << " of the " << lead << "-frame lead-in\n";
  EXPECT_LT(lift_off, lead);
  EXPECT_GE(lift_off, lead - 12);  // within its last 0.4 s
  for (int k = 0; k <= lift_off; ++k) EXPECT_TRUE(ref.contact[1][static_cast<std::size_t>(k)]);
  EXPECT_EQ(q.swing_frames_low, 0);
  EXPECT_LE(q.penetration_max_m, 1e-3);
  EXPECT_LE(q.stance_height_max_m, 1e-3);
}

// The whole-body stage's Gauss–Newton steps stall on JVRC-1's PyMO walk (no step along the
// direction lowers the cost while ZMP rows are missed): plain, it stops at 93 % of the stance frames
// within 1 cm (compact-stencil ZMP, 2026-12-07). Retried damped (`whole_body_extra_iterations`, the
// default 20), it goes on to 100 %, the stance soles held and no swing sole low. 98 % is asserted,
// and a clear gain over the stalled stage.
TEST(ComPlanPass, RetriesAStalledWholeBodyStepDamped) {
  RT_REQUIRE_SHARED(clip, "bvh/pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh");
  RT_REQUIRE_SHARED(robots, "robots");
  const std::unique_ptr<RobotModel> model = RobotModel::load("jvrc1");
  const ConvertResult plain = convert(*model, clip, false);
  const ConvertResult damped = convert(*model, clip, true);
  const ConvertResult stalled = convert_with_com_plan(*model, clip, "whole_body_extra_iterations=0");
  std::cout << "[ measured ] ZMP within 1 cm: plain Gauss-Newton " << stalled.quality.zmp_near_fraction << " (single support "
            << stalled.quality.zmp_single_near_fraction << "), damped retries " << damped.quality.zmp_near_fraction << " ("
            << damped.quality.zmp_single_near_fraction << ")\n";
  // Where plain Gauss-Newton ends depends on the build's floating-point path (Release 93 %, the
  // sanitizer build 96 %); the retries reach 100 % and 99.7 %.
  EXPECT_LT(stalled.quality.zmp_near_fraction, 0.98);
  EXPECT_GT(damped.quality.zmp_near_fraction, stalled.quality.zmp_near_fraction + 0.02);
  EXPECT_GT(damped.quality.zmp_near_fraction, 0.98);
  EXPECT_GT(damped.quality.zmp_single_near_fraction, 0.95);
  EXPECT_LT(damped.quality.landmark_error_median_m, plain.quality.landmark_error_median_m + 0.02);
  EXPECT_LE(damped.quality.foot_skating_max_m, 0.001);
  EXPECT_EQ(damped.quality.velocity_limit_violations, 0);
  EXPECT_EQ(damped.quality.swing_frames_low, 0);
  EXPECT_LE(damped.quality.stance_tilt_max_deg, 0.5);
}

// A plan the robot can follow only by distorting the motion is not exported. Without its lead,
// BTK's PiG gait must stop its COM inside the first and last steps; the rounds that do it move
// G1's landmark median from 3.4 to 12.7 cm (97 % of the stance frames within 1 cm of the support):
// with the default max_landmark_growth (2 cm) they are dropped, with a warning saying why.
TEST(ComPlanPass, DropsAPlanItCanOnlyFollowByMovingTheLandmarks) {
  RT_REQUIRE_SHARED(clip, "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  const ConvertResult plain = convert(*model, clip, false);
  const ConvertResult unguarded = convert_with_com_plan(*model, clip, "lead=0,max_landmark_growth=10");
  const ConvertResult guarded = convert_with_com_plan(*model, clip, "lead=0");
  const double base = plain.quality.landmark_error_median_m;
  std::cout << "[ measured ] landmark median: default " << base << ", unguarded " << unguarded.quality.landmark_error_median_m
            << ", guarded " << guarded.quality.landmark_error_median_m << " m\n";
  EXPECT_GT(unguarded.quality.landmark_error_median_m, base + 0.05);  // the negative control
  EXPECT_LT(guarded.quality.landmark_error_median_m, base + 0.02);
  bool warned = false;
  for (const Diagnostic& d : guarded.clip.diagnostics.items())
    warned |= d.message.find("moved the landmark error median") != std::string::npos;
  EXPECT_TRUE(warned);
}

// The ZMP is a second derivative: it is planned and corrected on the grid it is exported (and
// measured) at, whatever the ratio of the rates. BTK's PiG gait is at 100 Hz; exported at 50 Hz
// (mjlab's rate; every export frame falls between two source frames half the time) the bars hold
// on the 50 Hz frames.
TEST(ComPlanPass, PlansOnTheExportGrid) {
  RT_REQUIRE_SHARED(clip, "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  ConvertRequest request;
  request.clip_path = clip;
  request.write_outputs = false;
  request.fps = 50;
  const ConvertResult planned = run_convert(request, *model);
  request.disabled_passes = {"com-plan"};
  const ConvertResult plain = run_convert(request, *model);
  ASSERT_DOUBLE_EQ(plain.clip.motion.fps, 100.0);
  const Clip& c = planned.clip;
  EXPECT_DOUBLE_EQ(c.motion.fps, 50.0);
  EXPECT_DOUBLE_EQ(c.reference.fps, 50.0);
  EXPECT_EQ(c.reference.num_frames(), c.motion.num_frames());
  EXPECT_EQ(c.lead_in_frames, 50);
  for (std::size_t foot = 0; foot < 2; ++foot) EXPECT_EQ(c.contacts.in_contact[foot], c.reference.contact[foot]);
  expect_issue_bars(plain.quality, planned.quality);
  EXPECT_LE(planned.quality.stance_tilt_max_deg, 0.5);
}

// A pass that keeps nothing (here: no round and no whole-body stage) exports the clip as it came:
// at its own rate, without lead frames, the balance reference over the clip's own frames.
TEST(ComPlanPass, RemovesTheLeadWhenItKeepsNothing) {
  RT_REQUIRE_SHARED(clip, "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  const ConvertResult plain = convert(*model, clip, false);
  const ConvertResult idle = convert_with_com_plan(*model, clip, "iterations=0,whole_body_iterations=0");
  EXPECT_EQ(idle.clip.lead_in_frames + idle.clip.lead_out_frames, 0);
  EXPECT_EQ(idle.clip.motion.fps, plain.clip.motion.fps);
  EXPECT_EQ(idle.clip.motion.q, plain.clip.motion.q);
  EXPECT_EQ(idle.clip.contacts.in_contact, plain.clip.contacts.in_contact);
  const Reference& ref = idle.clip.reference;
  EXPECT_EQ(ref.num_frames(), plain.clip.reference.num_frames());
  EXPECT_EQ(ref.com_W.cols(), ref.num_frames());
  EXPECT_EQ(ref.cop_W.cols(), ref.num_frames());
  const PassRecord* pass = find_pass(idle, "com-plan");
  ASSERT_NE(pass, nullptr);
  EXPECT_EQ(pass->statistics.get("lead-in", -1), 0);
  EXPECT_EQ(pass->statistics.get("lead-out", -1), 0);
}

// The issue-13 bars a com-plan result keeps on the frames it changed: stance soles fixed, upright and
// not turning, nothing below the floor, swing soles clear, the limits, smoother than per-frame IK.
void expect_kinematic_bars(const QualityMetrics& q) {
  EXPECT_LE(q.foot_skating_max_m, 0.001);
  EXPECT_LE(q.heel_skating_max_m, 0.001);
  EXPECT_LE(q.stance_tilt_max_deg, 0.5);
  EXPECT_LE(q.stance_yaw_drift_max_deg, 0.5);
  EXPECT_GE(q.lowest_point_m, -0.002);
  EXPECT_EQ(q.swing_frames_low, 0);
  EXPECT_EQ(q.position_limit_violations, 0);
  EXPECT_EQ(q.velocity_limit_violations, 0);
  EXPECT_LT(q.jitter_rad_s3, q.jitter_per_frame_ik_rad_s3);
}

// Where the whole-body stage breaks a sole on some frames, those frames take the rounds' motion back
// instead of the stage being dropped whole. On H1 (no ankle roll, 3 cm soles) BTK's mocap36 gait
// kept nothing (30 % of the stance frames within 1 cm of the support); with the frames given back,
// 54 % (2026-12-07), the stance and floor bars held.
TEST(ComPlanPass, GivesBackTheFramesWhereTheWholeBodyStageBreaksASole) {
  RT_REQUIRE_SHARED(clip, "c3d/btk_mocap36_optitrack_fullbody.c3d");
  RT_REQUIRE_SHARED(robots, "robots");
  const std::unique_ptr<RobotModel> model = RobotModel::load("h1");
  const ConvertResult plain = convert(*model, clip, false);
  const ConvertResult whole = convert_with_com_plan(*model, clip, "whole_body_give_back=false");
  const ConvertResult given = convert(*model, clip, true);
  std::cout << "[ measured ] ZMP within 1 cm: without com-plan " << plain.quality.zmp_near_fraction << ", stage dropped whole "
            << whole.quality.zmp_near_fraction << ", frames given back " << given.quality.zmp_near_fraction << "\n";
  EXPECT_TRUE(whole.clip.motion.q == plain.clip.motion.q);  // the negative control: nothing kept
  EXPECT_GT(given.quality.zmp_near_fraction, plain.quality.zmp_near_fraction + 0.15);
  EXPECT_LT(given.quality.landmark_error_median_m, plain.quality.landmark_error_median_m + 0.02);
  expect_kinematic_bars(given.quality);
}

// A round whose followed motion moves a held sole is repaired locally instead of dropped: its plan
// pinned to the retargeted COM around the frames that gave, frames that still give left as they
// came. The subject: the LAFAN1 dance on G1 as refine retargeted it before it held back turns
// beyond the hip yaw (`hold_turns=false`): where the dancer spins on one foot, G1 folds to the floor
// for a second (34.8 s), and every round gives there. Without repairs nothing is kept (32 % of the
// stance frames within 1 cm of the support), with them 87 % (2026-12-07). The dance's own stance
// faults (refine's, before com-plan) stay as they were.
TEST(ComPlanPass, RepairsTheRoundsOfADanceWhereAHeldSoleGives) {
  RT_REQUIRE_SHARED(clip, "bvh/lafan1_dance1_subject2.bvh");
  RT_REQUIRE_SHARED(robots, "robots");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  const ConvertResult unrepaired = convert_with_com_plan(*model, clip, "repairs=0", "hold_turns=false");
  const ConvertResult repaired = convert_with_com_plan(*model, clip, "", "hold_turns=false");
  std::cout << "[ measured ] ZMP within 1 cm: without repairs " << unrepaired.quality.zmp_near_fraction << ", with "
            << repaired.quality.zmp_near_fraction << "\n";
  const QualityMetrics &before = unrepaired.quality, &q = repaired.quality;
  EXPECT_LT(before.zmp_near_fraction, 0.5);
  EXPECT_GT(q.zmp_near_fraction, 0.8);
  const PassRecord* pass = find_pass(repaired, "com-plan");
  ASSERT_NE(pass, nullptr);
  EXPECT_GT(pass->statistics.get("repairs", 0), 0);
  EXPECT_LT(q.landmark_error_median_m, before.landmark_error_median_m + 0.02);
  EXPECT_LE(q.foot_skating_max_m, before.foot_skating_max_m + 1e-6);
  EXPECT_LE(q.heel_skating_max_m, before.heel_skating_max_m + 1e-6);
  EXPECT_LE(q.stance_tilt_max_deg, before.stance_tilt_max_deg + 1e-6);
  EXPECT_GE(q.lowest_point_m, std::min(-0.002, before.lowest_point_m));
  EXPECT_LE(q.velocity_limit_violations, before.velocity_limit_violations);
  EXPECT_LT(q.jitter_rad_s3, q.jitter_per_frame_ik_rad_s3);
}

// The optical C3D gait (BTK mocap36): 38 % (10 %) before, 100 % (100 %) after.
TEST(ComPlanPass, MakesAnOpticalGaitNearlyFeasible) {
  RT_REQUIRE_SHARED(clip, "c3d/btk_mocap36_optitrack_fullbody.c3d");
  const std::unique_ptr<RobotModel> model = RobotModel::load("g1");
  const ConvertResult plain = convert(*model, clip, false), planned = convert(*model, clip, true);
  EXPECT_LT(plain.quality.zmp_near_fraction, 0.5);
  EXPECT_GT(planned.quality.zmp_near_fraction, 0.95);
  EXPECT_GT(planned.quality.zmp_single_near_fraction, 0.93);
  EXPECT_LE(planned.quality.foot_skating_max_m, 0.003);
  EXPECT_EQ(planned.quality.velocity_limit_violations, 0);
  EXPECT_LT(planned.quality.landmark_error_median_m, plain.quality.landmark_error_median_m + 0.01);
}

}  // namespace
}  // namespace rt
