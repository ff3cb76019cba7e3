#include "retarget/motion/landmarks.hpp"

#include <gtest/gtest.h>

namespace rt {
namespace {

TEST(Landmarks, NamesRoundTripAndAreUnique) {
  for (Landmark l : all_landmarks()) {
    const auto name = landmark_name(l);
    ASSERT_EQ(landmark_from_name(name), l) << name;
  }
  EXPECT_EQ(landmark_from_name("left_knee"), Landmark::LeftKnee);
  EXPECT_FALSE(landmark_from_name("left_kneee").has_value());
}

TEST(Landmarks, MirrorSwapsSides) {
  EXPECT_EQ(mirror(Landmark::LeftWrist), Landmark::RightWrist);
  EXPECT_EQ(mirror(Landmark::RightHeel), Landmark::LeftHeel);
  EXPECT_EQ(mirror(Landmark::Pelvis), Landmark::Pelvis);
  for (Landmark l : all_landmarks()) EXPECT_EQ(mirror(mirror(l)), l);
}

}  // namespace
}  // namespace rt
