#include "retarget/passes/refine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "retarget/core/error.hpp"
#include "retarget/core/lap_timer.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/leg_ends.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/ground.hpp"
#include "retarget/passes/ik_pass.hpp"
#include "retarget/passes/quality.hpp"
#include "src/refine/foot_plan.hpp"
#include "src/refine/signal_smoother.hpp"
#include "src/refine/smooth_correction.hpp"

namespace rt {

namespace {

using refine::FootMode;
using refine::FootTarget;
using refine::SolePose;

// Frames x joints above a speed limit (finite differences).
int speed_violations(const MatX& q, double fps, const VecX& limit) {
  int n = 0;
  for (Eigen::Index f = 1; f < q.cols(); ++f)
    for (Eigen::Index i = 0; i < limit.size(); ++i)
      if (limit[i] > 0 && std::abs(q(7 + i, f) - q(7 + i, f - 1)) * fps > limit[i] * (1 + 1e-9)) ++n;
  return n;
}

std::array<std::vector<SolePose>, 2> sole_poses(const RobotModel& model, RobotData& data, const MatX& q,
                                                const std::array<Mat3, 2>& R_L_sole) {
  std::array<std::vector<SolePose>, 2> out;
  for (auto& v : out) v.resize(static_cast<std::size_t>(q.cols()));
  for (Eigen::Index f = 0; f < q.cols(); ++f) {
    update_kinematics(model, data, q.col(f));
    for (int foot = 0; foot < 2; ++foot) {
      const auto k = static_cast<std::size_t>(foot);
      const Sole& sole = model.soles()[k];
      const Iso3 X = link_pose(model, data, sole.link);
      out[k][static_cast<std::size_t>(f)] = {X * sole.p_L_center, X.linear() * R_L_sole[k]};
    }
  }
  return out;
}

// Smooths every row of `y` (T columns) on its own: bounds per row in `lo`/`hi` (empty: none),
// speed limits per row in `max_speed` (<= 0 or empty: none), robust with `robust_floor` per row.
MatX smooth_rows(const MatX& y, double fps, const RefineOptions& ro, const VecX& lo, const VecX& hi, const VecX& max_speed,
                 const VecX& robust_floor, int* active_rows, int* downweighted) {
  const Eigen::Index T = y.cols();
  MatX out = y;
  if (!(ro.smoothing_hz > 0) || T < 3) return out;
  const double lambda = refine::smoothing_lambda(ro.smoothing_hz, fps);
  std::vector<double> row(static_cast<std::size_t>(T)), x;
  for (Eigen::Index r = 0; r < y.rows(); ++r) {
    refine::SmoothOptions o;
    o.lambda = lambda;
    o.robust_threshold = ro.robust_threshold;
    o.robust_floor = robust_floor[r];
    if (lo.size()) o.lo = lo[r];
    if (hi.size()) o.hi = hi[r];
    if (max_speed.size() && max_speed[r] > 0) o.max_step = max_speed[r] / fps;
    for (Eigen::Index f = 0; f < T; ++f) row[static_cast<std::size_t>(f)] = y(r, f);
    const refine::SmoothReport rep = refine::smooth_signal(row, o, x);
    *active_rows += rep.active_rows;
    *downweighted += rep.downweighted;
    for (Eigen::Index f = 0; f < T; ++f) out(r, f) = x[static_cast<std::size_t>(f)];
  }
  return out;
}

// Step 3 of the header: every coordinate of q smoothed on its own, the root quaternion with sign
// continuity and renormalised; joints within their position and speed limits.
MatX smooth_motion(const RobotModel& model, const MatX& q, double fps, const RefineOptions& ro, const VecX& speed_limit,
                   int* active_rows, int* downweighted) {
  const int nq = model.nq(), nu = model.nu();
  MatX src = q;
  for (Eigen::Index f = 1; f < q.cols(); ++f)
    if (src.col(f).segment<4>(3).dot(src.col(f - 1).segment<4>(3)) < 0) src.col(f).segment<4>(3) *= -1;
  VecX lo = VecX::Constant(nq, -1e300), hi = VecX::Constant(nq, 1e300), speed = VecX::Zero(nq);
  VecX floor = VecX::Constant(nq, 2e-3);  // [rad] (and quaternion units)
  floor.head<3>().setConstant(1e-3);       // [m]
  for (int i = 0; i < nu; ++i) {
    lo[7 + i] = model.q_lower()[i] + ro.limit_margin;
    hi[7 + i] = model.q_upper()[i] - ro.limit_margin;
    if (lo[7 + i] > hi[7 + i]) lo[7 + i] = hi[7 + i] = 0.5 * (model.q_lower()[i] + model.q_upper()[i]);
    speed[7 + i] = speed_limit[i];
  }
  MatX out = smooth_rows(src, fps, ro, lo, hi, speed, floor, active_rows, downweighted);
  for (Eigen::Index f = 0; f < q.cols(); ++f) out.col(f).segment<4>(3).normalize();
  return out;
}

// A leg as two points the root-height bound needs: its hip, which moves with the root, and its
// ankle, fixed in the sole frame (leg_ends.hpp), and the longest distance the bound allows between
// them: `max_extension` times their distance at the neutral pose (the leg straight, or nearly).
struct LegReach {
  int hip_link = -1;           ///< child link of the hip joint (its origin is the joint's)
  Vec3 ankle_S = Vec3::Zero(); ///< [m] ankle point in the sole frame, from the sole centre
  double length_m = 0;
};

std::array<LegReach, 2> leg_reaches(const RobotModel& model, RobotData& data, const std::array<Mat3, 2>& R_L_sole, double max_extension) {
  std::array<LegReach, 2> legs;
  const std::array<LegEnds, 2> ends = leg_ends(model);
  VecX q_neutral = model.standing_q();
  q_neutral.tail(model.nu()).setZero();
  update_kinematics(model, data, q_neutral);
  for (int foot = 0; foot < 2; ++foot) {
    const auto k = static_cast<std::size_t>(foot);
    const Sole& sole = model.soles()[k];
    const int hip = ends[k].hip_link, ankle = ends[k].ankle_link;
    if (hip < 0 || hip == ankle) continue;  // no leg to bend: no bound from this foot
    const Iso3 X_sole = link_pose(model, data, sole.link);
    const Vec3 p_ankle = link_pose(model, data, ankle).translation();
    legs[k].hip_link = hip;
    legs[k].ankle_S = R_L_sole[k].transpose() * (X_sole.inverse() * p_ankle - sole.p_L_center);
    legs[k].length_m = ends[k].length_m * max_extension;
  }
  return legs;
}

// Step 4b of the header: the root height of `q` (the smoothed motion) kept, on every frame, below
// the height from which both legs still reach their planned soles less `margin_m` (the hip rises
// with the root; the root's orientation is kept), and with a vertical acceleration within
// [-fall, rise] m/s² wherever a foot is in stance (a flight is left alone). The bound lowers the
// root by at most `max_drop_m` below its smoothed height: a stride the legs cannot reach without a
// deeper crouch (PyMO's, 10-20 cm) is left to the projection, as without the bound. The per-frame IK
// lowers the root for a frame or two where a leg cannot reach, the stride of a double support
// that a person bridges on heel and toe, and pops it back at the lift-off: 1-2 g the robot would
// have to make through its soles. Under the bound the dip is spread out instead: the root stays
// lower for longer and the knees bend. Returns the number of frames held at the bound.
int lower_root_to_reach(const RobotModel& model, RobotData& data, const std::array<LegReach, 2>& legs,
                        const refine::FootPlan& plan, double rise, double fall, double margin_m, double shift_m, double max_drop_m, double fps,
                        double lambda, MatX& q) {
  const Eigen::Index T = q.cols();
  if (T < 3) return 0;
  std::vector<double> z(static_cast<std::size_t>(T)), hi(static_cast<std::size_t>(T)), x;
  std::vector<bool> stance(static_cast<std::size_t>(T), false);
  for (Eigen::Index f = 0; f < T; ++f) {
    const auto fs = static_cast<std::size_t>(f);
    z[fs] = q(2, f);
    update_kinematics(model, data, q.col(f));
    std::array<Vec3, 2> d;  // hip from ankle [m], per stance foot
    std::array<bool, 2> held{{false, false}};
    for (int foot = 0; foot < 2; ++foot) {
      const auto k = static_cast<std::size_t>(foot);
      const refine::FootTarget& ft = plan.feet[k][fs];
      stance[fs] = stance[fs] || ft.mode == refine::FootMode::Stance;
      if (ft.mode != refine::FootMode::Stance || legs[k].hip_link < 0) continue;  // a swing leg folds
      d[k] = link_pose(model, data, legs[k].hip_link).translation() - (ft.pose.p_W + ft.pose.R_W * legs[k].ankle_S);
      held[k] = true;
    }
    // How far [m] the root could rise with its stance soles on their targets, the root free to move
    // horizontally by up to `shift_m` (as the projection does): the best of a small grid of shifts.
    double best = -1e300;
    constexpr int kGrid = 3;  // shifts of -shift_m .. shift_m in kGrid steps either way
    for (int ix = -kGrid; ix <= kGrid; ++ix)
      for (int iy = -kGrid; iy <= kGrid; ++iy) {
        const Vec2 s = Vec2(ix, iy) * (shift_m / kGrid);
        if (s.norm() > shift_m + 1e-12) continue;
        double up = 1e300;
        for (std::size_t k = 0; k < 2; ++k) {
          if (!held[k]) continue;
          const double reach = legs[k].length_m - margin_m, horizontal = (d[k].head<2>() + s).squaredNorm();
          // (Out of reach at any height: as low as max_drop_m allows.)
          up = std::min(up, horizontal < reach * reach ? std::sqrt(reach * reach - horizontal) - d[k].z() : -d[k].z() - 1.0);
        }
        best = std::max(best, up);
      }
    hi[fs] = z[fs] + std::max(-max_drop_m, std::min(0.0, best));
  }
  refine::CeilingOptions o;
  o.lambda = lambda;
  o.ceiling = hi;
  o.max_rise = rise / (fps * fps);
  o.max_fall = fall / (fps * fps);
  o.curvature_rows = stance;
  const refine::CeilingReport rep = refine::smooth_under_ceiling(z, o, x);
  for (Eigen::Index f = 0; f < T; ++f) q(2, f) = x[static_cast<std::size_t>(f)];
  return rep.active;
}

// Moves each anchor to where its sole can lie flat: the robot's leg may not reach the IK result's
// sole flat (an ankle-roll limit under a wide stance, a pitched foot), so with the root held at the
// IK pose of three frames of the phase (a quarter, half and three quarters in), the leg is solved
// for the sole flat (weight 1e4) as close as it gets to the anchor (weight 1), and the anchor takes
// the median of the poses reached.
void make_anchors_feasible(const RobotModel& model, RobotData& data, const MatX& q, const std::array<Mat3, 2>& R_L_sole,
                           std::vector<refine::SoleAnchor>& anchors) {
  IkOptions o;
  o.max_iterations = 50;
  o.regularization = 1e-4;
  o.step_tolerance = 1e-9;
  o.cost_tolerance = 1e-12;
  o.root_free = {false, false, false, false, false, false};
  const LandmarkIk ik(model, o);
  // The anchor's flat sole pose as an IK target; the heading weighs far more than the position.
  auto target_of = [&](const refine::SoleAnchor& a, double weight) {
    const auto k = static_cast<std::size_t>(a.foot);
    IkTarget t;
    t.link = model.soles()[k].link;
    t.p_L = model.soles()[k].p_L_center;
    t.p_W = Vec3(a.p_W.x(), a.p_W.y(), 0);
    t.weight = weight;
    t.R_L_frame = R_L_sole[k];
    t.R_W = Quat(AngleAxis(a.yaw, Vec3::UnitZ()));
    t.orientation_weight = 1e4 * weight;
    return t;
  };
  for (refine::SoleAnchor& a : anchors) {
    const auto k = static_cast<std::size_t>(a.foot);
    const Sole& sole = model.soles()[k];
    const IkTarget t = target_of(a, 1.0);
    std::vector<double> x, y;
    Vec2 heading = Vec2::Zero();
    for (const int num : {1, 2, 3}) {
      const int f = a.begin + (a.end - 1 - a.begin) * num / 4;
      VecX q_f = q.col(f);
      ik.solve(data, {t}, q_f, q_f);  // leaves data at the solution
      const Iso3 X = link_pose(model, data, sole.link);
      const Vec3 p = X * sole.p_L_center;
      x.push_back(p.x());
      y.push_back(p.y());
      const double yaw = refine::sole_yaw(X.linear() * R_L_sole[k]);
      heading += Vec2(std::cos(yaw), std::sin(yaw));
    }
    std::sort(x.begin(), x.end());
    std::sort(y.begin(), y.end());
    a.p_W = Vec2(x[1], y[1]);
    a.yaw = std::atan2(heading.y(), heading.x());
  }

  // A touchdown must also be reachable with the other foot where it stands: legs that cannot turn
  // or place a foot freely (H1's five joints, ±25° hip yaw) cannot land a foot as far round as a
  // performer who pivoted on the standing one. In time order, each anchor that lands while the
  // other foot's (already final) anchor holds is moved to the pose a two-foot IK (root free,
  // joint limits) reaches with that foot held firmly, in the middle of their double support. The
  // turn the landing foot cannot take is left to the next steps.
  IkOptions two;
  two.max_iterations = 100;
  two.regularization = 1e-6;
  two.step_tolerance = 1e-10;
  two.cost_tolerance = 1e-14;
  const LandmarkIk ik_two(model, two);
  std::vector<std::size_t> order(anchors.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return anchors[i].begin < anchors[j].begin; });
  for (std::size_t n = 0; n < order.size(); ++n) {
    refine::SoleAnchor& a = anchors[order[n]];
    const refine::SoleAnchor* standing = nullptr;
    for (std::size_t m = 0; m < n; ++m) {
      const refine::SoleAnchor& b = anchors[order[m]];
      if (b.foot != a.foot && b.begin < a.begin && a.begin < b.end) standing = &b;
    }
    if (!standing) continue;
    const int f = (a.begin + std::min(a.end, standing->end) - 1) / 2;
    VecX q_f = q.col(f);
    ik_two.solve(data, {target_of(*standing, 1e3), target_of(a, 1.0)}, q_f, q_f);
    const auto k = static_cast<std::size_t>(a.foot);
    const Iso3 X = link_pose(model, data, model.soles()[k].link);
    const Vec3 p = X * model.soles()[k].p_L_center;
    a.p_W = p.head<2>();
    a.yaw = refine::sole_yaw(X.linear() * R_L_sole[k]);
  }
}

// The range of the sole's heading relative to the root body's that a leg's hip-yaw joint gives:
// the leg's joint whose axis is nearest the vertical at the neutral pose (|cos| > 0.9), its limits
// signed by the axis direction, about the neutral relative heading. A leg without such a joint, or
// without limits on it, gives none (`valid` false: no bound from that foot).
struct TurnRange {
  bool valid = false;
  double neutral_rad = 0;      ///< sole heading minus root heading at the neutral pose
  double lo_rad = 0, hi_rad = 0;  ///< relative to neutral_rad
};

// The heading of a frame: the direction of its x axis on the floor. (Its twist about the vertical,
// better defined under a pelvis bent far forward, was tried: it made JVRC-1's LAFAN1 dance end at
// 27 % of the stance frames with the ZMP within 1 cm of the support against 77 %.)
double heading(const Mat3& R) { return std::atan2(R(1, 0), R(0, 0)); }
double wrap_angle(double a) { return std::remainder(a, 2 * M_PI); }

std::array<TurnRange, 2> turn_ranges(const RobotModel& model, RobotData& data, const std::array<Mat3, 2>& R_L_sole) {
  std::array<TurnRange, 2> out;
  VecX q_neutral = model.standing_q();
  q_neutral.tail(model.nu()).setZero();
  update_kinematics(model, data, q_neutral);
  const double root_heading = heading(Quat(q_neutral[3], q_neutral[4], q_neutral[5], q_neutral[6]).normalized().toRotationMatrix());
  for (int foot = 0; foot < 2; ++foot) {
    const auto k = static_cast<std::size_t>(foot);
    const Sole& sole = model.soles()[k];
    double best = 0.9;
    for (int l = sole.link; l >= 0 && model.links()[static_cast<std::size_t>(l)].parent_joint >= 0;) {
      const Joint& j = model.joints()[static_cast<std::size_t>(model.links()[static_cast<std::size_t>(l)].parent_joint)];
      if (j.type == JointType::Floating) break;
      if (j.qpos_index >= 0 && j.type == JointType::Revolute && j.has_position_limits) {
        const Vec3 axis_W = link_pose(model, data, j.parent_link).linear() * j.X_P_J.linear() * j.axis;
        if (std::abs(axis_W.z()) > best) {
          best = std::abs(axis_W.z());
          out[k].valid = true;
          out[k].lo_rad = axis_W.z() > 0 ? j.lower : -j.upper;
          out[k].hi_rad = axis_W.z() > 0 ? j.upper : -j.lower;
        }
      }
      l = j.parent_link;
    }
    out[k].neutral_rad = wrap_angle(heading(link_pose(model, data, sole.link).linear() * R_L_sole[k]) - root_heading);
  }
  return out;
}

// Step 4, turns beyond the legs: a performer who turns on a planted foot further than the robot's
// hip yaw allows (a pirouette) cannot be followed with the sole fixed; without a bound the
// projection reached for the anchor by folding the leg (G1 on the LAFAN1 dance: root 0.16 m high,
// knee at its limit, for a second). The root of `q` (the smoothed motion) is turned back about the
// stance anchors, on each frame, by the least angle that keeps every stance sole's heading relative
// to the root within its leg's range widened by `slack_rad` (relative headings unwrapped over each
// stance, so a full turn counts as one), blended over ±`ramp` frames; the projection turns the root
// through the slack, as it did every turn before. Returns the largest turn [rad]; `q` is untouched
// where every stance is within range.
double limit_turns_on_planted_feet(const std::array<TurnRange, 2>& ranges, const std::vector<refine::SoleAnchor>& anchors,
                                   double slack_rad, int ramp, MatX& q) {
  const int T = static_cast<int>(q.cols());
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> lo(static_cast<std::size_t>(T), -kInf), hi(static_cast<std::size_t>(T), kInf);
  std::vector<Vec2> pivot_sum(static_cast<std::size_t>(T), Vec2::Zero());
  std::vector<int> stance(static_cast<std::size_t>(T), 0);
  auto root_heading = [&](int f) { return heading(Quat(q(3, f), q(4, f), q(5, f), q(6, f)).normalized().toRotationMatrix()); };
  for (const refine::SoleAnchor& a : anchors) {
    const TurnRange& r = ranges[static_cast<std::size_t>(a.foot)];
    if (!r.valid || r.hi_rad - r.lo_rad + 2 * slack_rad < 0) continue;
    double rel = 0;  // sole heading relative to the root's, less the neutral one, unwrapped over the stance
    for (int f = a.begin; f < a.end; ++f) {
      const double wrapped = wrap_angle(a.yaw - root_heading(f) - r.neutral_rad);
      rel = f == a.begin ? wrapped : rel + wrap_angle(wrapped - rel);
      // Turning the root by d changes rel by -d: rel - d within [lo - slack, hi + slack].
      const auto i = static_cast<std::size_t>(f);
      lo[i] = std::max(lo[i], rel - (r.hi_rad + slack_rad));
      hi[i] = std::min(hi[i], rel - (r.lo_rad - slack_rad));
      pivot_sum[i] += a.p_W;
      ++stance[i];
    }
  }
  // The least turn per frame (the middle where two stance feet ask for more than one range allows).
  std::vector<double> turn(static_cast<std::size_t>(T), 0.0);
  bool any = false;
  for (std::size_t i = 0; i < turn.size(); ++i) {
    if (stance[i] == 0) continue;
    turn[i] = lo[i] <= hi[i] ? std::clamp(0.0, lo[i], hi[i]) : 0.5 * (lo[i] + hi[i]);
    any = any || turn[i] != 0;
  }
  if (!any) return 0;
  double largest = 0;
  for (int f = 0; f < T; ++f) {
    // Blended: the turn and its pivot (the anchors' mean, weighted by the turn) over ±ramp frames.
    double d = 0, total = 0, pivot_weight = 0;
    Vec2 pivot = Vec2::Zero();
    for (int g = std::max(0, f - ramp); g <= std::min(T - 1, f + ramp); ++g) {
      const auto i = static_cast<std::size_t>(g);
      const double w = 0.5 * (1 + std::cos(M_PI * std::abs(g - f) / (ramp + 1)));
      d += w * turn[i];
      total += w;
      if (turn[i] != 0) {
        pivot += w * std::abs(turn[i]) * pivot_sum[i] / stance[i];
        pivot_weight += w * std::abs(turn[i]);
      }
    }
    d /= total;
    if (d == 0 || pivot_weight == 0) continue;
    pivot /= pivot_weight;
    q.block<2, 1>(0, f) = pivot + Eigen::Rotation2Dd(d).toRotationMatrix() * (q.block<2, 1>(0, f) - pivot);
    const Quat turned = (Quat(AngleAxis(d, Vec3::UnitZ())) * Quat(q(3, f), q(4, f), q(5, f), q(6, f))).normalized();
    q.block<4, 1>(3, f) << turned.w(), turned.x(), turned.y(), turned.z();
    largest = std::max(largest, std::abs(d));
  }
  return largest;
}

// An IK target holding the sole of `foot` at `pose` (position weight w, orientation weight
// w · length²).
IkTarget sole_target(const RobotModel& model, int foot, const refine::SolePose& pose, double w, double length,
                     const std::array<Mat3, 2>& R_L_sole) {
  const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
  IkTarget t;
  t.link = sole.link;
  t.p_L = sole.p_L_center;
  t.p_W = pose.p_W;
  t.weight = w;
  t.R_L_frame = R_L_sole[static_cast<std::size_t>(foot)];
  t.R_W = Quat(pose.R_W);
  t.orientation_weight = w * length * length;
  return t;
}

bool is_foot_landmark(Landmark l) {
  return l == Landmark::LeftAnkle || l == Landmark::LeftToe || l == Landmark::LeftHeel || l == Landmark::RightAnkle ||
         l == Landmark::RightToe || l == Landmark::RightHeel;
}

// M_f of the smooth correction (smooth_correction.hpp): the landmark cost's Gauss–Newton matrix at
// each frame of q over `dofs`, so that a foot's correction is taken up where it costs the body's
// landmarks the least. The foot landmarks are left out: the foot plan places the feet. Empty when
// the clip has no landmark targets at this rate.
std::vector<MatX> landmark_metric(const RobotModel& model, RobotData& data, const LandmarkIk& ik, const LandmarkTargets& targets,
                                  const MatX& q, const std::vector<int>& dofs) {
  const Eigen::Index T = q.cols();
  for (const LandmarkTrack& track : targets.tracks)
    if (track.present && (track.p_W.cols() != T || track.state.size() != static_cast<std::size_t>(T))) return {};
  std::vector<MatX> out(static_cast<std::size_t>(T));
  std::vector<Landmark> landmarks;
  const auto n = static_cast<Eigen::Index>(dofs.size());
  for (Eigen::Index f = 0; f < T; ++f) {
    std::vector<IkTarget> all = make_ik_targets(model, ik, targets, static_cast<int>(f), 0.5, &landmarks), body;
    for (std::size_t k = 0; k < all.size(); ++k)
      if (!is_foot_landmark(landmarks[k])) body.push_back(all[k]);
    MatX& M = out[static_cast<std::size_t>(f)];
    M.setZero(n, n);
    if (body.empty()) continue;
    const MatX H = ik.targets_normal_matrix(data, body, q.col(f));
    for (Eigen::Index a = 0; a < n; ++a)
      for (Eigen::Index c = 0; c < n; ++c) M(a, c) = H(dofs[static_cast<std::size_t>(a)], dofs[static_cast<std::size_t>(c)]);
  }
  return out;
}

}  // namespace

RefinePass::RefinePass() {
  table_.add("smoothing_hz", options_.smoothing_hz, "[Hz] cutoff of the joint-space smoother (0: no smoothing)", {0, 1000, "Hz"});
  table_.add("root_rise_accel", options_.root_rise_accel,
             "[m/s^2] largest upward acceleration of the root height while a foot is in stance (0: no limit)", {0, 1000, "m/s^2"});
  table_.add("root_fall_accel", options_.root_fall_accel,
             "[m/s^2] largest downward acceleration of the root height while a foot is in stance (0: no limit)", {0, 1000, "m/s^2"});
  table_.add("root_max_drop", options_.root_max_drop_m,
             "[m] with the root limits: how far below its smoothed height the legs' reach may put the root", {0, 1, "m"});
  table_.add("max_leg_extension", options_.max_leg_extension,
             "stance legs' hip-ankle distance at most this fraction of their straight length (< 1: the root bound lowers the root to bend the knees)", {0.5, 1, ""});
  table_.add("robust_threshold", options_.robust_threshold, "[sigma] samples this far from the smoothed curve are weighted down (0: plain)");
  table_.add("velocity_margin", options_.velocity_margin, "fraction of each joint speed limit kept free");
  table_.add("max_joint_speed", options_.max_joint_speed, "[rad/s] cap on every joint's speed below its URDF limit (0: none)");
  table_.add("limit_margin", options_.limit_margin, "[rad, m] distance kept from the joint position limits");
  table_.add("swing_clearance", options_.swing_clearance_m, "[m] swing sole height beyond swing_guard of lift-off/touchdown");
  table_.add("swing_guard", options_.swing_guard_s, "[s] near lift-off and touchdown the swing sole may be lower", {0, 10, "s"});
  table_.add("swing_tilt_ramp", options_.swing_tilt_ramp_s,
             "[s] the swing sole's tilt fades in after lift-off and out before touchdown over this when longer than swing_guard (0: swing_guard)",
             {0, 2, "s"});
  table_.add("stance_weight", options_.stance_weight, "weight of the stance sole targets [1/m^2]");
  table_.add("swing_weight", options_.swing_weight, "weight of the swing sole targets [1/m^2]");
  table_.add("floor_weight", options_.floor_weight, "weight of collision points below the floor [1/m^2]");
  table_.add("hold_turns", options_.hold_turns,
             "hold back the root's turn where a stance sole's heading relative to it leaves the hip yaw's range by more than turn_slack");
  table_.add("turn_slack", options_.turn_slack, "[rad] how far beyond the hip yaw's range the projection turns the root itself",
             {-1, 3.2, "rad"});
  table_.add("rounds", options_.rounds, "smooth + project rounds at most", {0, 100, ""});
  table_.add("hold_iterations", options_.hold_iterations,
             "further (damped) Gauss-Newton steps of the smooth correction while a stance sole or a limit is missed (0: none)", {0, 1000, ""});
  table_.add("max_iterations", options_.max_iterations, "projection iterations per frame", {0, 10000, ""});
  table_.add("landmark_metric", options_.landmark_metric, "weigh the foot correction by the landmark cost (false: joint-space stiffness only)");
}

void RefinePass::run(Clip& clip, PassContext& ctx) {
  const RobotModel& model = ctx.model();
  RobotData& data = ctx.data();
  RobotMotion& motion = clip.motion;
  const RefineOptions& o = options_;
  const int T = motion.num_frames();
  const std::string where = clip.human.source.path.empty() ? clip.name : clip.human.source.path;
  if (T == 0) throw InputError("--passes", "refine needs the robot motion of the ik pass: put ik before refine");
  require_input(o.smoothing_hz >= 0 && o.robust_threshold >= 0 && o.velocity_margin >= 0 && o.velocity_margin < 1 && o.max_joint_speed >= 0 &&
                    o.limit_margin >= 0 && o.swing_clearance_m >= 0 && o.swing_clearance_m <= 0.5 && o.swing_guard_s >= 0 &&
                    o.swing_guard_s <= 2,
                "refine", "options need smoothing_hz >= 0, robust_threshold >= 0, velocity_margin in [0, 1), max_joint_speed >= 0, limit_margin >= 0, "
                          "swing_clearance in [0, 0.5] m, swing_guard in [0, 2] s");
  require_input(o.stance_weight > 0 && o.swing_weight > 0 && o.floor_weight > 0 && o.rounds >= 1 && o.rounds <= 20 &&
                    o.max_iterations >= 1 && o.max_iterations <= 1000,
                "refine", "weights must be > 0, rounds in [1, 20], max_iterations in [1, 1000]");
  if (T < 4 || !(motion.fps > 0)) {
    ctx.statistics.set("skipped", 1, "", "fewer than 4 frames");
    return;
  }
  const auto t_start = std::chrono::steady_clock::now();
  const double fps = motion.fps;
  const int nu = model.nu();
  const double jitter_before = joint_jitter(motion.q, fps);
  const int velocity_before = speed_violations(motion.q, fps, model.velocity_limits());

  // 1. Ground: the ground pass's per-frame vertical offset (stance feet near the floor).
  MatX q_in = motion.q;
  {
    Clip grounded;
    grounded.motion = motion;
    grounded.contacts = clip.contacts;
    Statistics statistics;
    Diagnostics diagnostics;
    PassContext ground_ctx{&model, &data, statistics, diagnostics};
    GroundPass().run(grounded, ground_ctx);
    q_in.row(2) = grounded.motion.q.row(2);
  }

  // 2. Anchors from the IK result's soles.
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  std::array<std::vector<std::uint8_t>, 2> contacts = clip.contacts.in_contact;
  for (auto& c : contacts)
    if (c.size() != static_cast<std::size_t>(T)) c.assign(static_cast<std::size_t>(T), 0);
  std::vector<refine::SoleAnchor> anchors = refine::stance_anchors(sole_poses(model, data, q_in, R_L_sole), contacts);
  make_anchors_feasible(model, data, q_in, R_L_sole, anchors);

  // Joint speed limits: the smoother keeps velocity_margin free of the URDF limit (or the cap).
  VecX hard_limit = model.velocity_limits();
  for (int i = 0; i < nu; ++i)
    if (o.max_joint_speed > 0) hard_limit[i] = hard_limit[i] > 0 ? std::min(hard_limit[i], o.max_joint_speed) : o.max_joint_speed;
  const VecX speed_limit = hard_limit * (1 - o.velocity_margin);

  // Who absorbs a foot's correction: the legs; the root and the rest of the body (whose landmarks
  // the smoothed motion tracks) are 30-100 times stiffer.
  constexpr double kRootHeightStiffness = 100;
  const bool root_limits = o.root_rise_accel > 0 || o.root_fall_accel > 0 || o.max_leg_extension < 1;
  VecX stiffness = refine::legs_first_stiffness(model);
  // The root height was set under the legs' reach (lower_root_to_reach): the legs bend to it
  // rather than the root rising back into the dips it was smoothed out of (10 times let them
  // come back: up to 2-3 g again on the shared walks).
  if (root_limits) stiffness[2] *= kRootHeightStiffness;
  std::vector<int> metric_dofs{0, 1, 2, 3, 4, 5};
  for (int foot = 0; foot < 2; ++foot)
    for (int d : link_dof_chain(model, model.soles()[static_cast<std::size_t>(foot)].link))
      if (d >= 6) metric_dofs.push_back(d);
  const double stance_length = 0.1, swing_length = 0.02;  // [m] orientation rows: w · length²

  refine::CorrectionOptions co;
  co.stance_weight = o.stance_weight;
  co.swing_weight = o.swing_weight;
  co.floor_weight = o.floor_weight;
  co.stance_length_m = stance_length;
  co.swing_length_m = swing_length;
  co.lambda = o.smoothing_hz > 0 ? refine::smoothing_lambda(o.smoothing_hz, fps) : 0.0;
  co.stiffness = stiffness;
  co.R_L_sole = R_L_sole;
  co.q_lower = model.q_lower().array() + 2 * o.limit_margin;
  co.q_upper = model.q_upper().array() - 2 * o.limit_margin;
  co.max_step = speed_limit / fps;
  co.metric_dofs = metric_dofs;
  co.extra_iterations = o.hold_iterations;

  // 5. The per-frame projection (every row met, jittery).
  IkOptions ik_options;
  ik_options.max_iterations = o.max_iterations;
  // A start for the smooth correction, which converges the rows the rest of the way.
  ik_options.step_tolerance = 1e-6;
  ik_options.cost_tolerance = 1e-6;
  ik_options.regularization = 1.0;
  ik_options.regularization_factors = stiffness;
  ik_options.joint_limit_margin = o.limit_margin;
  ik_options.initial_damping = 1e-8;  // the start is close: Gauss–Newton steps from the first iteration
  const LandmarkIk ik(model, ik_options);
  refine::FootPlan plan;
  std::vector<IkTarget> targets;
  // A fresh solve at a touchdown or lift-off is kept only if no joint moves faster than this
  // multiple of its speed limit from the previous frame (see project).
  constexpr double kFreshJumpRatio = 6.0;
  int iterations = 0;
  // How well frame f holds the plan at the kinematics in `data`: the stance soles' distance [m]
  // and angle [rad] from their anchors, the depth [m] of the lowest collision point below the
  // floor (stance soles excluded), and how far [m] a swing foot's geometry is below its planned
  // clearance. Held: within 1 mm, 0.5 deg and 1 mm (the clearance is judged by the fallback only).
  struct FrameHold {
    double position = 0, angle = 0, floor = 0, clearance = 0;
    bool held() const { return position <= 1e-3 && angle <= 0.5 * M_PI / 180 && floor <= 1e-3; }
  };
  std::vector<LowestPoint> low;
  auto frame_hold = [&](int f) {
    FrameHold h;
    std::array<int, 2> skip{{-1, -1}};
    std::array<double, 2> min_height{{0, 0}};
    for (int foot = 0; foot < 2; ++foot) {
      const auto k = static_cast<std::size_t>(foot);
      const FootTarget& ft = plan.feet[k][static_cast<std::size_t>(f)];
      const Sole& sole = model.soles()[k];
      if (ft.mode != FootMode::Stance) {
        min_height[k] = ft.min_height_m;
        continue;
      }
      skip[k] = sole.link;
      const Iso3 X = link_pose(model, data, sole.link);
      h.position = std::max(h.position, (X * sole.p_L_center - ft.pose.p_W).norm());
      h.angle = std::max(h.angle, AngleAxis(Mat3(X.linear() * R_L_sole[k] * ft.pose.R_W.transpose())).angle());
    }
    low.clear();
    collision_points_below(model, data, std::max(min_height[0], min_height[1]), low, skip[0], skip[1]);
    for (const LowestPoint& p : low) {
      h.floor = std::max(h.floor, -p.z_m);
      for (int foot = 0; foot < 2; ++foot)
        if (p.link == model.soles()[static_cast<std::size_t>(foot)].link)
          h.clearance = std::max(h.clearance, min_height[static_cast<std::size_t>(foot)] - p.z_m);
    }
    return h;
  };
  auto project = [&](const MatX& q_target_all, MatX& q_out) {
    iterations = 0;
    for (int f = 0; f < T; ++f) {
      targets.clear();
      IkFloorTerm floor;
      floor.weight = o.floor_weight;
      for (int foot = 0; foot < 2; ++foot) {
        const auto k = static_cast<std::size_t>(foot);
        const FootTarget& ft = plan.feet[k][static_cast<std::size_t>(f)];
        const int link = model.soles()[k].link;
        if (ft.mode == FootMode::Stance)
          floor.skip_links[k] = link;
        else
          floor.link_min_height_m.emplace_back(link, ft.min_height_m);
        if (ft.mode == FootMode::Free) continue;
        // Swing targets are held as firmly as stance ones at lift-off and touchdown, less in between
        // (the same rows as the smooth correction's).
        const double blend = ft.mode == FootMode::Stance ? 1.0 : ft.end_blend;
        targets.push_back(sole_target(model, foot, ft.pose, o.swing_weight + (o.stance_weight - o.swing_weight) * blend,
                                      swing_length + (stance_length - swing_length) * blend, R_L_sole));
      }
      // Warm start: the previous frame's correction carried over. Across a touchdown or a lift-off
      // the frame is also solved afresh and that is kept only if it holds the rows much better (a
      // warm start stuck on the wrong side of a flight) and stays near the previous frame: a fresh
      // solution that moves a joint more than kFreshJumpRatio times its speed limit in one frame is
      // another solution branch of a leg with several (H1's five joints at the CMU 131_01 crossover
      // touchdown: the trunk pitched from -47 to +47 deg and a hip by 1.4 rad between two frames,
      // 170 rad/s once blended in). The warm start is kept there; the smooth correction and its
      // speed rows take the rows it misses.
      VecX q_f = q_target_all.col(f);
      const bool modes_kept = f > 0 && plan.feet[0][static_cast<std::size_t>(f)].mode == plan.feet[0][static_cast<std::size_t>(f - 1)].mode &&
                              plan.feet[1][static_cast<std::size_t>(f)].mode == plan.feet[1][static_cast<std::size_t>(f - 1)].mode;
      if (f > 0)
        q_f = integrate(model, q_target_all.col(f), difference(model, q_target_all.col(f - 1), q_out.col(f - 1), 1.0), 1.0);
      const IkResult r = ik.solve(data, targets, q_target_all.col(f), q_f, {}, floor);
      iterations += r.solver.iterations;
      if (f > 0 && !modes_kept) {
        VecX q_fresh = q_target_all.col(f);
        const IkResult r_fresh = ik.solve(data, targets, q_target_all.col(f), q_fresh, {}, floor);
        iterations += r_fresh.solver.iterations;
        double jump = 0;  // the fastest joint from the previous frame, in multiples of its limit
        for (int i = 0; i < nu; ++i)
          if (hard_limit[i] > 0) jump = std::max(jump, std::abs(q_fresh[7 + i] - q_out(7 + i, f - 1)) * fps / hard_limit[i]);
        if (r_fresh.solver.cost < 0.5 * r.solver.cost && jump <= kFreshJumpRatio) q_f = q_fresh;
      }
      q_out.col(f) = q_f;
    }
  };

  // Where the smooth correction did not converge onto the rows (a motion its smooth solution cannot
  // follow within the iterations, e.g. a fast turn over a planted foot in a dance, or a swing foot
  // that dips for a frame or two below its clearance), the frames take the per-frame projection
  // instead where that holds the rows better, blended in over `ramp` frames on either side: the
  // feet and the floor come before smoothness (the speed check of the rounds follows). The
  // clearance rows sit 2 mm above the clearance itself: a miss beyond that is gross.
  const int ramp = std::max(2, static_cast<int>(std::lround(0.1 * fps)));
  auto bump = [&](std::vector<double>& weight, int f) {  // a raised cosine over f ± ramp
    for (int g = std::max(0, f - ramp); g <= std::min(T - 1, f + ramp); ++g) {
      const double u = static_cast<double>(std::abs(g - f)) / (ramp + 1);
      weight[static_cast<std::size_t>(g)] = std::max(weight[static_cast<std::size_t>(g)], 0.5 * (1 + std::cos(M_PI * u)));
    }
  };
  auto blend = [&](MatX& q_to, const MatX& q_frames, const std::vector<double>& weight, int first, int last) {
    for (int f = first; f <= last; ++f) {
      const double w = weight[static_cast<std::size_t>(f)];
      if (w > 0) q_to.col(f) = integrate(model, q_to.col(f), difference(model, q_to.col(f), q_frames.col(f), 1.0), w);
    }
  };
  auto fall_back = [&](MatX& q_smooth_corrected, const MatX& q_frames) {
    std::vector<double> weight(static_cast<std::size_t>(T), 0.0);
    std::vector<int> clearance_only;
    int frames = 0;
    for (int f = 0; f < T; ++f) {
      update_kinematics(model, data, q_smooth_corrected.col(f));
      const FrameHold a = frame_hold(f);
      // Only a gross miss: a small one costs less than the speed the per-frame solution adds.
      const bool held = a.position <= 3e-3 && a.angle <= 1.5 * M_PI / 180 && a.floor <= 2e-3;
      if (held && a.clearance <= 2e-3) continue;
      update_kinematics(model, data, q_frames.col(f));
      const FrameHold b = frame_hold(f);
      if (b.position + 0.1 * b.angle + b.floor + b.clearance >= a.position + 0.1 * a.angle + a.floor + a.clearance)
        continue;  // [m, rad/10 m]
      if (held) {
        clearance_only.push_back(f);
        continue;
      }
      ++frames;
      bump(weight, f);
    }
    blend(q_smooth_corrected, q_frames, weight, 0, T - 1);
    // A swing foot below its clearance (and nothing else missed) takes the per-frame projection only
    // where that makes no joint faster than its limit, lets no frame lose the hold of its stance
    // soles and floor, and drops no other swing frame below the clearance: a scuff is a smaller
    // fault than a joint the robot cannot drive (e.g. another leg solution of H1's five joints).
    auto window_holds = [&](int first, int last) {
      std::vector<FrameHold> holds;
      for (int f = first; f <= last; ++f) {
        update_kinematics(model, data, q_smooth_corrected.col(f));
        holds.push_back(frame_hold(f));
      }
      return holds;
    };
    for (std::size_t c = 0; c < clearance_only.size();) {
      std::size_t e = c + 1;  // frames whose ramps overlap are one cluster
      while (e < clearance_only.size() && clearance_only[e] - clearance_only[e - 1] <= 2 * ramp) ++e;
      std::vector<double> w(static_cast<std::size_t>(T), 0.0);
      for (std::size_t k = c; k < e; ++k) bump(w, clearance_only[k]);
      const int first = std::max(0, clearance_only[c] - ramp - 1), last = std::min(T - 1, clearance_only[e - 1] + ramp + 1);
      const MatX before = q_smooth_corrected.middleCols(first, last - first + 1);
      const std::vector<FrameHold> hold_before = window_holds(first, last);
      blend(q_smooth_corrected, q_frames, w, first, last);
      const std::vector<FrameHold> hold_after = window_holds(first, last);
      bool kept = speed_violations(q_smooth_corrected.middleCols(first, last - first + 1), fps, hard_limit) <=
                  speed_violations(before, fps, hard_limit);
      for (std::size_t k = 0; k < hold_after.size(); ++k) {
        const FrameHold &b = hold_before[k], &h = hold_after[k];
        kept = kept && (h.held() || !b.held()) && (h.clearance <= 2e-3 || h.clearance <= b.clearance);
      }
      if (!kept)
        q_smooth_corrected.middleCols(first, last - first + 1) = before;
      else
        frames += static_cast<int>(e - c);
      c = e;
    }
    return frames;
  };

  // 3, 5, 6, then again from the result while a joint is faster than its limit and the last round
  // at least halved the count (a motion too fast for the limits gains nothing from more rounds);
  // the round with the fewest violations is kept.
  // The root height's bound keeps the legs this far [m] from straight: a straight knee is a
  // singular pose for the projection and for a controller.
  constexpr double kReachMargin = 0.005;
  // ... and assumes the root may move this far [m] horizontally to reach them (the projection
  // moves it): without that the bound asked the G1 Bandai walk for 3 cm more crouch than needed.
  constexpr double kReachShift = 0.06;
  const std::array<TurnRange, 2> turns = turn_ranges(model, data, R_L_sole);
  const std::array<LegReach, 2> legs = root_limits ? leg_reaches(model, data, R_L_sole, o.max_leg_extension) : std::array<LegReach, 2>{};
  // Wall time per stage [ms], all rounds (the -v statistics).
  double ms_smooth = 0, ms_project = 0, ms_metric = 0, ms_correct = 0, ms_fallback = 0;
  LapTimer timer;
  struct Attempt {
    MatX q;
    int rounds = 0, active_rows = 0, downweighted = 0, fallback_frames = 0, root_rows = 0, projection_iterations = 0;
    double turn_limited = 0;  ///< [rad] largest root turn held back (hold_turns)
    refine::CorrectionReport correction;
    // The hold of the result.
    int frames_not_held = 0, velocity_after = 0;
    double worst_position = 0, worst_angle = 0, worst_floor = 0;
  };
  auto solve = [&](bool hold_turns) {
    Attempt out;
    MatX q = q_in, q_best;
    int best_violations = -1, previous_violations = velocity_before, fallback_frames = 0;
    for (int round = 0; round < o.rounds; ++round) {
      out.rounds = round + 1;
      timer.lap(ms_fallback);  // (the speed check of the previous round)
      out.active_rows = out.downweighted = 0;
      MatX q_smooth = smooth_motion(model, q, fps, o, speed_limit, &out.active_rows, &out.downweighted);
      if (round == 0) {  // 4. the feet's targets, shaped from the first smoothing of the IK motion
        refine::FootPlanOptions fo;
        fo.clearance_m = o.swing_clearance_m;
        fo.guard_s = o.swing_guard_s;
        fo.tilt_ramp_s = o.swing_tilt_ramp_s;
        for (int foot = 0; foot < 2; ++foot) fo.sole_size_m[static_cast<std::size_t>(foot)] = model.soles()[static_cast<std::size_t>(foot)].size_m;
        plan = refine::plan_feet(anchors, sole_poses(model, data, q_smooth, R_L_sole), contacts, fps, fo);
      }
      if (hold_turns)
        out.turn_limited = std::max(out.turn_limited, limit_turns_on_planted_feet(turns, anchors, o.turn_slack,
                                                                                  std::max(1, static_cast<int>(std::lround(0.1 * fps))), q_smooth));
      if (root_limits)
        out.root_rows = lower_root_to_reach(model, data, legs, plan, o.root_rise_accel > 0 ? o.root_rise_accel : 1e300,
                                            o.root_fall_accel > 0 ? o.root_fall_accel : 1e300, kReachMargin, kReachShift, o.root_max_drop_m, fps,
                                            co.lambda, q_smooth);
      timer.lap(ms_smooth);
      // Each frame on its own first (every row met, jittery), then smoothly over the clip from there.
      MatX q_frames(model.nq(), T);
      project(q_smooth, q_frames);
      out.projection_iterations = iterations;
      timer.lap(ms_project);
      if (o.landmark_metric) co.metric = landmark_metric(model, data, ik, clip.targets, q_smooth, metric_dofs);
      timer.lap(ms_metric);
      q = refine::solve_smooth_correction(model, data, q_smooth, q_frames, plan, co, &out.correction);
      timer.lap(ms_correct);
      fallback_frames = fall_back(q, q_frames);
      const int violations = speed_violations(q, fps, hard_limit);
      if (best_violations < 0 || violations < best_violations) {
        best_violations = violations;
        q_best = q;
        out.fallback_frames = fallback_frames;
      }
      if (violations == 0 || 2 * violations > previous_violations) break;
      previous_violations = violations;
    }
    timer.lap(ms_fallback);
    out.q = std::move(q_best);
    // The limit rows of the correction are penalties: what they leave (micro-radians) is clamped.
    for (int f = 0; f < T; ++f)
      for (int i = 0; i < nu; ++i) out.q(7 + i, f) = std::clamp(out.q(7 + i, f), model.q_lower()[i], model.q_upper()[i]);
    out.velocity_after = speed_violations(out.q, fps, hard_limit);
    for (int f = 0; f < T; ++f) {
      update_kinematics(model, data, out.q.col(f));
      const FrameHold h = frame_hold(f);
      out.frames_not_held += !h.held();
      out.worst_position = std::max(out.worst_position, h.position);
      out.worst_angle = std::max(out.worst_angle, h.angle);
      out.worst_floor = std::max(out.worst_floor, h.floor);
    }
    return out;
  };
  // A turn held back is a candidate: kept where it misses fewer frames (stance hold, joint speed)
  // than the same rounds without it. On G1 it is kept on the LAFAN1 dance (29 frames against 37)
  // and not on the Bandai dance, whose turns the projection takes up better itself (33 against 66:
  // the held-back turn tilts a stance sole 19 deg there).
  Attempt result = solve(o.hold_turns);
  bool turns_held = result.turn_limited > 0;
  if (turns_held) {
    Attempt plain = solve(false);
    if (plain.frames_not_held + plain.velocity_after <= result.frames_not_held + result.velocity_after) {
      plain.turn_limited = result.turn_limited;
      result = std::move(plain);
      turns_held = false;
    }
  }
  motion.q = result.q;
  const int rounds = result.rounds, frames_not_held = result.frames_not_held, velocity_after = result.velocity_after;
  const double worst_position = result.worst_position, worst_angle = result.worst_angle, worst_floor = result.worst_floor;
  const refine::CorrectionReport& correction = result.correction;
  if (frames_not_held > 0)
    ctx.diagnostics.warn(where, format("refine: the stance soles or the floor could not be held on %d frames (worst %.1f mm, %.2f deg, "
                                       "%.1f mm below the floor): the legs cannot reach both anchors, a joint limit is in the way, or "
                                       "the motion is too fast to be followed smoothly",
                                       frames_not_held, 1e3 * worst_position, worst_angle * 180 / M_PI, 1e3 * worst_floor));
  if (velocity_after > 0)
    ctx.diagnostics.warn(where, format("refine: %d frames x joints still above their speed limit after %d rounds", velocity_after, rounds));

  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  ctx.statistics.set("stance-anchors", static_cast<double>(anchors.size()));
  ctx.statistics.set("rounds", rounds, "", "smooth + project");
  ctx.statistics.set("turn-limited-max", result.turn_limited * 180 / M_PI, "deg",
                     std::string("root turned back where a stance sole's heading left the hip yaw's range (hold_turns)") +
                         (turns_held ? "; kept" : result.turn_limited > 0 ? "; not kept: the rounds without it held as many frames" : ""));
  ctx.statistics.set("smoother-active-rows", result.active_rows, "", "position or speed limits met by the smoother (last round)");
  ctx.statistics.set("root-height-bound-rows", result.root_rows, "frames", "root height held at the legs' reach (last round)");
  ctx.statistics.set("smoother-downweighted", result.downweighted, "samples", "coordinates x frames treated as outliers (last round)");
  ctx.statistics.set("correction-iterations", correction.iterations, "",
                     format("Gauss-Newton over the clip, %d coordinates, %d cost evaluations (last round)", correction.coordinates,
                            correction.evaluations));
  ctx.statistics.set("projection-iterations-per-frame", static_cast<double>(result.projection_iterations) / T, "", "last round");
  ctx.statistics.set("fallback-frames", result.fallback_frames, "frames", "the smooth correction missed the rows: per-frame projection used (the kept round)");
  ctx.statistics.set("stance-error-max", worst_position, "m", "sole centre from its anchor, source rate");
  ctx.statistics.set("stance-angle-max", worst_angle * 180 / M_PI, "deg", "sole frame from its anchor");
  ctx.statistics.set("frames-stance-not-held", frames_not_held, "frames", "beyond 1 mm or 0.5 deg, or 1 mm below the floor");
  ctx.statistics.set("floor-violation-max", worst_floor, "m", "collision point below the floor (stance soles excluded)");
  ctx.statistics.set("jitter-before", jitter_before, "rad/s^3");
  ctx.statistics.set("jitter-after", joint_jitter(motion.q, fps), "rad/s^3");
  ctx.statistics.set("velocity-violations-before", velocity_before, "", "frames x joints");
  ctx.statistics.set("velocity-violations-after", velocity_after, "", "frames x joints");
  ctx.statistics.set("frames-per-second", T / std::max(total_s, 1e-9), "frames/s", "source frames, refine only");
  ctx.statistics.set("time-smooth", ms_smooth, "ms", "smoothing and the foot plan, all rounds");
  ctx.statistics.set("time-project", ms_project, "ms", "per-frame projection, all rounds");
  ctx.statistics.set("time-metric", ms_metric, "ms", "landmark metric, all rounds");
  ctx.statistics.set("time-correct", ms_correct, "ms", "smooth correction, all rounds");
  ctx.statistics.set("time-fallback", ms_fallback, "ms", "fallback and speed checks, all rounds");
}

}  // namespace rt
