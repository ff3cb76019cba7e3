#include "retarget/sim/walking_controller.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "retarget/balance/support_polygon.hpp"
#include "retarget/balance/zmp_plan.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"
#include "retarget/sim/contact_trunk_map.hpp"
#include "retarget/sim/dynamics_check.hpp"

namespace rt {

namespace {

constexpr double kGravity = 9.81;
constexpr double kInf = std::numeric_limits<double>::infinity();

double wrap_pi(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// The transform part way (s in [0, 1]) from `a` to `b`: every parameter of eq. (22)–(24)
// interpolated, so the mapped reference moves continuously instead of jumping.
TrunkTransform blend(const TrunkTransform& a, const TrunkTransform& b, double s) {
  if (s >= 1) return b;
  if (s <= 0) return a;
  // Both written about b's reference centre, so that the translation part interpolates linearly:
  // apply(p) = c_act + Ω S'(p − c_ref); a about b.c_ref has c_act' = a.apply(b.c_ref).
  TrunkTransform out = b;
  out.c_act_W = (1 - s) * a.apply_position(b.c_ref_W) + s * b.c_act_W;
  out.yaw_rad = a.yaw_rad + s * wrap_pi(b.yaw_rad - a.yaw_rad);
  out.theta_ref_rad = a.theta_ref_rad + s * wrap_pi(b.theta_ref_rad - a.theta_ref_rad);
  out.scale = (1 - s) * a.scale + s * b.scale;
  return out;
}

std::array<Mat3, 2> sole_frames(const RobotModel& model) {
  RobotData data(model);
  return sole_frames_in_links(model, data);
}

// Column-wise linear interpolation of a grid of spacing `period` at time t, clamped to its ends.
Vec2 grid_at(const Eigen::Matrix2Xd& m, double period, double t) {
  const int K = static_cast<int>(m.cols());
  const double s = std::clamp(t / period, 0.0, static_cast<double>(K - 1));
  const int i = std::min(static_cast<int>(s), K - 1), j = std::min(i + 1, K - 1);
  return (1 - (s - i)) * m.col(i) + (s - i) * m.col(j);
}

TrackingOptions walking_tracking_options(const DynamicsCheckOptions& o) {
  TrackingOptions t = o.tracking;
  t.weights.vertical_force = o.walking.vertical_force_weight;
  t.foot_kp = o.walking.foot_kp;
  t.foot_kd = o.walking.foot_kd;
  t.contact.friction_margin = o.walking.friction_margin;
  return t;
}

Vec2 clamp_to_box(const Vec2& v, double box) { return v.cwiseMax(Vec2::Constant(-box)).cwiseMin(Vec2::Constant(box)); }

}  // namespace

WalkingController::WalkingController(const RobotModel& model, const ReferenceSignal& signal, const DynamicsCheckOptions& o)
    : model_(&model), signal_(&signal), o_(&o), w_(&o.walking), tracking_(model, walking_tracking_options(o)), R_L_sole_(sole_frames(model)) {
  RobotData data(model);
  BalancePlanOptions po = w_->plan;
  po.lead_in_s = o.settle_s;  // the settle phase is the plan's standing lead-in
  po.ankle_reach = w_->ankle_reach;
  reach_ = w_->ankle_reach ? ankle_reach(model, model.total_mass_kg() * kGravity) : whole_soles(model);
  plan_ = plan_reference_balance(model, data, signal, po);
  plan_delta_ = Eigen::Matrix2Xd::Zero(2, plan_.size());
  weight_n_ = model.total_mass_kg() * kGravity;
  prev_contact_ = signal.contact_at(0);
}

TrunkTransform WalkingController::current_map(double t_sim) const {
  if (w_->trunk_blend_s <= 0) return map_to_;
  return blend(map_from_, map_to_, (t_sim - blend_start_s_) / w_->trunk_blend_s);
}

std::pair<int, int> WalkingController::contact_run(int foot, int k) const {
  const auto& c = signal_->contacts()[static_cast<std::size_t>(foot)];
  const int T = static_cast<int>(c.size());
  const std::uint8_t v = c[static_cast<std::size_t>(k)];
  int a = k, b = k;
  while (a > 0 && c[static_cast<std::size_t>(a - 1)] == v) --a;
  while (b + 1 < T && c[static_cast<std::size_t>(b + 1)] == v) ++b;
  return {a, b};
}

double WalkingController::max_normal_force(int foot, double t_ref) const {
  if (w_->force_ramp_s <= 0) return kInf;
  const int T = signal_->num_frames();
  const double fps = signal_->fps();
  const int k = std::clamp(static_cast<int>(std::lround(t_ref * fps)), 0, T - 1);
  const auto [a, b] = contact_run(foot, k);
  // Time since the reference touchdown (none when the contact runs from the clip's start) and until
  // its lift-off (none when it runs to the end), each half a frame from the labelled frames.
  const double since = a == 0 ? kInf : t_ref - (a - 0.5) / fps;
  const double until = b == T - 1 ? kInf : (b + 0.5) / fps - t_ref;
  const double s = std::min(since, until) / w_->force_ramp_s;
  // A small floor keeps the QP away from the degenerate f_z = 0 = f_max.
  return s >= 1 ? kInf : std::max(0.02, s) * weight_n_;
}

Vec2 WalkingController::planned_com(double t, const TrunkTransform& map) const {
  const Vec2 c = plan_.com(t) + grid_at(plan_delta_, plan_.period_s, t - plan_.start_s);
  return map.apply_position(Vec3(c.x(), c.y(), 0)).head<2>();
}

Vec2 WalkingController::planned_com_velocity(double t, const TrunkTransform& map) const {
  const double h = plan_.period_s;
  const double u = t - plan_.start_s;
  Vec2 dv = Vec2::Zero();
  if (u >= 0 && u <= (plan_.size() - 1) * h) dv = (grid_at(plan_delta_, h, u + 0.5 * h) - grid_at(plan_delta_, h, u - 0.5 * h)) / h;
  return map.linear().topLeftCorner<2, 2>() * (plan_.com_velocity(t) + dv);
}

Vec2 WalkingController::planned_zmp(double t, const TrunkTransform& map) const {
  // The correction's own cart-table term: δ − h δ̈.
  const double h = plan_.period_s;
  const double gain = plan_.com_height(t) / kGravity;
  const double u = t - plan_.start_s;
  const Vec2 d0 = grid_at(plan_delta_, h, u);
  const Vec2 d = d0 - gain * (grid_at(plan_delta_, h, u + h) - 2 * d0 + grid_at(plan_delta_, h, u - h)) / (h * h);
  const Vec2 p = plan_.zmp(t) + d;
  return map.apply_position(Vec3(p.x(), p.y(), 0)).head<2>();
}

void WalkingController::control(const ControlInput& in, ControlOutput& out) {
  const RobotModel& model = *model_;
  const ReferenceSignal& signal = *signal_;
  const DynamicsCheckOptions& o = *o_;
  const WalkingControllerOptions& w = *w_;
  RobotData& data = *in.data;
  const ContactState& contacts = *in.contacts;
  const std::array<bool, 2>& loaded = in.feet->loaded;
  const double t_sim = in.t_sim_s, t_ref = in.t_ref_s;
  const bool settling = in.settling;
  const bool holding = in.t_signal_s < 0;  // the settle phase: the signal's first frame held still
  const Vec3& com = in.com_W;
  ++cycles_;

  // --- trunk mapping on new contacts, blended in ------------------------------------------------
  const std::array<bool, 2> contact_now = signal.contact_at(t_ref);
  if (contact_now != prev_contact_) contact_change_pending_ = true;
  prev_contact_ = contact_now;
  if (o.trunk_mapping && contact_change_pending_ && (contact_now[0] || contact_now[1])) {
    if (contact_feet_pushing(contact_now, contacts, w.trunk.force_threshold_n)) {
      map_from_ = current_map(t_sim);
      map_to_ = trunk_transform_at_contacts(model, data, signal.at(t_ref, TrunkTransform{}), contact_now, w.trunk);
      blend_start_s_ = t_sim;
      contact_change_pending_ = false;
      ++trunk_mapping_updates_;
    }
  }
  const TrunkTransform map = current_map(t_sim);
  ReferenceSample& r = out.reference;
  r = signal.at(t_ref, map);
  if (holding) hold_still(r);

  // --- balance: DCM tracking of the plan (its lead-in covers the settle phase) -------------------
  const double t_plan = std::max(in.t_signal_s, plan_.start_s);
  const double z_c = std::max(plan_.com_height(t_plan), 0.05);
  const double omega = std::sqrt(kGravity / z_c);
  const MatX J_com = com_jacobian(model, data);
  const Vec2 c = com.head<2>();
  const Vec2 c_dot = (J_com.topRows(2) * *in.v);
  const Vec2 xi = c + c_dot / omega;
  if (w.replan && o.dynamic_mapping && !settling && t_sim + 1e-12 >= next_replan_s_) {
    next_replan_s_ = t_sim + w.replan_period_s;
    maybe_replan(in, map, xi, omega);
  }
  const Vec2 c_p = planned_com(t_plan, map);
  const Vec2 xi_p = c_p + planned_com_velocity(t_plan, map) / omega;
  const Vec2 e = xi - xi_p;
  if (!settling) max_dcm_error_m_ = std::max(max_dcm_error_m_, e.norm());
  Vec2 p_des = planned_zmp(t_plan, map) + (1 + w.dcm_gain / omega) * e;
  // The support of the feet that are actually loaded (and meant to be down); a foot about to land
  // counts once it is loaded.
  std::vector<Vec2> corners;
  for (int f = 0; f < 2; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (!(loaded[fi] && contact_now[fi])) continue;
    for (const Vec3& q : reach_corners_W(sole_frame_W(model, data, f, R_L_sole_[fi]), reach_[fi])) corners.push_back(q.head<2>());
  }
  const SupportPolygon support = SupportPolygon::convex_hull(std::move(corners));
  bool clamped = false;
  if (!support.empty()) {
    const double sd = support.signed_distance(p_des);
    if (sd > -w.cop_clamp_margin_m) {
      // The closest point of the polygon shrunk by the margin (capped for small polygons).
      const Vec2 centre = support.centroid();
      const Vec2 edge = support.closest_boundary_point(p_des);
      const double inset = std::min(w.cop_clamp_margin_m, 0.5 * std::max(0.0, -support.signed_distance(centre)));
      const Vec2 towards = (centre - edge).norm() > 1e-9 ? Vec2((centre - edge).normalized()) : Vec2::Zero();
      p_des = edge + inset * towards;
      clamped = true;
    }
  }
  clamped_cycles_ += clamped && !settling;
  const Vec2 offset = map.linear().topLeftCorner<2, 2>() * plan_.offset(t_plan);
  const Vec2 c_ddot = omega * omega * (c - p_des + offset);
  out.com_ref_W = c_p;
  out.com_ref_original_W = signal.com_at(t_ref, map).head<2>();

  // --- foothold adjustment ----------------------------------------------------------------------
  const double fps = signal.fps();
  const int T = signal.num_frames();
  const int k_now = std::clamp(static_cast<int>(std::lround(t_ref * fps)), 0, T - 1);
  for (int f = 0; f < 2; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (contact_now[fi]) continue;
    const int b = contact_run(f, k_now).second;
    if (b + 1 >= T) continue;  // no touchdown ahead
    const double t_td = (b + 0.5) / fps;
    const double remaining = t_td - t_ref;
    if (!(w.foothold_adjustment && !settling && clamped && e.norm() > w.foothold_threshold_m && remaining > 0.05)) continue;
    // Where the error would be at touchdown with the COP held at the support's edge: it grows with ω
    // (looked ahead at most 0.5 s; clamped to the box per axis).
    const Vec2 target = clamp_to_box(e * std::exp(omega * std::min(remaining, 0.5)), w.foothold_box_m);
    // Moved towards the target at a bounded rate, so the swing foot's reference stays smooth.
    const double max_step = 0.5 * o.control_period_s;  // 0.5 m/s
    Vec2 step = target - foothold_offset_[fi];
    if (step.norm() > max_step) step *= max_step / step.norm();
    foothold_offset_[fi] += step;
    max_foothold_change_m_ = std::max(max_foothold_change_m_, foothold_offset_[fi].norm());
    ++foothold_adjustments_;
  }

  // --- feet --------------------------------------------------------------------------------------
  TrackingReference& tr = out.tracking;
  tr.q = r.q;
  tr.v = r.v;
  tr.a = r.a;
  tr.contact = r.contact;
  tr.desired_cop_W = p_des;
  // Trunk relative to the COM the balance controller steers (as the paper controller's
  // root_follows_com): the reference's trunk-to-COM offset placed at the measured COM, accelerated
  // as the commanded COP accelerates the COM.
  {
    const Eigen::Matrix<double, 5, 2> cm = signal.com_motion_at(in.t_signal_s, map);
    tr.q.head<2>() += c - cm.row(0).transpose();
    tr.v.head<2>() += c_dot - cm.row(1).transpose();
    tr.a.head<2>() += c_ddot - cm.row(2).transpose();
  }
  {
    // COM height: the reference's, differentiated over a frame either side (held still while
    // holding the first frame).
    const double h = 1.0 / signal.fps(), ts = std::max(in.t_signal_s, 0.0);
    const double z_ref = signal.com_at(ts, map).z();
    double zd_ref = 0, zdd_ref = 0;
    if (!holding) {
      const double z_prev = signal.com_at(ts - h, map).z(), z_next = signal.com_at(ts + h, map).z();
      zd_ref = (z_next - z_prev) / (2 * h);
      zdd_ref = (z_next - 2 * z_ref + z_prev) / (h * h);
    }
    const double zd = J_com.row(2).dot(*in.v);
    const double zdd = zdd_ref + w.com_height_kd * (zd_ref - zd) + w.com_height_kp * (z_ref - com.z());
    tr.desired_vertical_force_n = std::max(0.0, model.total_mass_kg() * (kGravity + zdd));
  }
  for (int f = 0; f < 2; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    tr.max_normal_force_n[fi] = holding ? kInf : max_normal_force(f, t_ref);
    // Early touchdown: a swing foot that lands (carries load) shortly before its reference touchdown
    // is a stance foot from then on, held where it landed, instead of being dragged on along its
    // swing while the floor pushes back.
    if (!r.contact[fi] && loaded[fi] && !holding) {
      const auto run = contact_run(f, k_now);
      if (run.second + 1 < T && (run.second + 0.5) / fps - t_ref < w.early_touchdown_s) {
        tr.contact[fi] = true;
        tr.max_normal_force_n[fi] = kInf;
        ++early_touchdown_cycles_;
      }
    }
    if (tr.contact[fi]) {
      if (loaded[fi]) {
        const Iso3 X = sole_frame_W(model, data, f, R_L_sole_[fi]);
        tr.X_W_sole[fi] = X;
        if (!stance_pose_[fi]) stance_pose_[fi] = flat_on_floor(X);
      } else {
        Iso3 X = flat_on_floor(r.X_W_sole[fi]);
        X.translation().head<2>() += foothold_offset_[fi];
        tr.X_W_sole[fi] = stance_pose_[fi] ? *stance_pose_[fi] : X;
      }
      tr.v_sole[fi].setZero();
      tr.a_sole[fi].setZero();
    } else {
      stance_pose_[fi].reset();
      tr.X_W_sole[fi] = r.X_W_sole[fi];
      tr.X_W_sole[fi].translation().head<2>() += foothold_offset_[fi];
      tr.v_sole[fi] = r.v_sole[fi];
      tr.a_sole[fi] = r.a_sole[fi];
    }
    // A new swing starts from the reference again.
    if (r.contact[fi] && loaded[fi]) foothold_offset_[fi].setZero();
  }

  tracking_.build(data, *in.q, *in.v, tr, problem_, workspace_, /*data_is_current=*/true);
  tracking_.solve(problem_, out.command, workspace_);
}

void WalkingController::maybe_replan(const ControlInput& in, const TrunkTransform& map, const Vec2& xi, double omega) {
  const auto start = std::chrono::steady_clock::now();
  const ReferenceSignal& signal = *signal_;
  const WalkingControllerOptions& w = *w_;
  // The window lies on the plan's grid: the feed-forward ZMP is the second difference of the plan
  // on that grid, which a coarser window interpolated linearly would turn into spikes.
  const double dt = plan_.period_s;
  const double t0 = plan_.start_s + std::ceil((in.t_ref_s - plan_.start_s) / dt - 1e-9) * dt;
  const int M = std::max(3, static_cast<int>(std::lround(w.replan_horizon_s / dt)));
  const double fps = signal.fps();
  const int T = signal.num_frames();
  const int k_now = std::clamp(static_cast<int>(std::lround(t0 * fps)), 0, T - 1);
  const Vec2 e = xi - (planned_com(t0, map) + planned_com_velocity(t0, map) / omega);

  // Predicted support at window sample j: stance feet that stay down where they are, the others
  // where the mapped reference (plus the foothold change) puts them.
  auto support_at = [&](double t) {
    const int k = std::clamp(static_cast<int>(std::lround(t * fps)), 0, T - 1);
    std::vector<Vec2> corners;
    for (int f = 0; f < 2; ++f) {
      const auto fi = static_cast<std::size_t>(f);
      if (!signal.contacts()[fi][static_cast<std::size_t>(k)]) continue;
      const auto run = contact_run(f, k_now);
      const bool same_stance = signal.contacts()[fi][static_cast<std::size_t>(k_now)] && k <= run.second && stance_pose_[fi];
      Iso3 X;
      if (same_stance) {
        X = *stance_pose_[fi];
      } else {
        const Iso3& X_ref = signal.soles_W()[fi][static_cast<std::size_t>(k)];
        Iso3 X_mapped = Iso3::Identity();
        X_mapped.translation() = map.apply_position(X_ref.translation());
        X_mapped.linear() = map.Omega() * X_ref.linear();
        X = flat_on_floor(X_mapped);
        X.translation().head<2>() += foothold_offset_[fi];
      }
      for (const Vec3& c : reach_corners_W(X, reach_[fi])) corners.push_back(c.head<2>());
    }
    return SupportPolygon::convex_hull(std::move(corners));
  };
  // Does the error, decaying under the DCM loop, keep the COP inside? Only a prediction clearly
  // outside (by more than the clamp margin) counts: a plan whose own ZMP runs along an edge is not
  // a reason to re-plan.
  if (e.norm() < w.replan_error_m) return;
  bool needed = false;
  double worst = 0;  // how far the predicted COP leaves the support
  std::vector<SupportPolygon> polygons(static_cast<std::size_t>(M + 1));
  for (int j = 0; j <= M; ++j) {
    const double t = t0 + j * dt;
    polygons[static_cast<std::size_t>(j)] = support_at(t);
    const SupportPolygon& s = polygons[static_cast<std::size_t>(j)];
    if (s.empty()) continue;
    const Vec2 p = planned_zmp(t, map) + (1 + w.dcm_gain / omega) * std::exp(-w.dcm_gain * j * dt) * e;
    const double sd = s.signed_distance(p);
    if (sd > w.cop_clamp_margin_m) needed = true;
    worst = std::max(worst, sd);
  }
  if (!needed) return;

  // Window QP from the measured state: the first two samples pinned to the measured COM and its
  // velocity, the rest pulled to the plan, ZMP inside each sample's polygon.
  const Vec2 c = in.com_W.head<2>();
  const Vec2 c_dot = omega * (xi - c);
  std::vector<ZmpPlanSample> samples(static_cast<std::size_t>(M + 1));
  for (int j = 0; j <= M; ++j) {
    ZmpPlanSample& s = samples[static_cast<std::size_t>(j)];
    const double t = t0 + j * dt;
    s.com_ref_W = planned_com(t, map);
    s.zmp_gain_s2 = plan_.com_height(t) / kGravity;
    s.zmp_offset_W = map.linear().topLeftCorner<2, 2>() * plan_.offset(t);
    s.support = polygons[static_cast<std::size_t>(j)].half_planes(w.cop_clamp_margin_m);
    if (!polygons[static_cast<std::size_t>(j)].empty()) s.zmp_centre_W = polygons[static_cast<std::size_t>(j)].centroid();
  }
  samples[0].com_ref_W = c;
  // Pinned far above the ZMP penalty (1e6): the measured state is a fact, not a wish.
  constexpr double kPin = 1e10;
  samples[0].com_weight_scale = kPin;
  samples[1].com_ref_W = c + c_dot * dt;
  samples[1].com_weight_scale = kPin;
  // ... and rejoining the plan at the window's end with its velocity.
  samples[static_cast<std::size_t>(M - 1)].com_weight_scale = kPin;
  samples[static_cast<std::size_t>(M)].com_weight_scale = kPin;
  ZmpPlanOptions po = w.plan.plan;
  po.period_s = dt;
  po.zmp_centre_weight = w.replan_zmp_centre_weight;
  po.rest_at_start = false;
  po.rest_at_end = false;
  const ZmpPlan z = plan_com_zmp(samples, po);
  // Kept only when its COP stays inside every window sample's support: a window that leaves it is a
  // feed-forward ZMP off the feet, worse than the clamped DCM loop alone.
  if (z.com_W.cols() != M + 1) return;
  if (z.max_violation_m > w.replan_max_violation_m || z.max_violation_m >= worst) {
    ++replans_rejected_;
    return;
  }
  replan_max_violation_m_ = std::max(replan_max_violation_m_, z.max_violation_m);
  // The change, back in unmapped coordinates on the plan grid. It starts a few samples before now
  // (extrapolated), so that the finite differences of the feed-forward ZMP never straddle the old
  // and the new plan.
  const Mat2 L_inv = map.linear().topLeftCorner<2, 2>().inverse();
  const double h = plan_.period_s;
  const Vec2 d0 = z.com_W.col(0) - planned_com(t0, map), d1 = z.com_W.col(1) - planned_com(t0 + dt, map);
  for (int k = 0; k < plan_.size(); ++k) {
    const double t = plan_.start_s + k * h;
    if (t < t0 - 3 * h || t > t0 + M * dt) continue;
    Vec2 change;
    if (t < t0) {
      change = d0 + (t - t0) / dt * (d1 - d0);
    } else {
      const double s = (t - t0) / dt;
      const int j = std::min(static_cast<int>(s), M - 1);
      const double a = s - j;
      change = (1 - a) * z.com_W.col(j) + a * z.com_W.col(j + 1) - planned_com(t, map);
    }
    plan_delta_.col(k) += L_inv * change;
  }
  ++replan_count_;
  planner_wall_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void WalkingController::finish(DynamicsCheckResult& res) const {
  res.trunk_mapping_updates = trunk_mapping_updates_;
  res.planner_wall_s = planner_wall_s_;
  DynamicsCheckResult::WalkingStats& s = res.walking;
  s.used = true;
  s.plan_max_shift_m = plan_.max_shift_m;
  s.plan_rms_shift_m = plan_.rms_shift_m;
  s.plan_max_shift_time_s = plan_.max_shift_time_s;
  s.plan_max_violation_m = plan_.max_violation_m;
  s.replans = replan_count_;
  s.replans_rejected = replans_rejected_;
  s.replan_max_violation_m = replan_max_violation_m_;
  s.foothold_adjustments = foothold_adjustments_;
  s.max_foothold_change_m = max_foothold_change_m_;
  s.cop_clamped_fraction = cycles_ ? static_cast<double>(clamped_cycles_) / cycles_ : 0;
  s.max_dcm_error_m = max_dcm_error_m_;
  s.early_touchdown_cycles = early_touchdown_cycles_;
}

}  // namespace rt
