#include "retarget/balance/com_replanner.hpp"

#include "retarget/core/error.hpp"

namespace rt {

CopPredictor::CopPredictor(const ClosedLoopModel& model, int horizon) : model_(model), horizon_(horizon) {
  if (horizon < 1 || horizon > 100000) throw InputError("COM re-planning: horizon must be in [1, 100000]");
  C_A_pow_.resize(static_cast<std::size_t>(horizon) + 1);
  impulse_.resize(static_cast<std::size_t>(horizon));
  C_A_pow_[0] = model.C;
  for (int n = 1; n <= horizon; ++n) C_A_pow_[static_cast<std::size_t>(n)] = C_A_pow_[static_cast<std::size_t>(n - 1)] * model.A;
  for (int j = 0; j < horizon; ++j) impulse_[static_cast<std::size_t>(j)] = C_A_pow_[static_cast<std::size_t>(j)] * model.B;
}

void CopPredictor::predict(const Mat42& x0, const Eigen::Ref<const Mat2X>& U, int n, Eigen::Ref<Mat2X> y_out) const {
  RT_DEMAND(n <= U.cols() && n <= y_out.cols(), "CopPredictor::predict: window too short");
  Mat42 x = x0;
  for (int k = 0; k < n; ++k) {
    x = model_.A * x + model_.B * U.col(k).transpose();
    y_out.col(k) = (model_.C * x).transpose();
  }
}

Vec2 CopPredictor::predict_at(const Mat42& x0, const Eigen::Ref<const Mat2X>& U, int n) const {
  RT_DEMAND(n >= 1 && n <= horizon_ && n <= U.cols(), "CopPredictor::predict_at: n out of range");
  Vec2 y = (C_A_pow(n) * x0).transpose();
  for (int k = 0; k < n; ++k) y += impulse(n - 1 - k) * U.col(k);
  return y;
}

ComReplanner::ComReplanner(const ClosedLoopModel& model, const ComReplanOptions& options)
    : options_(options), predictor_(model, options.horizon) {
  if (!(options.h_max >= 0 && options.h_max <= 1)) throw InputError("COM re-planning: h_max must be in [0, 1]");
  if (!(options.w > 0)) throw InputError("COM re-planning: w must be > 0");
}

Vec2 ComReplanner::solve(const Mat42& x0, Eigen::Ref<Mat2X> U, int n, const Vec2& y_ref, const Vec2& y_offset_n) const {
  // y_n = ŷ_n + mᵀδ with m_k = C A^{n−1−k} B. Minimising ½|y_n − y_ref|² + ½ δᵀWδ gives
  // (W + m mᵀ) δ = −m (ŷ_n − y_ref); Sherman–Morrison with diagonal W makes it O(n).
  const Vec2 y_hat = y_offset_n + predictor_.predict_at(x0, U, n);
  const Vec2 error = y_hat - y_ref;
  double m_Winv_m = 0;
  for (int k = 0; k < n; ++k) {
    const double m = predictor_.impulse(n - 1 - k);
    m_Winv_m += m * m / (options_.w * (k + 1.0) * (k + 1.0));
  }
  const Vec2 scale = error / (1.0 + m_Winv_m);
  for (int k = 0; k < n; ++k) {
    const double m = predictor_.impulse(n - 1 - k);
    U.col(k) -= (m / (options_.w * (k + 1.0) * (k + 1.0))) * scale;
  }
  return y_hat - m_Winv_m * scale;
}

std::optional<ReplanEvent> ComReplanner::step(const Mat42& x0, Eigen::Ref<Mat2X> U,
                                              const std::function<const SupportFrame&(int)>& support,
                                              const Mat2X* y_offset) const {
  const int N = options_.horizon;
  RT_DEMAND(U.cols() >= N, "ComReplanner::step: the COM window must hold N columns");
  RT_DEMAND(!y_offset || y_offset->cols() >= N, "ComReplanner::step: the COP offset must hold N columns");
  Mat2X y(2, N);
  predictor_.predict(x0, U, N, y);
  if (y_offset) y += y_offset->leftCols(N);

  auto finish = [&](int kind, int n, const Vec2& y_ref) {
    ReplanEvent e;
    e.kind = kind;
    e.n = n;
    e.y_predicted = y.col(n - 1);
    e.y_ref = y_ref;
    const Mat2X before = U.leftCols(n);
    e.y_after = solve(x0, U, n, y_ref, y_offset ? Vec2(y_offset->col(n - 1)) : Vec2::Zero());
    e.max_shift_m = (U.leftCols(n) - before).colwise().norm().maxCoeff();
    return e;
  };
  const double N_d = static_cast<double>(N);

  // Case 1: the first future step whose predicted COP leaves that step's support polygon.
  for (int n = 1; n <= N; ++n) {
    const SupportFrame& s = support(n);
    if (s.polygon.empty()) continue;  // flight phase: nothing to balance on
    const Vec2 y_n = y.col(n - 1);
    if (s.polygon.contains(y_n, options_.margin_m)) continue;
    const double h = options_.h_max * (N - n) / N_d;
    const Vec2 y_ref = h * s.polygon.closest_boundary_point(y_n) + (1 - h) * s.polygon.centroid();
    return finish(1, n, y_ref);
  }

  // Case 2: the first new contact whose predicted COP is still inside the previous polygon.
  for (int n = 1; n <= N; ++n) {
    const SupportFrame& before = support(n - 1);
    const SupportFrame& now = support(n);
    for (int foot = 0; foot < 2; ++foot) {
      if (before.contact[static_cast<std::size_t>(foot)] || !now.contact[static_cast<std::size_t>(foot)]) continue;
      const Vec2 y_n = y.col(n - 1);
      const Vec2 c2 = now.sole_center_W[static_cast<std::size_t>(foot)];
      const auto b2 = before.polygon.exit_point(y_n, c2);
      if (!b2) continue;  // the COP already left the old polygon (or no old polygon)
      const double h = options_.h_max * (N - n) / N_d;
      return finish(2, n, h * *b2 + (1 - h) * c2);
    }
  }
  return std::nullopt;
}

}  // namespace rt
