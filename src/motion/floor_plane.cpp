#include "retarget/motion/floor_plane.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace rt {

namespace {

constexpr Landmark kFeet[] = {Landmark::LeftAnkle, Landmark::LeftToe,  Landmark::LeftHeel,
                              Landmark::RightAnkle, Landmark::RightToe, Landmark::RightHeel};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  const auto k = static_cast<std::size_t>(std::floor(std::clamp(p, 0.0, 1.0) * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

double median_distance(const HumanMotion& h, Landmark a, Landmark b) {
  std::vector<double> d;
  for (int f = 0; f < h.num_frames; ++f)
    if (h[a].valid(f) && h[b].valid(f)) d.push_back((h[a].p_W.col(f) - h[b].p_W.col(f)).norm());
  return percentile(std::move(d), 0.5);
}

}  // namespace

double human_leg_length(const HumanMotion& h) {
  double sum = 0;
  int legs = 0;
  for (auto [hip, knee, ankle] : {std::array<Landmark, 3>{Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle},
                                  std::array<Landmark, 3>{Landmark::RightHip, Landmark::RightKnee, Landmark::RightAnkle}}) {
    if (!h.has(hip) || !h.has(knee) || !h.has(ankle)) continue;
    sum += median_distance(h, hip, knee) + median_distance(h, knee, ankle);
    ++legs;
  }
  return legs ? sum / legs : 0.0;
}

FloorPlane estimate_floor_plane(const HumanMotion& h, const FloorPlaneOptions& o) {
  FloorPlane plane;
  const int T = h.num_frames;
  if (T < 3 || !(h.fps > 0)) return plane;
  double leg = human_leg_length(h);
  if (!(leg > 0.2)) leg = 0.85;  // no legs: a typical adult's
  const double source_fps = h.fps * h.time_scale;  // frames per source second
  const double still = o.still_speed_legs_per_s * leg / source_fps;  // [m per frame]

  // Candidates: (x, y, z) of a still foot landmark, and which landmark it is.
  std::vector<Vec3> cand;
  std::vector<int> owner;
  int landmarks = 0;
  for (Landmark l : kFeet) {
    const LandmarkTrack& t = h[l];
    if (!t.present) continue;
    const std::size_t first = cand.size();
    for (int f = 1; f + 1 < T; ++f) {
      if (!t.valid(f - 1) || !t.valid(f) || !t.valid(f + 1)) continue;
      if ((t.p_W.col(f + 1).head<2>() - t.p_W.col(f - 1).head<2>()).norm() > 2 * still) continue;
      cand.push_back(t.p_W.col(f));
      owner.push_back(landmarks);
    }
    if (cand.size() - first < 3) {
      cand.resize(first);
      owner.resize(first);
    } else {
      ++landmarks;
    }
  }
  plane.candidates = static_cast<int>(cand.size());
  if (cand.size() < 10) return plane;

  // Directions the candidates span: slope only along those (PCA of the horizontal positions).
  Vec2 mean = Vec2::Zero();
  for (const Vec3& p : cand) mean += p.head<2>();
  mean /= static_cast<double>(cand.size());
  Mat2 cov = Mat2::Zero();
  for (const Vec3& p : cand) cov += (p.head<2>() - mean) * (p.head<2>() - mean).transpose();
  cov /= static_cast<double>(cand.size());
  const Eigen::SelfAdjointEigenSolver<Mat2> eig(cov);
  std::vector<Vec2> axes;
  for (int k = 0; k < 2; ++k)
    if (std::sqrt(std::max(0.0, eig.eigenvalues()[k])) >= o.min_spread_m) axes.push_back(eig.eigenvectors().col(k));

  // Trimmed least squares: z ≈ d_l + Σ s_k u_k, u_k = axis_k · (x − mean), with one height d_l per
  // landmark (an ankle rests higher than a toe; a per-landmark resting height taken before the fit
  // would itself be biased by the slope); candidates far above the fit are dropped.
  std::vector<std::uint8_t> keep(cand.size(), 1);
  const int n = landmarks + static_cast<int>(axes.size());
  VecX beta = VecX::Zero(n);
  auto regressors = [&](std::size_t i) {
    VecX u = VecX::Zero(n);
    u[owner[i]] = 1;
    for (std::size_t k = 0; k < axes.size(); ++k) u[landmarks + static_cast<Eigen::Index>(k)] = axes[k].dot(cand[i].head<2>() - mean);
    return u;
  };
  auto residual = [&](std::size_t i) { return cand[i].z() - regressors(i).dot(beta); };
  // The band kept above the fit narrows from 16 cm to 2 cm over the rounds: a tight band from the
  // start would lock in the first fit's bias, and a foot on the floor stays within a couple of
  // centimetres of the plane while a foot held still in the air is well above it.
  for (int round = 0; round < 8; ++round) {
    MatX A = MatX::Identity(n, n) * 1e-12;  // a landmark whose candidates were all dropped keeps d_l = 0
    VecX rhs = VecX::Zero(n);
    for (std::size_t i = 0; i < cand.size(); ++i) {
      if (!keep[i]) continue;
      const VecX u = regressors(i);
      A += u * u.transpose();
      rhs += u * cand[i].z();
    }
    beta = A.ldlt().solve(rhs);
    std::vector<double> r;
    for (std::size_t i = 0; i < cand.size(); ++i) r.push_back(residual(i));
    const double mid = percentile(r, 0.5);
    std::vector<double> dev;
    for (double v : r) dev.push_back(std::abs(v - mid));
    const double mad = std::max(percentile(dev, 0.5), 0.002);
    const double band = std::max(3 * mad, std::max(0.02, 0.16 / double(1 << round)));
    for (std::size_t i = 0; i < cand.size(); ++i) keep[i] = r[i] < mid + band;
  }
  Vec2 slope = Vec2::Zero();
  for (std::size_t k = 0; k < axes.size(); ++k) slope += beta[landmarks + static_cast<Eigen::Index>(k)] * axes[k];
  plane.a = slope.x();
  plane.b = slope.y();
  plane.c = beta.head(landmarks).minCoeff() - slope.dot(mean);
  plane.tilt_deg = std::atan(slope.norm()) * 180 / M_PI;
  if (plane.tilt_deg > o.max_tilt_deg) {
    plane = FloorPlane{};
    plane.candidates = static_cast<int>(cand.size());
    plane.rejected_steep = true;
    return plane;
  }
  std::vector<double> kept;
  for (std::size_t i = 0; i < cand.size(); ++i)
    if (keep[i]) kept.push_back(residual(i));
  plane.unevenness_m = percentile(kept, 0.9) - percentile(kept, 0.1);
  return plane;
}

void level_onto_floor(HumanMotion& h, const FloorPlane& plane) {
  for (LandmarkTrack& t : h.landmarks) {
    if (!t.present) continue;
    for (Eigen::Index f = 0; f < t.p_W.cols(); ++f) t.p_W(2, f) -= plane.a * t.p_W(0, f) + plane.b * t.p_W(1, f);
  }
}

}  // namespace rt
