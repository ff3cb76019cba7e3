#pragma once
/// Where each sole must be on every frame of a clip (private to rt_refine; the refine pass's feet).
///
/// Stance. Each labelled stance phase has one anchor: the sole flat on the floor (z = 0), at the
/// median horizontal position and the mean heading of the sole over the phase in the motion it is
/// planned from. The sole holds that pose on every frame of the phase: a planted foot neither
/// slides nor turns. A turn the subject makes by pivoting on a planted foot is therefore carried by
/// the legs and the body during that stance and by the next swing, which lands the foot at the
/// heading of its next stance.
///
/// Swing. Between the anchors A (lift-off) and B (touchdown) the sole follows the smoothed motion's
/// own swing, re-targeted onto the anchors:
///   horizontal   A + (B − A) σ + bump(u) · (the smoothed path's deviation from its chord),
///                σ = smootherstep(the smoothed foot's progress along its chord), u = time fraction,
///                bump = 16 u²(1 − u)²: the foot leaves and arrives with zero horizontal speed;
///   heading      from A's to B's along σ;
///   tilt         the smoothed foot's, faded out near both ends (lift-off and touchdown are flat):
///                × smootherstep(distance to the nearer end / max(guard, tilt_ramp)), the ramp at
///                most half the swing. A performer's toe-off leaves the sole tilted 40-65° at
///                lift-off; faded in over the 0.1 s guard that is a flick of the ankle and knee in
///                two 30 fps frames (refine{swing_tilt_ramp}, README "Swing tilt");
///   height       of the sole's lowest corner: E · smax(h, clearance + 3 mm), h the smoothed swing's
///                lowest-corner height over the chord between its end heights, E =
///                smootherstep(distance to the nearer end / guard): zero height and zero vertical
///                speed at both ends, at least the clearance beyond `guard`, whatever the tilt.
/// A swing cut by the clip's start or end keeps the smoothed pose at that end. A foot with no stance
/// at all is free (floor clearance only).

#include <array>
#include <cstdint>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt::refine {

/// A sole pose: centre of the sole's bottom face and the sole frame (x forward, z the sole normal).
struct SolePose {
  Vec3 p_W = Vec3::Zero();
  Mat3 R_W = Mat3::Identity();
};

enum class FootMode : std::uint8_t { Stance, Swing, Free };

struct FootTarget {
  FootMode mode = FootMode::Free;
  SolePose pose;               ///< target (Stance, Swing)
  double min_height_m = 0;     ///< floor clearance of the foot's geometry (Swing, Free)
  /// Swing: 1 at lift-off and touchdown, 0 beyond `guard` (1 − E): a solver holding swing targets
  /// less firmly than stance ones blends its weight with this, so a foot's hold does not jump.
  double end_blend = 0;
};

struct SoleAnchor {
  int foot = 0;
  int begin = 0, end = 0;  ///< frames [begin, end)
  Vec2 p_W = Vec2::Zero();
  double yaw = 0;          ///< [rad] heading of the sole's x axis
};

struct FootPlanOptions {
  double clearance_m = 0.015;  ///< swing sole above this beyond `guard_s` of lift-off and touchdown
  double guard_s = 0.1;        ///< [s]
  double tilt_ramp_s = 0;      ///< [s] the tilt fades in and out over this when longer than guard_s
  std::array<Vec2, 2> sole_size_m{{Vec2::Zero(), Vec2::Zero()}};  ///< per foot: length (sole x), width
};

struct FootPlan {
  std::array<std::vector<FootTarget>, 2> feet;  ///< per foot, per frame
  std::vector<SoleAnchor> anchors;
};

/// Heading [rad] of a sole frame (its x axis projected on the floor).
double sole_yaw(const Mat3& R_W_sole);

/// Anchors of every stance phase of `contacts` from the sole poses `soles` (per foot, per frame).
std::vector<SoleAnchor> stance_anchors(const std::array<std::vector<SolePose>, 2>& soles,
                                         const std::array<std::vector<std::uint8_t>, 2>& contacts);

/// The plan for every frame: stance anchors, swing targets shaped from `smoothed` (per foot, per
/// frame sole poses of the motion to follow) at `fps`.
FootPlan plan_feet(const std::vector<SoleAnchor>& anchors, const std::array<std::vector<SolePose>, 2>& smoothed,
                   const std::array<std::vector<std::uint8_t>, 2>& contacts, double fps, const FootPlanOptions& options);

}  // namespace rt::refine
