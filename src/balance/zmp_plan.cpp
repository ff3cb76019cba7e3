#include "retarget/balance/zmp_plan.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"

namespace rt {

namespace {

// Linear combination Σ_j a_j c_{k_j} of grid samples (one coordinate), in mapped unknowns.
struct Stencil {
  int sample[4];
  double coefficient[4];
  int size;
};

}  // namespace

ZmpPlan plan_com_zmp(const std::vector<ZmpPlanSample>& samples, const ZmpPlanOptions& o) {
  const int K = static_cast<int>(samples.size());
  RT_DEMAND(K > 0, "plan_com_zmp: no samples");
  RT_DEMAND(o.period_s > 0 && o.com_weight > 0 && o.jerk_weight >= 0 && o.flight_acceleration_weight >= 0 &&
                o.zmp_centre_weight >= 0,
            "plan_com_zmp: invalid options");
  const double dt = o.period_s;

  // Unknowns: one 2-vector per distinct sample. Rest at an end merges its three samples into one.
  const bool rest_start = o.rest_at_start && K >= 7, rest_end = o.rest_at_end && K >= 7;
  std::vector<int> var(static_cast<std::size_t>(K));
  int nvar = 0;
  for (int k = 0; k < K; ++k) {
    const bool merged = (rest_start && (k == 1 || k == 2)) || (rest_end && (k == K - 2 || k == K - 1));
    var[static_cast<std::size_t>(k)] = merged ? nvar - 1 : nvar++;
  }
  const int n = 2 * nvar;

  std::vector<Eigen::Triplet<double>> h_entries;
  VecX g = VecX::Zero(n);
  // Adds ½ w (Σ a_j c_{k_j} − t)² for both coordinates (t per coordinate).
  auto add_square = [&](const Stencil& st, double w, const Vec2& t) {
    for (int axis = 0; axis < 2; ++axis) {
      for (int a = 0; a < st.size; ++a) {
        const int ia = 2 * var[static_cast<std::size_t>(st.sample[a])] + axis;
        g[ia] -= w * st.coefficient[a] * t[axis];
        for (int b = 0; b < st.size; ++b) {
          const int ib = 2 * var[static_cast<std::size_t>(st.sample[b])] + axis;
          if (ib <= ia) h_entries.emplace_back(ia, ib, w * st.coefficient[a] * st.coefficient[b]);
        }
      }
    }
  };
  for (int k = 0; k < K; ++k)
    add_square({{k, 0, 0, 0}, {1, 0, 0, 0}, 1}, o.com_weight * samples[static_cast<std::size_t>(k)].com_weight_scale,
               samples[static_cast<std::size_t>(k)].com_ref_W);
  const double dt2 = dt * dt, dt3 = dt2 * dt;
  if (o.jerk_weight > 0)
    for (int k = 3; k < K; ++k)
      add_square({{k, k - 1, k - 2, k - 3}, {1 / dt3, -3 / dt3, 3 / dt3, -1 / dt3}, 4}, o.jerk_weight, Vec2::Zero());
  if (o.flight_acceleration_weight > 0)
    for (int k = 1; k + 1 < K; ++k)
      if (samples[static_cast<std::size_t>(k)].support.empty())
        add_square({{k - 1, k, k + 1, 0}, {1 / dt2, -2 / dt2, 1 / dt2, 0}, 3}, o.flight_acceleration_weight, Vec2::Zero());
  // ZMP rows: nᵀ(c_k − h (c_{k+1} − 2c_k + c_{k−1}) / dt²) ≤ d − nᵀΔp_k (soft: sparse_qp.hpp).
  std::vector<Eigen::Triplet<double>> a_entries;
  std::vector<double> rhs;
  std::vector<int> row_sample;
  auto zmp_stencil = [&](int k) -> Stencil {
    const double h = samples[static_cast<std::size_t>(k)].zmp_gain_s2 / dt2;
    if (k == 0 || k == K - 1) return {{k, 0, 0, 0}, {1, 0, 0, 0}, 1};
    return {{k - 1, k, k + 1, 0}, {-h, 1 + 2 * h, -h, 0}, 3};
  };
  if (o.zmp_centre_weight > 0)
    for (int k = 0; k < K; ++k) {
      const ZmpPlanSample& s = samples[static_cast<std::size_t>(k)];
      if (!s.support.empty()) add_square(zmp_stencil(k), o.zmp_centre_weight, s.zmp_centre_W - s.zmp_offset_W);
    }
  for (int k = 0; k < K; ++k) {
    const ZmpPlanSample& s = samples[static_cast<std::size_t>(k)];
    if (s.support.empty()) continue;
    const Stencil st = zmp_stencil(k);
    for (const HalfPlane& hp : s.support) {
      const int row = static_cast<int>(rhs.size());
      for (int a = 0; a < st.size; ++a)
        for (int axis = 0; axis < 2; ++axis)
          a_entries.emplace_back(row, 2 * var[static_cast<std::size_t>(st.sample[a])] + axis, hp.n[axis] * st.coefficient[a]);
      rhs.push_back(hp.d - hp.n.dot(s.zmp_offset_W));
      row_sample.push_back(k);
    }
  }
  const int m = static_cast<int>(rhs.size());
  SparseMat H(n, n);
  H.setFromTriplets(h_entries.begin(), h_entries.end());  // duplicates are summed
  SparseMat A(m, n);
  A.setFromTriplets(a_entries.begin(), a_entries.end());
  const VecX b = Eigen::Map<const VecX>(rhs.data(), m);

  VecX x;
  ZmpPlan plan;
  SparseQpOptions qp = o.qp;
  qp.penalty = o.violation_weight;
  plan.solver = solve_sparse_qp(H, g, A, b, x, qp);
  if (plan.solver.status == SparseQpStatus::Failed) return plan;
  plan.com_W.resize(2, K);
  for (int k = 0; k < K; ++k) plan.com_W.col(k) = x.segment<2>(2 * var[static_cast<std::size_t>(k)]);
  std::vector<double> sample_violation(static_cast<std::size_t>(K), 0.0);
  const VecX violation = A * x - b;
  for (int i = 0; i < m; ++i) {
    double& v = sample_violation[static_cast<std::size_t>(row_sample[static_cast<std::size_t>(i)])];
    v = std::max(v, violation[i]);
  }
  for (double v : sample_violation) {
    plan.max_violation_m = std::max(plan.max_violation_m, v);
    plan.violated_samples += v > 1e-4;
  }
  plan.zmp_W.resize(2, K);
  for (int k = 0; k < K; ++k) {
    const Stencil st = zmp_stencil(k);
    Vec2 p = samples[static_cast<std::size_t>(k)].zmp_offset_W;
    for (int a = 0; a < st.size; ++a) p += st.coefficient[a] * plan.com_W.col(st.sample[a]);
    plan.zmp_W.col(k) = p;
    const double shift = (plan.com_W.col(k) - samples[static_cast<std::size_t>(k)].com_ref_W).norm();
    if (shift > plan.max_shift_m) {
      plan.max_shift_m = shift;
      plan.max_shift_sample = k;
    }
  }
  return plan;
}

}  // namespace rt
