// Issue 4 acceptance over the real data: every BVH clip and every whole-body C3D trial converts for
// humanoid25, G1, H1 and JVRC-1 with the default pipeline, with 0 joint position-limit violations,
// 0 velocity-limit violations after refine, foot skating p95 <= 1 cm in labelled stance, penetration
// <= 2 mm and frame-0 soles flat within 0.5 deg and 1 mm of the floor; refine lowers jitter against
// the per-frame IK on the walking clips. Skips cleanly without ../shared/data.

#include <gtest/gtest.h>

#include "retarget/core/strings.hpp"
#include "retarget/jobs/convert_job.hpp"
#include "retarget/model/robot_model.hpp"
#include "shared_robots.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

struct Case {
  const char* robot;
  const char* clip;   // relative to the shared data folder
  bool walking;
};

const char* const kRobots[] = {"humanoid25", "g1", "h1", "jvrc1"};
const char* const kClips[] = {
    "bvh/bandai1_dance-short_normal_001.bvh", "bvh/bandai2_walk-turn-left_normal_001.bvh",
    "bvh/cmu_daz_martial_04.bvh",            "bvh/cmu_daz_salsa_10.bvh",
    "bvh/cmu_iclone_07_01_walk.bvh",         "bvh/cmu_max_131_01_start_walk_stop.bvh",
    "bvh/cmu_max_131_03_start_hop_stop_scaled_m.bvh", "bvh/cmu_mb_01_01_forward_jumps_turn.bvh",
    "bvh/games105_walk_and_turn_left.bvh",   "bvh/pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh",
    "c3d/btk_PiG_Motion-FlatFoot-One_vicon_fullbody.c3d", "c3d/btk_mocap36_optitrack_fullbody.c3d",
    "c3d/ezc3d_Qualisys_fullbody_forceplates.c3d",        "c3d/opensim_walking2_gait_forceplates.c3d"};
const char* const kWalking[] = {"bvh/bandai2_walk-turn-left_normal_001.bvh", "bvh/cmu_iclone_07_01_walk.bvh",
                                "bvh/cmu_max_131_01_start_walk_stop.bvh", "bvh/games105_walk_and_turn_left.bvh",
                                "bvh/pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh"};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const char* r : kRobots)
    for (const char* c : kClips) {
      bool walking = false;
      for (const char* w : kWalking) walking = walking || std::string(w) == c;
      out.push_back({r, c, walking});
    }
  return out;
}

class ConvertSharedData : public ::testing::TestWithParam<Case> {};

TEST_P(ConvertSharedData, MeetsTheQualityBounds) {
  const Case c = GetParam();
  RT_REQUIRE_SHARED(clip, c.clip);
  RT_REQUIRE_SHARED(robots, "robots");
  ConvertRequest request;
  request.clip_path = clip;
  request.write_outputs = false;
  if (std::string(c.clip).find("salsa") != std::string::npos) request.motion.source_fps = 60;  // data README
  const ConvertResult r = run_convert(request, test::shared_robot(c.robot));
  const QualityMetrics& q = r.quality;
  EXPECT_GT(r.clip.reference.num_frames(), 0);
  EXPECT_EQ(q.position_limit_violations, 0);
  EXPECT_EQ(q.velocity_limit_violations, 0) << "fastest joint at " << q.max_velocity_ratio << "x its limit";
  EXPECT_LE(q.foot_skating_p95_m, 0.01);
  EXPECT_LE(q.penetration_max_m, 0.002);
  EXPECT_LE(q.frame0_sole_tilt_deg, 0.5);
  EXPECT_LE(std::abs(q.frame0_sole_height_m), 0.001);
  if (c.walking) {
    EXPECT_LT(q.jitter_rad_s3, q.jitter_per_frame_ik_rad_s3);
  }
  std::cout << format("[ quality  ] %-10s %-52s landmark error median %.3f m p95 %.3f m, skating p95 %.4f m, "
                      "jitter %.0f (IK %.0f), %.0f ms\n",
                      c.robot, c.clip, q.landmark_error_median_m, q.landmark_error_p95_m, q.foot_skating_p95_m,
                      q.jitter_rad_s3, q.jitter_per_frame_ik_rad_s3, r.total_ms);
}

INSTANTIATE_TEST_SUITE_P(AllRobotsAllClips, ConvertSharedData, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return test::case_name(info.param.robot, info.param.clip); });

}  // namespace
}  // namespace rt
