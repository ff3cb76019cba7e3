#include "retarget/control/trunk_mapping.hpp"

#include <gtest/gtest.h>

#include "retarget/core/error.hpp"

namespace rt {
namespace {

// Corners of two 0.30 x 0.08 soles 0.16 m apart: clearly elongated along x, so the principal axes
// are well defined.
std::vector<Vec3> stance() {
  std::vector<Vec3> p;
  for (double y : {0.08, -0.08})
    for (double dx : {-0.15, 0.15})
      for (double dy : {-0.04, 0.04}) p.emplace_back(0.3 + dx, y + dy, 0.0);
  return p;
}

std::vector<Vec3> transformed(const std::vector<Vec3>& pts, const Mat3& R, const Vec3& t) {
  std::vector<Vec3> out;
  for (const Vec3& p : pts) out.push_back(R * p + t);
  return out;
}

TEST(TrunkMapping, PureTranslation) {
  const auto ref = stance();
  const Vec3 d(0.05, -0.03, 0.01);
  const TrunkTransform t = compute_trunk_transform(ref, transformed(ref, Mat3::Identity(), d));
  EXPECT_NEAR(t.yaw_rad, 0, 1e-12);
  EXPECT_TRUE(t.scale.isApprox(Vec2::Ones()));
  const Vec3 trunk(0.3, 0.0, 0.8);
  EXPECT_TRUE(t.apply_position(trunk).isApprox(trunk + d));
  EXPECT_LT(t.apply_orientation(Quat::Identity()).angularDistance(Quat::Identity()), 1e-12);
}

TEST(TrunkMapping, PureRotationAboutTheContactCentre) {
  const auto ref = stance();
  const double yaw = 0.3;
  const Mat3 R = AngleAxis(yaw, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 centre(0.3, 0, 0);
  const auto act = transformed(ref, R, centre - R * centre);  // rotate about the centre
  const TrunkTransform t = compute_trunk_transform(ref, act);
  EXPECT_NEAR(t.yaw_rad, yaw, 1e-9);
  EXPECT_TRUE(t.scale.isApprox(Vec2::Ones(), 1e-9));
  const Vec3 trunk(0.35, 0.02, 0.8);
  EXPECT_TRUE(t.apply_position(trunk).isApprox(R * (trunk - centre) + centre, 1e-9));
  const Quat q_ref(AngleAxis(0.2, Vec3::UnitX()));
  EXPECT_LT(t.apply_orientation(q_ref).angularDistance(Quat(R) * q_ref), 1e-9);
  // Every actual contact point is reproduced by mapping its reference point.
  for (std::size_t i = 0; i < ref.size(); ++i) EXPECT_TRUE(t.apply_position(ref[i]).isApprox(act[i], 1e-9));
}

TEST(TrunkMapping, AnisotropicScaleAlongPrincipalAxes) {
  const auto ref = stance();
  std::vector<Vec3> act;
  for (const Vec3& p : ref) act.emplace_back(0.3 + 1.2 * (p.x() - 0.3), 0.8 * p.y(), p.z());
  const TrunkTransform t = compute_trunk_transform(ref, act);
  EXPECT_NEAR(t.yaw_rad, 0, 1e-9);
  EXPECT_NEAR(t.scale.x(), 1.2, 1e-9);
  EXPECT_NEAR(t.scale.y(), 0.8, 1e-9);
  for (std::size_t i = 0; i < ref.size(); ++i) EXPECT_TRUE(t.apply_position(ref[i]).isApprox(act[i], 1e-9));
}

TEST(TrunkMapping, ScaleIsClampedAndDegenerateSetsAreSafe) {
  const auto ref = stance();
  std::vector<Vec3> act;
  for (const Vec3& p : ref) act.emplace_back(0.3 + 5.0 * (p.x() - 0.3), p.y(), p.z());
  EXPECT_NEAR(compute_trunk_transform(ref, act).scale.x(), 1.5, 1e-12);
  // A single point: translation only.
  const TrunkTransform one = compute_trunk_transform({Vec3(0, 0, 0)}, {Vec3(0.1, 0, 0)});
  EXPECT_TRUE(one.scale.isApprox(Vec2::Ones()));
  EXPECT_EQ(one.yaw_rad, 0);
  EXPECT_THROW(compute_trunk_transform({}, {}), InputError);
  EXPECT_THROW(compute_trunk_transform({Vec3::Zero()}, {}), InputError);
}

}  // namespace
}  // namespace rt
