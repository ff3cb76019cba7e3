#pragma once
/// Trunk mapping at a new contact (paper §V-B) as both check controllers use it: when every foot
/// the reference puts down pushes on the floor, eq. (20)–(24) match the reference's soles (laid
/// flat) to the robot's actual sole corners.

#include <array>

#include "retarget/control/trunk_mapping.hpp"
#include "retarget/sim/plant.hpp"
#include "retarget/sim/reference_signal.hpp"

namespace rt {

/// Whether every foot in `contact` presses on the floor with at least `threshold_n`.
bool contact_feet_pushing(const std::array<bool, 2>& contact, const ContactState& contacts, double threshold_n);

/// Eq. (20)–(24) from the feet in `contact`: the sole rectangles of the unmapped reference sample
/// (laid flat) against the robot's sole corners at `data`'s kinematics.
TrunkTransform trunk_transform_at_contacts(const RobotModel& model, const RobotData& data, const ReferenceSample& unmapped,
                                           const std::array<bool, 2>& contact, const TrunkMappingOptions& options);

/// The sample held still: velocities and accelerations of the joints and soles zeroed (the settle
/// phase holds the first frame).
void hold_still(ReferenceSample& sample);

}  // namespace rt
