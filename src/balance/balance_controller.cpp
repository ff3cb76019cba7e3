#include "retarget/balance/balance_controller.hpp"

#include "retarget/balance/lqr.hpp"
#include "retarget/core/error.hpp"

namespace rt {

BalanceController::BalanceController(const PendulumModel& model, const BalanceOptions& options)
    : model_(model), options_(options) {
  if (!(model.com_height_m > 0.05 && model.com_height_m < 10))
    throw InputError("balance model: COM height must be in (0.05, 10) m, got " + std::to_string(model.com_height_m));
  if (!(options.r > 0) || !(options.q_diag.array() >= 0).all())
    throw InputError("balance options: LQR weights must be Q >= 0 and R > 0");
  if (!(options.control_period_s > 0)) throw InputError("balance options: control period must be > 0");

  const Mat4 A = model_.A();
  const Vec4 B = model_.B();
  const MatX R = MatX::Constant(1, 1, options.r);
  K_ = lqr_gain(A, B, options.q_diag.asDiagonal().toDenseMatrix(), R);

  // Observer by duality: L = P Cᵀ Rₒ⁻¹ with P from the CARE of (Aᵀ, Cᵀ).
  Eigen::Matrix<double, 2, 4> Cm = Eigen::Matrix<double, 2, 4>::Zero();
  Cm(0, 0) = 1;
  Cm(1, 1) = 1;
  const MatX Ro = options.observer_measurement.asDiagonal().toDenseMatrix();
  const MatX Po = solve_care(A.transpose(), Cm.transpose(), options.observer_process.asDiagonal().toDenseMatrix(), Ro);
  L_ = Po * Cm.transpose() * Ro.inverse();

  const Vec4 E = PendulumModel::E();
  A_cl_ = A - B * K_;
  B_cl_ = B * (K_ * E);
  A_b_ = A - B * K_ - L_ * Cm;
  B_b_.leftCols<4>() = B * K_;
  B_b_.col(4) = B;
  B_b_.rightCols<2>() = L_;

  const auto [Ad, Bd] = discretize_zoh(A_b_, B_b_, options.control_period_s);
  A_b_d_ = Ad;
  B_b_d_ = Bd;
}

ClosedLoopModel BalanceController::closed_loop_model(double dt_s) const {
  if (!(dt_s > 0)) throw InputError("balance model: discretisation period must be > 0");
  const auto [Ad, Bd] = discretize_zoh(A_cl_, B_cl_, dt_s);
  ClosedLoopModel m;
  m.dt_s = dt_s;
  m.A = Ad;
  m.B = Bd;
  return m;
}

BalanceState BalanceController::rest_state(const Vec2& p_W_com) const {
  BalanceState s;
  s.s_hat.row(0) = p_W_com.transpose();
  s.s_hat.row(1) = p_W_com.transpose();
  return s;
}

Vec2 BalanceController::step(BalanceState& state, const BalanceReference& ref, const Vec2& c_meas,
                             const Vec2& p_meas) const {
  for (int axis = 0; axis < 2; ++axis) {
    Eigen::Matrix<double, 7, 1> u;
    u << ref.s_ref.col(axis), ref.a_ref[axis], c_meas[axis], p_meas[axis];
    state.s_hat.col(axis) = A_b_d_ * state.s_hat.col(axis) + B_b_d_ * u;
  }
  return state.desired_cop();
}

BalanceReference BalanceReference::at_rest(const Vec2& c_ref) {
  BalanceReference r;
  r.s_ref.row(0) = c_ref.transpose();
  r.s_ref.row(1) = c_ref.transpose();
  return r;
}

BalanceReference BalanceReference::from_com_motion(const Eigen::Matrix<double, 5, 2>& d, double omega_sq) {
  BalanceReference r;
  r.s_ref.row(0) = d.row(0);
  r.s_ref.row(1) = d.row(0) - d.row(2) / omega_sq;
  r.s_ref.row(2) = d.row(1);
  r.s_ref.row(3) = d.row(1) - d.row(3) / omega_sq;
  r.a_ref = (d.row(2) - d.row(4) / omega_sq).transpose();
  return r;
}

void BalanceReference::add_com_offset(const Vec2& delta) {
  s_ref.row(0) += delta.transpose();
  s_ref.row(1) += delta.transpose();
}

}  // namespace rt
