#include "retarget/balance/support_polygon.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rt {
namespace {

// Two 0.2 x 0.1 soles, centres at y = ±0.1.
std::vector<Vec2> two_feet() {
  std::vector<Vec2> pts;
  for (double yc : {0.1, -0.1})
    for (double dx : {-0.1, 0.1})
      for (double dy : {-0.05, 0.05}) pts.emplace_back(dx, yc + dy);
  return pts;
}

TEST(SupportPolygon, HullOfTwoFeet) {
  const auto poly = SupportPolygon::convex_hull(two_feet());
  ASSERT_EQ(poly.vertices().size(), 4u);
  EXPECT_NEAR(poly.area(), 0.2 * 0.3, 1e-12);
  EXPECT_TRUE(poly.centroid().isZero(1e-12));
  EXPECT_NEAR(poly.signed_distance(Vec2(0, 0)), -0.1, 1e-12);
  EXPECT_NEAR(poly.signed_distance(Vec2(0, 0.2)), 0.05, 1e-12);
  EXPECT_NEAR(poly.signed_distance(Vec2(0.2, 0.25)), std::hypot(0.1, 0.1), 1e-12);
  EXPECT_TRUE(poly.contains(Vec2(0.05, 0.1)));
  EXPECT_FALSE(poly.contains(Vec2(0.05, 0.1), 0.06));
  EXPECT_TRUE(poly.closest_boundary_point(Vec2(0.0, 0.3)).isApprox(Vec2(0.0, 0.15)));
}

// contains() tests edge half-planes; it must agree with the signed distance it stands for.
TEST(SupportPolygon, ContainsAgreesWithTheSignedDistance) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3), margin(0.0, 0.08);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Vec2> pts;
    for (int k = 0; k < 8; ++k) pts.emplace_back(u(rng), u(rng));
    const auto poly = SupportPolygon::convex_hull(pts);
    for (int k = 0; k < 200; ++k) {
      const Vec2 p(u(rng), u(rng));
      const double m = k % 4 == 0 ? 0.0 : margin(rng);
      const double sd = poly.signed_distance(p);
      if (std::abs(sd + m) < 1e-12) continue;  // on the boundary of the test: either answer
      EXPECT_EQ(poly.contains(p, m), sd <= -m) << "trial " << trial << " point " << p.transpose() << " margin " << m;
    }
  }
}

TEST(SupportPolygon, CounterClockwiseAndCollinearPointsDropped) {
  const auto poly = SupportPolygon::convex_hull({{0, 0}, {1, 0}, {0.5, 0}, {1, 1}, {0, 1}, {0.5, 0.5}});
  ASSERT_EQ(poly.vertices().size(), 4u);
  EXPECT_GT(poly.area(), 0);
}

TEST(SupportPolygon, ExitPointTowardsNewContact) {
  // One left sole; the new contact is at the right foot (paper Fig. 6).
  const auto left = SupportPolygon::convex_hull({{-0.1, 0.05}, {0.1, 0.05}, {0.1, 0.15}, {-0.1, 0.15}});
  const auto b = left.exit_point(Vec2(0, 0.1), Vec2(0, -0.1));
  ASSERT_TRUE(b.has_value());
  EXPECT_TRUE(b->isApprox(Vec2(0, 0.05)));
  EXPECT_FALSE(left.exit_point(Vec2(0, -0.2), Vec2(0, -0.1)).has_value());  // starts outside
  EXPECT_FALSE(left.exit_point(Vec2(0, 0.1), Vec2(0, 0.12)).has_value());   // never leaves
}

TEST(SupportPolygon, DegenerateHulls) {
  EXPECT_TRUE(SupportPolygon::convex_hull({}).empty());
  EXPECT_TRUE(std::isinf(SupportPolygon().signed_distance(Vec2::Zero())));
  const auto seg = SupportPolygon::convex_hull({{0, 0}, {1, 0}});
  EXPECT_NEAR(seg.signed_distance(Vec2(0.5, 0.2)), 0.2, 1e-12);
  EXPECT_TRUE(seg.centroid().isApprox(Vec2(0.5, 0)));
}

}  // namespace
}  // namespace rt
