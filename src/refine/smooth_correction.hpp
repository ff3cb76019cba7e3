#pragma once
/// The refine pass's foot correction (private to rt_refine): the smallest smooth change Δ(t) of a
/// smoothed motion that puts its soles where the foot plan says and its collision points above the
/// floor, found for the whole clip at once so that the correction is as smooth as the motion.
///
///   min_Δ  Σ_f [ Σ_rows w_r |r_r(q_f ⊕ Δ_f)|² + Δ_fᵀ (M_f + diag ρ) Δ_f ] + Σ_f Σ_i σ_i λ (Δ_f−1,i − 2 Δ_f,i + Δ_f+1,i)²
///
/// rows per frame: each foot with a target (refine/foot_plan.hpp) — the sole centre's position
/// error [m] and the sole frame's orientation error log(R Rᵀ_target) [rad] scaled by a length; each
/// collision point below its floor height, each joint beyond its position limit, and each joint whose
/// change between two frames exceeds its speed limit (all one-sided: only while violated, a C¹
/// penalty the smoothness term rounds off). M_f is the landmark cost's Gauss–Newton matrix at frame f
/// (over the `metric_dofs`): the correction goes where it costs the least landmark error, to second
/// order; ρ_i regularises what M_f leaves free. λ is the smoother's second-difference weight and σ_i
/// each coordinate's typical M + ρ, so Δ is smoothed like the motion wherever the rows leave it free
/// (in double support the six directions the two feet do not fix, in swing everything the swing
/// target does not).
///
/// Whole-body ZMP rows (optional, the com-plan pass's final stage): at every frame with a support,
/// each half-plane nᵀp ≤ d that the motion's multibody ZMP p violates (centroidal.hpp: the
/// metric's own finite differences at `fps`) is a one-sided row nᵀp − d. p depends on frames f − 1,
/// f, f + 1 through the COM's second difference and the angular momentum rate; its Jacobian holds
/// c_z / (g + c̈_z) fixed and takes L̇ ≈ A_L(q_f) (δ_f+1 − 2 δ_f + δ_f−1) fps² (the compact
/// stencil's leading term; A_L the centroidal angular momentum matrix), which keeps the normal
/// equations block pentadiagonal; the cost is the exact one, so the backtracking judges every step
/// by the real ZMP. A frame whose COM falls faster than (1 − zmp_min_support_g) g also gets a
/// one-sided row on c̈_z. These rows move every coordinate (the COM depends on all of them). A
/// motion that must start (end) at rest gets, at its first (last) frame, the static rows nᵀc − d on
/// its COM instead: at rest the ZMP is the COM.
///
/// Gauss–Newton: the rows are linearised at the current Δ, and the normal equations — block
/// pentadiagonal over frames, each block over the coordinates any row can move (the root, the legs,
/// and the chains of links that touched the floor) — are solved by a block banded Cholesky in
/// O(T n³), n the number of those coordinates (18 for G1 when only the feet are involved).

#include <array>
#include <vector>

#include "retarget/balance/support_polygon.hpp"
#include "retarget/model/robot_data.hpp"
#include "src/refine/foot_plan.hpp"

namespace rt::refine {

struct CorrectionOptions {
  double stance_weight = 1e6;   ///< [1/m²] stance sole position rows
  double swing_weight = 1e4;    ///< [1/m²] swing sole rows (blended to stance_weight at lift-off and touchdown)
  double floor_weight = 1e6;    ///< [1/m²] collision points below the floor
  double limit_weight = 1e6;    ///< [1/rad²] joints beyond their position limits
  VecX q_lower, q_upper;        ///< joint position limits (nu), margins included
  VecX max_step;                ///< largest joint change between frames (nu; <= 0: none) [rad]
  double stance_length_m = 0.1; ///< orientation rows weigh w · length² (0.5° ~ 0.9 mm at 0.1 m)
  double swing_length_m = 0.02; ///< ... in mid-swing (the tilt matters least there)
  double lambda = 0;            ///< second-difference weight (smoothing_lambda), 0: no coupling
  VecX stiffness;               ///< ρ per velocity coordinate (nv)
  std::vector<int> metric_dofs; ///< coordinates (v order) of the metric blocks
  std::vector<MatX> metric;     ///< M_f per frame over metric_dofs (empty: none)
  std::array<Mat3, 2> R_L_sole{{Mat3::Identity(), Mat3::Identity()}};
  int iterations = 8;           ///< Gauss–Newton steps at most (it stops earlier once the steps are below 1e-6)
  /// ... and at most this many more while a stance sole, a limit, a speed limit or a ZMP row is
  /// still missed beyond its tolerance (0.5 mm, 0.23 deg, 1 mrad, 1 mm). When > 0, a step that no
  /// backtracking makes cheaper while such a row is missed is retried damped (Levenberg–Marquardt,
  /// H + μ diag H, μ = 0.01, 0.1, 1) instead of ending the solve. 0: plain Gauss–Newton.
  int extra_iterations = 0;
  /// ZMP rows: per frame the half-planes the multibody ZMP must satisfy (empty vector: none at that
  /// frame; an empty list: no ZMP rows at all), their weight [1/m²] and the motion's rate [Hz].
  std::vector<std::vector<HalfPlane>> zmp_support;
  double zmp_weight = 1e4;
  /// At every frame with ZMP rows, the COM may not fall faster than (1 − this) g: the floor must
  /// push with at least this fraction of the weight (one-sided row on c̈_z, scaled by c_z / g to
  /// the ZMP rows' metres). Where it would push less the ZMP is ill-defined (the metric counts such
  /// a frame as outside), and the clamped ZMP rows could be met by the angular momentum alone.
  double zmp_min_support_g = 0.3;
  double fps = 0;
  /// The first / last frame is at rest: its COM (the ZMP of a body at rest) gets the ZMP rows.
  bool zmp_rest_start = false, zmp_rest_end = false;
};

struct CorrectionReport {
  int iterations = 0;
  int evaluations = 0;          ///< cost evaluations (each a pass over the clip's kinematics)
  int coordinates = 0;          ///< n of the blocks in the last step
  double max_step = 0;          ///< largest |δ| of the last step
  int zmp_rows = 0;             ///< ZMP rows still violated at the end
  double zmp_excess_max = 0;    ///< [m] largest of their residuals
};

/// ρ that lets the legs absorb a correction: 1 on the joints of the chains to the soles, 30 on the
/// rest of the body and the root's rotation, 100 on the root's translation (whose landmarks the
/// smoothed motion tracks).
VecX legs_first_stiffness(const RobotModel& model);

/// q_base ⊕ Δ (nq x T) for the plan, Gauss–Newton started from `q_start` (nq x T; typically the
/// per-frame solutions of the same rows, so that only smoothness is left to find). `data` is scratch.
MatX solve_smooth_correction(const RobotModel& model, RobotData& data, const MatX& q_base, const MatX& q_start,
                             const FootPlan& plan, const CorrectionOptions& options, CorrectionReport* report = nullptr);

/// Solves the symmetric positive definite block pentadiagonal system A x = b in place (b → x):
/// diagonal blocks D[f] (n x n, lower triangle read), first off-diagonal blocks E[f] = A(f+1, f),
/// second F[f] = A(f+2, f). D, E and F are overwritten by the Cholesky factor's blocks (no
/// allocation). Returns false when A is not positive definite.
bool solve_block_pentadiagonal(std::vector<MatX>& D, std::vector<MatX>& E, std::vector<MatX>& F, std::vector<VecX>& b);

}  // namespace rt::refine
