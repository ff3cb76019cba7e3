#include "retarget/ik/single_support_reach.hpp"

#include <algorithm>
#include <vector>

#include "retarget/core/strings.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {

namespace {

// Horizontal distance of p from the sole rectangle (sole frame S in W); 0 inside.
double outside_rectangle(const Iso3& X_W_S, const Vec2& size_m, const Vec3& p_W) {
  const Vec3 p_S = X_W_S.inverse() * p_W;
  const double dx = std::max(0.0, std::abs(p_S.x()) - 0.5 * size_m.x());
  const double dy = std::max(0.0, std::abs(p_S.y()) - 0.5 * size_m.y());
  return std::hypot(dx, dy);
}

}  // namespace

std::array<SingleSupportReach, 2> single_support_reach(const RobotModel& model, const SingleSupportReachOptions& o) {
  IkOptions ik_options;
  ik_options.max_iterations = std::max(1, o.iterations_per_step);
  ik_options.step_tolerance = 1e-7;
  ik_options.cost_tolerance = 1e-9;
  ik_options.regularization = 1e-4;
  const LandmarkIk ik(model, ik_options);
  RobotData data(model);
  const VecX q0 = model.standing_q();
  update_kinematics(model, data, q0);
  const Vec3 com0 = com_position(model, data);
  std::array<Iso3, 2> X_W_link, X_W_S;
  for (std::size_t k = 0; k < 2; ++k) {
    const Sole& s = model.soles()[k];
    X_W_link[k] = link_pose(model, data, s.link);
    X_W_S[k] = X_W_link[k];
    X_W_S[k].linear() = X_W_link[k].linear() * s.R_L_S;
    X_W_S[k].translation() = X_W_link[k] * s.p_L_center;
  }

  std::array<SingleSupportReach, 2> out;
  for (std::size_t held = 0; held < 2; ++held) {
    const std::size_t other = 1 - held;
    std::vector<IkTarget> targets(2);
    for (std::size_t k : {held, other}) {
      IkTarget& t = targets[k == held ? 0 : 1];
      const Sole& s = model.soles()[k];
      t.link = s.link;
      t.p_L = s.p_L_center;
      t.p_W = X_W_S[k].translation();
      t.R_W = Quat(X_W_link[k].linear());
      t.R_L_frame = Mat3::Identity();
    }
    targets[0].weight = targets[0].orientation_weight = 1e4;  // held: fixed in place
    targets[1].p_W.z() += o.lift_m;
    targets[1].weight = o.free_sole_weight;
    targets[1].orientation_weight = 0;
    SingleSupportReach& r = out[held];
    r.q = q0;
    const Vec2 goal = X_W_S[held].translation().head<2>();
    const int steps = std::max(1, o.continuation_steps);
    for (int i = 1; i <= steps; ++i) {
      IkComTarget com;
      com.weight = 1;
      com.horizontal_only = true;
      const double a = static_cast<double>(i) / steps;
      com.p_W << (1 - a) * com0.head<2>() + a * goal, com0.z();
      const VecX anchor = r.q;
      ik.solve(data, targets, anchor, r.q, com);
    }
    update_kinematics(model, data, r.q);
    r.com_W = com_position(model, data);
    r.com_to_centre_m = (r.com_W.head<2>() - goal).norm();
    r.standing_com_to_centre_m = (com0.head<2>() - goal).norm();
    r.com_outside_sole_m = outside_rectangle(X_W_S[held], model.soles()[held].size_m, r.com_W);
  }
  return out;
}

std::string describe_reach(const SingleSupportReach& r, double tolerance_m) {
  if (r.com_outside_sole_m <= tolerance_m) return format("reached (%.1f cm from its centre)", 100 * r.com_to_centre_m);
  return format("stops %.1f cm outside it", 100 * r.com_outside_sole_m);
}

Diagnostics check_single_support(const RobotModel& model, const std::array<SingleSupportReach, 2>& reach,
                                 double tolerance_m) {
  Diagnostics out;
  const char* side[2] = {"left", "right"};
  for (std::size_t f = 0; f < 2; ++f) {
    const SingleSupportReach& r = reach[f];
    if (r.com_outside_sole_m <= tolerance_m) continue;
    out.warn(model.config().where(std::string("feet.") + side[f]),
             format("the COM cannot be brought over the %s sole with the other foot lifted: it stops %.1f cm outside it "
                    "(%.1f cm from its centre, %.1f cm at the standing pose) within the joint limits; this robot cannot "
                    "stand on its %s foot, so foot lifts and slow steps will fail the check",
                    side[f], 100 * r.com_outside_sole_m, 100 * r.com_to_centre_m, 100 * r.standing_com_to_centre_m, side[f]));
  }
  return out;
}

}  // namespace rt
