#pragma once
/// Tracking controller of paper §IV-B (eq. 2–19): joint torques and contact wrenches minimising a
/// quadratic cost of COP, acceleration, torque, force and moment errors, in closed form.
///
/// Notation (all in the world frame W unless said otherwise):
///   q̈̂        desired generalised accelerations, eq. (2): feed-forward + PD on the reference
///   r̈̂        desired accelerations of the foot links (6-D: linear at the sole centre; angular)
///   q̈̂'       q̈̂ corrected by the foot tasks through J_c⁺, eq. (5)
///   y = (τ_J, f_c)   unknowns: movable-joint torques and one 6-D wrench (force; moment) per foot in
///                    contact, applied at that foot's sole centre
///   q̈(y)     from the equation of motion (6): M q̈ + c = S τ_J + J_fᵀ f_c
///
/// Eq. (11) as printed maps (F, N) to N + r_b × F, which vanishes for a COP at −r_b; we use the moment
/// about the desired COP, N − r_b × F (the same matrix with the sign of r_b flipped).

#include <array>
#include <limits>
#include <vector>

#include "retarget/control/dense_qp.hpp"
#include "retarget/core/types.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {

/// Positive weights of the cost terms (diagonal matrices W_* of eq. 8–17).
struct TrackingWeights {
  double root_linear = 1.0;     ///< W_q on root linear acceleration [(m/s²)⁻²]
  double root_angular = 10.0;   ///< W_q on root angular acceleration [(rad/s²)⁻²]
  double joint = 1.0;           ///< W_q on joint accelerations [(rad/s²)⁻²]
  double foot_linear = 10.0;    ///< W_c on swing-foot linear acceleration
  double foot_angular = 10.0;   ///< W_c on swing-foot angular acceleration
  /// W_c on the accelerations of feet in contact. High: the closed form then plans accelerations
  /// that keep the feet still, i.e. consistent with the rigid contact the real floor provides; with a
  /// low weight the planned contact forces differ from the floor's and the legs sag.
  double stance_foot = 1000.0;
  double cop = 10.0;            ///< W_b: moment about the desired COP [(N m)⁻²]
  double foot_cop = 1.0;        ///< W_p: moment of each foot wrench about its sole centre [(N m)⁻²]
  double torque = 1e-6;         ///< W_τ [(N m)⁻²]
  /// W_f on contact forces and moments [N⁻², (N m)⁻²]. Not negligible: the internal force between
  /// two feet in contact is free otherwise, and the solution spends it on lower joint torques by
  /// pinching the feet at the friction limit; a lightly loaded foot then slides and spins (slow
  /// steps on G1 fell with 1e-8).
  double force = 1e-4;
  double com_moment = 1e-3;     ///< W_m: total contact moment about the COM [(N m)⁻²]
  /// W_z on the total vertical contact force against the reference's `desired_vertical_force_n`
  /// [N⁻²]; 0 (the paper) leaves the COM height to the joint tasks.
  double vertical_force = 0.0;
};

/// Physical limits on the contact wrenches (issue 5). The paper's closed form (eq. 19) is
/// unconstrained and, on a lightly loaded foot, commands wrenches no floor can produce: pulling,
/// sliding, or with the foot's centre of pressure beyond its sole, which rolls the foot over its
/// edge. With `enabled`, eq. (18) is minimised subject to these limits by a small dual active-set QP
/// (dense_qp.hpp) over the contact wrenches (the torques are eliminated in closed form first); when
/// the closed form already satisfies them (most cycles) the result is identical and costs one
/// extra constraint evaluation.
///
/// Per foot in contact, in its sole frame (x, y along the sole's length and width turned by the
/// foot's heading, z vertical: the floor is horizontal):
///   f_z ≥ f_min;  |f_x|, |f_y| ≤ μ' f_z;  |n_x| ≤ Y f_z, |n_y| ≤ X f_z (COP inside the sole
///   shrunk by c: X = c·l/2, Y = c·w/2);  and the yaw moment within the exact bounds of a
///   rectangle whose corners each push inside the friction pyramid (Caron, Pham, Nakamura 2015):
///   −μ'(X+Y) f_z + |Y f_x − μ' n_x| + |X f_y − μ' n_y| ≤ n_z ≤ μ'(X+Y) f_z − |Y f_x + μ' n_x| − |X f_y + μ' n_y|,
///   with μ' = friction_margin · μ / √2 (the pyramid inscribed in the friction cone at margin 1).
///   (A bound |n_z| ≤ μ' min(X, Y) f_z alone admitted yaw moments that a foot loaded at an edge, or
///   pushed along its sole, cannot hold: G1's stance foot spun 30-70° before its falls on real
///   walks.)
struct ContactConstraintOptions {
  bool enabled = true;
  double friction = 0;             ///< μ; ≤ 0: the robot's floor friction (robot.yaml simulation.friction)
  double friction_margin = 1.0;    ///< scales the inscribed pyramid (≤ 1 adds safety)
  double cop_margin = 0.9;         ///< fraction of each sole's half-length/half-width the foot COP may use
  double min_normal_force_n = 0.0; ///< [N] f_min
};

struct TrackingOptions {
  double kp = 36.0;  ///< [1/s²] default joint gain of eq. (2) (paper: 36)
  double kd = 12.0;  ///< [1/s] default joint damping of eq. (2) (paper: 12)
  VecX kp_joint;     ///< per movable joint (model order); empty = kp everywhere
  VecX kd_joint;
  double root_kp = 36.0, root_kd = 12.0;  ///< trunk (root) 6-DOF gains
  double foot_kp = 36.0, foot_kd = 12.0;  ///< foot link gains (r̈̂)
  double pinv_damping = 1e-6;  ///< Tikhonov damping of J_c⁺ (legs are assumed non-singular)
  TrackingWeights weights;
  ContactConstraintOptions contact;
  /// When the solution asks a joint for more than its effort limit, solve eq. (18) again over
  /// (τ, f) with |τ_i| ≤ effort limit as constraints (beside the contact limits) instead of only
  /// clipping: clipping one torque of a coupled chain (a G1's 35 N m waist under a swinging leg)
  /// silently changes every acceleration the cost was balancing, whereas the constrained optimum
  /// re-distributes the effort to the joints and contact wrenches that still have room.
  bool torque_limits = true;
};

/// Desired state at one control instant (the reference after kinematic mapping).
struct TrackingReference {
  VecX q, v, a;  ///< nq, nv, nv
  /// Desired pose, 6-D velocity and acceleration ([linear at the sole centre; angular], W) of the
  /// left [0] and right [1] feet. For a foot in stance the caller usually latches its touchdown pose.
  std::array<Iso3, 2> X_W_sole{{Iso3::Identity(), Iso3::Identity()}};
  std::array<Vec6, 2> v_sole{{Vec6::Zero(), Vec6::Zero()}};
  std::array<Vec6, 2> a_sole{{Vec6::Zero(), Vec6::Zero()}};
  std::array<bool, 2> contact{{true, true}};  ///< feet allowed to exert contact wrenches
  Vec2 desired_cop_W = Vec2::Zero();          ///< r_b from the balance controller
  /// [N] upper bound on each foot's normal force (a contact-limit row f_z ≤ max when finite and the
  /// limits are enabled): ramps the load in and out at contact changes.
  std::array<double, 2> max_normal_force_n{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()}};
  /// [N] total vertical contact force wanted, m (g + z̈_com,desired); used with a positive
  /// TrackingWeights::vertical_force.
  double desired_vertical_force_n = 0.0;
};

/// Everything the quadratic form is built from; exposed so that tests can check each term.
struct TrackingProblem {
  std::array<bool, 2> contact{{true, true}};  ///< feet in contact (select the W_c weights)
  std::vector<int> contact_feet;  ///< feet with a wrench in f_c, in order
  std::array<double, 2> max_normal_force_n{{0, 0}};  ///< from the reference
  double desired_vertical_force_n = 0;                 ///< from the reference
  int nu = 0, nf = 0;             ///< sizes of τ_J and f_c
  VecX qdd_desired;               ///< q̈̂' (nv)
  std::array<Vec6, 2> rdd_desired;///< r̈̂ per foot
  MatX J_feet;                    ///< 12 x nv: both feet (eq. 3–5)
  VecX Jdot_v_feet;               ///< 12
  MatX J_contact;                 ///< nf x nv: feet in contact
  MatX M;                         ///< nv x nv
  VecX bias;                      ///< c (nv)
  MatXr G;                        ///< M⁻¹ [S, J_contactᵀ]  (nv x (nu + nf)):  q̈ = G y + a0
  VecX a0;                        ///< −M⁻¹ c
  std::vector<Vec3> r_contact_W;  ///< application points (sole centres) of the contact wrenches
  std::vector<Mat3> R_contact_W;  ///< frames of the contact limits: W's vertical, turned by each foot's heading
  MatX C_contact;                 ///< contact limits on f_c: C_contact f_c ≥ d_contact (empty when disabled)
  VecX d_contact;
  Vec3 p_W_com = Vec3::Zero();
  Vec2 desired_cop_W = Vec2::Zero();
  MatX P, P_p, V;                 ///< eq. (8)–(11), (16), (17)
  MatX A;                         ///< eq. (18): Z = ½ yᵀ A y + yᵀ b + const
  VecX b;
};

struct TrackingCommand {
  VecX tau;        ///< movable-joint torques after clamping to effort limits (model order)
  VecX tau_raw;    ///< the unconstrained demand (what the motion asks for; saturation is judged on it)
  VecX f_contact;  ///< contact wrenches (nf), per contact foot [force; moment] at the sole centre
  VecX qdd;        ///< q̈ implied by the unclamped solution
  int saturated_joints = 0;
  /// The unconstrained closed form (eq. 19) already satisfied the contact limits (always true when
  /// they are disabled); otherwise the QP moved the solution onto them.
  bool closed_form_feasible = true;
  int qp_iterations = 0;
  QpStatus qp_status = QpStatus::Solved;
  /// The torque-limited problem over (τ, f) was solved (`TrackingOptions::torque_limits`) and its
  /// solution applied; false when no joint exceeded its limit or that solve failed (then clipped).
  bool torque_limited = false;
};

/// Scratch memory of build() and solve(), owned by the caller (one per control loop) so that the
/// controller itself stays const and shareable between threads; reused across control cycles it
/// avoids per-cycle heap allocation.
struct TrackingWorkspace {
  MatX J_link, J_K;   ///< mj_jac output; foot Jacobians on the legs' dofs (12 x |K|)
  MatXr E, G_K;       ///< stacked weighted Jacobians of Z_q and Z_c; rows of G on the legs' dofs
  VecX q_err, qdd_hat, rdd_hat, w_c, e, x_K;
  Eigen::LLT<MatX> llt_tau;
  MatX X, A_red;
  VecX z_tau, b_red;
  DenseQp qp;
  MatX C_full;        ///< contact and torque limits on y = (τ, f)
  VecX d_full, y_full;
  DenseQp qp_full;
};

class TrackingController {
 public:
  TrackingController(const RobotModel& model, TrackingOptions options);

  const TrackingOptions& options() const { return options_; }

  /// Builds the problem for measured state (q, v) into `problem`, reusing its storage. Updates
  /// `data` (the controller's own mjData) unless `data_is_current` says the caller already ran
  /// update_dynamics(q, v) on it.
  void build(RobotData& data, const VecXCRef& q, const VecXCRef& v, const TrackingReference& ref,
             TrackingProblem& problem, TrackingWorkspace& workspace, bool data_is_current = false) const;
  /// Eq. (19) y = −A⁻¹ b — subject to the contact limits when they are enabled — then, where a
  /// torque exceeds its effort limit, the same problem subject to the torque limits too
  /// (`TrackingOptions::torque_limits`), then clamps torques. The torques are eliminated first: with A = [A_ττ A_τf; A_fτ A_ff], the wrenches
  /// minimise the Schur complement ½ fᵀ(A_ff − A_fτ A_ττ⁻¹ A_τf) f + ..., and τ = −A_ττ⁻¹(b_τ + A_τf f).
  void solve(const TrackingProblem& problem, TrackingCommand& command, TrackingWorkspace& workspace) const;

  /// Conveniences that allocate a fresh problem, workspace and command (tests, one-off calls).
  TrackingProblem build(RobotData& data, const VecXCRef& q, const VecXCRef& v, const TrackingReference& ref,
                        bool data_is_current = false) const;
  TrackingCommand solve(const TrackingProblem& problem) const;
  TrackingCommand compute(RobotData& data, const VecXCRef& q, const VecXCRef& v, const TrackingReference& ref,
                          bool data_is_current = false) const {
    return solve(build(data, q, v, ref, data_is_current));
  }

  /// Individual cost terms at a candidate y, evaluated directly from their definitions
  /// (eq. 8, 12–17), for tests and diagnostics: {Z_b, Z_q, Z_c, Z_τ, Z_f, Z_p, Z_m, Z_z}.
  std::array<double, 8> cost_terms(const TrackingProblem& problem, const VecX& y) const;

 private:
  /// Diagonal of W_c for both feet (stance or swing weights).
  void foot_weights(const std::array<bool, 2>& contact, VecX& w_c) const;
  /// Rows of the contact limits for the problem's contact feet.
  void contact_limits(TrackingProblem& p) const;
  /// Eq. (18) over y = (τ, f) subject to the contact and torque limits, into workspace.y_full;
  /// false when the QP did not reach its minimum.
  bool solve_torque_limited(const TrackingProblem& p, TrackingWorkspace& ws) const;

  const RobotModel* model_;
  TrackingOptions options_;
  VecX kp_, kd_;       ///< per generalised velocity (nv)
  VecX w_q_;           ///< diagonal of W_q (nv)
  std::vector<int> feet_dofs_;  ///< dofs that move either foot (link_dof_chain), ascending
  double friction_ = 1.0;  ///< μ of the contact limits
};

}  // namespace rt
