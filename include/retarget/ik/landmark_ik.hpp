#pragma once
/// Per-frame inverse kinematics on landmarks (design.md §3.2): floating-base pose + joint angles
/// minimising weighted landmark position and orientation errors plus a small regulariser towards
/// the previous frame, with the joint position limits as hard bounds (bounded_lm.hpp).
///
/// Residuals, all weighted by the square roots of their weights:
///   position     √w_i (p_W(link_i, p_L_i)(q) − p_W_target_i)                 [m]
///   orientation  √w_o,i log(R_W_target_i (R_W_link_i(q) R_L_lm_i)ᵀ)           [rad]
///   regulariser  √λ (q ⊖ q_prev)                                             [rad, m]
/// R_L_lm_i is the landmark frame in the link frame, taken from the robot's zero configuration
/// (root at the origin, all joints 0), where every landmark frame is aligned with the world:
/// x forward, y left, z up (robot configs are written for robots that stand so at q = 0).

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/ik/bounded_lm.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {

struct IkOptions {
  int max_iterations = 30;
  double step_tolerance = 1e-4;      ///< [rad, m] stop when no joint or root coordinate moves more
  double cost_tolerance = 1e-2;      ///< stop when a step lowers the cost by less than this fraction
  double regularization = 1e-3;      ///< λ: weight of q ⊖ q_prev relative to a unit landmark weight
  /// Optional per-coordinate factors of λ (size nv, v order); empty: 1 for every coordinate.
  VecX regularization_factors;
  double initial_damping = 1e-3;     ///< Levenberg–Marquardt damping at the start, relative to the mean diagonal
  double joint_limit_margin = 1e-4;  ///< [rad] the solution stays this far inside the limits
  /// Which root coordinates may move (v order: x, y, z, then rotation about the root's x, y, z).
  std::array<bool, 6> root_free{{true, true, true, true, true, true}};
};

/// One tracked point (and optionally orientation) for one frame.
struct IkTarget {
  int link = -1;
  Vec3 p_L = Vec3::Zero();         ///< [m] tracked point in the link frame
  Vec3 p_W = Vec3::Zero();         ///< [m] target position in W
  double weight = 1.0;             ///< position weight (0 disables)
  Mat3 R_L_frame = Mat3::Identity();  ///< landmark frame in the link frame
  Quat R_W = Quat::Identity();     ///< target orientation of the landmark frame in W
  double orientation_weight = 0.0; ///< 0 disables the orientation residual
};

/// Optional whole-body COM target (the COM-following IK of the com-replan pass).
struct IkComTarget {
  Vec3 p_W = Vec3::Zero();  ///< [m] target COM
  double weight = 0;        ///< 0 disables
  bool horizontal_only = true;  ///< track x, y only (the balance model's axes)
};

/// Optional floor term: every collision support point of the robot (collision_hull.hpp) at or above
/// a minimum height, as a one-sided quadratic penalty ½ w min(0, z − z_min)² (a C¹ cost, so
/// Gauss–Newton sees only the points currently below). z_min is 0, or per link where given.
struct IkFloorTerm {
  double weight = 0;                      ///< 0 disables
  std::vector<std::pair<int, double>> link_min_height_m;  ///< (link, z_min) overrides, e.g. a swing foot's clearance
  std::array<int, 2> skip_links{{-1, -1}};  ///< links left out (stance feet held by their targets)
};

/// Optional per-solve joint bounds (nu each, movable-joint order), intersected with the URDF limits:
/// e.g. a velocity bound around the previous frame's solution.
struct IkJointBounds {
  VecX lower;
  VecX upper;
};

struct IkResult {
  BoundedLmResult solver;
  double rms_error_m = 0;   ///< weighted RMS position error over the targets with weight > 0
  double max_error_m = 0;   ///< largest (unweighted) position error
  int worst_target = -1;    ///< index into the targets of max_error_m
};

class LandmarkIk {
 public:
  LandmarkIk(const RobotModel& model, IkOptions options = {});

  /// Landmark frame orientation in a link frame from the zero configuration (see file comment).
  Mat3 landmark_frame_in_link(int link) const;

  /// Solves one frame in place: `q` is the warm start and the result (nq); `q_prev` the
  /// regularisation anchor. Joint values outside the limits in the warm start are clamped first.
  IkResult solve(RobotData& data, const std::vector<IkTarget>& targets, const VecX& q_prev, VecX& q,
                 const IkComTarget& com = {}, const IkFloorTerm& floor = {},
                 const IkJointBounds* bounds = nullptr) const;

  /// Gauss–Newton matrix Σ w JᵀJ (nv x nv, v order) of the targets' residuals at q: how much the
  /// target cost grows, to second order, for a change of q (the refine pass weighs its foot
  /// corrections with it). Updates `data`.
  MatX targets_normal_matrix(RobotData& data, const std::vector<IkTarget>& targets, const VecX& q) const;

  const IkOptions& options() const { return options_; }

 private:
  // Adds the targets' cost, and (H, g not null) their Gauss–Newton terms (upper triangle), at the
  // kinematics in `data`; jp, jr are 3 x nv scratch.
  double add_targets(const RobotData& data, const std::vector<IkTarget>& targets, MatX* H, VecX* g, MatXr& jp,
                     MatXr& jr) const;

  const RobotModel* model_;
  IkOptions options_;
  std::vector<Mat3> R_L_lm_;  ///< per link
  std::vector<std::vector<int>> chains_;  ///< per link: the dofs (ascending) that move it
};

}  // namespace rt
