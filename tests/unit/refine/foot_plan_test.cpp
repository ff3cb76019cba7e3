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

// A performer's toe-off at 30 fps: the source sole leaves its stance pitched 50 deg (heel up) and
// levels out by mid-swing. Faded in over the 0.1 s guard, the planned sole turns through most of
// that in two frames; a longer tilt ramp spreads it, and mid-swing keeps the source's tilt.
TEST(FootPlan, ATiltRampSpreadsTheToeOffTilt) {
  const int T = 40;
  const double fps = 30;
  std::array<std::vector<std::uint8_t>, 2> contacts;
  std::array<std::vector<SolePose>, 2> soles;
  for (auto& c : contacts) c.assign(T, 1);
  for (int f = 10; f < 28; ++f) contacts[0][static_cast<std::size_t>(f)] = 0;  // swing [10, 28): 0.6 s
  for (auto& s : soles) s.resize(T);
  for (int f = 0; f < T; ++f) {
    const double u = std::clamp((f - 9) / 19.0, 0.0, 1.0);
    const double pitch = f < 10 ? 0.0 : f >= 28 ? 0.0 : 0.87 * std::max(0.0, 1 - 2 * u) + 0.15 * std::sin(M_PI * u);
    SolePose& p = soles[0][static_cast<std::size_t>(f)];
    p.p_W = Vec3(0.4 * u, 0.1, 0.08 * std::sin(M_PI * u) + 0.06 * std::sin(pitch));
    p.R_W = yaw_pitch(0, pitch);
    soles[1][static_cast<std::size_t>(f)].p_W = Vec3(0.2, -0.1, 0);
  }
  const std::vector<SoleAnchor> anchors = stance_anchors(soles, contacts);
  auto largest_tilt_step = [&](const FootPlan& plan) {  // [rad per frame]
    double out = 0;
    for (int f = 10; f <= 28; ++f) {
      const Mat3 d = plan.feet[0][static_cast<std::size_t>(f - 1)].pose.R_W.transpose() * plan.feet[0][static_cast<std::size_t>(f)].pose.R_W;
      out = std::max(out, AngleAxis(d).angle());
    }
    return out;
  };
  FootPlanOptions o;
  const FootPlan guard_only = plan_feet(anchors, soles, contacts, fps, o);
  o.tilt_ramp_s = 0.25;
  const FootPlan ramped = plan_feet(anchors, soles, contacts, fps, o);
  EXPECT_GT(largest_tilt_step(guard_only), 0.3);  // about 20 deg between two frames
  EXPECT_LT(largest_tilt_step(ramped), 0.5 * largest_tilt_step(guard_only));
  // Lift-off and touchdown stay flat, and mid-swing keeps the source's tilt.
  for (const int f : {10, 27}) EXPECT_GT(ramped.feet[0][static_cast<std::size_t>(f)].pose.R_W(2, 2), std::cos(3 * M_PI / 180));
  const double mid_source = std::acos(soles[0][19].R_W(2, 2)), mid_planned = std::acos(ramped.feet[0][19].pose.R_W(2, 2));
  EXPECT_NEAR(mid_planned, mid_source, 1e-9);
  // The clearance still holds beyond the guard.
  for (int f = 14; f < 24; ++f) EXPECT_GE(ramped.feet[0][static_cast<std::size_t>(f)].pose.p_W.z(), o.clearance_m);
}

}  // namespace
}  // namespace rt::refine
