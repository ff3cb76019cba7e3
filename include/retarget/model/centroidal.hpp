#pragma once
/// Centroidal momentum and the multibody ZMP of a motion (design.md §6 "ZMP"; issue 14).
///
/// The ground must supply the rate of change of the robot's momentum against gravity. With total
/// mass m, COM c, centroidal angular momentum L (about c) and the floor at z = 0, the point where
/// the horizontal moment of that wrench vanishes is
///
///     p_x = c_x − (c_z c̈_x + L̇_y / m) / (g + c̈_z),     p_y = c_y − (c_z c̈_y − L̇_x / m) / (g + c̈_z).
///
/// This is the ZMP the balance controller must realise with the feet's contact forces; a motion is
/// dynamically feasible on flat ground only where p lies in the support polygon.

#include "retarget/core/types.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {

class RobotModel;

struct CentroidalMomentum {
  Vec3 com_W = Vec3::Zero();               ///< [m]
  Vec3 linear_W = Vec3::Zero();            ///< [kg m/s] m ċ
  Vec3 angular_com_W = Vec3::Zero();       ///< [kg m²/s] about the COM, world axes
};

/// Centroidal momentum at (q, v) (mj_comVel + mj_subtreeVel on the root body). Updates `data`.
CentroidalMomentum centroidal_momentum(const RobotModel& model, RobotData& data, const VecXCRef& q, const VecXCRef& v);

/// 6 x nv centroidal momentum matrix A(q) (Orin and Goswami): (L; m ċ) = A v, the angular
/// momentum about the COM and the linear momentum (world axes) of the generalised velocity v.
/// Column j is the momentum of the subtree dof j moves at unit speed: that subtree's composite
/// inertia times j's motion axis (MuJoCo's com-based cinert and cdof), O(bodies + dofs). Needs
/// update_kinematics at q.
Matrix6X centroidal_momentum_matrix(const RobotModel& model, const RobotData& data);

/// 3 x nv centroidal angular momentum matrix A_L(q): the angular rows of the above, L = A_L v (the
/// sum over the bodies of m_b (x_b − c) × J_b + I_b,W J_ω,b). Needs update_kinematics at q.
MatX centroidal_angular_matrix(const RobotModel& model, const RobotData& data);

/// Multibody ZMP of a sampled motion: per frame, COM and ZMP from finite differences of the
/// configurations q (nq x T, uniform rate fps) on a compact stencil, frames f − 1, f, f + 1 only:
/// c̈ by second differences of the COM, L̇ by the difference of L at the half-frames f ± ½
/// (half_frame_angular_momentum), so both parts see the same frames, as each body's own second
/// difference does. A wider stencil for L̇ alone (L at each frame from central differences, then
/// differenced again over f ± 1: frames f − 2 … f + 2, blind to an oscillation at half the frame
/// rate) disagreed with the COM's part: the whole-body stage of com-plan, which holds this ZMP in
/// the support, met it on every stance frame of the shared walks while a per-body evaluation found
/// 20–50 % of them more than 1 cm outside. The ZMP also divides by g + c̈_z, at least
/// kZmpMinSupport_g g. Frames 0 and T − 1 (and every frame when T < 3) reuse their neighbour's
/// derivatives; metrics leave them out.
struct MultibodyZmp {
  Mat3X com_W;               ///< [m] 3 x T
  Eigen::Matrix2Xd zmp_W;    ///< [m] 2 x T
  Eigen::VectorXd zmp_gain_s2;  ///< per frame c_z / (g + c̈_z) [s²] (the cart-table height over g)
  Eigen::VectorXd vertical_accel_mps2;  ///< per frame g + c̈_z as it is [m/s²]
};
MultibodyZmp multibody_zmp(const RobotModel& model, RobotData& data, const MatX& q, double fps);

/// Centroidal angular momentum [kg m²/s] at the half-frame between configurations q_a and q_b, dt
/// apart: ½ (A_L(q_a) + A_L(q_b)) times the velocity that takes q_a to q_b in dt (second-order
/// accurate at the midpoint). A_L_a, A_L_b: centroidal_angular_matrix at q_a and q_b.
Vec3 half_frame_angular_momentum(const RobotModel& model, const MatX& A_L_a, const MatX& A_L_b, const VecXCRef& q_a,
                                 const VecXCRef& q_b, double dt_s);

/// One frame's ZMP from the COM at frames f − 1, f, f + 1 and L at the half-frames f − ½, f + ½.
struct ZmpSample {
  Vec2 zmp_W = Vec2::Zero();       ///< [m]
  double vertical_accel = 0;       ///< g + c̈_z [m/s²], at least kZmpMinSupport_g g (what the ZMP divides by)
  double vertical_accel_raw = 0;   ///< g + c̈_z [m/s²] as it is (the floor's push per kg; <= 0: it would have to pull)
};
ZmpSample zmp_sample(const Vec3& com_before_W, const Vec3& com_W, const Vec3& com_after_W, const Vec3& L_before,
                     const Vec3& L_after, double mass_kg, double fps);

/// Standard gravity used by the ZMP [m/s²].
inline constexpr double kGravity = 9.81;

/// Below this fraction of the weight the floor's push (m (g + c̈_z)) holds nothing and the ZMP is
/// ill-defined: the ZMP divides by at least this much, and the metric (passes/quality.hpp) counts a
/// stance frame that falls faster as outside its support.
inline constexpr double kZmpMinSupport_g = 0.1;

}  // namespace rt
