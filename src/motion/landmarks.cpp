#include "retarget/motion/landmarks.hpp"

namespace rt {

namespace {
constexpr std::array<std::string_view, kLandmarkCount> kNames = {
    "pelvis",         "spine",          "chest",         "neck",          "head",
    "left_hip",       "left_knee",      "left_ankle",    "left_toe",      "left_heel",
    "left_shoulder",  "left_elbow",     "left_wrist",    "left_hand",     "right_hip",
    "right_knee",     "right_ankle",    "right_toe",     "right_heel",    "right_shoulder",
    "right_elbow",    "right_wrist",    "right_hand"};

constexpr int kFirstLeft = index(Landmark::LeftHip);
constexpr int kFirstRight = index(Landmark::RightHip);
constexpr int kSideCount = kFirstRight - kFirstLeft;
static_assert(kFirstRight + kSideCount == kLandmarkCount, "left and right blocks must match");
}  // namespace

const std::array<Landmark, kLandmarkCount>& all_landmarks() {
  static const std::array<Landmark, kLandmarkCount> all = [] {
    std::array<Landmark, kLandmarkCount> a{};
    for (int i = 0; i < kLandmarkCount; ++i) a[static_cast<std::size_t>(i)] = static_cast<Landmark>(i);
    return a;
  }();
  return all;
}

std::string_view landmark_name(Landmark l) {
  const int i = index(l);
  return (i >= 0 && i < kLandmarkCount) ? kNames[static_cast<std::size_t>(i)] : std::string_view("invalid");
}

std::optional<Landmark> landmark_from_name(std::string_view name) {
  for (int i = 0; i < kLandmarkCount; ++i)
    if (kNames[static_cast<std::size_t>(i)] == name) return static_cast<Landmark>(i);
  return std::nullopt;
}

Landmark mirror(Landmark l) {
  const int i = index(l);
  if (i >= kFirstLeft && i < kFirstRight) return static_cast<Landmark>(i + kSideCount);
  if (i >= kFirstRight && i < kLandmarkCount) return static_cast<Landmark>(i - kSideCount);
  return l;
}

}  // namespace rt
