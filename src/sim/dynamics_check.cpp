#include "retarget/sim/dynamics_check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "retarget/balance/support_polygon.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/sim/plant.hpp"
#include "retarget/sim/reference_signal.hpp"

namespace rt {

namespace {

constexpr double kGravity = 9.81;
const Vec2 kNaN2(std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN());

// Sole corners of a sole frame (x forward, z normal) at its centre.
std::array<Vec3, 4> sole_corners(const Iso3& X_W_sole, const Sole& sole) {
  const double hx = 0.5 * sole.size_m.x(), hy = 0.5 * sole.size_m.y();
  return {X_W_sole * Vec3(hx, hy, 0), X_W_sole * Vec3(-hx, hy, 0), X_W_sole * Vec3(-hx, -hy, 0),
          X_W_sole * Vec3(hx, -hy, 0)};
}

// The same sole frame projected flat onto the floor, keeping its heading.
Iso3 flat_on_floor(const Iso3& X) {
  const Vec3 x = X.linear().col(0);
  Iso3 out = Iso3::Identity();
  out.linear() = AngleAxis(std::atan2(x.y(), x.x()), Vec3::UnitZ()).toRotationMatrix();
  out.translation() = Vec3(X.translation().x(), X.translation().y(), 0.0);
  return out;
}

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

// Values memoised per integer key in [0, size): lookups are an index, and clear() is O(1) (each
// slot carries the generation that filled it).
template <class T>
class Memo {
 public:
  explicit Memo(std::size_t size) : slots_(size) {}
  std::size_t size() const { return slots_.size(); }
  void clear() { ++generation_; }
  /// The value for `key`, computed by make() on the first request since the last clear().
  template <class Make>
  const T& get(std::size_t key, const Make& make) {
    Slot& s = slots_[key];
    if (s.generation != generation_) {
      s.value = make();
      s.generation = generation_;
    }
    return s.value;
  }

 private:
  struct Slot {
    T value{};
    unsigned long generation = 0;
  };
  std::vector<Slot> slots_;
  unsigned long generation_ = 1;
};

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

DynamicsCheckOptions default_check_options(const RobotModel& model) {
  DynamicsCheckOptions o;
  const ControllerConfig& c = model.config().controller;
  o.tracking.kp = c.kp;
  o.tracking.kd = c.kd;
  o.tracking.root_kp = c.kp;
  o.tracking.root_kd = c.kd;
  o.tracking.foot_kp = c.kp;
  o.tracking.foot_kd = c.kd;
  if (!c.joint_gains.empty()) {
    o.tracking.kp_joint = VecX::Constant(model.nu(), c.kp);
    o.tracking.kd_joint = VecX::Constant(model.nu(), c.kd);
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

DynamicsCheckResult run_dynamics_check(const RobotModel& model, const Reference& reference, const DynamicsCheckOptions& o) {
  const auto wall0 = std::chrono::steady_clock::now();
  RobotData ref_data(model), ctrl_data(model);
  const ReferenceSignal signal(model, ref_data, reference, o.com_smoothing_s);
  Plant plant(model);
  const int nu = model.nu();
  const double dt_sim = model.config().simulation.timestep_s;
  const int substeps = std::max(1, static_cast<int>(std::lround(o.control_period_s / dt_sim)));
  const double dt_ctrl = substeps * dt_sim;
  const double weight_n = model.total_mass_kg() * kGravity;
  const double load_threshold_n = o.contact_force_fraction * weight_n;
  const double touch_threshold_n = o.touch_force_fraction * weight_n;
  const double friction = model.config().simulation.friction;

  BalanceOptions bo = o.balance;
  bo.control_period_s = dt_ctrl;
  const BalanceController balance(PendulumModel{model.standing_com_height_m(), kGravity}, bo);
  const TrackingController tracking(model, o.tracking);
  const ComReplanner planner(balance.closed_loop_model(o.replan.period_s), o.replan);
  const int N = o.replan.horizon;
  const double dt_plan = o.replan.period_s;
  const double omega_sq = balance.model().omega_sq();

  DynamicsCheckResult res;
  res.clip_duration_s = signal.duration_s();

  // Start: the first reference frame, lowered or raised so the lowest sole corner touches the floor.
  TrunkTransform map;
  VecX q0 = signal.at(0, map).q;
  update_kinematics(model, ctrl_data, q0);
  q0[2] -= std::min(lowest_sole_corner_z(model, ctrl_data, 0), lowest_sole_corner_z(model, ctrl_data, 1));
  plant.reset(q0, VecX::Zero(model.nv()));
  update_kinematics(model, ctrl_data, q0);
  BalanceState bstate = balance.rest_state(com_position(model, ctrl_data).head<2>());

  // COM reference: the (trunk-mapped) reference COM plus the re-planner's corrections, kept on the
  // planner's time grid (sim time, settle included).
  const double total_s = o.settle_s + signal.duration_s();
  const int K = static_cast<int>(std::ceil(total_s / dt_plan)) + N + 2;
  Eigen::Matrix2Xd com_delta = Eigen::Matrix2Xd::Zero(2, K);
  auto clip_time = [&](double t_sim) { return std::clamp(t_sim - o.settle_s, 0.0, signal.duration_s()); };
  auto original_com = [&](double t_sim) -> Vec2 { return signal.com_at(clip_time(t_sim), map).head<2>(); };
  // Balance reference of the original (trunk-mapped) reference COM motion, without re-planning.
  auto balance_reference = [&](double t_sim) -> BalanceReference {
    if (!o.balance_feedforward) return BalanceReference::at_rest(original_com(t_sim));
    return BalanceReference::from_com_motion(signal.com_motion_at(t_sim - o.settle_s, map), omega_sq);
  };
  // The reference COP over the planner's window, memoised per simulation step: consecutive planning
  // steps ask for mostly the same future times (on the simulation grid when the planner's period is
  // a multiple of the step), and it only changes when the trunk map does.
  const double plan_steps = dt_plan / dt_sim;
  const bool on_sim_grid = std::abs(plan_steps - std::round(plan_steps)) < 1e-9;
  Memo<Vec2> cop_ref_memo(on_sim_grid ? static_cast<std::size_t>(std::ceil((total_s + (N + 2) * dt_plan) / dt_sim)) + 2 : 0);
  auto reference_cop = [&](double t_sim) -> Vec2 {
    const auto make = [&] { return balance_reference(t_sim).cop(); };
    const long long key = std::llround(t_sim / dt_sim);
    if (key < 0 || key >= static_cast<long long>(cop_ref_memo.size())) return make();
    return cop_ref_memo.get(static_cast<std::size_t>(key), make);
  };
  auto delta_at = [&](double t_sim) -> Vec2 {
    const double s = std::clamp(t_sim / dt_plan, 0.0, static_cast<double>(K - 1));
    const int k = std::min(static_cast<int>(s), K - 2);
    const double w = s - k;
    return (1 - w) * com_delta.col(k) + w * com_delta.col(k + 1);
  };

  const double com_fall_z = o.fall_com_fraction * model.standing_com_height_m();
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, ref_data);
  std::array<std::optional<Iso3>, 2> stance_pose;
  std::array<bool, 2> prev_contact = signal.contact_at(0);
  bool contact_change_pending = false;

  std::vector<Violation>& out = res.violations;
  std::array<ViolationTracker, 2> not_achieved = {ViolationTracker(ViolationKind::ContactNotAchieved, "N", o.contact_tolerance_s),
                                                  ViolationTracker(ViolationKind::ContactNotAchieved, "N", o.contact_tolerance_s)};
  std::array<ViolationTracker, 2> no_lift_off = {ViolationTracker(ViolationKind::LiftOffNotAchieved, "N", o.contact_tolerance_s),
                                                 ViolationTracker(ViolationKind::LiftOffNotAchieved, "N", o.contact_tolerance_s)};
  std::array<ViolationTracker, 2> slip = {ViolationTracker(ViolationKind::FootSlip, "m/s", o.min_violation_s),
                                          ViolationTracker(ViolationKind::FootSlip, "m/s", o.min_violation_s)};
  ViolationTracker cop_edge(ViolationKind::CopNearEdge, "m", o.min_violation_s);
  ViolationTracker saturation(ViolationKind::TorqueSaturation, "ratio", o.min_violation_s);
  ViolationTracker limit(ViolationKind::JointLimit, "rad", o.min_violation_s);
  const char* foot_name[2] = {"left foot", "right foot"};

  std::vector<int> group(static_cast<std::size_t>(nu));
  for (int i = 0; i < nu; ++i)
    group[static_cast<std::size_t>(i)] = joint_group(model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(i)])].name);

  double joint_sq = 0, com_sq = 0, cop_sq = 0;
  long joint_n = 0, clip_ticks = 0, cop_n = 0;
  double next_record = 0, next_plan = 0;
  // Support per reference frame for the planner. It depends on the trunk map, which feet are loaded
  // and held, and the current reference frame; kept across planner ticks while none of them changes.
  Memo<SupportFrame> support_cache(static_cast<std::size_t>(signal.num_frames()));
  std::array<int, 7> support_inputs{};
  int stance_pose_changes = 0;
  Eigen::Matrix2Xd y_offset(2, N);            // reference COP over the planner's window
  TrackingProblem tproblem;                   // tracking controller storage, reused every cycle
  TrackingWorkspace tworkspace;
  TrackingCommand cmd;

  for (long tick = 0;; ++tick) {
    const auto cycle_start = std::chrono::steady_clock::now();
    const double t_sim = plant.time_s();
    const double t_clip = t_sim - o.settle_s;
    if (t_clip > signal.duration_s() + 1e-9) break;
    if (o.progress && tick % std::max(1L, std::lround(0.1 / o.control_period_s)) == 0)  // every 0.1 s of clip time
      o.progress(std::clamp(t_clip, 0.0, signal.duration_s()), signal.duration_s());
    const bool settling = t_clip < 0;
    const double t_ref = clip_time(t_sim);
    const VecX q = plant.q(), v = plant.v();
    const ContactState contacts = plant.contacts();
    // The controller's own data for the measured state: MuJoCo's position and velocity stages of
    // the step about to be taken compute exactly what update_dynamics(q, v) would.
    plant.begin_step();
    assign_dynamics(model, ctrl_data, *plant.mj());
    const Vec3 com = com_position(model, ctrl_data);

    // --- falls --------------------------------------------------------------------------------
    std::string fall;
    if (!contacts.non_sole_links.empty())
      fall = "link '" + model.links()[static_cast<std::size_t>(contacts.non_sole_links.front())].name + "' touched the floor";
    else if (com.z() < com_fall_z)
      fall = format("COM height %.3f m below %.3f m", com.z(), com_fall_z);
    else {
      const Quat root(q[3], q[4], q[5], q[6]);
      const double tilt = std::acos(std::clamp((root * Vec3::UnitZ()).z(), -1.0, 1.0));
      if (tilt > o.fall_tilt_rad) fall = format("trunk tilted %.1f deg", tilt * 180 / M_PI);
    }
    if (plant.unstable()) fall = "the simulation became numerically unstable";
    if (!fall.empty()) {
      res.fell = true;
      res.fall_time_s = std::max(t_clip, 0.0);
      out.push_back({ViolationKind::Fall, res.fall_time_s, res.fall_time_s, 1.0, "", fall + (settling ? " (while settling on the first frame)" : "")});
      break;
    }

    // --- reference, contact schedule, trunk mapping --------------------------------------------
    ReferenceSample r = signal.at(t_ref, map);
    if (settling) {
      r.v.setZero();
      r.a.setZero();
      for (auto& x : r.v_sole) x.setZero();
      for (auto& x : r.a_sole) x.setZero();
    }
    std::array<bool, 2> loaded{};
    for (int f = 0; f < 2; ++f) loaded[static_cast<std::size_t>(f)] = contacts.feet[static_cast<std::size_t>(f)].normal_force_n > load_threshold_n;
    // On the floor: pressing on it, or resting on it with (almost) no load. The second matters when
    // the reference itself shifts nearly all the weight onto the other foot before a lift.
    std::array<bool, 2> on_floor{};
    std::array<double, 2> sole_z{};
    for (int f = 0; f < 2; ++f) {
      const auto fi = static_cast<std::size_t>(f);
      sole_z[fi] = lowest_sole_corner_z(model, ctrl_data, f);
      on_floor[fi] = contacts.feet[fi].normal_force_n > touch_threshold_n || sole_z[fi] < o.on_floor_gap_m;
    }
    if (r.contact != prev_contact) contact_change_pending = true;
    prev_contact = r.contact;
    if (o.trunk_mapping && contact_change_pending && (r.contact[0] || r.contact[1])) {
      bool all_pushing = true;
      for (int f = 0; f < 2; ++f)
        if (r.contact[static_cast<std::size_t>(f)] && contacts.feet[static_cast<std::size_t>(f)].normal_force_n < o.trunk.force_threshold_n) all_pushing = false;
      if (all_pushing) {
        std::vector<Vec3> p_ref, p_act;
        const TrunkTransform identity;
        const ReferenceSample unmapped = signal.at(t_ref, identity);
        for (int f = 0; f < 2; ++f) {
          if (!r.contact[static_cast<std::size_t>(f)]) continue;
          const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
          const Iso3 X_link = link_pose(model, ctrl_data, sole.link);
          // Eq. (20)-(24) use only centres, principal axes and spreads: corner order is irrelevant.
          for (const Vec3& c : sole_corners(flat_on_floor(unmapped.X_W_sole[static_cast<std::size_t>(f)]), sole)) p_ref.push_back(c);
          for (const Vec3& c : sole.corners_L()) p_act.push_back(X_link * c);
        }
        map = compute_trunk_transform(p_ref, p_act, o.trunk);
        cop_ref_memo.clear();
        contact_change_pending = false;
        ++res.trunk_mapping_updates;
        r = signal.at(t_ref, map);
        if (settling) {
          r.v.setZero();
          r.a.setZero();
        }
      }
    }

    // --- online dynamic mapping (paper §VI) at the planner's period ------------------------------
    const auto planner_start = std::chrono::steady_clock::now();
    if (o.dynamic_mapping && t_sim + 1e-12 >= next_plan) {
      next_plan += dt_plan;
      const int k0 = std::min(static_cast<int>(std::lround(t_sim / dt_plan)), K - N - 1);
      // Eq. (25)-(27): with feed-forward in error coordinates (x0 = ŝ − s_ref, U = δ, plus the
      // reference COP), else the paper's (x0 = ŝ, U = c_ref + δ).
      Eigen::Matrix2Xd U(2, N);
      Mat42 x0 = bstate.s_hat;
      if (o.balance_feedforward) {
        x0 -= balance_reference(t_sim).s_ref;
        for (int j = 0; j < N; ++j) {
          U.col(j) = com_delta.col(k0 + j);
          y_offset.col(j) = reference_cop(t_sim + (j + 1) * dt_plan);
        }
      } else {
        for (int j = 0; j < N; ++j) U.col(j) = original_com(t_sim + j * dt_plan) + com_delta.col(k0 + j);
      }
      const std::array<bool, 2> contact_now = signal.contact_at(t_ref);
      const std::array<int, 7> inputs = {static_cast<int>(std::lround(t_ref * signal.fps())), loaded[0], loaded[1],
                                         contact_now[0], contact_now[1], stance_pose_changes, res.trunk_mapping_updates};
      if (inputs != support_inputs) {
        support_cache.clear();
        support_inputs = inputs;
      }
      // The support polygon of a reference frame, as the planner sees it now.
      const auto make_support = [&](int frame) {
        SupportFrame s;
        std::vector<Vec2> corners;
        for (int f = 0; f < 2; ++f) {
          s.contact[static_cast<std::size_t>(f)] = signal.contacts()[static_cast<std::size_t>(f)][static_cast<std::size_t>(frame)] != 0;
          const Sole& sole = model.soles()[static_cast<std::size_t>(f)];
          // A loaded foot that stays down until then is where it actually is; others where the
          // (mapped) reference puts them.
          const Iso3& X_ref = signal.soles_W()[static_cast<std::size_t>(f)][static_cast<std::size_t>(frame)];
          Iso3 X_mapped = Iso3::Identity();
          X_mapped.translation() = map.apply_position(X_ref.translation());
          X_mapped.linear() = map.Omega() * X_ref.linear();
          Iso3 X = flat_on_floor(X_mapped);
          if (loaded[static_cast<std::size_t>(f)] && stance_pose[static_cast<std::size_t>(f)] && contact_now[static_cast<std::size_t>(f)]) {
            bool stays = true;
            for (int g = static_cast<int>(std::lround(t_ref * signal.fps())); g <= frame && stays; ++g)
              stays = signal.contacts()[static_cast<std::size_t>(f)][static_cast<std::size_t>(std::min(g, signal.num_frames() - 1))] != 0;
            if (stays) X = *stance_pose[static_cast<std::size_t>(f)];
          }
          s.sole_center_W[static_cast<std::size_t>(f)] = X.translation().head<2>();
          if (s.contact[static_cast<std::size_t>(f)])
            for (const Vec3& c : sole_corners(X, sole)) corners.push_back(c.head<2>());
        }
        s.polygon = SupportPolygon::convex_hull(std::move(corners));
        return s;
      };
      const auto support = [&](int j) -> const SupportFrame& {
        const double tj = clip_time(t_sim + j * dt_plan);
        const int frame = std::clamp(static_cast<int>(std::lround(tj * signal.fps())), 0, signal.num_frames() - 1);
        return support_cache.get(static_cast<std::size_t>(frame), [&] { return make_support(frame); });
      };
      const Eigen::Matrix2Xd before = U;
      const auto event = planner.step(x0, U, support, o.balance_feedforward ? &y_offset : nullptr);
      if (event) {
        com_delta.middleCols(k0, N) += U - before;
        res.replans.push_back({std::max(t_clip, -o.settle_s), *event});
      }
      if (!res.replans.empty())
        res.planner_wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - planner_start).count();
    }

    // --- balance controller (eq. 1) -------------------------------------------------------------
    const Vec2 delta = delta_at(t_sim);
    const Vec2 c_ref = original_com(t_sim) + delta;
    const bool touching = contacts.normal_force_n > 1e-6;
    const Vec2 p_meas = touching ? contacts.cop_W : bstate.desired_cop();
    BalanceReference bref = balance_reference(t_sim);
    bref.add_com_offset(delta);
    const Vec2 p_des = balance.step(bstate, bref, com.head<2>(), p_meas);

    // --- feet: a loaded stance foot is held where it is (no position feedback: the floor, not the
    // controller, decides its height, and soft contact sinks it a little); a stance foot not yet
    // loaded is brought down onto the floor flat; swing feet follow the reference ------------------
    TrackingReference tr;
    tr.q = r.q;
    tr.v = r.v;
    tr.a = r.a;
    tr.contact = r.contact;
    tr.desired_cop_W = p_des;
    if (o.root_follows_com) {
      // Trunk reference relative to the COM the balance controller steers: original offset of the
      // trunk from the reference COM, placed at the estimated COM; its acceleration is the one the
      // desired COP gives the pendulum.
      const Eigen::Matrix<double, 5, 2> cm = signal.com_motion_at(t_clip, map);
      tr.q.head<2>() += bstate.com() - cm.row(0).transpose();
      tr.v.head<2>() += bstate.com_velocity() - cm.row(1).transpose();
      tr.a.head<2>() += omega_sq * (bstate.com() - p_des) - cm.row(2).transpose();
    }
    for (int f = 0; f < 2; ++f) {
      const auto fi = static_cast<std::size_t>(f);
      const Sole& sole = model.soles()[fi];
      if (r.contact[fi]) {
        if (loaded[fi]) {
          const Iso3 X_link = link_pose(model, ctrl_data, sole.link);
          Iso3 X = Iso3::Identity();
          X.translation() = X_link * sole.p_L_center;
          X.linear() = X_link.linear() * R_L_sole[fi];
          tr.X_W_sole[fi] = X;
          if (!stance_pose[fi]) {
            stance_pose[fi] = flat_on_floor(X);
            ++stance_pose_changes;
          }
        } else {
          tr.X_W_sole[fi] = stance_pose[fi] ? *stance_pose[fi] : flat_on_floor(r.X_W_sole[fi]);
        }
        tr.v_sole[fi].setZero();
        tr.a_sole[fi].setZero();
      } else {
        if (stance_pose[fi]) ++stance_pose_changes;
        stance_pose[fi].reset();
        tr.X_W_sole[fi] = r.X_W_sole[fi];
        tr.v_sole[fi] = r.v_sole[fi];
        tr.a_sole[fi] = r.a_sole[fi];
      }
    }

    // --- tracking controller (eq. 2-19) ---------------------------------------------------------
    tracking.build(ctrl_data, q, v, tr, tproblem, tworkspace, /*data_is_current=*/true);
    tracking.solve(tproblem, cmd, tworkspace);

    // --- monitors (clip time only) -------------------------------------------------------------
    if (!settling) {
      ++clip_ticks;
      // Feasibility of the commanded wrenches (f = (force; moment) at each sole centre).
      std::array<Vec3, 2> f_cmd{{Vec3::Zero(), Vec3::Zero()}};
      {
        ForceCheck fc = check_wrenches(model, cmd, tracking_contact_feet(tr.contact), tr.X_W_sole, friction);
        DynamicsCheckResult::ForceFeasibility& ff = res.force_feasibility;
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
        const std::vector<int> feet = tracking_contact_feet(tr.contact);
        for (std::size_t i = 0; i < feet.size(); ++i) {
          const Vec6 w = cmd.f_contact.segment<6>(static_cast<Eigen::Index>(6 * i));
          const Sole& sole = model.soles()[static_cast<std::size_t>(feet[i])];
          const Vec3 r = link_pose(model, ctrl_data, sole.link) * sole.p_L_center;
          F += w.head<3>();
          N += r.cross(w.head<3>()) + w.tail<3>();
        }
        if (F.z() > 1e-6) cop_cmd = Vec2(-N.y() / F.z(), N.x() / F.z());
      }
      std::array<double, 2> foot_speed{};
      const VecX dq = r.q.tail(nu) - q.tail(nu);
      joint_sq += dq.squaredNorm();
      joint_n += nu;
      // Against the reference motion's own COM (trunk-mapped): the re-planned reference input is
      // spiky by design (eq. 31), the controller's COM is not.
      const Vec2 com_err = com.head<2>() - original_com(t_sim);
      com_sq += com_err.squaredNorm();
      res.com_max_error_m = std::max(res.com_max_error_m, com_err.norm());
      if (touching) {
        cop_sq += (contacts.cop_W - p_des).squaredNorm();
        ++cop_n;
      }
      std::vector<Vec2> support_pts;
      for (int f = 0; f < 2; ++f) {
        const auto fi = static_cast<std::size_t>(f);
        const Sole& sole = model.soles()[fi];
        const double fn = contacts.feet[fi].normal_force_n;
        // Detail strings are only built while a condition holds (this runs every control cycle).
        const bool unmet = r.contact[fi] && !on_floor[fi];
        not_achieved[fi].update(t_clip, unmet, fn,
                                unmet ? format("%s %.0f mm above the floor, carries %.0f N", foot_name[f], sole_z[fi] * 1e3, fn) : "", out);
        const bool stuck = !r.contact[fi] && loaded[fi];
        no_lift_off[fi].update(t_clip, stuck, fn, stuck ? format("%s still carries %.0f N", foot_name[f], fn) : "", out);
        const MatX J = link_jacobian(model, ctrl_data, sole.link, sole.p_L_center);
        const double speed = (J.topRows(2) * v).norm();
        foot_speed[fi] = speed;
        const bool sliding = r.contact[fi] && loaded[fi] && speed > o.slip_speed_mps;
        slip[fi].update(t_clip, sliding, speed, sliding ? format("%s sole slides at %.3f m/s", foot_name[f], speed) : "", out);
        if (loaded[fi]) {
          const Iso3 X = link_pose(model, ctrl_data, sole.link);
          for (const Vec3& c : sole.corners_L()) support_pts.push_back((X * c).head<2>());
        }
      }
      const SupportPolygon support = SupportPolygon::convex_hull(support_pts);
      if (touching && !support.empty()) {
        const double sd = support.signed_distance(contacts.cop_W);
        const bool near = sd > -o.cop_margin_m;
        cop_edge.update(t_clip, near, sd,
                        near ? format("COP %.3f m %s the support polygon's edge", std::abs(sd), sd > 0 ? "outside" : "inside") : "",
                        out);
      } else {
        cop_edge.update(t_clip, false, 0, "", out);
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
      if (cmd.saturated_joints > 0) ++res.saturated_control_cycles;
      const bool saturated = cmd.saturated_joints > 0;
      saturation.update(t_clip, saturated, worst_ratio,
                        saturated ? format("%s at %.2fx its effort limit", joint_name(worst_joint).c_str(), worst_ratio) : "", out);
      const bool at_limit = worst_limit > 0;
      limit.update(t_clip, at_limit, worst_limit + o.joint_limit_margin_rad,
                   at_limit ? joint_name(limit_joint) + " at its position limit" : "", out);

      if (t_clip + 1e-12 >= next_record) {
        next_record += o.record_period_s;
        DynamicsTrace& tr_out = res.trace;
        tr_out.t_s.push_back(t_clip);
        tr_out.com_W.push_back(com);
        tr_out.com_ref_W.push_back(c_ref);
        tr_out.com_ref_original_W.push_back(original_com(t_sim));
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
        tr_out.contact_actual.push_back(loaded);
        tr_out.foot_force_n.push_back({contacts.feet[0].normal_force_n, contacts.feet[1].normal_force_n});
        tr_out.foot_force_cmd_W.push_back(f_cmd);
        tr_out.foot_force_W.push_back({contacts.feet[0].force_W, contacts.feet[1].force_W});
        tr_out.cop_commanded_W.push_back(cop_cmd);
        tr_out.foot_speed_mps.push_back(foot_speed);
        std::array<double, 4> sq{}, n{};
        for (int i = 0; i < nu; ++i) {
          const auto g = static_cast<std::size_t>(group[static_cast<std::size_t>(i)]);
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

    plant.step(cmd.tau, substeps);
    if (!res.replans.empty()) {
      res.active_loop_wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - cycle_start).count();
      ++res.active_cycles;
    }
  }

  const double t_end = std::max(0.0, std::min(plant.time_s() - o.settle_s, signal.duration_s()));
  for (auto* t : {&not_achieved[0], &not_achieved[1], &no_lift_off[0], &no_lift_off[1], &slip[0], &slip[1]}) t->finish(t_end, out);
  for (auto* t : {&cop_edge, &saturation, &limit}) t->finish(t_end, out);
  std::sort(out.begin(), out.end(), [](const Violation& a, const Violation& b) { return a.start_s < b.start_s; });

  res.simulated_s = res.fell ? res.fall_time_s : signal.duration_s();
  res.passed = std::none_of(out.begin(), out.end(), [](const Violation& v) { return violation_fails_check(v.kind); });
  res.joint_rms_error_rad = joint_n ? std::sqrt(joint_sq / joint_n) : 0;
  res.com_rms_error_m = clip_ticks ? std::sqrt(com_sq / clip_ticks) : 0;
  res.cop_rms_error_m = cop_n ? std::sqrt(cop_sq / cop_n) : 0;
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  res.real_time_factor = res.wall_s > 0 ? plant.time_s() / res.wall_s : 0;
  return res;
}

}  // namespace rt
