#include "retarget/motion/c3d/rigid_cluster.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace rt {

std::optional<Iso3> fit_rigid_transform(const Mat3X& from, const Mat3X& to, double min_spread_m, double* rms_m) {
  const Eigen::Index n = from.cols();
  if (n < 3 || to.cols() != n) return std::nullopt;
  const Vec3 cf = from.rowwise().mean();
  const Vec3 ct = to.rowwise().mean();
  const Mat3X a = from.colwise() - cf;
  const Mat3X b = to.colwise() - ct;
  // Kabsch through the closed-form eigen-decomposition of H^T H (H = a b^T = U S V^T), which is
  // several times faster than a 3x3 Jacobi SVD and is called once per cluster and frame.
  const Mat3 h = a * b.transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(h.transpose() * h);  // eigenvalues ascending: S^2
  const Vec3 s2 = eig.eigenvalues();
  // A cluster that does not spread in two directions (collinear markers) fixes no rotation; for
  // a rigid motion the singular values of H are the scatter eigenvalues of `from`.
  const double min_sv = static_cast<double>(n) * min_spread_m * min_spread_m;
  if (!(s2(1) > min_sv * min_sv) || !s2.allFinite()) return std::nullopt;
  const Vec3 v2 = eig.eigenvectors().col(2), v1 = eig.eigenvectors().col(1);
  Vec3 u2 = h * v2 / std::sqrt(s2(2));
  Vec3 u1 = h * v1 / std::sqrt(s2(1));
  u2.normalize();
  u1 = (u1 - u1.dot(u2) * u2).normalized();
  // With v0 = v1 x v2 and u0 = u1 x u2 the smallest singular pair gets the sign that makes R
  // proper; this is Kabsch's reflection correction (R = V diag(1, 1, d) U^T) in closed form.
  const Mat3 r = (v1.cross(v2)) * (u1.cross(u2)).transpose() + v1 * u1.transpose() + v2 * u2.transpose();
  if (!r.allFinite()) return std::nullopt;
  Iso3 x = Iso3::Identity();
  x.linear() = r;
  x.translation() = ct - r * cf;
  if (rms_m) *rms_m = std::sqrt(((r * a) - b).squaredNorm() / static_cast<double>(n));
  return x;
}

namespace {

bool measured(const MarkerTrajectory& m, int f) { return m.state[static_cast<std::size_t>(f)] == SampleState::Measured; }

// Estimate of marker `target` at frame f from its measured position at frame g.
std::optional<Vec3> transfer(const MarkerTrajectories& ms, const std::vector<int>& cluster, int target, int g, int f,
                             double max_rms) {
  int common[16];
  int k = 0;
  for (int i : cluster) {
    if (i == target || k == 16) continue;
    const MarkerTrajectory& m = ms.markers[static_cast<std::size_t>(i)];
    if (measured(m, f) && measured(m, g)) common[k++] = i;
  }
  if (k < 3) return std::nullopt;
  Mat3X from(3, k), to(3, k);
  for (int j = 0; j < k; ++j) {
    const MarkerTrajectory& m = ms.markers[static_cast<std::size_t>(common[j])];
    from.col(j) = m.p_F.col(g);
    to.col(j) = m.p_F.col(f);
  }
  double rms = 0;
  const auto x = fit_rigid_transform(from, to, 0.01, &rms);
  if (!x || rms > max_rms) return std::nullopt;
  return *x * ms.markers[static_cast<std::size_t>(target)].p_F.col(g);
}

}  // namespace

int fill_from_rigid_cluster(MarkerTrajectories& ms, const std::vector<int>& cluster, double max_rms_m) {
  if (cluster.size() < 4) return 0;  // a marker needs 3 others
  const int frames = ms.num_frames;
  int filled = 0;
  std::vector<std::pair<int, Vec3>> updates;
  for (int target : cluster) {
    MarkerTrajectory& t = ms.markers[static_cast<std::size_t>(target)];
    std::vector<int> prev(static_cast<std::size_t>(frames), -1), next(static_cast<std::size_t>(frames), -1);
    bool any_gap = false, any_valid = false;
    for (int f = 0, last = -1; f < frames; ++f) {
      if (measured(t, f)) last = f, any_valid = true;
      else any_gap = true;
      prev[static_cast<std::size_t>(f)] = last;
    }
    if (!any_gap || !any_valid) continue;
    for (int f = frames - 1, last = -1; f >= 0; --f) {
      if (measured(t, f)) last = f;
      next[static_cast<std::size_t>(f)] = last;
    }
    updates.clear();
    for (int f = 0; f < frames; ++f) {
      if (t.state[static_cast<std::size_t>(f)] != SampleState::Missing) continue;
      const int g0 = prev[static_cast<std::size_t>(f)], g1 = next[static_cast<std::size_t>(f)];
      std::optional<Vec3> e0, e1;
      if (g0 >= 0) e0 = transfer(ms, cluster, target, g0, f, max_rms_m);
      if (g1 >= 0) e1 = transfer(ms, cluster, target, g1, f, max_rms_m);
      if (e0 && e1) {
        const double w = static_cast<double>(f - g0) / static_cast<double>(g1 - g0);
        updates.emplace_back(f, (1 - w) * *e0 + w * *e1);
      } else if (e0) {
        updates.emplace_back(f, *e0);
      } else if (e1) {
        updates.emplace_back(f, *e1);
      }
    }
    for (const auto& [f, p] : updates) {
      t.p_F.col(f) = p;
      t.state[static_cast<std::size_t>(f)] = SampleState::Interpolated;
    }
    filled += static_cast<int>(updates.size());
  }
  return filled;
}

int ClusterPoses::valid_count() const { return static_cast<int>(std::count(valid.begin(), valid.end(), 1)); }

ClusterPoses track_cluster(const MarkerTrajectories& ms, const std::vector<int>& cluster) {
  ClusterPoses out;
  const int frames = ms.num_frames;
  out.X_F_S.assign(static_cast<std::size_t>(frames), Iso3::Identity());
  out.valid.assign(static_cast<std::size_t>(frames), 0);
  int best = 2;
  for (int f = 0; f < frames; ++f) {
    int n = 0;
    for (int i : cluster) n += measured(ms.markers[static_cast<std::size_t>(i)], f);
    if (n > best) {
      best = n;
      out.reference_frame = f;
      if (n == static_cast<int>(cluster.size())) break;
    }
  }
  if (out.reference_frame < 0) return out;
  const int r = out.reference_frame;
  std::vector<int> used;
  for (int f = 0; f < frames; ++f) {
    used.clear();
    for (int i : cluster) {
      const MarkerTrajectory& m = ms.markers[static_cast<std::size_t>(i)];
      if (measured(m, f) && measured(m, r)) used.push_back(i);
    }
    if (used.size() < 3) continue;
    Mat3X from(3, static_cast<Eigen::Index>(used.size())), to(3, static_cast<Eigen::Index>(used.size()));
    for (std::size_t j = 0; j < used.size(); ++j) {
      const MarkerTrajectory& m = ms.markers[static_cast<std::size_t>(used[j])];
      from.col(static_cast<Eigen::Index>(j)) = m.p_F.col(r);
      to.col(static_cast<Eigen::Index>(j)) = m.p_F.col(f);
    }
    double rms = 0;
    const auto x = fit_rigid_transform(from, to, 0.01, &rms);
    if (!x || rms > 0.02) continue;
    out.X_F_S[static_cast<std::size_t>(f)] = *x;
    out.valid[static_cast<std::size_t>(f)] = 1;
  }
  return out;
}

std::optional<FunctionalJoint> score_joint_centre(const ClusterPoses& a, const ClusterPoses& b, const Vec3& prior_a,
                                                  const Vec3& prior_b, double regularisation) {
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  Mat6 normal = Mat6::Zero();
  Vec6 rhs = Vec6::Zero();
  int n = 0;
  const std::size_t frames = std::min(a.valid.size(), b.valid.size());
  for (std::size_t f = 0; f < frames; ++f) {
    if (!a.valid[f] || !b.valid[f]) continue;
    Eigen::Matrix<double, 3, 6> m;
    m.leftCols<3>() = a.X_F_S[f].linear();
    m.rightCols<3>() = -b.X_F_S[f].linear();
    const Vec3 d = b.X_F_S[f].translation() - a.X_F_S[f].translation();
    normal += m.transpose() * m;
    rhs += m.transpose() * d;
    ++n;
  }
  if (n < 10) return std::nullopt;
  Vec6 prior;
  prior << prior_a, prior_b;
  const double lambda = regularisation * n;
  normal += lambda * Mat6::Identity();
  rhs += lambda * prior;
  const Vec6 x = normal.ldlt().solve(rhs);
  if (!x.allFinite()) return std::nullopt;
  FunctionalJoint j;
  j.c_a = x.head<3>();
  j.c_b = x.tail<3>();
  j.frames_used = n;
  double sum = 0;
  for (std::size_t f = 0; f < frames; ++f) {
    if (!a.valid[f] || !b.valid[f]) continue;
    sum += (a.X_F_S[f] * j.c_a - b.X_F_S[f] * j.c_b).squaredNorm();
  }
  j.rms_m = std::sqrt(sum / n);
  return j;
}

}  // namespace rt
