#pragma once
/// Chart coordinates of a robot configuration for the refine NLP (private to rt_refine).
///
/// The refine pass represents a trajectory as a cubic B-spline (bspline.hpp), which needs a vector
/// space: the root quaternion is replaced by yaw and tilt,
///
///   x = [p_W_root (3), ψ (1), a, b (2), joints (nu)]          (size nv = 6 + nu)
///   R_W_root = Rz(ψ) · Exp([a, b, 0])
///
/// ψ is the twist about the world vertical (unwrapped along a trajectory, so turning clips are
/// continuous) and (a, b) the tilt as a rotation vector about a horizontal axis of the yawed frame.
/// The chart covers every orientation except the root upside down (tilt = π); the pass checks
/// tilt_angle() before using it. Joints are identical in q and x, so joint limits stay plain bounds.
///
/// Derivatives: the generalised velocity v of robot_model.hpp has the root angular velocity in the
/// root frame; ω_root = root_rate_matrix(a, b) · (ψ̇, ȧ, ḃ), so a MuJoCo Jacobian J (columns for v)
/// becomes a chart Jacobian by multiplying its columns 3..5 by that matrix (to_chart_jacobian).

#include <array>

#include "retarget/core/types.hpp"

namespace rt::refine {

/// Yaw ψ [rad] of a root quaternion (w x y z), on the branch nearest `yaw_hint` (2π unwrapping).
double root_yaw(const Quat& R_W_root, double yaw_hint);

/// Tilt [rad] of a root orientation: the angle between its z axis and the world vertical.
double tilt_angle(const Quat& R_W_root);

/// Chart coordinates of q (nq -> nv); ψ is unwrapped to the branch nearest `yaw_hint`.
VecX chart_from_q(const VecXCRef& q, double yaw_hint);

/// Configuration q (nq) of chart coordinates x (nv).
void q_from_chart(const VecXCRef& x, VecXRef q);

/// Root orientation of (ψ, a, b).
Quat root_rotation(double yaw, double a, double b);

/// 3 x 3 matrix M with ω_root (root frame) = M · (ψ̇, ȧ, ḃ) at tilt (a, b).
Mat3 root_rate_matrix(double a, double b);

/// Derivatives of the root's world angular velocity per unit tilt rate, ω_a = Rz(ψ) J_l(s) e_x and
/// ω_b = Rz(ψ) J_l(s) e_y, with respect to the tilt coordinates: out[2 i + j] = ∂ω_j / ∂s_i
/// (i, j: 0 = a, 1 = b). The yaw rate's ω = e_z is constant. Used for the constraint curvature.
void root_omega_derivatives(double yaw, double a, double b, std::array<Vec3, 4>& out);

/// SO(3) right Jacobian J_r(θ) (Exp(θ + δ) ≈ Exp(θ) Exp(J_r(θ) δ)).
Mat3 so3_right_jacobian(const Vec3& theta);

/// Inverse of the SO(3) left Jacobian: log(Exp(δ) Exp(φ)) ≈ φ + J_l⁻¹(φ) δ.
Mat3 so3_left_jacobian_inverse(const Vec3& phi);

/// Rotation vector of a rotation matrix (angle in [0, π]).
Vec3 so3_log(const Mat3& R);

}  // namespace rt::refine
