#pragma once
/// Whole-clip COM plan over known footsteps (issue 14; design.md §3.4): the horizontal COM c(t) on a
/// uniform grid that stays close to the retargeted COM while the cart-table ZMP
///
///     p_k = c_k − h_k c̈_k + Δp_k,      h_k = z_k / (g + z̈_k)  [s²]
///
/// lies inside each sample's support polygon (already shrunk by the margin). Δp_k is the multibody
/// correction: the difference between the whole-body ZMP of the motion that realised the previous
/// plan and that plan's cart-table ZMP (the two-stage preview of Kajita et al., ICRA 2003). The
/// problem is a sparse QP (sparse_qp.hpp):
///
///     minimise  ½ Σ_k w_c ‖c_k − c_ref,k‖² + ½ Σ_k w_j ‖c⃛_k‖² + ½ Σ_flight w_a ‖c̈_k‖²
///               + ½ Σ_support w_z ‖p_k − p_centre,k‖²
///     subject to  n_iᵀ p_k ≤ d_i  for every half-plane of sample k's polygon,
///
/// the constraints soft with the quadratic penalty ½ w_e max(0, n_iᵀp_k − d_i)² (sparse_qp.hpp): an
/// angular-momentum burst the cart-table model cannot absorb gives the least violation instead of
/// no plan; a feasible plan violates by micrometres.
///
/// with c̈, c⃛ central/backward finite differences on the grid. "Rest" at an end holds the first
/// (last) three samples equal: zero velocity and acceleration there, so the ZMP equals the COM.
/// Samples with no polygon (flight: no foot down) carry no ZMP constraint; their horizontal COM
/// acceleration is penalised instead (ballistic flight has none).

#include <vector>

#include "retarget/balance/sparse_qp.hpp"
#include "retarget/balance/support_polygon.hpp"
#include "retarget/core/types.hpp"

namespace rt {

/// One grid sample of the plan's input.
struct ZmpPlanSample {
  Vec2 com_ref_W = Vec2::Zero();      ///< [m] retargeted COM (x, y)
  double zmp_gain_s2 = 0;             ///< h_k = z / (g + z̈) [s²]
  Vec2 zmp_offset_W = Vec2::Zero();   ///< [m] Δp_k, multibody correction
  std::vector<HalfPlane> support;     ///< ZMP constraints nᵀp ≤ d (empty: flight)
  /// Multiplies w_c at this sample: large values pin the plan to com_ref_W there (a receding-horizon
  /// window starting from a measured state).
  double com_weight_scale = 1.0;
  /// Where the ZMP is pulled to by ZmpPlanOptions::zmp_centre_weight (e.g. the polygon's centroid).
  Vec2 zmp_centre_W = Vec2::Zero();
};

struct ZmpPlanOptions {
  double period_s = 0.01;             ///< grid spacing [s]
  double com_weight = 1.0;            ///< w_c [1/m²]
  /// w_j [s⁶/m²]: with w_c = 1 the unconstrained plan is the retargeted COM low-passed at about
  /// (w_c / w_j)^(1/6) rad/s: 2e-8 gives 19 rad/s (3 Hz), above walking's COM content (≤ 2 Hz).
  double jerk_weight = 2e-8;
  double flight_acceleration_weight = 1e-3;  ///< w_a [s⁴/m²] on flight samples
  /// w_z [1/m²] on ‖p_k − zmp_centre_k‖² for samples with support: a plan that tracks the COM alone
  /// shifts the weight as late as it can, with its ZMP on the polygon's edge, and leaves a
  /// controller no margin; 0 (the default) leaves the cost as above.
  double zmp_centre_weight = 0;
  /// w_e [1/m²]: 1e6 makes 1 mm outside cost as much as a 1 m COM shift.
  double violation_weight = 1e6;
  bool rest_at_start = true;
  bool rest_at_end = true;
  SparseQpOptions qp;                 ///< iteration limit (its penalty is violation_weight)
};

struct ZmpPlan {
  Eigen::Matrix2Xd com_W;   ///< [m] planned COM, 2 x K
  Eigen::Matrix2Xd zmp_W;   ///< [m] its ZMP p_k (cart-table + offset), 2 x K
  SparseQpResult solver;
  double max_shift_m = 0;   ///< max_k ‖c_k − c_ref,k‖
  int max_shift_sample = -1;
  double max_violation_m = 0;  ///< how far the planned ZMP leaves its shrunk polygon at worst
  int violated_samples = 0;    ///< samples with a slack above 1e-4 m
};

/// Plans on `samples` (at least one). The ZMP rows use the grid's own second differences; the first
/// and last sample use p = c (rest) when K < 7 or their end is not at rest.
ZmpPlan plan_com_zmp(const std::vector<ZmpPlanSample>& samples, const ZmpPlanOptions& options = {});

}  // namespace rt
