#include "retarget/model/collision_hull.hpp"

#include <gtest/gtest.h>

#include <random>

#include "model_cache.hpp"
#include "retarget/model/kinematics.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

TEST(CollisionHull, HullVerticesOfACubeWithInteriorPoints) {
  std::vector<Vec3> points;
  for (int k = 0; k < 8; ++k) points.emplace_back(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  for (int i = 0; i < 200; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  const std::vector<Vec3> hull = convex_hull_vertices(points);
  EXPECT_EQ(hull.size(), 8u);
  for (const Vec3& p : hull) EXPECT_DOUBLE_EQ(p.cwiseAbs().minCoeff(), 1.0);
  // A flat set has no 3-D hull: its extreme points stand in (the square's corners among them).
  std::vector<Vec3> flat;
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j <= 10; ++j) flat.emplace_back(i * 0.1, j * 0.1, 0);
  const std::vector<Vec3> support = convex_hull_vertices(flat);
  EXPECT_LT(support.size(), flat.size());
  int corners = 0;
  for (const Vec3& p : support) corners += (p.x() == 0 || p.x() == 1.0) && (p.y() == 0 || p.y() == 1.0);
  EXPECT_EQ(corners, 4);
}

TEST(CollisionHull, SphereBoundsCoverThePoints) {
  const CollisionHull h = make_hull(3, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 2, 0)}, 0.1);
  EXPECT_EQ(h.link, 3);
  for (const Vec3& p : h.points_L) EXPECT_LE((p - h.bound_center_L).norm() + 0.1, h.bound_radius_m + 1e-12);
}

// humanoid25 standing: its soles are the lowest geometry, on the floor; lowered by 5 cm, every
// point found below the floor is 5 cm lower than before.
TEST(CollisionHull, LowestPointOfAStandingRobotIsItsSoles) {
  const RobotModel& model = test::cached_robot(test::source_path("robots/humanoid25"));
  ASSERT_FALSE(model.collision_hulls().empty());
  RobotData data(model);
  VecX q = model.standing_q();
  update_kinematics(model, data, q);
  const LowestPoint low = lowest_collision_point(model, data);
  ASSERT_GE(low.link, 0);
  const int left = model.soles()[0].link, right = model.soles()[1].link;
  EXPECT_TRUE(low.link == left || low.link == right) << model.links()[static_cast<std::size_t>(low.link)].name;
  EXPECT_NEAR(low.z_m, std::min(lowest_sole_corner_z(model, data, 0), lowest_sole_corner_z(model, data, 1)), 2e-3);
  std::vector<LowestPoint> below;
  collision_points_below(model, data, 0.001, below);
  q[2] -= 0.05;
  update_kinematics(model, data, q);
  EXPECT_NEAR(lowest_collision_point(model, data).z_m, low.z_m - 0.05, 1e-9);
  std::vector<LowestPoint> below_lowered;
  collision_points_below(model, data, 0.001 - 0.05, below_lowered);
  EXPECT_EQ(below.size(), below_lowered.size());
  // Skipping both feet leaves nothing that low.
  below_lowered.clear();
  collision_points_below(model, data, 0.001 - 0.05, below_lowered, left, right);
  EXPECT_TRUE(below_lowered.empty());
}

TEST(CollisionHull, G1MeshesAreReducedToTheirHulls) {
  RT_REQUIRE_SHARED(robots, "robots");
  const RobotModel& model = test::cached_robot(test::source_path("robots/g1"));
  std::size_t points = 0;
  for (const CollisionHull& h : model.collision_hulls()) points += h.points_L.size();
  EXPECT_GT(model.collision_hulls().size(), 10u);
  EXPECT_LT(points, 20000u);
  RobotData data(model);
  update_kinematics(model, data, model.standing_q());
  const LowestPoint low = lowest_collision_point(model, data);
  const std::string name = model.links()[static_cast<std::size_t>(low.link)].name;
  EXPECT_NE(name.find("ankle"), std::string::npos) << name;
  EXPECT_GT(low.z_m, -0.01);
}

}  // namespace
}  // namespace rt
