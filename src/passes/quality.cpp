#include "retarget/passes/quality.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/flat_contact.hpp"
#include "retarget/passes/ground.hpp"

namespace rt {

namespace {
double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::floor(p * static_cast<double>(v.size() - 1)))];
}
}  // namespace

double joint_jitter(const MatX& q, double fps) {
  const Eigen::Index T = q.cols(), nu = q.rows() - 7;
  if (T < 4 || nu <= 0) return 0;
  double sum = 0;
  for (Eigen::Index f = 0; f + 3 < T; ++f) {
    const VecX d3 = q.block(7, f + 3, nu, 1) - 3 * q.block(7, f + 2, nu, 1) + 3 * q.block(7, f + 1, nu, 1) - q.block(7, f, nu, 1);
    sum += d3.squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>((T - 3) * nu)) * fps * fps * fps;
}

QualityMetrics compute_quality(const RobotModel& model, RobotData& data, const Clip& clip) {
  QualityMetrics m;
  const RobotMotion& motion = clip.motion;
  const int T = motion.num_frames(), nu = model.nu();
  if (T == 0) return m;

  std::vector<double> per_frame, skating;
  std::array<double, kLandmarkCount> sum{};
  std::array<int, kLandmarkCount> count{};
  std::array<Vec2, 2> stance_start{{Vec2::Zero(), Vec2::Zero()}};
  const bool has_targets = clip.targets[Landmark::Pelvis].present;
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, motion.q.col(f));
    if (has_targets) {
      double s = 0;
      int n = 0;
      for (const LandmarkTarget& lt : model.config().landmarks) {
        const LandmarkTrack& t = clip.targets[lt.landmark];
        if (lt.weight <= 0 || !t.valid(f)) continue;
        const double d = (link_point(model, data, model.link_index(lt.link), lt.p_L_offset) - t.p_W.col(f)).norm();
        s += d;
        ++n;
        sum[static_cast<std::size_t>(index(lt.landmark))] += d;
        ++count[static_cast<std::size_t>(index(lt.landmark))];
      }
      if (n) per_frame.push_back(s / n);
    }
    for (int foot = 0; foot < 2; ++foot) {
      const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
      m.penetration_max_m = std::max(m.penetration_max_m, -lowest_sole_corner_z(model, data, foot));
      if (clip.contacts.empty()) continue;
      const auto& c = clip.contacts.in_contact[static_cast<std::size_t>(foot)];
      if (!c[static_cast<std::size_t>(f)]) continue;
      const Vec2 p = link_point(model, data, sole.link, sole.p_L_center).head<2>();
      if (f == 0 || !c[static_cast<std::size_t>(f - 1)]) stance_start[static_cast<std::size_t>(foot)] = p;
      skating.push_back((p - stance_start[static_cast<std::size_t>(foot)]).norm());
    }
    for (int i = 0; i < nu; ++i) {
      const double v = motion.q(7 + i, f);
      if (v < model.q_lower()[i] - 1e-9 || v > model.q_upper()[i] + 1e-9) ++m.position_limit_violations;
      if (f > 0 && model.velocity_limits()[i] > 0) {
        const double ratio = std::abs(v - motion.q(7 + i, f - 1)) * motion.fps / model.velocity_limits()[i];
        m.max_velocity_ratio = std::max(m.max_velocity_ratio, ratio);
        if (ratio > 1.0) ++m.velocity_limit_violations;
      }
    }
  }
  m.landmark_error_median_m = percentile(per_frame, 0.5);
  m.landmark_error_p95_m = percentile(per_frame, 0.95);
  double worst = -1;
  for (Landmark l : all_landmarks()) {
    const auto k = static_cast<std::size_t>(index(l));
    if (count[k] && sum[k] / count[k] > worst) {
      worst = sum[k] / count[k];
      m.worst_landmark = std::string(landmark_name(l));
    }
  }
  m.foot_skating_p95_m = percentile(skating, 0.95);
  m.foot_skating_max_m = skating.empty() ? 0 : *std::max_element(skating.begin(), skating.end());
  m.jitter_rad_s3 = joint_jitter(motion.q, motion.fps);
  m.jitter_per_frame_ik_rad_s3 =
      motion.q_per_frame_ik.cols() == T ? joint_jitter(motion.q_per_frame_ik, motion.fps) : m.jitter_rad_s3;
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  for (int foot = 0; foot < 2; ++foot) {
    const auto [tilt, height] = sole_tilt_and_height(model, data, motion.q.col(0), foot, R_L_sole[static_cast<std::size_t>(foot)]);
    m.frame0_sole_tilt_deg = std::max(m.frame0_sole_tilt_deg, tilt * 180 / M_PI);
    if (std::abs(height) > std::abs(m.frame0_sole_height_m)) m.frame0_sole_height_m = height;
  }
  return m;
}

}  // namespace rt
