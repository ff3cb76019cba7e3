#include "retarget/sim/paper_controller.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "retarget/balance/support_polygon.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"
#include "retarget/sim/contact_trunk_map.hpp"

namespace rt {

namespace {

constexpr double kGravity = 9.81;

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

std::array<Mat3, 2> sole_frames(const RobotModel& model) {
  RobotData data(model);
  return sole_frames_in_links(model, data);
}

}  // namespace

struct PaperController::Memos {
  Memo<Vec2> cop_ref;
  Memo<SupportFrame> support;
};

PaperController::PaperController(const RobotModel& model, const ReferenceSignal& signal, const DynamicsCheckOptions& o,
                                 const Vec2& start_com_W)
    : model_(&model),
      signal_(&signal),
      o_(&o),
      dt_sim_(model.config().simulation.timestep_s),
      balance_(PendulumModel{model.standing_com_height_m(), kGravity},
               [&] {
                 BalanceOptions bo = o.balance;
                 const int substeps = std::max(1, static_cast<int>(std::lround(o.control_period_s / dt_sim_)));
                 bo.control_period_s = substeps * dt_sim_;
                 return bo;
               }()),
      tracking_(model,
                [&] {
                  // The paper's eq. (19) clips saturated torques; the torque-limited solve is ours.
                  TrackingOptions t = o.tracking;
                  t.torque_limits = false;
                  return t;
                }()),
      planner_(balance_.closed_loop_model(o.replan.period_s), o.replan),
      R_L_sole_(sole_frames(model)) {
  N_ = o.replan.horizon;
  dt_plan_ = o.replan.period_s;
  omega_sq_ = balance_.model().omega_sq();
  total_s_ = o.settle_s + signal.duration_s();
  K_ = static_cast<int>(std::ceil(total_s_ / dt_plan_)) + N_ + 2;
  com_delta_ = Eigen::Matrix2Xd::Zero(2, K_);
  y_offset_.resize(2, N_);
  bstate_ = balance_.rest_state(start_com_W);
  prev_contact_ = signal.contact_at(0);
  // The reference COP over the planner's window, memoised per simulation step: consecutive planning
  // steps ask for mostly the same future times (on the simulation grid when the planner's period is
  // a multiple of the step), and it only changes when the trunk map does.
  const double plan_steps = dt_plan_ / dt_sim_;
  const bool on_sim_grid = std::abs(plan_steps - std::round(plan_steps)) < 1e-9;
  memos_.reset(new Memos{
      Memo<Vec2>(on_sim_grid ? static_cast<std::size_t>(std::ceil((total_s_ + (N_ + 2) * dt_plan_) / dt_sim_)) + 2 : 0),
      Memo<SupportFrame>(static_cast<std::size_t>(signal.num_frames()))});
}

PaperController::~PaperController() = default;

double PaperController::clip_time(double t_sim) const {
  return std::clamp(t_sim - o_->settle_s, 0.0, signal_->duration_s());
}

Vec2 PaperController::original_com(double t_sim) const { return signal_->com_at(clip_time(t_sim), map_).head<2>(); }

// Balance reference of the original (trunk-mapped) reference COM motion, without re-planning.
BalanceReference PaperController::balance_reference(double t_sim) const {
  if (!o_->balance_feedforward) return BalanceReference::at_rest(original_com(t_sim));
  return BalanceReference::from_com_motion(signal_->com_motion_at(t_sim - o_->settle_s, map_), omega_sq_);
}

Vec2 PaperController::reference_cop(double t_sim) {
  const auto make = [&] { return balance_reference(t_sim).cop(); };
  const long long key = std::llround(t_sim / dt_sim_);
  if (key < 0 || key >= static_cast<long long>(memos_->cop_ref.size())) return make();
  return memos_->cop_ref.get(static_cast<std::size_t>(key), make);
}

Vec2 PaperController::delta_at(double t_sim) const {
  const double s = std::clamp(t_sim / dt_plan_, 0.0, static_cast<double>(K_ - 1));
  const int k = std::min(static_cast<int>(s), K_ - 2);
  const double w = s - k;
  return (1 - w) * com_delta_.col(k) + w * com_delta_.col(k + 1);
}

void PaperController::control(const ControlInput& in, ControlOutput& out) {
  const RobotModel& model = *model_;
  const ReferenceSignal& signal = *signal_;
  const DynamicsCheckOptions& o = *o_;
  RobotData& data = *in.data;
  const ContactState& contacts = *in.contacts;
  const std::array<bool, 2>& loaded = in.feet->loaded;
  const double t_sim = in.t_sim_s, t_clip = in.t_clip_s, t_ref = in.t_ref_s;
  const bool settling = in.settling;
  const Vec3& com = in.com_W;

  // --- reference, contact schedule, trunk mapping --------------------------------------------
  ReferenceSample& r = out.reference;
  r = signal.at(t_ref, map_);
  if (settling) hold_still(r);
  if (r.contact != prev_contact_) contact_change_pending_ = true;
  prev_contact_ = r.contact;
  if (o.trunk_mapping && contact_change_pending_ && (r.contact[0] || r.contact[1])) {
    if (contact_feet_pushing(r.contact, contacts, o.trunk.force_threshold_n)) {
      map_ = trunk_transform_at_contacts(model, data, signal.at(t_ref, TrunkTransform{}), r.contact, o.trunk);
      memos_->cop_ref.clear();
      contact_change_pending_ = false;
      ++trunk_mapping_updates_;
      r = signal.at(t_ref, map_);
      if (settling) {
        r.v.setZero();
        r.a.setZero();
      }
    }
  }

  // --- online dynamic mapping (paper §VI) at the planner's period ------------------------------
  const auto planner_start = std::chrono::steady_clock::now();
  const int N = N_;
  if (o.dynamic_mapping && t_sim + 1e-12 >= next_plan_) {
    next_plan_ += dt_plan_;
    const int k0 = std::min(static_cast<int>(std::lround(t_sim / dt_plan_)), K_ - N - 1);
    // Eq. (25)-(27): with feed-forward in error coordinates (x0 = ŝ − s_ref, U = δ, plus the
    // reference COP), else the paper's (x0 = ŝ, U = c_ref + δ).
    Eigen::Matrix2Xd U(2, N);
    Mat42 x0 = bstate_.s_hat;
    if (o.balance_feedforward) {
      x0 -= balance_reference(t_sim).s_ref;
      for (int j = 0; j < N; ++j) {
        U.col(j) = com_delta_.col(k0 + j);
        y_offset_.col(j) = reference_cop(t_sim + (j + 1) * dt_plan_);
      }
    } else {
      for (int j = 0; j < N; ++j) U.col(j) = original_com(t_sim + j * dt_plan_) + com_delta_.col(k0 + j);
    }
    const std::array<bool, 2> contact_now = signal.contact_at(t_ref);
    const std::array<int, 7> inputs = {static_cast<int>(std::lround(t_ref * signal.fps())), loaded[0], loaded[1],
                                       contact_now[0], contact_now[1], stance_pose_changes_, trunk_mapping_updates_};
    if (inputs != support_inputs_) {
      memos_->support.clear();
      support_inputs_ = inputs;
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
        X_mapped.translation() = map_.apply_position(X_ref.translation());
        X_mapped.linear() = map_.Omega() * X_ref.linear();
        Iso3 X = flat_on_floor(X_mapped);
        if (loaded[static_cast<std::size_t>(f)] && stance_pose_[static_cast<std::size_t>(f)] && contact_now[static_cast<std::size_t>(f)]) {
          bool stays = true;
          for (int g = static_cast<int>(std::lround(t_ref * signal.fps())); g <= frame && stays; ++g)
            stays = signal.contacts()[static_cast<std::size_t>(f)][static_cast<std::size_t>(std::min(g, signal.num_frames() - 1))] != 0;
          if (stays) X = *stance_pose_[static_cast<std::size_t>(f)];
        }
        s.sole_center_W[static_cast<std::size_t>(f)] = X.translation().head<2>();
        if (s.contact[static_cast<std::size_t>(f)])
          for (const Vec3& c : sole_corners_W(X, sole)) corners.push_back(c.head<2>());
      }
      s.polygon = SupportPolygon::convex_hull(std::move(corners));
      return s;
    };
    const auto support = [&](int j) -> const SupportFrame& {
      const double tj = clip_time(t_sim + j * dt_plan_);
      const int frame = std::clamp(static_cast<int>(std::lround(tj * signal.fps())), 0, signal.num_frames() - 1);
      return memos_->support.get(static_cast<std::size_t>(frame), [&] { return make_support(frame); });
    };
    const Eigen::Matrix2Xd before = U;
    const auto event = planner_.step(x0, U, support, o.balance_feedforward ? &y_offset_ : nullptr);
    if (event) {
      com_delta_.middleCols(k0, N) += U - before;
      replans_.push_back({std::max(t_clip, -o.settle_s), *event});
    }
    if (!replans_.empty())
      planner_wall_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - planner_start).count();
  }

  // --- balance controller (eq. 1) -------------------------------------------------------------
  const Vec2 delta = delta_at(t_sim);
  const Vec2 c_ref = original_com(t_sim) + delta;
  const bool touching = contacts.normal_force_n > 1e-6;
  const Vec2 p_meas = touching ? contacts.cop_W : bstate_.desired_cop();
  BalanceReference bref = balance_reference(t_sim);
  bref.add_com_offset(delta);
  const Vec2 p_des = balance_.step(bstate_, bref, com.head<2>(), p_meas);
  out.com_ref_W = c_ref;
  out.com_ref_original_W = original_com(t_sim);

  // --- feet: a loaded stance foot is held where it is (no position feedback: the floor, not the
  // controller, decides its height, and soft contact sinks it a little); a stance foot not yet
  // loaded is brought down onto the floor flat; swing feet follow the reference ------------------
  TrackingReference& tr = out.tracking;
  tr.q = r.q;
  tr.v = r.v;
  tr.a = r.a;
  tr.contact = r.contact;
  tr.desired_cop_W = p_des;
  if (o.root_follows_com) {
    // Trunk reference relative to the COM the balance controller steers: original offset of the
    // trunk from the reference COM, placed at the estimated COM; its acceleration is the one the
    // desired COP gives the pendulum.
    const Eigen::Matrix<double, 5, 2> cm = signal.com_motion_at(t_clip, map_);
    tr.q.head<2>() += bstate_.com() - cm.row(0).transpose();
    tr.v.head<2>() += bstate_.com_velocity() - cm.row(1).transpose();
    tr.a.head<2>() += omega_sq_ * (bstate_.com() - p_des) - cm.row(2).transpose();
  }
  for (int f = 0; f < 2; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (r.contact[fi]) {
      if (loaded[fi]) {
        const Iso3 X = sole_frame_W(model, data, f, R_L_sole_[fi]);
        tr.X_W_sole[fi] = X;
        if (!stance_pose_[fi]) {
          stance_pose_[fi] = flat_on_floor(X);
          ++stance_pose_changes_;
        }
      } else {
        tr.X_W_sole[fi] = stance_pose_[fi] ? *stance_pose_[fi] : flat_on_floor(r.X_W_sole[fi]);
      }
      tr.v_sole[fi].setZero();
      tr.a_sole[fi].setZero();
    } else {
      if (stance_pose_[fi]) ++stance_pose_changes_;
      stance_pose_[fi].reset();
      tr.X_W_sole[fi] = r.X_W_sole[fi];
      tr.v_sole[fi] = r.v_sole[fi];
      tr.a_sole[fi] = r.a_sole[fi];
    }
  }

  // --- tracking controller (eq. 2-19) ---------------------------------------------------------
  tracking_.build(data, *in.q, *in.v, tr, problem_, workspace_, /*data_is_current=*/true);
  tracking_.solve(problem_, out.command, workspace_);
}

void PaperController::finish(DynamicsCheckResult& res) const {
  res.replans = replans_;
  res.trunk_mapping_updates = trunk_mapping_updates_;
  res.planner_wall_s = planner_wall_s_;
}

}  // namespace rt
