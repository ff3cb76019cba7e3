#pragma once
/// ReferenceSignal: a Reference turned into what the controllers need at any time t — the
/// generalised reference q, q̇, q̈ (eq. 2), the feet's reference poses, velocities and
/// accelerations (eq. 4–5), the reference COM (balance controller input) and the contact
/// schedule — precomputed per reference frame and interpolated in between.
///
/// Trunk mapping (paper §V-B) moves the whole reference by a TrunkTransform: the root pose, the
/// feet and the COM are mapped; joint angles are not.

#include <array>
#include <vector>

#include "retarget/control/trunk_mapping.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

/// The reference at one instant (already trunk-mapped).
struct ReferenceSample {
  VecX q, v, a;                              ///< nq, nv, nv
  std::array<Iso3, 2> X_W_sole;              ///< sole frame (x forward, z normal) at the sole centre
  std::array<Vec6, 2> v_sole, a_sole;        ///< [linear at the sole centre; angular], W
  Vec3 p_W_com = Vec3::Zero();
  std::array<bool, 2> contact{{true, true}};
};

class ReferenceSignal {
 public:
  /// `reference` must have a contact schedule (label one first for third-party files).
  /// `com_smoothing_s`: standard deviation [s] of the Gaussian that smooths the reference COM before
  /// it is differentiated for com_motion_at (0 = none): the fourth derivative of a 30 fps
  /// trajectory amplifies 0.1 mm of jitter to metres per second⁴.
  ReferenceSignal(const RobotModel& model, RobotData& data, const Reference& reference, double com_smoothing_s = 0.0);

  double duration_s() const { return duration_s_; }
  double fps() const { return fps_; }
  int num_frames() const { return static_cast<int>(q_.cols()); }
  /// Reference (mapped by `map`) at time t, clamped to [0, duration].
  ReferenceSample at(double t_s, const TrunkTransform& map) const;
  /// Reference COM at t (mapped), without computing the rest of the sample.
  Vec3 com_at(double t_s, const TrunkTransform& map) const;
  /// Horizontal reference COM and its first four time derivatives at t (mapped; rows c, ċ, c̈, c⃛,
  /// c⁗, columns x, y), for the balance controller's feed-forward. The derivatives are those of the
  /// COM smoothed by a Gaussian of `com_smoothing_s` (constructor), zero outside the clip.
  Eigen::Matrix<double, 5, 2> com_motion_at(double t_s, const TrunkTransform& map) const;
  /// Contact flags at t (nearest frame).
  std::array<bool, 2> contact_at(double t_s) const;
  /// Unmapped frame data, for plots and the COM re-planner.
  const Mat3X& com_W() const { return com_; }
  const std::array<std::vector<Iso3>, 2>& soles_W() const { return sole_; }
  const std::array<std::vector<std::uint8_t>, 2>& contacts() const { return contact_; }
  const MatX& q_frames() const { return q_; }

 private:
  const RobotModel* model_;
  double fps_ = 0, duration_s_ = 0;
  MatX q_, v_, a_;
  std::array<std::vector<Iso3>, 2> sole_;
  std::array<Eigen::Matrix<double, 6, Eigen::Dynamic>, 2> sole_v_, sole_a_;
  Mat3X com_;
  std::array<Eigen::Matrix2Xd, 4> com_derivatives_;  ///< ċ, c̈, c⃛, c⁗ per frame (horizontal, unmapped)
  std::array<std::vector<std::uint8_t>, 2> contact_;
};

}  // namespace rt
