#include "retarget/model/standing_hold.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {

namespace {

double tilt_of(const mjData* d, int body) {
  // Root z axis = third column of the row-major xmat; its angle to world z.
  const double zz = d->xmat[9 * body + 8];
  return std::acos(std::clamp(zz, -1.0, 1.0));
}

}  // namespace

StandingHoldResult simulate_standing_hold(const RobotModel& model, const StandingHoldOptions& options) {
  const VecX q_ref = options.q_target.size() ? options.q_target : model.standing_q();
  RT_DEMAND(q_ref.size() == model.nq(), "q_target has the wrong size");
  const double kp = options.kp >= 0 ? options.kp : model.config().simulation.hold_kp;
  const double kd = options.kd >= 0 ? options.kd : model.config().simulation.hold_kd;

  const mjModel* m = model.mj();
  RobotData data(model);
  mjData* d = data.mj();
  mju_copy(d->qpos, q_ref.data(), m->nq);
  mju_zero(d->qvel, m->nv);
  mj_forward(m, d);

  const int root = model.root_body();
  StandingHoldResult r;
  r.initial_root_height_m = r.min_root_height_m = r.max_root_height_m = d->xpos[3 * root + 2];
  const Vec3 com0 = Eigen::Map<const Vec3>(d->subtree_com + 3 * root);
  r.initial_com_height_m = com0.z();

  // Per-joint gains: the configured ones, capped at half the explicit-integration stability limit
  // of the joint's own inertia (mass-matrix diagonal incl. armature): one gain pair that holds a
  // 60 kg robot's knees would make a 4 g finger joint oscillate at a 1 ms step.
  const int nu = model.nu();
  const double dt = m->opt.timestep;
  VecX kp_joint(nu), kd_joint(nu);
  for (int k = 0; k < nu; ++k) {
    const double inertia = d->qM[m->dof_Madr[6 + k]];
    kp_joint[k] = std::min(kp, 0.5 * inertia / (dt * dt));
    kd_joint[k] = std::min(kd, 0.5 * inertia / dt);
  }
  const int steps = static_cast<int>(std::ceil(options.duration_s / m->opt.timestep - 1e-9));
  for (int step = 0; step < steps; ++step) {
    for (int k = 0; k < nu; ++k)
      d->ctrl[k] = kp_joint[k] * (q_ref[7 + k] - d->qpos[7 + k]) - kd_joint[k] * d->qvel[6 + k];
    mj_step(m, d);
    ++r.steps;
    r.simulated_s = d->time;

    const double z = d->xpos[3 * root + 2];
    r.min_root_height_m = std::min(r.min_root_height_m, z);
    r.max_root_height_m = std::max(r.max_root_height_m, z);
    const double tilt = tilt_of(d, root);
    r.max_tilt_rad = std::max(r.max_tilt_rad, tilt);
    const Vec3 com = Eigen::Map<const Vec3>(d->subtree_com + 3 * root);
    r.max_com_drift_m = std::max(r.max_com_drift_m, (com - com0).head<2>().norm());

    if (d->warning[mjWARN_BADQACC].number > 0) {
      r.unstable = r.fell = true;
      r.failure = format("MuJoCo reported an unstable simulation (bad qacc) at t = %.3f s", d->time);
      break;
    }
    for (int c = 0; c < d->ncon && !r.fell; ++c) {
      const mjContact& con = d->contact[c];
      const int other = con.geom1 == model.floor_geom() ? con.geom2 : con.geom2 == model.floor_geom() ? con.geom1 : -1;
      if (other < 0 || model.sole_side(other) >= 0) continue;
      const int link = model.geom_link(other);
      r.fell = true;
      r.failure = format("link '%s' touched the floor at t = %.3f s",
                         link >= 0 ? model.links()[static_cast<std::size_t>(link)].name.c_str() : "?", d->time);
    }
    if (!r.fell && com.z() < options.min_com_height_fraction * r.initial_com_height_m) {
      r.fell = true;
      r.failure = format("COM dropped to %.3f m at t = %.3f s", com.z(), d->time);
    }
    if (!r.fell && tilt > options.max_tilt_rad) {
      r.fell = true;
      r.failure = format("root tilted %.1f deg at t = %.3f s", tilt * 180 / M_PI, d->time);
    }
    if (r.fell) break;
  }
  r.final_root_height_m = d->xpos[3 * root + 2];
  r.final_com_height_m = d->subtree_com[3 * root + 2];
  for (int k = 0; k < nu; ++k)
    r.final_max_joint_error = std::max(r.final_max_joint_error, std::abs(d->qpos[7 + k] - q_ref[7 + k]));
  return r;
}

}  // namespace rt
