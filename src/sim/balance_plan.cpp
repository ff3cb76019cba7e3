#include "retarget/sim/balance_plan.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/gaussian_filter.hpp"
#include "retarget/model/ankle_reach.hpp"
#include "retarget/model/centroidal.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/sim/reference_signal.hpp"

namespace rt {

namespace {

// Columns of `m` (one per frame at `fps`) linearly interpolated at time t, clamped to the ends.
Vec2 at_time(const Eigen::Matrix2Xd& m, double fps, double t) {
  const int T = static_cast<int>(m.cols());
  const double s = std::clamp(t * fps, 0.0, static_cast<double>(T - 1));
  const int i = std::min(static_cast<int>(s), T - 1), j = std::min(i + 1, T - 1);
  return (1 - (s - i)) * m.col(i) + (s - i) * m.col(j);
}

}  // namespace

Vec2 BalancePlan::sample(const Eigen::Matrix2Xd& m, double t_s) const { return at_time(m, 1.0 / period_s, t_s - start_s); }

Vec2 BalancePlan::com_velocity(double t_s) const {
  if (t_s < start_s || t_s > start_s + (size() - 1) * period_s) return Vec2::Zero();
  return sample(com_velocity_W, t_s);
}

Vec2 BalancePlan::offset(double t_s) const {
  if (t_s < start_s || t_s > start_s + (size() - 1) * period_s) return Vec2::Zero();
  return sample(offset_W, t_s);
}

double BalancePlan::com_height(double t_s) const {
  const double s = std::clamp((t_s - start_s) / period_s, 0.0, static_cast<double>(size() - 1));
  const int i = std::min(static_cast<int>(s), size() - 1), j = std::min(i + 1, size() - 1);
  return (1 - (s - i)) * com_height_m[i] + (s - i) * com_height_m[j];
}

BalancePlan plan_reference_balance(const RobotModel& model, RobotData& data, const ReferenceSignal& signal,
                                   const BalancePlanOptions& o) {
  RT_DEMAND(o.period_s > 0 && o.margin_m >= 0 && o.offset_smoothing_s >= 0 && o.max_offset_m > 0 && o.lead_in_s >= 0,
            "plan_reference_balance: invalid options");
  const double fps = signal.fps();
  const int T = signal.num_frames();
  const MultibodyZmp mb = multibody_zmp(model, data, signal.q_frames(), fps);

  // Δp per frame: the multibody ZMP minus the cart-table ZMP of the same COM, smoothed and capped.
  Eigen::Matrix2Xd offset = Eigen::Matrix2Xd::Zero(2, T);
  if (o.angular_offset && T >= 3) {
    for (int f = 0; f < T; ++f) {
      const int i = std::clamp(f, 1, T - 2);
      const Vec2 acc = (mb.com_W.col(i + 1) - 2 * mb.com_W.col(i) + mb.com_W.col(i - 1)).head<2>() * fps * fps;
      offset.col(f) = mb.zmp_W.col(f) - (mb.com_W.col(f).head<2>() - mb.zmp_gain_s2[f] * acc);
    }
    offset = gaussian_filter(offset, o.offset_smoothing_s * fps);
    for (int f = 0; f < T; ++f)
      if (offset.col(f).norm() > o.max_offset_m) offset.col(f) *= o.max_offset_m / offset.col(f).norm();
  }

  // Support per frame: the hull of the stance sole rectangles (the ankles' reach), laid flat, shrunk
  // by the margin.
  const std::array<SoleReach, 2> reach =
      o.ankle_reach ? ankle_reach(model, model.total_mass_kg() * 9.81) : whole_soles(model);
  std::vector<std::vector<HalfPlane>> support(static_cast<std::size_t>(T));
  std::vector<Vec2> centre(static_cast<std::size_t>(T), Vec2::Zero());
  for (int f = 0; f < T; ++f) {
    std::vector<Vec2> corners;
    for (int foot = 0; foot < 2; ++foot) {
      if (!signal.contacts()[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)]) continue;
      const Iso3& X = signal.soles_W()[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)];
      const Vec3 x = X.linear().col(0);
      const double yaw = std::atan2(x.y(), x.x());
      const Eigen::Rotation2Dd R(yaw);
      const Vec2 c = X.translation().head<2>();
      const SoleReach& r = reach[static_cast<std::size_t>(foot)];
      for (const Vec2& s : {r.max_S, Vec2(r.min_S.x(), r.max_S.y()), r.min_S, Vec2(r.max_S.x(), r.min_S.y())})
        corners.push_back(c + R * s);
    }
    const SupportPolygon polygon = SupportPolygon::convex_hull(std::move(corners));
    support[static_cast<std::size_t>(f)] = polygon.half_planes(o.margin_m);
    if (!polygon.empty()) centre[static_cast<std::size_t>(f)] = polygon.centroid();
  }

  const double dt = o.period_s;
  const int lead = static_cast<int>(std::lround(o.lead_in_s / dt));
  const int K = lead + std::max(1, static_cast<int>(std::floor(signal.duration_s() / dt + 1e-9)) + 1);
  std::vector<ZmpPlanSample> samples(static_cast<std::size_t>(K));
  BalancePlan plan;
  plan.period_s = dt;
  plan.start_s = -lead * dt;
  plan.com_height_m.resize(K);
  plan.offset_W.resize(2, K);
  const Eigen::Matrix2Xd com_xy = mb.com_W.topRows<2>();
  const Eigen::Matrix2Xd gain = mb.zmp_gain_s2.transpose().replicate(2, 1);
  const Eigen::Matrix2Xd com_z = mb.com_W.bottomRows<1>().replicate(2, 1);
  for (int k = 0; k < K; ++k) {
    ZmpPlanSample& s = samples[static_cast<std::size_t>(k)];
    // The lead-in holds the first frame: its COM, support and gain, no angular part.
    const double t = std::max(0.0, (k - lead) * dt);
    s.com_ref_W = at_time(com_xy, fps, t);
    s.zmp_gain_s2 = at_time(gain, fps, t)[0];
    s.zmp_offset_W = k < lead ? Vec2::Zero() : at_time(offset, fps, t);
    const auto frame = static_cast<std::size_t>(std::clamp(static_cast<int>(std::lround(t * fps)), 0, T - 1));
    s.support = support[frame];
    s.zmp_centre_W = centre[frame];
    plan.offset_W.col(k) = s.zmp_offset_W;
    plan.com_height_m[k] = at_time(com_z, fps, t)[0];
  }
  // The robot starts at rest on the first frame's COM, so the plan starts there too (pinned; the
  // ZMP centring, 100 times the COM's weight, once started it at the support's centroid: 12 cm from
  // where a com-plan reference of PyMO's walk put G1's COM, which the controller then chased with
  // the COP clamped at the edge for the whole settle phase).
  samples.front().com_weight_scale = 1e4;
  ZmpPlanOptions po = o.plan;
  po.period_s = dt;
  // The check starts the robot at rest on the first frame; it ends when the clip does, so the end
  // needs no rest (a clip that ends mid-walk would otherwise have to stop inside the clip).
  po.rest_at_start = true;
  po.rest_at_end = false;
  const ZmpPlan z = plan_com_zmp(samples, po);
  if (z.com_W.cols() == K) {
    plan.com_W = z.com_W;
    plan.zmp_W = z.zmp_W;
    plan.max_violation_m = z.max_violation_m;
  } else {
    // No plan (the solver failed): the reference's own COM and ZMP, so the check judges it as is.
    plan.com_W.resize(2, K);
    plan.zmp_W.resize(2, K);
    for (int k = 0; k < K; ++k) {
      plan.com_W.col(k) = samples[static_cast<std::size_t>(k)].com_ref_W;
      plan.zmp_W.col(k) = at_time(mb.zmp_W, fps, std::max(0.0, (k - lead) * dt));
    }
    plan.max_violation_m = -1;
  }
  plan.com_velocity_W = Eigen::Matrix2Xd::Zero(2, K);
  for (int k = 0; k < K; ++k) {
    const int a = std::max(0, k - 1), b = std::min(K - 1, k + 1);
    if (b > a) plan.com_velocity_W.col(k) = (plan.com_W.col(b) - plan.com_W.col(a)) / ((b - a) * dt);
  }
  // The shift the reference needs is that of the plan without the ZMP centring (which moves the COM
  // for margin, not for feasibility), measured over the clip (not the lead-in).
  Eigen::Matrix2Xd needed = plan.com_W;
  if (po.zmp_centre_weight > 0) {
    ZmpPlanOptions feasibility = po;
    feasibility.zmp_centre_weight = 0;
    const ZmpPlan f = plan_com_zmp(samples, feasibility);
    if (f.com_W.cols() == K) needed = f.com_W;
  }
  // Judged where the reference determines it: not in the lead-in, and not in the clip's last 1/ω
  // (the pendulum's time constant, sqrt(z_c/g)): a clip cut mid-step ends with its COM falling
  // towards a step the clip no longer shows, and a plan with a free end then lets the COM run off
  // in those last samples to keep the ZMP on the last foot (on the Bandai walk for humanoid25, a
  // shift of a few mm 0.25 s before the end became 12 cm at the last sample).
  const int end_guard = std::min(K - lead - 1, static_cast<int>(std::lround(std::sqrt(plan.com_height_m.mean() / kGravity) / dt)));
  const int judged_end = K - std::max(0, end_guard);
  double sq = 0;
  for (int k = lead; k < judged_end; ++k) {
    const double d = (needed.col(k) - samples[static_cast<std::size_t>(k)].com_ref_W).norm();
    sq += d * d;
    if (d > plan.max_shift_m) {
      plan.max_shift_m = d;
      plan.max_shift_time_s = (k - lead) * dt;
    }
  }
  plan.rms_shift_m = std::sqrt(sq / std::max(1, judged_end - lead));
  return plan;
}

}  // namespace rt
