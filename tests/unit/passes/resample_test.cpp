#include "retarget/passes/resample.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "retarget/model/robot_model.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

std::vector<std::uint8_t> stance(int T, std::initializer_list<std::pair<int, int>> runs) {
  std::vector<std::uint8_t> v(static_cast<std::size_t>(T), 0);
  for (const auto& [begin, end] : runs)
    for (int f = begin; f < end; ++f) v[static_cast<std::size_t>(f)] = 1;
  return v;
}

std::vector<int> stance_frames(const std::vector<std::uint8_t>& c) {
  std::vector<int> out;
  for (std::size_t f = 0; f < c.size(); ++f)
    if (c[f]) out.push_back(static_cast<int>(f));
  return out;
}

class ResampleContacts : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { model_ = RobotModel::load(test::source_path("robots/humanoid25")); }
  static void TearDownTestSuite() { model_.reset(); }

  // 2.54 s at 100 Hz (255 frames, as the BTK Plug-in Gait trial), standing, exported at 30 Hz.
  static Reference resample(const std::vector<std::uint8_t>& left, const std::vector<std::uint8_t>& right) {
    RobotMotion motion;
    motion.fps = 100;
    motion.q = model_->standing_q().replicate(1, static_cast<Eigen::Index>(left.size()));
    ContactSchedule contacts;
    contacts.in_contact = {left, right};
    return resample_motion(*model_, motion, contacts, Mat3X(), Eigen::Matrix2Xd(), 30);
  }
  static std::unique_ptr<RobotModel> model_;
};
std::unique_ptr<RobotModel> ResampleContacts::model_;

TEST_F(ResampleContacts, LongStancesTakeTheNearestSourceFrame) {
  const int T = 255;
  const Reference ref = resample(stance(T, {{0, 100}, {160, 255}}), stance(T, {{0, T}}));
  ASSERT_EQ(ref.num_frames(), 77);  // 0 .. 2.533 s
  // Export frame k samples source frame round(k * 100 / 30): 0..99 -> k 0..29 (k = 30 is 100),
  // 160..254 -> k 48 (160) .. 76.
  std::vector<int> expected;
  for (int k = 0; k <= 29; ++k) expected.push_back(k);
  for (int k = 48; k <= 76; ++k) expected.push_back(k);
  EXPECT_EQ(stance_frames(ref.contact[0]), expected);
  EXPECT_EQ(stance_frames(ref.contact[1]).size(), 77u);
}

TEST_F(ResampleContacts, AStanceNoExportFrameSamplesIsKeptOnTheNearestOne) {
  const int T = 255;
  // Left: a one-frame stance at 1.51 s (export frames 45 and 46 sample source frames 150 and 153)
  // and a touchdown on the clip's last source frame (2.54 s, after the last export frame, 2.533 s).
  const Reference ref = resample(stance(T, {{0, 100}, {151, 152}, {254, 255}}), stance(T, {{0, T}}));
  ASSERT_EQ(ref.num_frames(), 77);
  const std::vector<int> left = stance_frames(ref.contact[0]);
  EXPECT_EQ(left.size(), 30u + 2u);
  EXPECT_EQ(left[30], 45);  // 1.51 s -> 1.50 s
  EXPECT_EQ(left[31], 76);  // the touchdown at the end is kept on the last frame
}

}  // namespace
}  // namespace rt
