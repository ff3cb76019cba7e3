#pragma once
/// Shared fixtures of the refine tests: cached robot models, a synthetic standing clip with a known
/// ground truth, and real clips run through the per-frame passes.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <string>

#include "retarget/core/strings.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/motion/load_motion.hpp"
#include "retarget/passes/quality.hpp"
#include "retarget/passes/registry.hpp"
#include "support/test_paths.hpp"

namespace rt::test {

/// RobotModel of robots/<name> (or a robot.yaml path), loaded once per process.
inline const RobotModel& robot(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<RobotModel>> models;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = models[name];
  if (!slot) slot = RobotModel::load(name.find('/') == std::string::npos ? source_path("robots/" + name) : name);
  return *slot;
}

/// Ground truth of the synthetic clip: the standing pose with the arms waving, the waist turning
/// and the root swaying (legs fixed, so both feet stay flat on the floor at z = 0).
inline MatX synthetic_truth(const RobotModel& model, int frames, double fps) {
  MatX q(model.nq(), frames);
  const int l_shoulder = model.joints()[static_cast<std::size_t>(model.joint_index("l_shoulder_pitch"))].qpos_index;
  const int r_shoulder = model.joints()[static_cast<std::size_t>(model.joint_index("r_shoulder_pitch"))].qpos_index;
  const int waist = model.joints()[static_cast<std::size_t>(model.joint_index("waist_yaw"))].qpos_index;
  for (int f = 0; f < frames; ++f) {
    const double t = f / fps;
    VecX qf = model.standing_q();
    qf[l_shoulder] += 0.5 * std::sin(2 * M_PI * 0.7 * t);
    qf[r_shoulder] -= 0.4 * std::sin(2 * M_PI * 0.5 * t);
    qf[waist] += 0.25 * std::sin(2 * M_PI * 0.4 * t);
    q.col(f) = qf;
  }
  return q;
}

/// Landmark targets from forward kinematics of `q` (exact positions and orientations).
inline LandmarkTargets targets_from_motion(const RobotModel& model, const MatX& q) {
  const LandmarkIk ik(model);
  RobotData data(model);
  LandmarkTargets targets;
  const int T = static_cast<int>(q.cols());
  for (const LandmarkTarget& lt : model.config().landmarks) {
    LandmarkTrack& track = targets[lt.landmark];
    track.present = true;
    track.has_orientation = true;
    track.p_W.resize(3, T);
    track.state.assign(static_cast<std::size_t>(T), SampleState::Measured);
    track.R_W.resize(static_cast<std::size_t>(T));
  }
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, q.col(f));
    for (const LandmarkTarget& lt : model.config().landmarks) {
      LandmarkTrack& track = targets[lt.landmark];
      const int link = model.link_index(lt.link);
      const Iso3 X = link_pose(model, data, link);
      track.p_W.col(f) = X * lt.p_L_offset;
      track.R_W[static_cast<std::size_t>(f)] = Quat(X.linear() * ik.landmark_frame_in_link(link));
    }
  }
  return targets;
}

/// A synthetic clip whose "per-frame IK" is the ground truth plus joint noise (σ = 0.01 rad), root
/// noise (σ = 3 mm) and a 3-frame jump of 0.8 rad in one shoulder (far above its velocity limit);
/// both feet are labelled in stance for the whole clip.
inline Clip synthetic_clip(const RobotModel& model, MatX* truth = nullptr, int frames = 180, double fps = 60) {
  Clip clip;
  clip.name = "synthetic";
  clip.human.source.path = "synthetic";
  clip.human.fps = fps;
  clip.human.num_frames = frames;
  const MatX q_true = synthetic_truth(model, frames, fps);
  if (truth) *truth = q_true;
  clip.targets = targets_from_motion(model, q_true);
  std::mt19937 rng(11);
  std::normal_distribution<double> joint_noise(0.0, 0.01), root_noise(0.0, 0.003);
  MatX q = q_true;
  for (int f = 0; f < frames; ++f) {
    for (int i = 0; i < 3; ++i) q(i, f) += root_noise(rng);
    for (int i = 7; i < model.nq(); ++i) {
      const int u = i - 7;
      q(i, f) = std::clamp(q(i, f) + joint_noise(rng), model.q_lower()[u], model.q_upper()[u]);
    }
  }
  const int shoulder = model.joints()[static_cast<std::size_t>(model.joint_index("l_shoulder_pitch"))].qpos_index;
  for (int f = frames / 2; f < std::min(frames, frames / 2 + 3); ++f)
    q(shoulder, f) = std::clamp(q(shoulder, f) + 0.8, model.q_lower()[shoulder - 7], model.q_upper()[shoulder - 7]);
  clip.motion.fps = fps;
  clip.motion.q = q;
  clip.motion.q_per_frame_ik = q;
  clip.motion.landmark_error_m = VecX::Zero(frames);
  clip.motion.worst_landmark.assign(static_cast<std::size_t>(frames), -1);
  for (auto& c : clip.contacts.in_contact) c.assign(static_cast<std::size_t>(frames), 1);
  return clip;
}

/// Keeps the first `frames` frames of a loaded motion.
inline void truncate(HumanMotion& human, int frames) {
  if (frames >= human.num_frames) return;
  human.num_frames = frames;
  for (LandmarkTrack& t : human.landmarks) {
    if (!t.present) continue;
    t.p_W.conservativeResize(3, frames);
    t.state.resize(static_cast<std::size_t>(frames));
    if (t.has_orientation) t.R_W.resize(static_cast<std::size_t>(frames));
  }
}

/// Statistics and diagnostics of one pass run.
struct PassRun {
  Statistics statistics;
  Diagnostics diagnostics;
};

/// Runs a fresh `PassT` on `clip` with `options` ("k=v,k=v"; `name` is the pass's name in errors).
template <class PassT>
PassRun run_pass(Clip& clip, const RobotModel& model, const std::string& options, const std::string& name) {
  PassRun out;
  RobotData data(model);
  PassT pass;
  for (const std::string& kv : split(options, ","))
    if (!kv.empty()) pass.options().set(kv.substr(0, kv.find('=')), kv.substr(kv.find('=') + 1), name);
  PassContext ctx{&model, &data, out.statistics, out.diagnostics};
  pass.run(clip, ctx);
  return out;
}

/// Result of running a clip through the per-frame passes, refine and ground.
struct Converted {
  Clip clip;
  std::vector<PassRecord> records;
  QualityMetrics quality;
  const Statistics* refine = nullptr;  ///< the refine pass's statistics (into records)
};

/// Loads a clip (optionally its first `frames` frames) and runs `spec` on it.
inline Converted convert(const RobotModel& model, const std::string& path, int frames = 0,
                         const std::string& spec = "scale,label-contacts,ik,flat-contact,refine,ground") {
  Converted out;
  out.clip.name = path;
  out.clip.human = load_motion(path);
  if (frames > 0) truncate(out.clip.human, frames);
  RobotData data(model);
  out.records = Pipeline::parse(spec, builtin_passes()).run(out.clip, &model, &data);
  for (const PassRecord& r : out.records)
    if (r.name == "refine" || r.name == "refine-ipopt") out.refine = &r.statistics;
  out.quality = compute_quality(model, data, out.clip);
  return out;
}

/// Issue 4's kinematic acceptance metrics (what the opt-in refine-ipopt pass is held to): no failed
/// window, no limit violations, skating p95 <= 1 cm, penetration <= 2 mm, less jitter than
/// per-frame IK, flat soles on the floor at frame 0.
inline void expect_issue4_acceptance(const Converted& c) {
  ASSERT_NE(c.refine, nullptr);
  if (c.refine->has("failed-windows")) {
    EXPECT_EQ(c.refine->get("failed-windows", -1), 0);
  }
  EXPECT_EQ(c.quality.position_limit_violations, 0);
  EXPECT_EQ(c.quality.velocity_limit_violations, 0);
  EXPECT_LE(c.quality.foot_skating_p95_m, 0.01);
  EXPECT_LE(c.quality.penetration_max_m, 0.002);
  EXPECT_LT(c.quality.jitter_rad_s3, c.quality.jitter_per_frame_ik_rad_s3);
  EXPECT_LT(c.quality.frame0_sole_tilt_deg, 0.5);
  EXPECT_LT(std::abs(c.quality.frame0_sole_height_m), 0.001);
}

/// Largest joint difference [rad] between a motion and the ground truth it was made from (nq x T each).
inline double max_joint_error_rad(const MatX& q, const MatX& truth) {
  const Eigen::Index nu = q.rows() - 7;
  return (q.bottomRows(nu) - truth.bottomRows(nu)).cwiseAbs().maxCoeff();
}

/// The stance and floor bars of issue 13: every labelled stance held (drift <= 1 mm at the sole
/// centre and heel, yaw and tilt <= 0.5 deg, height <= 1 mm), nothing below -2 mm.
inline void expect_stance_held(const QualityMetrics& q) {
  EXPECT_LE(q.foot_skating_max_m, 1e-3);
  EXPECT_LE(q.heel_skating_max_m, 1e-3);
  EXPECT_LE(q.stance_yaw_drift_max_deg, 0.5);
  EXPECT_LE(q.stance_tilt_max_deg, 0.5);
  EXPECT_LE(q.stance_height_max_m, 1e-3);
  EXPECT_GE(q.lowest_point_m, -2e-3) << q.lowest_link;
}

/// The kinematic acceptance metrics of issues 4 and 13 after refine + ground (design.md §6): no
/// failed window (refine-ipopt), no limit violations, every labelled stance held (drift <= 1 mm,
/// yaw <= 0.5 deg, flat, on the floor), nothing below the floor, swing soles clear, less jitter
/// than per-frame IK, flat soles on the floor at frame 0.
inline void expect_refine_acceptance(const Converted& c) {
  ASSERT_NE(c.refine, nullptr);
  if (c.refine->has("failed-windows")) {
    EXPECT_EQ(c.refine->get("failed-windows", -1), 0);
  }
  const QualityMetrics& q = c.quality;
  EXPECT_EQ(q.position_limit_violations, 0);
  EXPECT_EQ(q.velocity_limit_violations, 0) << q.fastest_joint << " at " << q.max_velocity_ratio << "x its limit";
  expect_stance_held(q);
  EXPECT_LE(q.penetration_max_m, 0.002);
  EXPECT_EQ(q.swing_frames_low, 0) << "lowest swing sole " << q.swing_clearance_min_m << " m";
  EXPECT_EQ(q.frames_without_stance, 0);
  EXPECT_LT(q.jitter_rad_s3, q.jitter_per_frame_ik_rad_s3);
  EXPECT_LT(q.frame0_sole_tilt_deg, 0.5);
  EXPECT_LT(std::abs(q.frame0_sole_height_m), 0.001);
}

}  // namespace rt::test
