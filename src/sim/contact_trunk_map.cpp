#include "retarget/sim/contact_trunk_map.hpp"

#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"

namespace rt {

bool contact_feet_pushing(const std::array<bool, 2>& contact, const ContactState& contacts, double threshold_n) {
  for (std::size_t f = 0; f < 2; ++f)
    if (contact[f] && contacts.feet[f].normal_force_n < threshold_n) return false;
  return true;
}

TrunkTransform trunk_transform_at_contacts(const RobotModel& model, const RobotData& data, const ReferenceSample& unmapped,
                                           const std::array<bool, 2>& contact, const TrunkMappingOptions& options) {
  std::vector<Vec3> p_ref, p_act;
  for (std::size_t f = 0; f < 2; ++f) {
    if (!contact[f]) continue;
    const Sole& sole = model.soles()[f];
    const Iso3 X_link = link_pose(model, data, sole.link);
    // Eq. (20)-(24) use only centres, principal axes and spreads: corner order is irrelevant.
    for (const Vec3& c : sole_corners_W(flat_on_floor(unmapped.X_W_sole[f]), sole)) p_ref.push_back(c);
    for (const Vec3& c : sole.corners_L()) p_act.push_back(X_link * c);
  }
  return compute_trunk_transform(p_ref, p_act, options);
}

void hold_still(ReferenceSample& r) {
  r.v.setZero();
  r.a.setZero();
  for (auto& x : r.v_sole) x.setZero();
  for (auto& x : r.a_sole) x.setZero();
}

}  // namespace rt
