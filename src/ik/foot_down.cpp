#include "retarget/ik/foot_down.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/joint_groups.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"

namespace rt {

IkTarget sole_pose_target(const RobotModel& model, int foot, const Iso3& X_W_sole, const Mat3& R_L_sole) {
  const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
  IkTarget t;
  t.link = sole.link;
  t.p_L = sole.p_L_center;
  t.p_W = X_W_sole.translation();
  t.weight = 1e4;
  t.R_L_frame = R_L_sole;
  t.R_W = Quat(X_W_sole.linear());
  t.orientation_weight = 1e3;
  return t;
}

double sole_corner_miss(const RobotModel& model, const RobotData& data, int foot, const Mat3& R_L_sole, const Iso3& X_W_sole) {
  const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
  const auto got = sole_corners_W(sole_frame_W(model, data, foot, R_L_sole), sole);
  const auto want = sole_corners_W(X_W_sole, sole);
  double worst = 0;
  for (std::size_t c = 0; c < 4; ++c) worst = std::max(worst, (got[c] - want[c]).norm());
  return worst;
}

IkOptions sole_ik_options(bool root_height_free) {
  IkOptions io;
  io.root_free = {false, false, root_height_free, false, false, false};
  io.max_iterations = 100;
  io.step_tolerance = 1e-9;
  io.cost_tolerance = 1e-12;
  io.regularization = 1e-6;
  return io;
}

FootDown put_foot_down(const RobotModel& model, RobotData& data, const VecX& q0, int foot,
                       const std::array<Mat3, 2>& R_L_sole, double max_corner_miss_m) {
  FootDown out;
  out.q = q0;
  update_kinematics(model, data, q0);
  // Both soles as IK targets: the stance one where it is, the airborne one flat on the floor below
  // its pose.
  std::vector<IkTarget> targets(2);
  std::array<Iso3, 2> X_target;
  for (int f = 0; f < 2; ++f) {
    Iso3 X = sole_frame_W(model, data, f, R_L_sole[static_cast<std::size_t>(f)]);
    if (f == foot) {
      out.foot_height_m = lowest_sole_corner_z(model, data, f) - lowest_sole_corner_z(model, data, 1 - f);
      X = flat_on_floor(X);
      X.translation().z() = lowest_sole_corner_z(model, data, 1 - f);
    }
    X_target[static_cast<std::size_t>(f)] = X;
    targets[static_cast<std::size_t>(f)] = sole_pose_target(model, f, X, R_L_sole[static_cast<std::size_t>(f)]);
  }
  // How far the soles' corners end up from their targets' corners.
  const auto corner_miss = [&](const VecX& q) {
    update_kinematics(model, data, q);
    return std::max(sole_corner_miss(model, data, 0, R_L_sole[0], X_target[0]), sole_corner_miss(model, data, 1, R_L_sole[1], X_target[1]));
  };
  IkOptions io = sole_ik_options(false);
  VecX q_down = q0;
  LandmarkIk(model, io).solve(data, targets, q0, q_down);
  double miss = corner_miss(q_down);
  if (miss > max_corner_miss_m) {
    io = sole_ik_options(true);
    // The legs start a tenth of the way to the middle of their joints' ranges: a straight stance
    // knee is where the root's height does not change with the knee to first order, and the
    // solver would not leave it.
    VecX q_start = q0;
    const std::vector<JointGroup> groups = joint_groups(model);
    for (int i = 0; i < model.nu(); ++i)
      if (groups[static_cast<std::size_t>(i)] == JointGroup::Legs && std::isfinite(model.q_lower()[i]) &&
          std::isfinite(model.q_upper()[i]))
        q_start[7 + i] += 0.1 * (0.5 * (model.q_lower()[i] + model.q_upper()[i]) - q0[7 + i]);
    VecX q_lowered = q_start;
    LandmarkIk(model, io).solve(data, targets, q_start, q_lowered);
    const double miss_lowered = corner_miss(q_lowered);
    if (miss_lowered < miss) {
      q_down = q_lowered;
      miss = miss_lowered;
    }
  }
  out.q = q_down;
  out.corner_miss_m = miss;
  out.reached = miss <= max_corner_miss_m;
  out.root_drop_m = q0[2] - q_down[2];
  return out;
}

}  // namespace rt
