#include "retarget/control/trunk_mapping.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"

namespace rt {

namespace {

struct Principal {
  Vec3 centre = Vec3::Zero();
  double theta = 0;            // angle of the first principal axis from +x
  Vec2 singular = Vec2::Zero();
};

Principal principal(const std::vector<Vec3>& pts) {
  Principal p;
  for (const Vec3& v : pts) p.centre += v;
  p.centre /= static_cast<double>(pts.size());
  Eigen::Matrix2Xd X(2, static_cast<Eigen::Index>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) X.col(static_cast<Eigen::Index>(i)) = (pts[i] - p.centre).head<2>();
  const Eigen::JacobiSVD<Eigen::Matrix2Xd> svd(X, Eigen::ComputeFullU);
  // A single point gives one singular value (2 x 1 matrix): the missing one is 0.
  for (Eigen::Index i = 0; i < std::min<Eigen::Index>(2, svd.singularValues().size()); ++i)
    p.singular[i] = svd.singularValues()[i];
  p.theta = std::atan2(svd.matrixU()(1, 0), svd.matrixU()(0, 0));
  return p;
}

Mat3 rot_z(double a) { return AngleAxis(a, Vec3::UnitZ()).toRotationMatrix(); }

}  // namespace

Mat3 TrunkTransform::Omega() const { return rot_z(yaw_rad); }

Vec3 TrunkTransform::apply_position(const Vec3& p_hat_W) const {
  const Vec3 S(scale.x(), scale.y(), 1.0);
  const Vec3 local = rot_z(-theta_ref_rad) * (p_hat_W - c_ref_W);
  return c_act_W + rot_z(theta_ref_rad + yaw_rad) * S.cwiseProduct(local);
}

Mat3 TrunkTransform::linear() const {
  return rot_z(theta_ref_rad + yaw_rad) * Vec3(scale.x(), scale.y(), 1.0).asDiagonal() * rot_z(-theta_ref_rad);
}

Quat TrunkTransform::apply_orientation(const Quat& R_hat_W) const {
  return (Quat(AngleAxis(yaw_rad, Vec3::UnitZ())) * R_hat_W).normalized();
}

TrunkTransform compute_trunk_transform(const std::vector<Vec3>& p_ref, const std::vector<Vec3>& p_act,
                                       const TrunkMappingOptions& o) {
  if (p_ref.empty() || p_ref.size() != p_act.size())
    throw InputError("trunk mapping: expected matching non-empty contact point sets, got " +
                     std::to_string(p_ref.size()) + " reference and " + std::to_string(p_act.size()) + " actual");
  const Principal ref = principal(p_ref), act = principal(p_act);
  TrunkTransform t;
  t.c_ref_W = ref.centre;
  t.c_act_W = act.centre;
  t.theta_ref_rad = ref.theta;
  const bool oriented = ref.singular[0] >= o.min_spread_m && act.singular[0] >= o.min_spread_m &&
                        ref.singular[1] < o.isotropy_ratio * ref.singular[0] &&
                        act.singular[1] < o.isotropy_ratio * act.singular[0];
  if (oriented) {
    // A principal axis has no sign: take the smallest rotation between the two axes.
    double d = std::remainder(act.theta - ref.theta, M_PI);
    if (d <= -M_PI / 2) d += M_PI;
    t.yaw_rad = d;
  }
  for (int i = 0; i < 2; ++i) {
    if (ref.singular[i] >= o.min_spread_m && act.singular[i] >= o.min_spread_m)
      t.scale[i] = std::clamp(act.singular[i] / ref.singular[i], 1.0 / o.max_scale, o.max_scale);
  }
  return t;
}

}  // namespace rt
