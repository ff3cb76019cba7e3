#pragma once
/// `refine-ipopt` pass (opt-in; the default `refine` pass is refine.hpp): the project's first refine,
/// a windowed trajectory NLP solved with Ipopt over the per-frame IK result, at the source rate. Kept
/// for ablation. It holds stance feet (centre position, height, flatness, not heading) only at its
/// collocation frames, checks only the sole corners against the floor, and is 5-20x slower than
/// `refine`; measured on the shared clips it leaves up to 6 cm of stance drift between knots.
///
/// Trajectory. Each coordinate of x = [root position, root yaw ψ, root tilt (a, b), joints] (a chart
/// that turns the root quaternion into a vector space; it excludes only an upside-down root) is a
/// uniform cubic B-spline with one knot every `stride` = round(source fps / knot_fps) source frames.
/// The NLP's variables are the control points. Every source frame of the output is the spline's
/// value, so the result is C² at the source rate, and two B-spline properties carry the limits from
/// the control points to every source frame exactly: the curve stays in the convex hull of its
/// control points (joint position limits are plain variable bounds), and its derivative is a
/// quadratic B-spline of the control-point differences (|C_{j+1} − C_j| ≤ v_max·h bounds the joint
/// velocity everywhere, so also every finite difference between source frames).
///
/// Costs and constraints are evaluated at collocation frames: every knot frame plus the last frame.
///   objective  Σ landmark position and orientation errors (the IK pass's targets and weights:
///              make_ik_targets + lock_stance_feet) + pull_weight·|x − x_IK|² at each collocation frame
///              + acceleration_weight·|ẍ|² at each control point (second differences / h²);
///   equality   per foot in labelled stance: sole centre at the phase's anchor (x, y; one anchor
///              variable pair per phase), at z = 0, sole flat (normal vertical);
///   inequality joint velocity limits (linear, URDF, minus velocity_margin); every sole corner of a
///              swing foot within floor_check_height of the floor (in the initial guess) at z ≥ 0.
/// Gauss–Newton Hessian with exact sparsity (per-frame chain blocks, ±3 control-point coupling),
/// precomputed index maps; Ipopt with MUMPS tuned as in dependencies.md §5.
///
/// Windows: `window` control points each, consecutive windows sharing `overlap`. A window is
/// warm-started from the IK fit and, in the overlap, from the previous window's solution, which it
/// re-optimises with the later frames in view. Its first three control points stay pinned to the
/// previous solution: the hand-over is C² and every constraint across the junction holds. A window
/// Ipopt cannot solve (status other than solved / acceptable) keeps its initial guess (the
/// B-spline fit of the per-frame IK), is counted in `failed-windows` and a warning names its frames;
/// a numerically hard clip never throws.
///
/// Ipopt is not thread-safe: every solve is serialised by a process-wide mutex (src/refine).

#include "retarget/pipeline/pass.hpp"

namespace rt {

struct RefineIpoptOptions {
  double knot_fps = 30.0;            ///< [Hz] knot rate; stride = max(1, round(source fps / knot_fps))
  int window = 96;                   ///< control points per window
  int overlap = 8;                   ///< control points shared by consecutive windows (>= 3; 3 are pinned)
  double acceleration_weight = 1e-6; ///< weight of |ẍ|² per control point [(rad/s²)⁻², (m/s²)⁻²], vs landmark weight 1 per m²
  double pull_weight = 1e-3;         ///< weight of |x − x_IK|² per collocation frame (rad², m²)
  double interpolated_weight = 0.5;  ///< weight factor of gap-filled landmark samples (as ik)
  double stance_weight = 1.0;        ///< weight factor of foot landmarks in stance (the constraints hold the feet)
  double velocity_margin = 0.02;     ///< fraction of each URDF velocity limit kept free (>= 0.001: solver tolerance)
  double velocity_activation = 0.5;  ///< velocity rows enter the NLP when the guess uses this much of them (or a solve violates them)
  double limit_margin = 1e-4;        ///< [rad, m] distance kept from the joint position limits
  double floor_check_height = 0.15;  ///< [m] swing-foot corners below this (initial guess) get z >= 0
  int max_iterations = 300;          ///< Ipopt iterations per window (100 left a window of the Bandai dance unsolved)
  double tolerance = 1e-6;           ///< Ipopt tol
  double mu_init = 1e-3;             ///< Ipopt initial barrier parameter (small: the start is good)
};

class RefineIpoptPass final : public Pass {
 public:
  RefineIpoptPass();
  std::string name() const override { return "refine-ipopt"; }
  std::string description() const override {
    return "(ablation) the former refine: windowed trajectory NLP (Ipopt), stance held at collocation frames only";
  }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& context) override;

 private:
  RefineIpoptOptions options_;
  OptionTable table_;
};

}  // namespace rt
