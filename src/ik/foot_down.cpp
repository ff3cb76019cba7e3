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
    const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
    Iso3 X = sole_frame_W(model, data, f, R_L_sole[static_cast<std::size_t>(f)]);
    if (f == foot) {
      out.foot_height_m = lowest_sole_corner_z(model, data, f) - lowest_sole_corner_z(model, data, 1 - f);
      X = flat_on_floor(X);
      X.translation().z() = lowest_sole_corner_z(model, data, 1 - f);
    }
    X_target[static_cast<std::size_t>(f)] = X;
    IkTarget& t = targets[static_cast<std::size_t>(f)];
    t.link = sole.link;
    t.p_L = sole.p_L_center;
    t.p_W = X.translation();
    t.weight = 1e4;
    t.R_L_frame = R_L_sole[static_cast<std::size_t>(f)];
    t.R_W = Quat(X.linear());
    t.orientation_weight = 1e3;
  }
  // How far the soles' corners end up from their targets' corners.
  const auto corner_miss = [&](const VecX& q) {
    update_kinematics(model, data, q);
    double worst = 0;
    for (std::size_t f = 0; f < 2; ++f) {
      const Sole& sole = model.soles()[f];
      const auto got = sole_corners_W(sole_frame_W(model, data, static_cast<int>(f), R_L_sole[f]), sole);
      const auto want = sole_corners_W(X_target[f], sole);
      for (std::size_t c = 0; c < 4; ++c) worst = std::max(worst, (got[c] - want[c]).norm());
    }
    return worst;
  };
  IkOptions io;
  io.root_free = {false, false, false, false, false, false};
  io.max_iterations = 100;
  io.step_tolerance = 1e-9;
  io.cost_tolerance = 1e-12;
  io.regularization = 1e-6;
  VecX q_down = q0;
  LandmarkIk(model, io).solve(data, targets, q0, q_down);
  double miss = corner_miss(q_down);
  if (miss > max_corner_miss_m) {
    io.root_free[2] = true;
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
