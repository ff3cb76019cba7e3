#include "src/refine/foot_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace rt::refine {
namespace {

Mat3 yaw_pitch(double yaw, double pitch) {
  return (AngleAxis(yaw, Vec3::UnitZ()) * AngleAxis(pitch, Vec3::UnitY())).toRotationMatrix();
}

// One foot: stance [0, 30), swing [30, 70), stance [70, 100) at 100 fps; the other foot stands.
struct Walk {
  std::array<std::vector<std::uint8_t>, 2> contacts;
  std::array<std::vector<SolePose>, 2> soles;
  Walk() {
    const int T = 100;
    for (auto& c : contacts) c.assign(T, 1);
    for (int f = 30; f < 70; ++f) contacts[0][static_cast<std::size_t>(f)] = 0;
    for (auto& s : soles) s.resize(T);
    for (int f = 0; f < T; ++f) {
      const double u = std::clamp((f - 29) / 41.0, 0.0, 1.0);
      SolePose& p = soles[0][static_cast<std::size_t>(f)];
      // The source foot slides a little in stance, drifts sideways in swing and pitches.
      p.p_W = Vec3(0.5 * u + (f < 30 ? 0.002 * f / 30 : 0), 0.1 + 0.03 * std::sin(M_PI * u), 0.06 * std::sin(M_PI * u) + 0.004);
      p.R_W = yaw_pitch(0.3 * u + (f < 30 ? 0.02 * std::sin(f * 0.3) : 0), 0.3 * std::sin(2 * M_PI * u));
      soles[1][static_cast<std::size_t>(f)].p_W = Vec3(0.25, -0.1, 0.002);
    }
  }
};

TEST(FootPlan, AnchorsAreTheMedianPositionAndMeanHeadingOfEachStance) {
  const Walk w;
  const std::vector<SoleAnchor> anchors = stance_anchors(w.soles, w.contacts);
  ASSERT_EQ(anchors.size(), 3u);  // left: two phases, right: one
  EXPECT_EQ(anchors[0].foot, 0);
  EXPECT_EQ(anchors[0].begin, 0);
  EXPECT_EQ(anchors[0].end, 30);
  EXPECT_NEAR(anchors[0].p_W.x(), 0.001, 1e-4);
  EXPECT_NEAR(anchors[0].yaw, 0.0, 0.01);
  EXPECT_NEAR(anchors[1].p_W.x(), 0.5, 1e-9);
  EXPECT_NEAR(anchors[1].yaw, 0.3, 1e-9);
  // Headings around ±π average to π, not 0.
  std::array<std::vector<SolePose>, 2> soles;
  std::array<std::vector<std::uint8_t>, 2> contacts{{std::vector<std::uint8_t>(4, 1), std::vector<std::uint8_t>(4, 0)}};
  soles[0].resize(4);
  soles[1].resize(4);
  for (int f = 0; f < 4; ++f) soles[0][static_cast<std::size_t>(f)].R_W = yaw_pitch(f % 2 ? 3.1 : -3.1, 0);
  const auto wrapped = stance_anchors(soles, contacts);
  ASSERT_EQ(wrapped.size(), 1u);
  EXPECT_NEAR(std::abs(wrapped[0].yaw), M_PI, 1e-9);
}

TEST(FootPlan, StanceIsFixedAndFlatSwingLeavesAndLandsVerticallyWithClearance) {
  const Walk w;
  const double fps = 100;
  FootPlanOptions o;
  const FootPlan plan = plan_feet(stance_anchors(w.soles, w.contacts), w.soles, w.contacts, fps, o);
  const auto& left = plan.feet[0];
  const SoleAnchor& A = plan.anchors[0];
  const SoleAnchor& B = plan.anchors[1];
  for (int f = 0; f < 30; ++f) {
    const FootTarget& t = left[static_cast<std::size_t>(f)];
    ASSERT_EQ(t.mode, FootMode::Stance);
    EXPECT_EQ(t.pose.p_W, Vec3(A.p_W.x(), A.p_W.y(), 0));
    EXPECT_NEAR(t.pose.R_W(2, 2), 1.0, 1e-12);  // flat
    EXPECT_NEAR(sole_yaw(t.pose.R_W), A.yaw, 1e-12);
  }
  double clearance_min = INFINITY;
  for (int f = 30; f < 70; ++f) {
    const FootTarget& t = left[static_cast<std::size_t>(f)];
    ASSERT_EQ(t.mode, FootMode::Swing);
    const int from_end = std::min(f - 29, 70 - f);
    if (from_end > o.guard_s * fps) clearance_min = std::min(clearance_min, t.pose.p_W.z());
    EXPECT_GE(t.pose.p_W.z(), 0.0);
  }
  EXPECT_GE(clearance_min, o.clearance_m);
  // First and last swing frames: close to the anchors, barely above the floor, nearly flat, and the
  // foot moves mostly vertically there.
  const FootTarget& first = left[30];
  const FootTarget& last = left[69];
  EXPECT_LT((first.pose.p_W.head<2>() - A.p_W).norm(), 1e-3);
  EXPECT_LT((last.pose.p_W.head<2>() - B.p_W).norm(), 1e-3);
  EXPECT_LT(first.pose.p_W.z(), 1e-3);
  EXPECT_LT(last.pose.p_W.z(), 1e-3);
  EXPECT_GT(first.pose.R_W(2, 2), std::cos(0.5 * M_PI / 180));
  EXPECT_GT(last.pose.R_W(2, 2), std::cos(0.5 * M_PI / 180));
  EXPECT_NEAR(sole_yaw(last.pose.R_W), B.yaw, 1e-3);
  // Mid-swing follows the source's sideways drift and keeps its tilt.
  EXPECT_GT(left[50].pose.p_W.y(), A.p_W.y() + 0.02);
  EXPECT_LT(left[40].pose.R_W(2, 2), std::cos(0.1));
  // The standing foot is held where it stands, on the floor.
  for (const FootTarget& t : plan.feet[1]) {
    ASSERT_EQ(t.mode, FootMode::Stance);
    EXPECT_EQ(t.pose.p_W.z(), 0.0);
  }
}

TEST(FootPlan, AFootWithoutStanceIsFreeAndCutSwingsKeepTheirEnd) {
  Walk w;
  w.contacts[1].assign(100, 0);                            // never down
  for (int f = 0; f < 10; ++f) w.contacts[0][static_cast<std::size_t>(f)] = 0;  // starts in the air
  const FootPlan plan = plan_feet(stance_anchors(w.soles, w.contacts), w.soles, w.contacts, 100, {});
  for (const FootTarget& t : plan.feet[1]) EXPECT_EQ(t.mode, FootMode::Free);
  EXPECT_EQ(plan.feet[0][0].mode, FootMode::Swing);
  EXPECT_LT((plan.feet[0][0].pose.p_W.head<2>() - w.soles[0][0].p_W.head<2>()).norm(), 1e-9);
}

}  // namespace
}  // namespace rt::refine
