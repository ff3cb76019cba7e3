#include "retarget/sim/violation_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "retarget/balance/support_polygon.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"

namespace rt {

namespace {

constexpr double kGravity = 9.81;
const Vec2 kNaN2(std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN());

// Joint groups for the tracking-error traces: 0 legs, 1 torso (everything not a leg or an arm),
// 2 arms; by the usual naming of humanoid joints.
int joint_group(const std::string& name) {
  const std::string n = to_lower(name);
  for (const char* leg : {"hip", "knee", "ankle", "leg", "thigh", "shank", "foot", "crus"})
    if (n.find(leg) != std::string::npos) return 0;
  for (const char* arm : {"shoulder", "elbow", "wrist", "hand", "arm", "finger", "thumb", "index", "little"})
    if (n.find(arm) != std::string::npos) return 2;
  return 1;
}

std::vector<int> tracking_contact_feet(const std::array<bool, 2>& contact) {
  std::vector<int> feet;
  for (int f = 0; f < 2; ++f)
    if (contact[static_cast<std::size_t>(f)]) feet.push_back(f);
  return feet;
}

struct ForceCheck {
  bool any = false, pulling = false, sliding = false, cop_outside = false;
  double worst_friction_ratio = 0;
  std::array<Vec3, 2> force_W{{Vec3::Zero(), Vec3::Zero()}};
};

// Whether the commanded contact wrenches (force; moment at the sole centre, per foot in `feet`) can
// be produced by a rigid flat floor with friction coefficient mu under the sole rectangles.
ForceCheck check_wrenches(const RobotModel& model, const TrackingCommand& cmd, const std::vector<int>& feet,
                          const std::array<Iso3, 2>& X_W_sole, double mu) {
  ForceCheck c;
  for (std::size_t i = 0; i < feet.size(); ++i) {
    const auto f = static_cast<std::size_t>(feet[i]);
    const Vec6 w = cmd.f_contact.segment<6>(static_cast<Eigen::Index>(6 * i));
    c.any = true;
    c.force_W[f] = w.head<3>();
    // Tolerance: the QP puts wrenches exactly on these limits (f_z = 0 for a foot about to lift).
    constexpr double kTolN = 1e-3;
    const double fz = w[2];
    if (fz < -kTolN) c.pulling = true;
    if (fz <= kTolN) continue;
    const double ft = w.head<2>().norm();
    c.worst_friction_ratio = std::max(c.worst_friction_ratio, ft / (mu * fz));
    if (ft > mu * fz + kTolN) c.sliding = true;
    // Centre of pressure of this foot relative to its sole centre: n_x = d_y f_z, n_y = −d_x f_z.
    const Vec3 d_W(-w[4] / fz, w[3] / fz, 0);
    const Vec3 d_S = flat_on_floor(X_W_sole[f]).linear().transpose() * d_W;
    const Sole& sole = model.soles()[f];
    if (std::abs(d_S.x()) > 0.5 * sole.size_m.x() + 1e-6 || std::abs(d_S.y()) > 0.5 * sole.size_m.y() + 1e-6)
      c.cop_outside = true;
  }
  return c;
}

}  // namespace

ViolationMonitor::ViolationMonitor(const RobotModel& model, const DynamicsCheckOptions& o,
                                   const std::array<std::vector<std::uint8_t>, 2>& contacts, double fps)
    : model_(&model),
      o_(&o),
      fps_(fps),
      not_achieved_{ViolationTracker(ViolationKind::ContactNotAchieved, "N", o.contact_tolerance_s),
                    ViolationTracker(ViolationKind::ContactNotAchieved, "N", o.contact_tolerance_s)},
      no_lift_off_{ViolationTracker(ViolationKind::LiftOffNotAchieved, "N", o.contact_tolerance_s),
                   ViolationTracker(ViolationKind::LiftOffNotAchieved, "N", o.contact_tolerance_s)},
      slip_{ViolationTracker(ViolationKind::FootSlip, "m/s", o.min_violation_s),
            ViolationTracker(ViolationKind::FootSlip, "m/s", o.min_violation_s)},
      moved_{ViolationTracker(ViolationKind::StanceFootMoved, "m", o.min_violation_s),
             ViolationTracker(ViolationKind::StanceFootMoved, "m", o.min_violation_s)},
      cop_edge_(ViolationKind::CopNearEdge, "m", o.min_violation_s),
      saturation_(ViolationKind::TorqueSaturation, "ratio", o.min_violation_s),
      limit_(ViolationKind::JointLimit, "rad", o.min_violation_s) {
  const double weight_n = model.total_mass_kg() * kGravity;
  load_threshold_n_ = o.contact_force_fraction * weight_n;
  touch_threshold_n_ = o.touch_force_fraction * weight_n;
  friction_ = o.floor_friction > 0 ? o.floor_friction : model.config().simulation.friction;
  com_fall_z_ = o.fall_com_fraction * model.standing_com_height_m();
  // A phase is a run of equal labels; the clip's first and last runs are cut by its ends, so they
  // keep the full tolerance (a short run there is not a short step).
  for (std::size_t f = 0; f < 2; ++f) {
    const std::vector<std::uint8_t>& c = contacts[f];
    std::vector<double>& tol = contact_tolerance_s_[f];
    tol.assign(c.size(), o.contact_tolerance_s);
    for (std::size_t a = 0; a < c.size();) {
      std::size_t b = a;
      while (b < c.size() && c[b] == c[a]) ++b;
      if (a > 0 && b < c.size())
        std::fill(tol.begin() + static_cast<std::ptrdiff_t>(a), tol.begin() + static_cast<std::ptrdiff_t>(b),
                  std::min(o.contact_tolerance_s, o.contact_tolerance_fraction * static_cast<double>(b - a) / fps));
      a = b;
    }
  }
  const int nu = model.nu();
  group_.resize(static_cast<std::size_t>(nu));
  for (int i = 0; i < nu; ++i)
    group_[static_cast<std::size_t>(i)] =
        joint_group(model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(i)])].name);
}

FootStates ViolationMonitor::foot_states(const ContactState& contacts, const RobotData& data) const {
  FootStates s;
  for (int f = 0; f < 2; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    s.loaded[fi] = contacts.feet[fi].normal_force_n > load_threshold_n_;
    // On the floor: pressing on it, or resting on it with (almost) no load. The second matters when
    // the reference itself shifts nearly all the weight onto the other foot before a lift.
    s.sole_z_m[fi] = lowest_sole_corner_z(*model_, data, f);
    s.on_floor[fi] = contacts.feet[fi].normal_force_n > touch_threshold_n_ || s.sole_z_m[fi] < o_->on_floor_gap_m;
  }
  return s;
}

std::string ViolationMonitor::fall_reason(const VecX& q, const Vec3& com, const ContactState& contacts, bool unstable) const {
  std::string fall;
  if (!contacts.non_sole_links.empty())
    fall = "link '" + model_->links()[static_cast<std::size_t>(contacts.non_sole_links.front())].name + "' touched the floor";
  else if (com.z() < com_fall_z_)
    fall = format("COM height %.3f m below %.3f m", com.z(), com_fall_z_);
  else {
    const Quat root(q[3], q[4], q[5], q[6]);
    const double tilt = std::acos(std::clamp((root * Vec3::UnitZ()).z(), -1.0, 1.0));
    if (tilt > o_->fall_tilt_rad) fall = format("trunk tilted %.1f deg", tilt * 180 / M_PI);
  }
  if (unstable) fall = "the simulation became numerically unstable";
  return fall;
}

void ViolationMonitor::observe(const ControlInput& in, const ControlOutput& ctl) {
  const RobotModel& model = *model_;
  const DynamicsCheckOptions& o = *o_;
  const RobotData& data = *in.data;
  const VecX& q = *in.q;
  const VecX& v = *in.v;
  const ContactState& contacts = *in.contacts;
  const FootStates& feet = *in.feet;
  const ReferenceSample& r = ctl.reference;
  const TrackingReference& tr = ctl.tracking;
  const TrackingCommand& cmd = ctl.command;
  const double t_clip = in.t_clip_s;
  const Vec3& com = in.com_W;
  const Vec2& p_des = tr.desired_cop_W;
  const int nu = model.nu();
  std::vector<Violation>& out = result_.violations;
  static const char* const foot_name[2] = {"left foot", "right foot"};

  ++clip_ticks_;
  // Feasibility of the commanded wrenches (f = (force; moment) at each sole centre).
  std::array<Vec3, 2> f_cmd{{Vec3::Zero(), Vec3::Zero()}};
  {
    const ForceCheck fc = check_wrenches(model, cmd, tracking_contact_feet(tr.contact), tr.X_W_sole, friction_);
    DynamicsCheckResult::ForceFeasibility& ff = result_.force_feasibility;
    if (!cmd.closed_form_feasible) ++ff.closed_form_infeasible;
    ff.max_qp_iterations = std::max(ff.max_qp_iterations, cmd.qp_iterations);
    if (cmd.qp_status != QpStatus::Solved) ++ff.qp_failures;
    if (fc.any) {
      ++ff.cycles;
      ff.pulling += fc.pulling;
      ff.sliding += fc.sliding;
      ff.cop_outside += fc.cop_outside;
      ff.worst_friction_ratio = std::max(ff.worst_friction_ratio, fc.worst_friction_ratio);
    }
    f_cmd = fc.force_W;
  }
  Vec2 cop_cmd = kNaN2;
  {
    // COP of the commanded wrenches: horizontal moment about the floor point p vanishes.
    Vec3 F = Vec3::Zero(), N = Vec3::Zero();
    const std::vector<int> contact_feet = tracking_contact_feet(tr.contact);
    for (std::size_t i = 0; i < contact_feet.size(); ++i) {
      const Vec6 w = cmd.f_contact.segment<6>(static_cast<Eigen::Index>(6 * i));
      const Sole& sole = model.soles()[static_cast<std::size_t>(contact_feet[i])];
      const Vec3 p = link_pose(model, data, sole.link) * sole.p_L_center;
      F += w.head<3>();
      N += p.cross(w.head<3>()) + w.tail<3>();
    }
    if (F.z() > 1e-6) cop_cmd = Vec2(-N.y() / F.z(), N.x() / F.z());
  }
  const bool touching = contacts.normal_force_n > 1e-6;
  std::array<double, 2> foot_speed{};
  const VecX dq = r.q.tail(nu) - q.tail(nu);
  joint_sq_ += dq.squaredNorm();
  joint_n_ += nu;
  // Against the reference motion's own COM (trunk-mapped): a re-planned COM reference may be spiky
  // by design (paper eq. 31), the controller's COM is not.
  const Vec2 com_err = com.head<2>() - ctl.com_ref_original_W;
  com_sq_ += com_err.squaredNorm();
  result_.com_max_error_m = std::max(result_.com_max_error_m, com_err.norm());
  if (touching) {
    cop_sq_ += (contacts.cop_W - p_des).squaredNorm();
    ++cop_n_;
  }
  std::vector<Vec2> support_pts;
  for (int f = 0; f < 2; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    const Sole& sole = model.soles()[fi];
    const double fn = contacts.feet[fi].normal_force_n;
    if (!contact_tolerance_s_[fi].empty()) {
      const auto k = static_cast<std::size_t>(
          std::clamp<long>(std::lround(in.t_ref_s * fps_), 0L, static_cast<long>(contact_tolerance_s_[fi].size()) - 1));
      not_achieved_[fi].set_min_duration(contact_tolerance_s_[fi][k]);
      no_lift_off_[fi].set_min_duration(contact_tolerance_s_[fi][k]);
    }
    // Detail strings are only built while a condition holds (this runs every control cycle).
    const bool unmet = r.contact[fi] && !feet.on_floor[fi];
    not_achieved_[fi].update(t_clip, unmet, fn,
                             unmet ? format("%s %.0f mm above the floor, carries %.0f N", foot_name[f], feet.sole_z_m[fi] * 1e3, fn) : "",
                             out);
    const bool stuck = !r.contact[fi] && feet.loaded[fi];
    no_lift_off_[fi].update(t_clip, stuck, fn, stuck ? format("%s still carries %.0f N", foot_name[f], fn) : "", out);
    // The sole's fastest point over the floor: a foot that spins on the spot (yaw slip on a fast
    // pivot) slides at its toe and heel while its centre stays put.
    const Eigen::Matrix<double, 6, 1> twist = link_jacobian(model, data, sole.link, sole.p_L_center) * v;
    const Vec3 v_centre = twist.head<3>(), omega = twist.tail<3>();
    const Iso3 X = link_pose(model, data, sole.link);
    const std::array<Vec3, 4> corners_L = sole.corners_L();
    double speed = v_centre.head<2>().norm();
    for (const Vec3& c : corners_L) speed = std::max(speed, (v_centre + omega.cross(X.linear() * (c - sole.p_L_center))).head<2>().norm());
    foot_speed[fi] = speed;
    const bool sliding = r.contact[fi] && feet.loaded[fi] && speed > o.slip_speed_mps;
    slip_[fi].update(t_clip, sliding, speed,
                     sliding ? format("%s sole slides at %.3f m/s (fastest corner; centre %.3f m/s, turning %.2f rad/s)", foot_name[f],
                                      speed, v_centre.head<2>().norm(), std::abs(omega.z()))
                             : "",
                     out);
    // How far the stance foot has moved over the floor from where it was planted (its first loaded
    // instant in this reference stance): the horizontal displacement of its sole centre, i.e. of
    // the footstep. A turn about the centre is reported with it (and as foot-slip while it spins).
    if (!r.contact[fi]) planted_[fi].reset();
    double moved = 0;
    if (r.contact[fi] && feet.loaded[fi]) {
      if (!planted_[fi]) planted_[fi] = X;
      moved = ((X * sole.p_L_center) - (*planted_[fi] * sole.p_L_center)).head<2>().norm();
    }
    const bool moved_off = moved > o.max_stance_foot_travel_m;
    std::string moved_detail;
    if (moved_off) {
      const Vec3 heading = X.linear().col(0), heading0 = planted_[fi]->linear().col(0);
      const double turn = std::atan2(heading0.x() * heading.y() - heading0.y() * heading.x(), heading0.head<2>().dot(heading.head<2>()));
      moved_detail = format("%s sole centre %.0f mm from where it was planted, turned %.0f deg", foot_name[f], moved * 1e3,
                            std::abs(turn) * 180 / M_PI);
    }
    moved_[fi].update(t_clip, moved_off, moved, moved_detail, out);
    if (feet.loaded[fi])
      for (const Vec3& c : corners_L) support_pts.push_back((X * c).head<2>());
  }
  const SupportPolygon support = SupportPolygon::convex_hull(support_pts);
  if (touching && !support.empty()) {
    const double sd = support.signed_distance(contacts.cop_W);
    const bool near = sd > -o.cop_margin_m;
    cop_edge_.update(t_clip, near, sd,
                     near ? format("COP %.3f m %s the support polygon's edge", std::abs(sd), sd > 0 ? "outside" : "inside") : "",
                     out);
  } else {
    cop_edge_.update(t_clip, false, 0, "", out);
  }
  double worst_ratio = 0;
  int worst_joint = -1;
  double worst_limit = -INFINITY;
  int limit_joint = -1;
  for (int i = 0; i < nu; ++i) {
    const double eff = model.effort_limits()[i];
    if (eff > 0 && std::abs(cmd.tau_raw[i]) / eff > worst_ratio) {
      worst_ratio = std::abs(cmd.tau_raw[i]) / eff;
      worst_joint = i;
    }
    const double over = std::max(q[7 + i] - (model.q_upper()[i] - o.joint_limit_margin_rad),
                                 (model.q_lower()[i] + o.joint_limit_margin_rad) - q[7 + i]);
    if (over > worst_limit) {
      worst_limit = over;
      limit_joint = i;
    }
  }
  auto joint_name = [&](int i) {
    return model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(i)])].name;
  };
  if (cmd.saturated_joints > 0) ++result_.saturated_control_cycles;
  const bool saturated = cmd.saturated_joints > 0;
  saturation_.update(t_clip, saturated, worst_ratio,
                     saturated ? format("%s at %.2fx its effort limit", joint_name(worst_joint).c_str(), worst_ratio) : "", out);
  const bool at_limit = worst_limit > 0;
  limit_.update(t_clip, at_limit, worst_limit + o.joint_limit_margin_rad,
                at_limit ? joint_name(limit_joint) + " at its position limit" : "", out);

  if (t_clip + 1e-12 >= next_record_) {
    next_record_ += o.record_period_s;
    DynamicsTrace& tr_out = result_.trace;
    tr_out.t_s.push_back(t_clip);
    tr_out.com_W.push_back(com);
    tr_out.com_ref_W.push_back(ctl.com_ref_W);
    tr_out.com_ref_original_W.push_back(ctl.com_ref_original_W);
    tr_out.cop_W.push_back(touching ? contacts.cop_W : kNaN2);
    tr_out.cop_desired_W.push_back(p_des);
    if (support.empty()) {
      tr_out.support_min_W.push_back(kNaN2);
      tr_out.support_max_W.push_back(kNaN2);
    } else {
      Vec2 lo = support.vertices().front(), hi = lo;
      for (const Vec2& p : support.vertices()) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      tr_out.support_min_W.push_back(lo);
      tr_out.support_max_W.push_back(hi);
    }
    tr_out.contact_ref.push_back(r.contact);
    tr_out.contact_actual.push_back(feet.loaded);
    tr_out.foot_force_n.push_back({contacts.feet[0].normal_force_n, contacts.feet[1].normal_force_n});
    tr_out.foot_force_cmd_W.push_back(f_cmd);
    tr_out.foot_force_W.push_back({contacts.feet[0].force_W, contacts.feet[1].force_W});
    tr_out.cop_commanded_W.push_back(cop_cmd);
    tr_out.foot_speed_mps.push_back(foot_speed);
    std::array<double, 4> sq{}, n{};
    for (int i = 0; i < nu; ++i) {
      const auto g = static_cast<std::size_t>(group_[static_cast<std::size_t>(i)]);
      sq[g] += dq[i] * dq[i];
      n[g] += 1;
      sq[3] += dq[i] * dq[i];
      n[3] += 1;
    }
    std::array<double, 4> rms{};
    for (std::size_t g = 0; g < 4; ++g) rms[g] = n[g] > 0 ? std::sqrt(sq[g] / n[g]) : 0;
    tr_out.tracking_error_rad.push_back(rms);
  }
}

void ViolationMonitor::finish(double t_end, DynamicsCheckResult& res) {
  std::vector<Violation>& out = result_.violations;
  for (auto* t : {&not_achieved_[0], &not_achieved_[1], &no_lift_off_[0], &no_lift_off_[1], &slip_[0], &slip_[1],
                  &moved_[0], &moved_[1]})
    t->finish(t_end, out);
  for (auto* t : {&cop_edge_, &saturation_, &limit_}) t->finish(t_end, out);
  std::sort(out.begin(), out.end(), [](const Violation& a, const Violation& b) { return a.start_s < b.start_s; });
  res.violations = std::move(out);
  res.trace = std::move(result_.trace);
  res.force_feasibility = result_.force_feasibility;
  res.saturated_control_cycles = result_.saturated_control_cycles;
  res.com_max_error_m = result_.com_max_error_m;
  res.joint_rms_error_rad = joint_n_ ? std::sqrt(joint_sq_ / joint_n_) : 0;
  res.com_rms_error_m = clip_ticks_ ? std::sqrt(com_sq_ / clip_ticks_) : 0;
  res.cop_rms_error_m = cop_n_ ? std::sqrt(cop_sq_ / cop_n_) : 0;
}

}  // namespace rt
