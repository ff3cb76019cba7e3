#pragma once
/// The joint torques a motion asks of the joints with no foot below them (waist, arms, head), by
/// inverse dynamics of its own frames (issue 15).
///
/// For such a joint the torque depends only on the motion of the bodies it carries, not on how the
/// floor pushes the feet: with the frames' velocities and accelerations from central differences at
/// the motion's rate, MuJoCo's mj_inverse (URDF masses and inertias, the robot's armature) gives it
/// exactly. A ratio |τ| / effort limit above 1 is a frame that no controller can track as it is:
/// the joint saturates and the body it carries lags (the dynamics check reports
/// `torque-saturation` there). Leg joints are left out: their torque depends on the contact forces.

#include <string>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {

class RobotModel;

struct TorqueDemand {
  /// Per movable joint (model order): the largest |τ| / effort limit over the frames and its time
  /// [s]; 0 for the joints left out (a foot below them, or no effort limit).
  std::vector<double> joint_max_ratio, joint_max_time_s;
  std::vector<bool> judged;    ///< per movable joint: no foot below it and an effort limit
  double max_ratio = 0;        ///< over the judged joints
  int max_joint = -1;          ///< movable-joint index of the largest, -1 when none
  double max_time_s = 0;
  int frames_over = 0;         ///< frames where a judged joint is above its effort limit
  int frames = 0;              ///< frames judged: all but the first and last
  /// Per frame (T): the largest ratio over the judged joints and its joint (0 and -1 at the ends).
  std::vector<double> frame_max_ratio;
  std::vector<int> frame_max_joint;
};

/// Per movable joint: whether a sole link hangs below it.
std::vector<bool> joints_carrying_a_foot(const RobotModel& model);

/// The demand of the motion q (nq x T) at `fps` [Hz]. Updates `data`.
TorqueDemand torque_demand(const RobotModel& model, RobotData& data, const MatX& q, double fps);

}  // namespace rt
