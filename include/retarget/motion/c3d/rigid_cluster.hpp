#pragma once
/// Rigid-cluster tools for marker data: markers on one body segment keep their mutual distances
/// (up to skin motion), so a segment's pose can be tracked from any three of them. Used to fill
/// marker gaps from the segment's other markers and to locate functional joint centres.

#include <optional>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/motion/c3d/marker_trajectories.hpp"

namespace rt {

/// Least-squares rigid transform X with X * from.col(i) ~ to.col(i) (Kabsch / SVD, reflection
/// excluded). nullopt when there are fewer than 3 points or when `from` does not spread at least
/// `min_spread_m` (RMS about its centroid) in two directions (collinear markers fix no rotation).
/// `rms_m`, when given, receives the RMS residual of the fit.
std::optional<Iso3> fit_rigid_transform(const Mat3X& from, const Mat3X& to, double min_spread_m = 0.01,
                                        double* rms_m = nullptr);

/// Fills gaps of every marker in `cluster` (indices into `markers`) from the other markers of the
/// cluster: at a missing frame f, the cluster's motion between the marker's last valid frame
/// before f (and first one after f) and f is fitted on the markers measured at both frames (at
/// least 3), and applied to the marker; the two estimates are blended linearly in time. Filled
/// samples become SampleState::Interpolated. Fits with an RMS residual above `max_rms_m` are
/// rejected. Only measured samples serve as references, so the result does not depend on the
/// order of the markers. Returns the number of samples filled.
int fill_from_rigid_cluster(MarkerTrajectories& markers, const std::vector<int>& cluster, double max_rms_m = 0.02);

/// Poses of a marker cluster over time: X_F_S[f] maps the cluster's reference configuration (its
/// marker positions at `reference_frame`, in the file frame F) to its configuration at frame f.
struct ClusterPoses {
  int reference_frame = -1;
  std::vector<Iso3> X_F_S;
  std::vector<char> valid;  ///< 1 where at least 3 measured markers gave a fit
  int valid_count() const;
};

/// Tracks `cluster` (at least 3 markers measured together in some frame); the reference is the
/// first frame in which the most cluster markers are measured.
ClusterPoses track_cluster(const MarkerTrajectories& markers, const std::vector<int>& cluster);

/// A joint centre fixed in two segments: c_a in segment a's reference configuration, c_b in b's.
struct FunctionalJoint {
  Vec3 c_a = Vec3::Zero();
  Vec3 c_b = Vec3::Zero();
  double rms_m = 0;     ///< RMS distance between the two per-frame estimates
  int frames_used = 0;
};

/// SCoRE (Ehrig et al. 2006, J Biomech 39:2798): the point that moves least relative to both
/// segments, min sum_f |X_a[f] c_a - X_b[f] c_b|^2, solved as linear least squares over the frames
/// where both poses are valid. Hinge-like joints (knee, ankle) leave the position along the axis
/// undetermined, so a Tikhonov term `regularisation * frames * |c - prior|^2` pulls the solution
/// towards the priors (given in each segment's reference configuration) only in the directions
/// the motion does not determine. nullopt with fewer than 10 common frames.
std::optional<FunctionalJoint> score_joint_centre(const ClusterPoses& a, const ClusterPoses& b, const Vec3& prior_a,
                                                  const Vec3& prior_b, double regularisation = 1e-3);

}  // namespace rt
