#pragma once
/// The canonical human landmark set (design.md §3.1). Every motion source (BVH skeleton, C3D
/// marker set) is reduced to these points; retargeting only ever sees landmarks.

#include <array>
#include <optional>
#include <string_view>

namespace rt {

enum class Landmark : int {
  Pelvis,  ///< hip-joint centre midpoint / skeleton root; carries orientation
  Spine,   ///< lower spine (lumbar)
  Chest,   ///< upper spine / thorax; carries orientation
  Neck,    ///< base of the neck (C7 level)
  Head,    ///< head centre or top-of-neck joint
  LeftHip,
  LeftKnee,
  LeftAnkle,  ///< ankle joint centre; the foot orientation is attached here
  LeftToe,    ///< ball of the foot / toe joint
  LeftHeel,
  LeftShoulder,  ///< gleno-humeral joint centre
  LeftElbow,
  LeftWrist,
  LeftHand,  ///< hand centre / finger base
  RightHip,
  RightKnee,
  RightAnkle,
  RightToe,
  RightHeel,
  RightShoulder,
  RightElbow,
  RightWrist,
  RightHand,
  Count
};

inline constexpr int kLandmarkCount = static_cast<int>(Landmark::Count);

/// All landmarks in enum order (handy for range-for).
const std::array<Landmark, kLandmarkCount>& all_landmarks();

/// snake_case name used in robot.yaml, profiles, reports: "pelvis", "left_knee", ...
std::string_view landmark_name(Landmark l);

/// Inverse of landmark_name; nullopt for unknown names.
std::optional<Landmark> landmark_from_name(std::string_view name);

/// Left <-> right counterpart (central landmarks map to themselves).
Landmark mirror(Landmark l);

inline constexpr int index(Landmark l) { return static_cast<int>(l); }

}  // namespace rt
