#pragma once
/// Balance controller of paper §IV-A (eq. 1): LQR state feedback on the pendulum model plus an
/// observer fed the measured COM and COP. Its output, the base position of the estimated state,
/// is the desired COP handed to the tracking controller.
///
/// Model vs data: BalanceController holds the designed gains and discrete matrices (immutable,
/// shareable); BalanceState holds the estimate of one run.
///
/// Per axis:
///   plant          ṡ = A s + B a                         (pendulum_model.hpp)
///   feedback       a = a_ref − K (ŝ − s_ref)             (LQR, weights Q and R)
///   observer       ŝ̇ = A ŝ + B a + L (y_m − C_m ŝ),  y_m = (c_meas, p_meas),  C_m = [I₂ 0]
///   => eq. (1)     ŝ̇ = A_b ŝ + B_b u_b,  u_b = (s_ref, a_ref, c_meas, p_meas)
///   prediction     s⁺ = A_d s + B_d c_ref,  y = C s = p     (eq. 25–26: no observer, closed loop
///                  of the model itself, discretised exactly at the planner's period)
///
/// The reference state. The paper's regulator drives the state to s_ref = E c_ref = (c_ref, c_ref,
/// 0, 0) with a_ref = 0: right for a COM reference at rest, but a moving reference is then tracked
/// with a lag of the order of velocity × 0.3 s (12 cm on a 0.15 m / 0.7 s shift) and the desired
/// COP ignores the acceleration the reference motion itself needs. With feed-forward
/// (BalanceReference::from_com_motion) the reference is the pendulum state consistent with the
/// reference COM motion,
///     s_ref = (c, c − c̈/ω², ċ, ċ − c⃛/ω²),   a_ref = c̈ − c⁗/ω²,
/// i.e. the COP the reference motion itself implies (its ZMP) and its derivative. The tracking
/// error e = s − s_ref then obeys ė = A_cl e: exact tracking of the reference COM by the model, and
/// the COP of the model is p_ref + C e. A change δ of the COM reference on top (the dynamic
/// mapping's re-planning, eq. 30–34) enters as in the paper, s_ref += E δ, which gives the error
/// dynamics ė = A_cl e + B_cl δ: eq. (25)–(26) in error coordinates, so the re-planner predicts
/// with the same (A, B, C) and adds p_ref (com_replanner.hpp).

#include "retarget/balance/pendulum_model.hpp"
#include "retarget/core/types.hpp"

namespace rt {

struct BalanceOptions {
  /// LQR state weights on (c − c_ref, p − c_ref, ċ, ṗ) [1/m², 1/m², s²/m², s²/m²].
  Vec4 q_diag = Vec4(100.0, 1.0, 1.0, 0.1);
  /// LQR weight on the base acceleration a [s⁴/m²].
  double r = 0.01;
  /// Observer design (dual LQR / steady-state Kalman): process noise on (c, p, ċ, ṗ) and
  /// measurement noise on (c_meas, p_meas). Larger process noise = faster, noisier estimate.
  Vec4 observer_process = Vec4(1e-4, 1e-4, 1e-1, 1e-1);
  Vec2 observer_measurement = Vec2(1e-6, 1e-4);
  /// Controller period [s] at which `step` integrates the observer.
  double control_period_s = 0.002;
};

/// Reference of the balance controller for both axes (columns x, y): the pendulum state s_ref (rows
/// c, p, ċ, ṗ) and the base acceleration a_ref it is driven to.
struct BalanceReference {
  Eigen::Matrix<double, 4, 2> s_ref = Eigen::Matrix<double, 4, 2>::Zero();
  Vec2 a_ref = Vec2::Zero();

  /// The paper's regulator reference: (c_ref, c_ref, 0, 0), a_ref = 0.
  static BalanceReference at_rest(const Vec2& c_ref);
  /// Feed-forward reference consistent with a COM motion: rows of `derivatives` are c, ċ, c̈, c⃛, c⁗
  /// (columns x, y) [m, m/s, m/s², m/s³, m/s⁴]; ω² = g / z_c.
  static BalanceReference from_com_motion(const Eigen::Matrix<double, 5, 2>& derivatives, double omega_sq);
  /// Adds a change δ of the COM reference through the paper's channel: s_ref += E δ.
  void add_com_offset(const Vec2& delta);
  Vec2 cop() const { return s_ref.row(1).transpose(); }
};

/// Discrete closed-loop model of the balance controller (eq. 25–26) for one axis.
struct ClosedLoopModel {
  double dt_s = 0.005;
  Mat4 A = Mat4::Identity();     ///< s⁺ = A s + B c_ref
  Vec4 B = Vec4::Zero();
  Eigen::RowVector4d C = Eigen::RowVector4d(0, 1, 0, 0);  ///< y = C s: the COP
};

/// Estimated pendulum state of both horizontal axes: column 0 = x, column 1 = y, rows (c, p, ċ, ṗ).
struct BalanceState {
  Eigen::Matrix<double, 4, 2> s_hat = Eigen::Matrix<double, 4, 2>::Zero();

  /// Desired COP (the base position of the estimate), W frame, [m].
  Vec2 desired_cop() const { return s_hat.row(1).transpose(); }
  Vec2 com() const { return s_hat.row(0).transpose(); }
  Vec2 com_velocity() const { return s_hat.row(2).transpose(); }
};

class BalanceController {
 public:
  BalanceController(const PendulumModel& model, const BalanceOptions& options = {});

  const PendulumModel& model() const { return model_; }
  const BalanceOptions& options() const { return options_; }
  /// LQR gain (1 x 4) and observer gain (4 x 2).
  const Eigen::RowVector4d& K() const { return K_; }
  const Eigen::Matrix<double, 4, 2>& L() const { return L_; }
  /// Continuous eq. (1) matrices: A_b (4 x 4) and B_b (4 x 7) for u_b = (s_ref, a_ref, c_meas, p_meas).
  /// With the paper's reference s_ref = E c_ref, a_ref = 0 the input matrix reduces to
  /// [B_b·(E, 0, 0, 0)ᵀ, L] for (c_ref, c_meas, p_meas).
  const Mat4& A_b() const { return A_b_; }
  const Eigen::Matrix<double, 4, 7>& B_b() const { return B_b_; }
  /// Continuous closed loop of the model under state feedback: ṡ = A_cl s + B_cl c_ref.
  const Mat4& A_cl() const { return A_cl_; }
  const Vec4& B_cl() const { return B_cl_; }

  /// Eq. (25)–(26) discretised (zero-order hold on c_ref) at `dt_s`.
  ClosedLoopModel closed_loop_model(double dt_s) const;

  /// Initial estimate at rest: COM and COP at `p_W_com` (horizontal), zero velocities.
  BalanceState rest_state(const Vec2& p_W_com) const;

  /// One control period: integrates eq. (1) exactly over control_period_s with the inputs held,
  /// and returns the desired COP (= state.desired_cop()).
  Vec2 step(BalanceState& state, const BalanceReference& ref, const Vec2& c_meas, const Vec2& p_meas) const;
  /// The paper's regulator: step with BalanceReference::at_rest(c_ref).
  Vec2 step(BalanceState& state, const Vec2& c_ref, const Vec2& c_meas, const Vec2& p_meas) const {
    return step(state, BalanceReference::at_rest(c_ref), c_meas, p_meas);
  }

 private:
  PendulumModel model_;
  BalanceOptions options_;
  Eigen::RowVector4d K_;
  Eigen::Matrix<double, 4, 2> L_;
  Mat4 A_b_;
  Eigen::Matrix<double, 4, 7> B_b_;
  Mat4 A_cl_;
  Vec4 B_cl_;
  Mat4 A_b_d_;                      ///< eq. (1) discretised at control_period_s
  Eigen::Matrix<double, 4, 7> B_b_d_;
};

}  // namespace rt
