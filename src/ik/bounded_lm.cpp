#include "retarget/ik/bounded_lm.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"

namespace rt {

BoundedLmResult solve_bounded_lm(const LeastSquaresProblem& problem, VecX& x, const BoundedLmOptions& o) {
  const int n = problem.tangent_size;
  BoundedLmResult result;
  VecX lower(n), upper(n), g(n), delta(n);
  MatX H(n, n);
  double cost = problem.evaluate(x, &H, &g);
  ++result.evaluations;
  result.initial_cost = cost;
  double lambda = o.initial_damping * std::max(H.diagonal().mean(), 1e-12);
  std::vector<int> free;
  free.reserve(static_cast<std::size_t>(n));

  for (int it = 0; it < o.max_iterations; ++it) {
    result.iterations = it + 1;
    problem.step_bounds(x, lower, upper);
    // Active set: a variable on a bound whose descent direction points out of the box is frozen.
    free.clear();
    for (int i = 0; i < n; ++i) {
      const bool at_lower = lower[i] >= -1e-12 && g[i] > 0;
      const bool at_upper = upper[i] <= 1e-12 && g[i] < 0;
      if (!at_lower && !at_upper) free.push_back(i);
    }
    result.active_bounds = n - static_cast<int>(free.size());
    if (free.empty()) {
      result.converged = true;
      break;
    }
    const int nf = static_cast<int>(free.size());
    MatX Hf(nf, nf);
    VecX gf(nf);
    for (int a = 0; a < nf; ++a) {
      gf[a] = g[free[static_cast<std::size_t>(a)]];
      for (int b = 0; b < nf; ++b) Hf(a, b) = H(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
    }

    bool accepted = false;
    while (!accepted) {
      MatX A = Hf;
      A.diagonal().array() += lambda;
      const VecX df = -A.llt().solve(gf);  // H + λI is positive definite
      delta.setZero();
      for (int a = 0; a < nf; ++a) delta[free[static_cast<std::size_t>(a)]] = df[a];
      // Projection onto the box (the frozen variables stay at zero).
      delta = delta.cwiseMax(lower).cwiseMin(upper);
      if (delta.lpNorm<Eigen::Infinity>() < o.step_tolerance) {
        result.converged = true;
        break;
      }
      const VecX x_new = problem.retract(x, delta);
      const double cost_new = problem.evaluate(x_new, nullptr, nullptr);
      ++result.evaluations;
      if (std::isfinite(cost_new) && cost_new < cost) {
        const double decrease = (cost - cost_new) / std::max(cost, 1e-300);
        x = x_new;
        cost = cost_new;
        lambda = std::max(lambda / 3.0, o.min_damping);
        accepted = true;
        if (decrease < o.cost_tolerance) result.converged = true;
      } else {
        lambda *= 4.0;
        if (lambda > o.max_damping) {
          result.converged = true;  // no further decrease possible at this point
          break;
        }
      }
    }
    if (result.converged) break;
    cost = problem.evaluate(x, &H, &g);
    ++result.evaluations;
  }
  result.cost = cost;
  return result;
}

}  // namespace rt
