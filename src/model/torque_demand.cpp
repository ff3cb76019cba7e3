#include "retarget/model/torque_demand.hpp"

#include <mujoco/mujoco.h>

#include <cmath>

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

std::vector<bool> joints_carrying_a_foot(const RobotModel& model) {
  std::vector<bool> out(static_cast<std::size_t>(model.nu()), false);
  for (const Sole& sole : model.soles())
    for (int l = sole.link; l >= 0;) {
      const int j = model.links()[static_cast<std::size_t>(l)].parent_joint;
      if (j < 0) break;
      const Joint& joint = model.joints()[static_cast<std::size_t>(j)];
      if (joint.dof_index >= 6) out[static_cast<std::size_t>(joint.dof_index - 6)] = true;
      l = joint.parent_link;
    }
  return out;
}

TorqueDemand torque_demand(const RobotModel& model, RobotData& data, const MatX& q, double fps) {
  const int nu = model.nu(), T = static_cast<int>(q.cols());
  TorqueDemand out;
  out.joint_max_ratio.assign(static_cast<std::size_t>(nu), 0.0);
  out.joint_max_time_s.assign(static_cast<std::size_t>(nu), 0.0);
  const std::vector<bool> foot = joints_carrying_a_foot(model);
  const VecX& effort = model.effort_limits();
  out.judged.assign(static_cast<std::size_t>(nu), false);
  out.frame_max_ratio.assign(static_cast<std::size_t>(std::max(T, 0)), 0.0);
  out.frame_max_joint.assign(static_cast<std::size_t>(std::max(T, 0)), -1);
  bool any = false;
  for (int i = 0; i < nu; ++i) {
    out.judged[static_cast<std::size_t>(i)] = !foot[static_cast<std::size_t>(i)] && effort[i] > 0;
    any = any || out.judged[static_cast<std::size_t>(i)];
  }
  if (!any || T < 3 || !(fps > 0)) return out;
  const mjModel* m = model.mj();
  mjData* d = data.mj();
  const double dt = 1.0 / fps;
  VecX v_prev = difference(model, q.col(0), q.col(1), dt);
  for (int f = 1; f + 1 < T; ++f) {
    const VecX v_next = difference(model, q.col(f), q.col(f + 1), dt);
    for (int k = 0; k < m->nq; ++k) d->qpos[k] = q(k, f);
    for (int k = 0; k < m->nv; ++k) {
      d->qvel[k] = 0.5 * (v_prev[k] + v_next[k]);
      d->qacc[k] = (v_next[k] - v_prev[k]) * fps;
    }
    mj_inverse(m, d);
    bool over = false;
    for (int i = 0; i < nu; ++i) {
      if (!out.judged[static_cast<std::size_t>(i)]) continue;
      const double ratio = std::abs(d->qfrc_inverse[6 + i]) / effort[i];
      over = over || ratio > 1;
      if (ratio > out.frame_max_ratio[static_cast<std::size_t>(f)]) {
        out.frame_max_ratio[static_cast<std::size_t>(f)] = ratio;
        out.frame_max_joint[static_cast<std::size_t>(f)] = i;
      }
      if (ratio > out.joint_max_ratio[static_cast<std::size_t>(i)]) {
        out.joint_max_ratio[static_cast<std::size_t>(i)] = ratio;
        out.joint_max_time_s[static_cast<std::size_t>(i)] = f * dt;
      }
      if (ratio > out.max_ratio) {
        out.max_ratio = ratio;
        out.max_joint = i;
        out.max_time_s = f * dt;
      }
    }
    out.frames_over += over;
    ++out.frames;
    v_prev = v_next;
  }
  return out;
}

}  // namespace rt
