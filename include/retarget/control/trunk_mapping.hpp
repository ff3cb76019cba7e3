#pragma once
/// Trunk trajectory mapping (paper §V-B, eq. 20–24): when a new contact is established, the
/// reference trunk pose is moved, turned about the vertical and scaled so that its relation to the
/// actual contact points matches its relation to the reference contact points.
///
/// Interpretation of eq. (22): the scale S acts along the principal axes of the reference contact
/// points (p = c + R(θ₁) S R(−θ̂₁) (p̂ − ĉ) = Ω S' (p̂ − ĉ) + c with S' = R(θ̂₁) S R(−θ̂₁)); for
/// contact sets aligned with the world axes this is exactly the paper's Ω S (p̂ − ĉ) + c.

#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

struct TrunkMappingOptions {
  double force_threshold_n = 100.0;  ///< [N] every contact link must push this hard before an update
  /// Scale ratios s_i/ŝ_i are clamped to [1/max_scale, max_scale]; degenerate directions (a
  /// singular value below min_spread_m) keep scale 1.
  double max_scale = 1.5;
  double min_spread_m = 0.01;
  /// Principal axes are ill-defined for isotropic point sets: when s₂/s₁ exceeds this, no rotation.
  double isotropy_ratio = 0.95;
};

/// The transform of eq. (22)–(24).
struct TrunkTransform {
  Vec3 c_ref_W = Vec3::Zero();   ///< ĉ, eq. (20)
  Vec3 c_act_W = Vec3::Zero();   ///< c, eq. (21)
  double yaw_rad = 0;            ///< θ₁ − θ̂₁, wrapped to (−π/2, π/2]
  double theta_ref_rad = 0;      ///< θ̂₁
  Vec2 scale = Vec2::Ones();     ///< (s₁/ŝ₁, s₂/ŝ₂)

  /// Eq. (22): p = c + Ω S' (p̂ − ĉ).
  Vec3 apply_position(const Vec3& p_hat_W) const;
  /// Eq. (23): R = Ω R̂.
  Quat apply_orientation(const Quat& R_hat_W) const;
  Mat3 Omega() const;
  /// The linear part Ω S' of eq. (22): maps displacements, velocities and accelerations of mapped
  /// points (apply_position(p) = apply_position(0) + linear() p).
  Mat3 linear() const;
};

/// Eq. (20)–(24) from matching reference and actual contact points (same count and order, W).
/// Throws InputError when the sets are empty or differ in size.
TrunkTransform compute_trunk_transform(const std::vector<Vec3>& p_ref_W, const std::vector<Vec3>& p_act_W,
                                       const TrunkMappingOptions& options = {});

}  // namespace rt
