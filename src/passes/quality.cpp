#include "retarget/passes/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "retarget/model/centroidal.hpp"
#include "retarget/model/collision_hull.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/torque_demand.hpp"
#include "retarget/passes/flat_contact.hpp"
#include "retarget/passes/stance_support.hpp"

namespace rt {

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::floor(p * static_cast<double>(v.size() - 1)))];
}

double max_of(const std::vector<double>& v) { return v.empty() ? 0 : *std::max_element(v.begin(), v.end()); }

double wrap_angle(double a) { return std::remainder(a, 2 * M_PI); }

// The robot motion of a reference (export columns -> model order).
MatX reference_q(const RobotModel& model, const Reference& ref) {
  MatX q(model.nq(), ref.num_frames());
  const std::vector<int>& order = model.export_joint_order();
  for (int k = 0; k < ref.num_frames(); ++k) {
    q.col(k).head<3>() = ref.root_pos_W.col(k);
    const Quat R = model.root_body_orientation(ref.root_quat_W[static_cast<std::size_t>(k)]);
    q.col(k).segment<4>(3) << R.w(), R.x(), R.y(), R.z();
    for (std::size_t c = 0; c < order.size(); ++c) q(7 + order[c], k) = ref.joint_pos(static_cast<Eigen::Index>(c), k);
  }
  return q;
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

QualityMetrics foot_metrics(const RobotModel& model, RobotData& data, const MatX& q, double fps,
                            const std::array<std::vector<std::uint8_t>, 2>& contacts, bool stance_only) {
  QualityMetrics m;
  const int T = static_cast<int>(q.cols());
  if (T == 0) return m;
  const bool labelled = contacts[0].size() == static_cast<std::size_t>(T) && contacts[1].size() == static_cast<std::size_t>(T);
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  const int guard = static_cast<int>(std::ceil(kSwingGuard_s * fps - 1e-9));

  // Per foot: frames to the nearest lift-off / touchdown of its swing (a swing cut by the clip's
  // start or end only counts from its labelled side).
  std::array<std::vector<int>, 2> swing_distance;
  if (labelled)
    for (int foot = 0; foot < 2; ++foot) {
      const auto& c = contacts[static_cast<std::size_t>(foot)];
      auto& d = swing_distance[static_cast<std::size_t>(foot)];
      d.assign(static_cast<std::size_t>(T), -1);
      for (int f = 0; f < T;) {
        if (c[static_cast<std::size_t>(f)]) {
          ++f;
          continue;
        }
        int g = f;
        while (g < T && !c[static_cast<std::size_t>(g)]) ++g;
        for (int k = f; k < g; ++k) {
          int dist = std::numeric_limits<int>::max();
          if (f > 0) dist = std::min(dist, k - f + 1);
          if (g < T) dist = std::min(dist, g - k);
          d[static_cast<std::size_t>(k)] = dist;
        }
        f = g;
      }
    }

  std::vector<double> centre_travel, heel_travel, swing_low;
  std::array<Vec2, 2> start_centre{}, start_heel{};
  std::array<double, 2> start_yaw{};
  std::array<int, 2> phase_start{{0, 0}};
  double worst_travel = -1;
  m.lowest_point_m = INFINITY;
  m.swing_clearance_min_m = INFINITY;
  int flight_run = 0, longest_flight = 0;
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, q.col(f));
    const LowestPoint low = stance_only ? LowestPoint{} : lowest_collision_point(model, data);
    if (low.link >= 0 && low.z_m < m.lowest_point_m) {
      m.lowest_point_m = low.z_m;
      m.lowest_link = model.links()[static_cast<std::size_t>(low.link)].name;
      m.lowest_time_s = f / fps;
    }
    bool any_stance = false;
    for (int foot = 0; foot < 2; ++foot) {
      const auto k = static_cast<std::size_t>(foot);
      const Sole& sole = model.soles()[k];
      const double lowest_corner = lowest_sole_corner_z(model, data, foot);
      m.penetration_max_m = std::max(m.penetration_max_m, -lowest_corner);
      if (!labelled) continue;
      if (!contacts[k][static_cast<std::size_t>(f)]) {
        const int d = swing_distance[k][static_cast<std::size_t>(f)];
        if (d > guard) {
          m.swing_clearance_min_m = std::min(m.swing_clearance_min_m, lowest_corner);
          m.swing_frames_low += lowest_corner < kSwingClearance_m;
        }
        continue;
      }
      any_stance = true;
      const Iso3 X = link_pose(model, data, sole.link);
      const Mat3 R_sole = X.linear() * R_L_sole[k];
      const Vec2 centre = (X * sole.p_L_center).head<2>();
      const Vec2 heel = (X * (sole.p_L_center - sole.R_L_S * Vec3(0.5 * sole.size_m.x(), 0, 0))).head<2>();
      const double yaw = std::atan2(R_sole(1, 0), R_sole(0, 0));
      if (f == 0 || !contacts[k][static_cast<std::size_t>(f - 1)]) {
        start_centre[k] = centre;
        start_heel[k] = heel;
        start_yaw[k] = yaw;
        phase_start[k] = f;
      }
      const double travel = (centre - start_centre[k]).norm();
      centre_travel.push_back(travel);
      heel_travel.push_back((heel - start_heel[k]).norm());
      if (travel > worst_travel) {
        worst_travel = travel;
        m.worst_stance_foot = foot;
        m.worst_stance_start_s = phase_start[k] / fps;
      }
      m.stance_yaw_drift_max_deg = std::max(m.stance_yaw_drift_max_deg, std::abs(wrap_angle(yaw - start_yaw[k])) * 180 / M_PI);
      m.stance_tilt_max_deg = std::max(m.stance_tilt_max_deg, std::acos(std::clamp(R_sole(2, 2), -1.0, 1.0)) * 180 / M_PI);
      m.stance_height_max_m = std::max(m.stance_height_max_m, std::abs((X * sole.p_L_center).z()));
    }
    if (labelled) {
      flight_run = any_stance ? 0 : flight_run + 1;
      m.frames_without_stance += !any_stance;
      longest_flight = std::max(longest_flight, flight_run);
    }
  }
  if (!std::isfinite(m.lowest_point_m)) m.lowest_point_m = 0;
  if (!std::isfinite(m.swing_clearance_min_m)) m.swing_clearance_min_m = 0;
  m.longest_flight_s = longest_flight / fps;
  m.foot_skating_p95_m = percentile(centre_travel, 0.95);
  m.foot_skating_max_m = max_of(centre_travel);
  m.heel_skating_p95_m = percentile(heel_travel, 0.95);
  m.heel_skating_max_m = max_of(heel_travel);
  for (int foot = 0; foot < 2; ++foot) {
    if (labelled && !contacts[static_cast<std::size_t>(foot)][0]) continue;  // a foot in the air at frame 0
    const auto [tilt, height] = sole_tilt_and_height(model, data, q.col(0), foot, R_L_sole[static_cast<std::size_t>(foot)]);
    m.frame0_sole_tilt_deg = std::max(m.frame0_sole_tilt_deg, tilt * 180 / M_PI);
    if (std::abs(height) > std::abs(m.frame0_sole_height_m)) m.frame0_sole_height_m = height;
  }
  if (!stance_only) add_zmp_metrics(model, data, q, fps, contacts, m);
  return m;
}

double zmp_distance_outside(const SupportPolygon& support, const MultibodyZmp& zmp, int f) {
  const double d = support.signed_distance(zmp.zmp_W.col(f));
  return zmp.vertical_accel_mps2[f] < kZmpMinSupport_g * kGravity ? std::max(d, 2 * kZmpNear_m) : d;
}

void add_zmp_metrics(const RobotModel& model, RobotData& data, const MatX& q, double fps,
                     const std::array<std::vector<std::uint8_t>, 2>& contacts, QualityMetrics& m) {
  const int T = static_cast<int>(q.cols());
  if (T < 3 || contacts[0].size() != static_cast<std::size_t>(T) || contacts[1].size() != static_cast<std::size_t>(T)) return;
  const MultibodyZmp zmp = multibody_zmp(model, data, q, fps);
  int inside = 0, near = 0, single_inside = 0, single_near = 0;
  m.zmp_stance_frames = m.zmp_single_support_frames = 0;
  m.zmp_outside_max_m = 0;
  for (int f = 1; f + 1 < T; ++f) {
    const std::array<bool, 2> down{{contacts[0][static_cast<std::size_t>(f)] != 0, contacts[1][static_cast<std::size_t>(f)] != 0}};
    if (!down[0] && !down[1]) continue;
    update_kinematics(model, data, q.col(f));
    const double d = zmp_distance_outside(stance_support_polygon(model, data, down), zmp, f);
    const bool single = down[0] != down[1];
    ++m.zmp_stance_frames;
    m.zmp_single_support_frames += single;
    inside += d <= 0;
    near += d <= kZmpNear_m;
    single_inside += single && d <= 0;
    single_near += single && d <= kZmpNear_m;
    if (d > m.zmp_outside_max_m) {
      m.zmp_outside_max_m = d;
      m.zmp_outside_time_s = f / fps;
    }
  }
  auto fraction = [](int n, int of) { return of > 0 ? static_cast<double>(n) / of : 1.0; };
  m.zmp_inside_fraction = fraction(inside, m.zmp_stance_frames);
  m.zmp_near_fraction = fraction(near, m.zmp_stance_frames);
  m.zmp_single_inside_fraction = fraction(single_inside, m.zmp_single_support_frames);
  m.zmp_single_near_fraction = fraction(single_near, m.zmp_single_support_frames);
}

double frame_landmark_error_m(const RobotModel& model, RobotData& data, const LandmarkTargets& targets, const VecXCRef& q,
                              int frame, std::array<std::vector<double>, kLandmarkCount>* per_landmark) {
  update_kinematics(model, data, q);
  double sum = 0;
  int n = 0;
  for (const LandmarkTarget& lt : model.config().landmarks) {
    const LandmarkTrack& t = targets[lt.landmark];
    if (lt.weight <= 0 || !t.valid(frame)) continue;
    const double d = (link_point(model, data, model.link_index(lt.link), lt.p_L_offset) - t.p_W.col(frame)).norm();
    sum += d;
    ++n;
    if (per_landmark) (*per_landmark)[static_cast<std::size_t>(index(lt.landmark))].push_back(d);
  }
  return n ? sum / n : NAN;
}

QualityMetrics compute_quality(const RobotModel& model, RobotData& data, const Clip& clip) {
  const RobotMotion& motion = clip.motion;
  const int T = motion.num_frames(), nu = model.nu();
  if (T == 0) return {};
  const Reference& ref = clip.reference;
  // The exported frames (the source-rate motion without a resample pass): feet, floor, ZMP and
  // torque demand are measured on them.
  const bool exported = ref.num_frames() > 0;
  const MatX q_out = exported ? reference_q(model, ref) : motion.q;
  const double fps_out = exported ? ref.fps : motion.fps;
  QualityMetrics m = foot_metrics(model, data, q_out, fps_out, exported ? ref.contact : clip.contacts.in_contact);

  // Landmark errors at the robot motion's rate (the source's; the export rate after com-plan), on
  // the source's frames (a standing lead-in or lead-out has no source sample: its targets are the
  // end's, held).
  std::vector<double> per_frame;
  std::array<std::vector<double>, kLandmarkCount> per_landmark;
  if (clip.targets[Landmark::Pelvis].present)
    for (int f = clip.lead_in_frames; f < T - clip.lead_out_frames; ++f) {
      const double e = frame_landmark_error_m(model, data, clip.targets, motion.q.col(f), f, &per_landmark);
      if (std::isfinite(e)) per_frame.push_back(e);
    }
  m.landmark_error_median_m = percentile(per_frame, 0.5);
  m.landmark_error_p95_m = percentile(per_frame, 0.95);
  double worst = -1;
  for (Landmark l : all_landmarks()) {
    const std::vector<double>& e = per_landmark[static_cast<std::size_t>(index(l))];
    if (e.empty()) continue;
    LandmarkErrorStat s;
    s.landmark = std::string(landmark_name(l));
    s.median_m = percentile(e, 0.5);
    s.p95_m = percentile(e, 0.95);
    m.landmark_errors.push_back(s);
    double mean = 0;
    for (double d : e) mean += d;
    mean /= static_cast<double>(e.size());
    if (mean > worst) {
      worst = mean;
      m.worst_landmark = s.landmark;
    }
  }

  // Limits at the robot motion's rate.
  for (int f = 0; f < T; ++f)
    for (int i = 0; i < nu; ++i) {
      const double v = motion.q(7 + i, f);
      if (v < model.q_lower()[i] - 1e-9 || v > model.q_upper()[i] + 1e-9) ++m.position_limit_violations;
      if (f == 0) continue;
      const double speed = std::abs(v - motion.q(7 + i, f - 1)) * motion.fps;
      if (speed > m.fastest_joint_speed) {
        m.fastest_joint_speed = speed;
        m.fastest_joint = model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(i)])].name;
      }
      if (model.velocity_limits()[i] > 0) {
        const double ratio = speed / model.velocity_limits()[i];
        m.max_velocity_ratio = std::max(m.max_velocity_ratio, ratio);
        if (ratio > 1.0) ++m.velocity_limit_violations;
      }
    }
  const TorqueDemand td = torque_demand(model, data, q_out, fps_out);
  m.torque_demand_max_ratio = td.max_ratio;
  m.torque_demand_time_s = td.max_time_s;
  m.torque_demand_frames_over = td.frames_over;
  if (td.max_joint >= 0)
    m.torque_demand_joint = model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(td.max_joint)])].name;
  m.jitter_rad_s3 = joint_jitter(motion.q, motion.fps);
  m.jitter_per_frame_ik_rad_s3 =
      motion.q_per_frame_ik.cols() == T ? joint_jitter(motion.q_per_frame_ik, motion.fps) : m.jitter_rad_s3;
  return m;
}

}  // namespace rt
