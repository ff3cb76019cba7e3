#pragma once
/// Sole rectangles derived from a foot's geometry: the lowest flat face of the foot in the pose it
/// stands in, whatever the foot link's own axes (a z-down or DH-style foot frame, a mesh in any
/// up axis). Used by RobotModel for `sole: derive` and by `retarget init-robot`.

#include <array>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

/// Triangles of a foot in a frame F whose z axis is world up (the foot link's geometry turned by
/// the link's orientation in the standing pose). Winding is not relied on.
struct FootSurface {
  std::vector<Vec3> vertices_F;                ///< [m]
  std::vector<std::array<int, 3>> triangles;  ///< indices into vertices_F
};

struct SoleFitOptions {
  /// Triangles whose normal is within this angle of vertical, touching the lowest band, make up
  /// the bottom face; their area-weighted normal is the sole normal.
  double max_face_tilt_rad = 0.5235987755982988;  ///< 30 deg
  /// [m] height band of the bottom face: vertices within it of the lowest point along the sole
  /// normal are on the sole (rounded and chamfered edges above it are not).
  double face_band_m = 0.002;
  /// [m] candidates for the bottom face come at least this close to the lowest vertex (a foot
  /// tilted in the standing pose still has its whole face found).
  double candidate_band_m = 0.01;
  /// Forward direction in F (the robot's +X); the sole's length is measured along its projection
  /// onto the sole plane.
  Vec3 forward_F = Vec3::UnitX();
};

struct SoleFit {
  Vec3 p_F_center = Vec3::Zero();  ///< [m] centre of the sole rectangle (on its bottom face)
  Mat3 R_F_S = Mat3::Identity();   ///< sole frame: x forward, y left, z the normal into the foot
  Vec2 size_m = Vec2::Zero();      ///< [m] length along sole x, width along sole y
  double tilt_rad = 0;             ///< angle between the sole normal and F's z (world up)
  int face_vertices = 0;           ///< vertices found on the bottom face
};

/// Fits the sole rectangle: the bounds, along the forward and left directions of the sole plane,
/// of the vertices on the bottom face. Returns size zero when the surface has no triangles.
SoleFit fit_sole(const FootSurface& surface, const SoleFitOptions& options = {});

}  // namespace rt
