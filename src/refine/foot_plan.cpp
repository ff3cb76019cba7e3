#include "src/refine/foot_plan.hpp"

#include <algorithm>
#include <cmath>

namespace rt::refine {

namespace {

double smootherstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (x * (6 * x - 15) + 10);
}

double smooth_max(double a, double b, double eps) { return 0.5 * (a + b + std::sqrt((a - b) * (a - b) + eps * eps)); }

Mat3 yaw_rotation(double yaw) { return AngleAxis(yaw, Vec3::UnitZ()).toRotationMatrix(); }

// Height of the lowest sole corner relative to the sole centre for sole orientation R (<= 0 when
// tilted).
double lowest_corner_offset(const Mat3& R, const Vec2& size) {
  double z = 0;
  for (const double sx : {-0.5, 0.5})
    for (const double sy : {-0.5, 0.5}) z = std::min(z, (R * Vec3(sx * size.x(), sy * size.y(), 0)).z());
  return z;
}

Vec3 rotation_log(const Mat3& R) {
  const AngleAxis aa(R);
  return aa.angle() * aa.axis();
}

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

double sole_yaw(const Mat3& R) { return std::atan2(R(1, 0), R(0, 0)); }

std::vector<SoleAnchor> stance_anchors(const std::array<std::vector<SolePose>, 2>& soles,
                                         const std::array<std::vector<std::uint8_t>, 2>& contacts) {
  std::vector<SoleAnchor> out;
  for (int foot = 0; foot < 2; ++foot) {
    const auto& c = contacts[static_cast<std::size_t>(foot)];
    const auto& s = soles[static_cast<std::size_t>(foot)];
    const int T = static_cast<int>(c.size());
    for (int f = 0; f < T;) {
      if (!c[static_cast<std::size_t>(f)]) {
        ++f;
        continue;
      }
      SoleAnchor a;
      a.foot = foot;
      a.begin = f;
      while (f < T && c[static_cast<std::size_t>(f)]) ++f;
      a.end = f;
      std::vector<double> x, y;
      Vec2 heading = Vec2::Zero();
      for (int k = a.begin; k < a.end; ++k) {
        const SolePose& p = s[static_cast<std::size_t>(k)];
        x.push_back(p.p_W.x());
        y.push_back(p.p_W.y());
        const double yaw = sole_yaw(p.R_W);
        heading += Vec2(std::cos(yaw), std::sin(yaw));  // circular mean
      }
      a.p_W = Vec2(median(std::move(x)), median(std::move(y)));
      a.yaw = heading.norm() > 1e-9 ? std::atan2(heading.y(), heading.x()) : sole_yaw(s[static_cast<std::size_t>(a.begin)].R_W);
      out.push_back(a);
    }
  }
  return out;
}

FootPlan plan_feet(const std::vector<SoleAnchor>& anchors, const std::array<std::vector<SolePose>, 2>& smoothed,
                   const std::array<std::vector<std::uint8_t>, 2>& contacts, double fps, const FootPlanOptions& o) {
  FootPlan plan;
  plan.anchors = anchors;
  const int T = static_cast<int>(contacts[0].size());
  for (int foot = 0; foot < 2; ++foot) {
    auto& targets = plan.feet[static_cast<std::size_t>(foot)];
    targets.assign(static_cast<std::size_t>(T), FootTarget{});
    const auto& S = smoothed[static_cast<std::size_t>(foot)];
    const Vec2 size = o.sole_size_m[static_cast<std::size_t>(foot)];
    auto low = [&](const SolePose& p) { return p.p_W.z() + lowest_corner_offset(p.R_W, size); };
    // Anchor index per frame (stance), and each stance's pose.
    std::vector<int> anchor_of(static_cast<std::size_t>(T), -1);
    for (std::size_t k = 0; k < anchors.size(); ++k) {
      const SoleAnchor& a = anchors[k];
      if (a.foot != foot) continue;
      for (int f = a.begin; f < a.end; ++f) {
        anchor_of[static_cast<std::size_t>(f)] = static_cast<int>(k);
        FootTarget& t = targets[static_cast<std::size_t>(f)];
        t.mode = FootMode::Stance;
        t.pose.p_W = Vec3(a.p_W.x(), a.p_W.y(), 0);
        t.pose.R_W = yaw_rotation(a.yaw);
      }
    }
    const bool any_stance = std::find_if(anchor_of.begin(), anchor_of.end(), [](int k) { return k >= 0; }) != anchor_of.end();
    if (!any_stance) {
      for (FootTarget& t : targets) t.min_height_m = 0;
      continue;
    }
    // Swings: runs of frames without an anchor.
    for (int a = 0; a < T;) {
      if (anchor_of[static_cast<std::size_t>(a)] >= 0) {
        ++a;
        continue;
      }
      int b = a;
      while (b < T && anchor_of[static_cast<std::size_t>(b)] < 0) ++b;
      // End poses: the anchors, or the smoothed pose where the clip cuts the swing.
      const bool open_start = a == 0, open_end = b == T;
      const int f0 = open_start ? 0 : a - 1, f1 = open_end ? T - 1 : b;
      SolePose A = open_start ? S[0] : targets[static_cast<std::size_t>(f0)].pose;
      SolePose B = open_end ? S[static_cast<std::size_t>(T - 1)] : targets[static_cast<std::size_t>(f1)].pose;
      const double span = std::max(1, f1 - f0);
      const double guard = std::max(1.0, std::min(o.guard_s * fps, 0.5 * span));
      const double tilt_ramp = std::max(guard, std::min(o.tilt_ramp_s * fps, 0.5 * span));  // [frames]
      const Vec2 chord_h = S[static_cast<std::size_t>(f1)].p_W.head<2>() - S[static_cast<std::size_t>(f0)].p_W.head<2>();
      const double yaw_A = sole_yaw(A.R_W), yaw_B = sole_yaw(B.R_W);
      const double turn = std::remainder(yaw_B - yaw_A, 2 * M_PI);
      double progress = 0;  // running maximum: monotone
      for (int f = a; f < b; ++f) {
        const SolePose& s = S[static_cast<std::size_t>(f)];
        const double u = (f - f0) / span;
        double p_h = u;
        if (chord_h.squaredNorm() > 1e-4)
          p_h = std::clamp((s.p_W.head<2>() - S[static_cast<std::size_t>(f0)].p_W.head<2>()).dot(chord_h) / chord_h.squaredNorm(), 0.0, 1.0);
        progress = std::max(progress, p_h);
        const double sigma = smootherstep(progress);
        const double bump = 16 * u * u * (1 - u) * (1 - u);
        const Vec2 deviation = s.p_W.head<2>() - (S[static_cast<std::size_t>(f0)].p_W.head<2>() + chord_h * progress);
        // Distance to the nearer anchored end, in frames (a cut end does not count).
        double d = INFINITY;
        if (!open_start) d = std::min(d, static_cast<double>(f - f0));
        if (!open_end) d = std::min(d, static_cast<double>(f1 - f));
        const double E = std::isfinite(d) ? smootherstep(d / guard) : 1.0;
        const double E_tilt = o.tilt_ramp_s > 0 && std::isfinite(d) ? smootherstep(d / tilt_ramp) : E;
        // Lowest-corner height over the chord between the end heights (the ends' own where the clip cuts).
        const double z0 = open_start ? 0.0 : low(S[static_cast<std::size_t>(f0)]);
        const double z1 = open_end ? 0.0 : low(S[static_cast<std::size_t>(f1)]);
        const double h = low(s) - ((1 - u) * z0 + u * z1);
        FootTarget& t = targets[static_cast<std::size_t>(f)];
        t.mode = FootMode::Swing;
        t.pose.p_W.head<2>() = A.p_W.head<2>() + (B.p_W.head<2>() - A.p_W.head<2>()) * sigma + bump * deviation;
        const double yaw = yaw_A + turn * sigma;
        const Mat3 tilt = yaw_rotation(sole_yaw(s.R_W)).transpose() * s.R_W;
        const Vec3 tilt_log = rotation_log(tilt);  // faded out towards flat lift-off and touchdown
        t.pose.R_W = yaw_rotation(yaw) * (tilt_log.norm() > 1e-12
                                              ? AngleAxis(E_tilt * tilt_log.norm(), tilt_log.normalized()).toRotationMatrix()
                                              : Mat3::Identity());
        t.pose.p_W.z() = E * smooth_max(h, o.clearance_m + 0.003, 0.01) - lowest_corner_offset(t.pose.R_W, size);
        t.min_height_m = (o.clearance_m + 0.002) * E;  // 2 mm over: the floor rows are penalties
        t.end_blend = 1 - E;
      }
      a = b;
    }
  }
  return plan;
}

}  // namespace rt::refine
