#pragma once
/// Published joint-centre constructions used by the C3D marker-set profiles. All positions and
/// lengths are in metres; every function works in whatever frame its inputs are expressed in.
///
/// Pelvis frame P (used by the hip regressions): origin at the midpoint of the two ASIS markers,
/// x anterior (towards the ASIS midpoint from the sacrum / PSIS midpoint, made orthogonal to y),
/// y towards the left ASIS, z up (= x cross y).

#include <optional>

#include "retarget/core/types.hpp"

namespace rt {

/// Pelvis frame from the ASIS markers and a posterior point (sacrum marker or PSIS midpoint).
/// `pelvis_width_m` is the inter-ASIS distance and `pelvis_depth_m` the distance from the ASIS
/// midpoint to the posterior point measured along x (so a single PSIS gives the same depth as the
/// PSIS midpoint). nullopt when the markers are degenerate (coincident or collinear).
struct PelvisFrame {
  Iso3 X_F_P;  ///< pose of the pelvis frame in the input frame F
  double pelvis_width_m = 0;
  double pelvis_depth_m = 0;
};
std::optional<PelvisFrame> pelvis_frame(const Vec3& p_F_lasi, const Vec3& p_F_rasi, const Vec3& p_F_posterior);

/// Harrington et al. 2007 (J Biomech 40:595-602), the pelvis width + depth regression:
///   x = -0.24 PD - 9.9 mm,  z_ISB (up) = -0.30 PW - 10.9 mm,  lateral = 0.33 PW + 7.3 mm
/// with PW the inter-ASIS distance and PD the pelvis depth. Returns the hip joint centre in P.
Vec3 hip_centre_harrington(double pelvis_width_m, double pelvis_depth_m, bool left);

/// Davis et al. 1991 (Hum Mov Sci 10:575-587) as implemented by Vicon Plug-in Gait, for subjects
/// measured for it (leg length, ASIS-trochanter distance):
///   C = 0.115 LL - 15.3 mm,  theta = 0.5 rad,  beta = 0.314 rad,  a = inter-ASIS distance / 2
///   x = C cos(theta) sin(beta) - (d_AT + r) cos(beta)
///   y = +-(a - C sin(theta))                        (+ for the left hip)
///   z = -C cos(theta) cos(beta) - (d_AT + r) sin(beta)
/// with r the marker radius and d_AT = 0.1288 LL - 48.56 mm when the ASIS-trochanter distance is
/// unknown (<= 0). Returns the hip joint centre in P.
Vec3 hip_centre_davis(double leg_length_m, double asis_trocanter_m, double inter_asis_m, double marker_radius_m,
                      bool left);

/// Bell et al. 1990 (J Biomech 23:617-621), for pelvises without posterior markers:
///   x = -0.19 PW,  z = -0.30 PW,  lateral = 0.36 PW.
Vec3 hip_centre_bell(double pelvis_width_m, bool left);

/// Which solution of the chord construction to take: the joint centre lies on the opposite side
/// of the line proximal->lateral from a laterally placed wand (knee: THI, ankle: TIB).
enum class ChordSide { AwayFromPlaneMarker, TowardPlaneMarker };

/// The Plug-in Gait "chord function": the joint centre J lies in the plane of the proximal joint
/// centre P, the lateral marker L and the plane marker W, at distance `offset_m` from L, with the
/// angle P-J-L a right angle:  J = L + offset (cos a u + sin a v), cos a = offset / |P - L|,
/// u = (P - L)/|P - L| and v the in-plane unit normal to u on the side chosen by `side`.
/// nullopt when the inputs are degenerate (W on the line P-L, or |P - L| <= offset).
std::optional<Vec3> chord_joint_centre(const Vec3& p_proximal, const Vec3& p_lateral, const Vec3& p_plane,
                                       double offset_m, ChordSide side = ChordSide::AwayFromPlaneMarker);

/// Elbow joint centre from the lateral epicondyle marker E, the shoulder joint centre S and the
/// midpoint M of the wrist markers, as in Vicon Plug-in Gait: the chord construction with
/// proximal point S, lateral marker E and plane point E + s n, n = (E - S) x (M - E) (s = +1 for the
/// left arm, -1 for the right, so that the point lies medially), i.e. E moved by `offset_m` roughly
/// along the flexion axis with the angle S-J-E a right angle. Like Plug-in Gait it takes the
/// axis direction from the marker rather than the joint centre, which costs a few millimetres
/// with a bent elbow and up to offset * sqrt(2) with a fully extended one (n then points
/// antero-posteriorly). Returns E when E lies on the line S-M, nullopt for degenerate inputs.
std::optional<Vec3> elbow_joint_centre(const Vec3& p_shoulder, const Vec3& p_lateral_epicondyle,
                                       const Vec3& p_wrist_markers_mid, double offset_m, bool left);

}  // namespace rt
