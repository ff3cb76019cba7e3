#pragma once
/// The refine pass's trajectory NLP over one window of spline control points (private to
/// rt_refine; solver-independent, so tests can check it against finite differences).
///
/// Variables: the free coordinates of the window's free control points (chart coordinates,
/// trajectory_chart.hpp; bspline.hpp), control-point major, then the horizontal anchor (x, y) of
/// every stance phase whose anchor is not fixed yet. The first `num_pinned` control points are
/// constants (the previous window's solution): they make the hand-over between windows C² and keep
/// every constraint that spans the junction satisfied. Coordinates outside `free_coordinates` are
/// constants too (the pass solves the coordinates that move the feet first, then the others).
///
/// Objective f = ½|r|²:
///   per collocation point c (a source frame, x_c = Σ β C):
///     landmarks    √w (p_W(link, p_L)(x_c) − p_W_target)                 [m]
///                  √w_o log(R_W_link R_L_frame R_W_targetᵀ)              [rad]  (as landmark_ik.hpp)
///     pull         √w_pull (x_c − x_ik,c)                                 towards the per-frame IK
///   per interior control point j:
///     acceleration √w_acc (C_{j−1} − 2 C_j + C_{j+1}) / h²                [m/s², rad/s²]
/// Constraints:
///   velocity     |C_{j+1} − C_j| ≤ max_step  per joint (linear)        URDF velocity limits
///   stance       per stance foot at c: sole centre x, y = phase anchor; sole centre z = 0;
///                sole normal n_x = n_y = 0 (flat)                       equalities
///   floor        per swing foot at c flagged `floor`: each sole corner z ≥ 0
///   still        per stance foot at c flagged `still` (a phase's first and last frame): sole
///                centre horizontal velocity = 0, so the foot lands and lifts off at rest instead
///                of sliding between collocation frames
/// Bounds: joints inside their position limits (minus a margin); root and anchors free.
///
/// Velocity rows are an active set: a row is in the NLP when the initial guess already uses at
/// least `velocity_activation` of its bound, or when the caller forces it (after a solve violated
/// it); the rest are checked afterwards. Most joints never come near their URDF velocity limits, and
/// every row left out shrinks the KKT systems Ipopt factorises.
///
/// Hessian of the Lagrangian: Gauss–Newton JᵀJ for the objective plus the curvature Σ λ ∇²g of
/// the stance and floor rows (the still rows' curvature, a third derivative, is left out) (second derivatives of forward kinematics from the joint axes:
/// ∂²p/∂x_i∂x_j = ω_i × ∂p/∂x_j for i up the chain from j), projected per collocation point onto
/// its positive semidefinite part. The projection keeps the matrix positive semidefinite (no inertia
/// correction) while damping the directions in which Gauss–Newton alone under-estimates the
/// curvature; without it, iterates drift along the stance constraints' curved manifold.

#include <Eigen/Eigenvalues>
#include <array>
#include <cstdint>
#include <vector>

#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/robot_model.hpp"
#include "src/refine/bspline.hpp"

namespace rt::refine {

/// Robot-level data shared by every window: kinematic chains, the union sparsity pattern of a
/// collocation point's Hessian block, sole geometry, bounds in chart coordinates.
struct NlpRobot {
  NlpRobot(const RobotModel& model, double limit_margin);

  const RobotModel* model = nullptr;
  int nv = 0;
  std::vector<std::vector<int>> chains;  ///< per link: dofs (ascending) that move it
  /// Pattern of a point's nv x nv Hessian block: union of chain x chain over the landmark and sole
  /// links, plus the diagonal. Row-major.
  std::vector<std::uint8_t> pattern;
  std::vector<std::uint8_t> moves_feet;  ///< per coordinate: in the chain of a sole link
  std::array<Vec3, 2> n_L_sole;      ///< sole normal in the foot link frame
  VecX lower, upper;                  ///< chart bounds (joints: limits ∓ margin; root ±inf)
  VecX velocity_limit;                ///< per chart coordinate [rad/s] (0: none; root coordinates)
};

/// A source frame where landmark costs and contact constraints are evaluated.
struct CollocationPoint {
  int frame = 0;
  SplineSupport support;                      ///< global control point indices
  std::vector<IkTarget> targets;
  VecX x_ik;                                  ///< chart coordinates of the per-frame IK
  std::array<int, 2> stance{{-1, -1}};        ///< per foot: index into WindowSpec::anchors, or -1
  std::array<bool, 2> floor{{false, false}};  ///< per foot: sole corners constrained to z >= 0
  std::array<bool, 2> still{{false, false}};  ///< per stance foot: sole centre velocity = 0
};

struct StanceAnchor {
  int foot = 0;
  bool fixed = false;          ///< fixed by an earlier window: a constant, not a variable
  Vec2 p_W = Vec2::Zero();     ///< [m] the anchor (initial guess when not fixed)
};

struct NlpWeights {
  double acceleration = 1e-6;     ///< w_acc
  double pull = 1e-3;             ///< w_pull
  double velocity_margin = 0.02;  ///< fraction of each velocity limit kept free
  double velocity_activation = 0.5;  ///< velocity rows used by the initial guess beyond this fraction enter
};

struct WindowSpec {
  int first_control = 0;       ///< global index of the window's first control point
  int num_pinned = 0;          ///< leading control points held constant
  MatX controls;               ///< nv x (window size): initial guess; pinned ones are constants
  double segment_s = 0;        ///< [s] duration of one spline segment (h)
  std::vector<std::uint8_t> free_coordinates;  ///< per chart coordinate, 1 = optimised (empty: all)
  std::vector<CollocationPoint> points;  ///< supports within the window, at least one free
  std::vector<StanceAnchor> anchors;
  /// Velocity rows (gap j between local control points j and j+1, coordinate i) at index
  /// j·nv + i forced into the NLP (empty: none forced).
  std::vector<std::uint8_t> forced_velocity_rows;
};

class WindowNlp {
 public:
  WindowNlp(const NlpRobot& robot, RobotData& data, const WindowSpec& spec, const NlpWeights& weights);

  int num_variables() const { return n_; }
  int num_constraints() const { return m_; }
  const VecX& x_lower() const { return x_lower_; }
  const VecX& x_upper() const { return x_upper_; }
  const VecX& g_lower() const { return g_lower_; }
  const VecX& g_upper() const { return g_upper_; }
  const std::vector<int>& jac_rows() const { return jac_rows_; }
  const std::vector<int>& jac_cols() const { return jac_cols_; }
  const std::vector<int>& hess_rows() const { return hess_rows_; }  ///< lower triangle (row >= col)
  const std::vector<int>& hess_cols() const { return hess_cols_; }
  int num_equalities() const { return num_equalities_; }
  int num_floor_rows() const { return num_floor_rows_; }
  int num_velocity_rows() const { return static_cast<int>(velocity_rows_.size()); }
  bool nonlinear_inequalities() const { return num_floor_rows_ > 0; }

  /// Initial point from the spec (free controls, then free anchors).
  VecX initial_point() const;

  /// Evaluates objective, gradient, constraints, Jacobian and Gauss–Newton Hessian at x.
  void evaluate(const double* x);
  double objective() const { return f_; }
  const VecX& gradient() const { return grad_; }
  const VecX& constraints() const { return g_; }
  const VecX& jac_values() const { return jac_; }
  const VecX& hess_values() const { return hess_; }  ///< objective part (Gauss–Newton)

  /// Lagrangian Hessian values at the point last evaluated: obj_factor · JᵀJ + Σ λ_r ∇²g_r with
  /// each point's constraint part projected onto its positive semidefinite cone when `convexify`
  /// (exact when false: tests compare it with finite differences).
  void lagrangian_hessian(double obj_factor, const double* lambda, double* values, bool convexify = true);

  /// Stacked residual vector r(x) with f = ½|r|² (tests compare JᵀJ with the Hessian).
  VecX residuals(const double* x);

  /// Control points of the window (nv x size, pinned ones and fixed coordinates included) and the
  /// anchors at x.
  MatX controls(const double* x) const;
  std::vector<StanceAnchor> anchors(const double* x) const;

  /// Largest violation of the constraints and bounds at the point last evaluated.
  double max_violation(const double* x) const;

  /// Velocity rows (j·nv + i, as WindowSpec::forced_velocity_rows) of the free coordinates on
  /// which the controls `C` (nv x size) use more than `fraction` of the bound plus `tolerance`.
  std::vector<int> velocity_rows_above(const MatX& C, double fraction, double tolerance = 0) const;

 private:
  struct LinkJacobian {
    int link = -1;
    Vec3 p_W_origin;
    MatXr jp, jr;  // 3 x nv at the link's body origin, chart columns
  };
  struct RowSpan {   // one constraint row generated at a point
    int foot;
    int kind;        // 0..4 stance (x, y, z, n_x, n_y), 5..8 floor corners, 9..10 horizontal velocity (x, y)
    int chain_link;  // link whose free chain gives the columns
    int anchor_var;  // -1 or the anchor variable (x or y row)
    int value_offset;  // first entry in the Jacobian values
    int hess_offset;   // first entry of its second derivatives (free chain upper triangle)
  };
  struct PointRows {
    int first_row = 0;
    std::vector<RowSpan> rows;
  };

  int var(int local_control, int coord) const {
    return (local_control - spec_.num_pinned) * num_free_coords_ + coord_var_[static_cast<std::size_t>(coord)];
  }
  bool is_free(int local_control) const { return local_control >= spec_.num_pinned; }
  double max_step(int coord) const;
  void set_controls(const double* x);
  void build_structure();
  int block_offset(int l1, int l2) const;  // Hessian block (l1 >= l2, local controls), -1 if absent
  const LinkJacobian& link_jacobian(int link, bool need_jacobian);
  // Adds Hc_ (symmetric, nv x nv) of a point, weighted by its spline weights, to the Hessian blocks
  // of its control points.
  void scatter_point_block(const CollocationPoint& pt, double* values) const;
  Vec3 point_second_derivative(const LinkJacobian& L, const Vec3& op, const Vec3& r_root, int i, int j) const;
  void evaluate_still_row(const CollocationPoint& pt, const RowSpan& rs, const Vec3& point, const LinkJacobian& L,
                          bool derivatives, int row);
  // Evaluates one point: cost, and (when `derivatives`) gradient/Hessian blocks and constraint rows.
  // `residuals` (optional) receives the point's weighted residuals, `num_residuals` their count.
  double evaluate_point(int p, bool derivatives, double* residuals, int* num_residuals);

  const NlpRobot& robot_;
  RobotData& data_;
  WindowSpec spec_;
  NlpWeights weights_;
  int nv_ = 0, size_ = 0, num_free_ = 0, n_ = 0, m_ = 0;
  int num_free_coords_ = 0;
  std::vector<int> coord_var_;               // per coordinate: index among the free ones, or -1
  std::vector<int> free_coords_;             // the free coordinates, ascending
  std::vector<std::vector<int>> free_chains_;  // per link: free coordinates of its chain
  int num_equalities_ = 0, num_floor_rows_ = 0;
  std::vector<int> anchor_var_;  // per anchor: first variable (x; y = +1) or -1 when fixed
  VecX x_lower_, x_upper_, g_lower_, g_upper_;
  std::vector<int> jac_rows_, jac_cols_, hess_rows_, hess_cols_;
  // Hessian index maps: block offsets, the pattern's entry lists and the positions of (i, i).
  std::vector<int> block_offsets_;  // size_ x 4 (l1, l1 − l2)
  std::vector<std::pair<int, int>> pattern_full_, pattern_lower_;
  std::vector<int> diag_full_, diag_lower_;  // per free coordinate (in free order)
  VecX con_hess_;  // per constraint row: ∂²g over its free chain (upper triangle, chain order)
  // Velocity rows: (local control j, coordinate i) for C_{j+1,i} − C_{j,i}.
  std::vector<std::pair<int, int>> velocity_rows_;
  int velocity_jac_entries_ = 0;
  std::vector<PointRows> point_rows_;
  // Workspace.
  MatX C_;  // nv x size
  VecX q_, xc_;
  MatX Hc_;
  VecX gc_;
  MatX chain_block_;
  Eigen::SelfAdjointEigenSolver<MatX> eigen_;
  std::vector<LinkJacobian> link_cache_;
  std::vector<int> link_slot_;  // per link: index into link_cache_ or -1
  int num_used_links_ = 0;
  Mat3X J_;                     // a residual block's Jacobian over its free chain
  std::array<Vec3, 4> dw_;      // root_omega_derivatives at the current point
  double f_ = 0;
  VecX grad_, g_, jac_, hess_;
};

}  // namespace rt::refine
