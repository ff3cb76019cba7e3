#include "retarget/sim/dynamics_check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "retarget/core/strings.hpp"
#include "retarget/model/joint_groups.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/sim/lead_in.hpp"
#include "retarget/sim/paper_controller.hpp"
#include "retarget/sim/plant.hpp"
#include "retarget/sim/reference_consistency.hpp"
#include "retarget/sim/reference_signal.hpp"
#include "retarget/sim/violation_monitor.hpp"
#include "retarget/sim/walking_controller.hpp"

namespace rt {

DynamicsCheckOptions default_check_options(const RobotModel& model) {
  DynamicsCheckOptions o;
  const ControllerConfig& c = model.config().controller;
  o.tracking.kp = c.kp;
  o.tracking.kd = c.kd;
  o.tracking.root_kp = c.kp;
  o.tracking.root_kd = c.kd;
  o.tracking.foot_kp = c.kp;
  o.tracking.foot_kd = c.kd;
  if (c.foot_gains.kp > 0) {
    o.walking.foot_kp = c.foot_gains.kp;
    o.walking.foot_kd = c.foot_gains.kd;
  }
  if (!c.joint_gains.empty() || !c.group_gains.empty()) {
    o.tracking.kp_joint = VecX::Constant(model.nu(), c.kp);
    o.tracking.kd_joint = VecX::Constant(model.nu(), c.kd);
    const std::vector<JointGroup> groups = joint_groups(model);
    for (int i = 0; i < model.nu(); ++i) {
      const auto it = c.group_gains.find(joint_group_name(groups[static_cast<std::size_t>(i)]));
      if (it == c.group_gains.end()) continue;
      o.tracking.kp_joint[i] = it->second.kp;
      o.tracking.kd_joint[i] = it->second.kd;
    }
    for (const auto& [name, gains] : c.joint_gains) {
      const int j = model.joint_index(name);
      const int i = model.joints()[static_cast<std::size_t>(j)].qpos_index - 7;
      if (i < 0) continue;
      o.tracking.kp_joint[i] = gains.kp;
      o.tracking.kd_joint[i] = gains.kd;
    }
  }
  return o;
}

const char* check_controller_name(CheckControllerKind kind) {
  switch (kind) {
    case CheckControllerKind::Walking: return "walking";
    case CheckControllerKind::Paper: return "paper";
  }
  return "?";
}

DynamicsCheckResult run_dynamics_check(const RobotModel& model, const Reference& reference, const DynamicsCheckOptions& o) {
  const auto wall0 = std::chrono::steady_clock::now();
  RobotData ref_data(model), ctrl_data(model);
  // The walking controller starts a clip that begins mid-step from a standing lead-in.
  LeadIn lead_in;
  if (o.controller == CheckControllerKind::Walking)
    lead_in = standing_lead_in(model, reference, o.walking.lead_in);
  else
    lead_in.reference = reference;
  const ReferenceSignal signal(model, ref_data, lead_in.reference, o.com_smoothing_s);
  const double lead_s = lead_in.duration_s;
  const double clip_duration = signal.duration_s() - lead_s;
  Plant plant(model, PlantOptions{o.mass_scale, o.floor_friction});
  const double dt_sim = model.config().simulation.timestep_s;
  const int substeps = std::max(1, static_cast<int>(std::lround(o.control_period_s / dt_sim)));

  DynamicsCheckResult res;
  res.clip_duration_s = clip_duration;

  // Start: the first reference frame, lowered or raised so the lowest sole corner touches the floor.
  VecX q0 = signal.at(0, TrunkTransform{}).q;
  update_kinematics(model, ctrl_data, q0);
  q0[2] -= std::min(lowest_sole_corner_z(model, ctrl_data, 0), lowest_sole_corner_z(model, ctrl_data, 1));
  plant.reset(q0, VecX::Zero(model.nv()));
  update_kinematics(model, ctrl_data, q0);
  const Vec2 start_com = com_position(model, ctrl_data).head<2>();

  std::unique_ptr<CheckController> controller;
  if (o.controller == CheckControllerKind::Paper)
    controller = std::make_unique<PaperController>(model, signal, o, start_com);
  else
    controller = std::make_unique<WalkingController>(model, signal, o);
  ViolationMonitor monitor(model, o, signal.contacts(), signal.fps());
  for (Violation& v : stance_off_floor(signal, lead_s, o.stance_height_tolerance_m)) monitor.violations().push_back(std::move(v));
  for (Violation& v : reference_joint_speed(model, signal, lead_s)) monitor.violations().push_back(std::move(v));
  for (Violation& v : reference_torque_demand(model, ref_data, signal, lead_s)) monitor.violations().push_back(std::move(v));
  if (o.controller == CheckControllerKind::Walking) {
    const BalancePlan& plan = static_cast<const WalkingController&>(*controller).plan();
    res.walking.lead_in_s = lead_s;
    res.walking.lead_in_foot = lead_in.foot;
    res.walking.lead_in_foot_height_m = lead_in.foot_height_m;
    res.walking.lead_in_root_drop_m = lead_in.root_drop_m;
    res.walking.lead_in_skipped = lead_in.skipped;
    const double t_shift = std::max(0.0, plan.max_shift_time_s - lead_s);
    if (plan.max_shift_m > o.walking.plan.max_shift_m)
      monitor.violations().push_back({ViolationKind::HeavyCorrection, t_shift, t_shift, plan.max_shift_m, "m",
                                      format("the balance plan moved the COM by %.3f m (RMS %.3f m) to keep the ZMP in the support; "
                                             "bound %.3f m",
                                             plan.max_shift_m, plan.rms_shift_m, o.walking.plan.max_shift_m)});
  }

  ControlInput in;
  ControlOutput out;
  for (long tick = 0;; ++tick) {
    const auto cycle_start = std::chrono::steady_clock::now();
    const double t_sim = plant.time_s();
    const double t_signal = t_sim - o.settle_s;
    const double t_clip = t_signal - lead_s;
    if (t_clip > clip_duration + 1e-9) break;
    if (o.progress && tick % std::max(1L, std::lround(0.1 / o.control_period_s)) == 0)  // every 0.1 s of clip time
      o.progress(std::clamp(t_clip, 0.0, clip_duration), clip_duration);
    const VecX q = plant.q(), v = plant.v();
    const ContactState contacts = plant.contacts();
    // The controller's own data for the measured state: MuJoCo's position and velocity stages of
    // the step about to be taken compute exactly what update_dynamics(q, v) would (when the plant
    // simulates the nominal model).
    plant.begin_step();
    if (plant.nominal())
      assign_dynamics(model, ctrl_data, *plant.mj());
    else
      update_dynamics(model, ctrl_data, q, v);
    const Vec3 com = com_position(model, ctrl_data);

    const std::string fall = monitor.fall_reason(q, com, contacts, plant.unstable());
    if (!fall.empty()) {
      res.fell = true;
      res.fall_time_s = std::max(t_clip, 0.0);
      monitor.violations().push_back({ViolationKind::Fall, res.fall_time_s, res.fall_time_s, 1.0, "",
                                      fall + (t_clip < 0 ? " (while settling on the first frame)" : "")});
      break;
    }
    const FootStates feet = monitor.foot_states(contacts, ctrl_data);
    in.t_sim_s = t_sim;
    in.t_clip_s = t_clip;
    in.t_signal_s = t_signal;
    in.t_ref_s = std::clamp(t_signal, 0.0, signal.duration_s());
    in.settling = t_clip < 0;
    in.q = &q;
    in.v = &v;
    in.contacts = &contacts;
    in.feet = &feet;
    in.data = &ctrl_data;
    in.com_W = com;
    controller->control(in, out);
    if (!in.settling) monitor.observe(in, out);

    plant.step(out.command.tau, substeps);
    if (controller->planner_active()) {
      res.active_loop_wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - cycle_start).count();
      ++res.active_cycles;
    }
  }

  const double t_end = std::max(0.0, std::min(plant.time_s() - o.settle_s - lead_s, clip_duration));
  monitor.finish(t_end, res);
  explain_fall(res.violations);
  controller->finish(res);
  res.simulated_s = res.fell ? res.fall_time_s : clip_duration;
  res.passed = std::none_of(res.violations.begin(), res.violations.end(), [](const Violation& v) { return violation_fails_check(v.kind); });
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  res.real_time_factor = res.wall_s > 0 ? plant.time_s() / res.wall_s : 0;
  return res;
}

}  // namespace rt
