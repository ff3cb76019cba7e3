#pragma once
/// Control-aware COM re-planning (paper §VI, eq. 25–34; design.md §3.4).
///
/// The closed-loop balance model (eq. 25–26) predicts the COP N steps ahead from a state and the
/// reference COM. When the prediction leaves the support polygon of that future frame (case 1), or
/// a foot is about to land while the COP is still inside the previous polygon (case 2), a new COM
/// window U' minimising eq. (31) is computed in closed form and replaces the reference.
///
/// Both horizontal axes use the same scalar model, so every quantity below has an x and a y
/// column/row (2 x n matrices: row 0 = x, row 1 = y).

#include <array>
#include <functional>
#include <optional>

#include "retarget/balance/balance_controller.hpp"
#include "retarget/balance/support_polygon.hpp"

namespace rt {

using Mat42 = Eigen::Matrix<double, 4, 2>;
using Mat2X = Eigen::Matrix2Xd;

/// Predicts the COP of the closed-loop model (eq. 27) with precomputed C·Aⁿ and impulse responses
/// C·Aʲ·B, so a full-window prediction costs O(N) and any single ŷ_n costs O(n).
class CopPredictor {
 public:
  CopPredictor(const ClosedLoopModel& model, int horizon);

  int horizon() const { return horizon_; }
  const ClosedLoopModel& model() const { return model_; }
  /// C·Aⁿ for n = 0..horizon.
  const Eigen::RowVector4d& C_A_pow(int n) const { return C_A_pow_[static_cast<std::size_t>(n)]; }
  /// C·Aʲ·B for j = 0..horizon-1 (impulse response; column n−1−k of C·M_n, eq. 28).
  double impulse(int j) const { return impulse_[static_cast<std::size_t>(j)]; }

  /// ŷ_1..ŷ_n (2 x n) from state x0 and inputs u_0..u_{n−1} (U: 2 x ≥ n), by forward recursion.
  void predict(const Mat42& x0, const Eigen::Ref<const Mat2X>& U, int n, Eigen::Ref<Mat2X> y_out) const;
  /// ŷ_n alone via eq. (27): C Aⁿ x0 + Σ_k C A^{n−1−k} B u_k.
  Vec2 predict_at(const Mat42& x0, const Eigen::Ref<const Mat2X>& U, int n) const;

 private:
  ClosedLoopModel model_;
  int horizon_;
  std::vector<Eigen::RowVector4d> C_A_pow_;
  std::vector<double> impulse_;
};

struct ComReplanOptions {
  int horizon = 100;         ///< N: prediction window in model steps (paper: 100)
  double period_s = 0.005;   ///< discretisation of eq. (25) [s] (paper: 5 ms; N·period = 0.5 s look-ahead)
  double h_max = 0.8;        ///< eq. (33)/(34): how close to the border y_ref may be, h = h_max (N − n)/N
  double w = 0.01;           ///< eq. (31): W_ii = w·i², penalty on changing the COM reference late in the window
  double margin_m = 0.0;     ///< case 1 fires when the predicted COP is less than this inside the polygon
};

/// What the support looks like at one future model step.
struct SupportFrame {
  SupportPolygon polygon;                  ///< hull of the soles in contact (W, horizontal)
  std::array<bool, 2> contact{{true, true}};  ///< left, right in contact
  std::array<Vec2, 2> sole_center_W{{Vec2::Zero(), Vec2::Zero()}};  ///< sole centres (used by case 2)
};

/// One activation of the re-planner.
struct ReplanEvent {
  int kind = 0;        ///< 1: predicted COP leaves the polygon; 2: a foot lands while the COP is inside the old polygon
  int n = 0;           ///< model steps ahead where the event was predicted
  Vec2 y_predicted = Vec2::Zero();  ///< ŷ_n before re-planning
  Vec2 y_ref = Vec2::Zero();        ///< desired COP at step n (eq. 33/34)
  Vec2 y_after = Vec2::Zero();      ///< ŷ_n after re-planning
  double max_shift_m = 0;           ///< largest change of the COM reference in the window
};

class ComReplanner {
 public:
  ComReplanner(const ClosedLoopModel& model, const ComReplanOptions& options);

  const ComReplanOptions& options() const { return options_; }
  const CopPredictor& predictor() const { return predictor_; }

  /// One planning step at the current time.
  /// `x0`: model state now; `U`: reference COM for the next N steps (2 x N, u_0 = now), modified in
  /// place when re-planning activates; `support(k)`: the support k steps ahead, k = 0..N.
  /// `y_offset` (2 x N, optional): a known part of the COP added to the model's output, column n−1
  /// for ŷ_n. With the balance controller's feed-forward (balance_controller.hpp) the model runs in
  /// error coordinates: x0 = ŝ − s_ref, U = the COM changes δ, and y_offset = the reference COP
  /// p_ref over the window; eq. (27)–(34) are unchanged otherwise.
  std::optional<ReplanEvent> step(const Mat42& x0, Eigen::Ref<Mat2X> U,
                                  const std::function<const SupportFrame&(int)>& support,
                                  const Mat2X* y_offset = nullptr) const;

  /// Closed-form minimiser of eq. (31) for target `y_ref` at step n: adds δ = U' − Û to the first
  /// n columns of U and returns ŷ_n after the change (including `y_offset_n`, the known part of
  /// the COP at step n). W_ii = w·i² (i = 1..n).
  Vec2 solve(const Mat42& x0, Eigen::Ref<Mat2X> U, int n, const Vec2& y_ref, const Vec2& y_offset_n = Vec2::Zero()) const;

 private:
  ComReplanOptions options_;
  CopPredictor predictor_;
};

}  // namespace rt
