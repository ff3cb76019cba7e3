#include "src/refine/trajectory_chart.hpp"

#include <cmath>

namespace rt::refine {

namespace {

Mat3 skew(const Vec3& v) {
  Mat3 S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

Vec3 quat_log(const Quat& q_in) {
  Quat q = q_in.normalized();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s < 1e-12) return 2.0 * q.vec();  // first order: θ ≈ 2 sin(θ/2)
  return (2.0 * std::atan2(s, q.w()) / s) * q.vec();
}

}  // namespace

double root_yaw(const Quat& R_W_root, double yaw_hint) {
  // Swing-twist decomposition about z: R = Swing · Rz(ψ), the twist quaternion being (w, 0, 0, z).
  const double psi = 2.0 * std::atan2(R_W_root.z(), R_W_root.w());
  return psi + 2.0 * M_PI * std::round((yaw_hint - psi) / (2.0 * M_PI));
}

double tilt_angle(const Quat& R_W_root) {
  const Vec3 z = R_W_root.normalized() * Vec3::UnitZ();
  return std::acos(std::clamp(z.z(), -1.0, 1.0));
}

VecX chart_from_q(const VecXCRef& q, double yaw_hint) {
  const Eigen::Index nu = q.size() - 7;
  VecX x(6 + nu);
  x.head<3>() = q.head<3>();
  const Quat R(q[3], q[4], q[5], q[6]);
  const double psi = root_yaw(R.normalized(), yaw_hint);
  const Quat twist(AngleAxis(psi, Vec3::UnitZ()));
  // R = Swing · Rz(ψ) = Rz(ψ) · Exp(Rz(-ψ) log(Swing)).
  const Vec3 s_W = quat_log(R.normalized() * twist.conjugate());
  const Vec3 s = twist.conjugate() * s_W;
  x[3] = psi;
  x[4] = s.x();
  x[5] = s.y();
  x.tail(nu) = q.tail(nu);
  return x;
}

Quat root_rotation(double yaw, double a, double b) {
  const Vec3 s(a, b, 0);
  const double th = s.norm();
  const Quat tilt = th < 1e-15 ? Quat::Identity() : Quat(AngleAxis(th, s / th));
  return Quat(AngleAxis(yaw, Vec3::UnitZ())) * tilt;
}

void q_from_chart(const VecXCRef& x, VecXRef q) {
  const Eigen::Index nu = x.size() - 6;
  q.head<3>() = x.head<3>();
  const Quat R = root_rotation(x[3], x[4], x[5]);
  q[3] = R.w();
  q[4] = R.x();
  q[5] = R.y();
  q[6] = R.z();
  q.tail(nu) = x.tail(nu);
}

Mat3 so3_right_jacobian(const Vec3& theta) {
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  const Mat3 K = skew(theta);
  double c1, c2;  // (1 - cos t) / t², (t - sin t) / t³
  if (t < 1e-4) {
    c1 = 0.5 - t2 / 24.0;
    c2 = 1.0 / 6.0 - t2 / 120.0;
  } else {
    c1 = (1.0 - std::cos(t)) / t2;
    c2 = (t - std::sin(t)) / (t2 * t);
  }
  return Mat3::Identity() - c1 * K + c2 * K * K;
}

Mat3 so3_left_jacobian_inverse(const Vec3& phi) {
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const Mat3 K = skew(phi);
  double c;  // 1/t² − (1 + cos t) / (2 t sin t)
  if (t < 1e-4)
    c = 1.0 / 12.0 + t2 / 720.0;
  else if (t > M_PI - 1e-6)
    c = 1.0 / t2;  // the limit at π (the log is not differentiable there; the bound keeps it finite)
  else
    c = 1.0 / t2 - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t));
  return Mat3::Identity() - 0.5 * K + c * K * K;
}

Mat3 root_rate_matrix(double a, double b) {
  // R = Rz(ψ) E(s): Rᵀ Ṙ = Eᵀ [e_z]× E ψ̇ + [J_r(s) ṡ]×, so ω = Eᵀ e_z ψ̇ + J_r(s) ṡ.
  const Vec3 s(a, b, 0);
  const double th = s.norm();
  const Mat3 E = th < 1e-15 ? Mat3::Identity() : Mat3(AngleAxis(th, s / th));
  const Mat3 Jr = so3_right_jacobian(s);
  Mat3 M;
  M.col(0) = E.transpose().col(2);
  M.col(1) = Jr.col(0);
  M.col(2) = Jr.col(1);
  return M;
}

void root_omega_derivatives(double yaw, double a, double b, std::array<Vec3, 4>& out) {
  // J_l(s) = J_r(−s); its derivative by central differences (J_l is smooth; the step error is
  // O(h²) ≈ 1e-12, far below what a Hessian of the Lagrangian needs).
  const Mat3 Rz = AngleAxis(yaw, Vec3::UnitZ()).toRotationMatrix();
  const double h = 1e-6;
  for (int i = 0; i < 2; ++i) {
    Vec3 sp(a, b, 0), sm(a, b, 0);
    sp[i] += h;
    sm[i] -= h;
    const Mat3 dJ = (so3_right_jacobian(-sp) - so3_right_jacobian(-sm)) / (2 * h);
    for (int j = 0; j < 2; ++j) out[static_cast<std::size_t>(2 * i + j)] = Rz * dJ.col(j);
  }
}

Vec3 so3_log(const Mat3& R) { return quat_log(Quat(R)); }

}  // namespace rt::refine
