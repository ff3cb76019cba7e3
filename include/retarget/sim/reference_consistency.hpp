#pragma once
/// Checks of the reference itself, before it is simulated: what no controller should be asked to
/// hide. A controller maps the reference onto where the robot's feet actually are (trunk mapping),
/// so a reference whose labelled stance feet are far off the floor (a root that jumps 0.3 m in one
/// frame, a clip with its floor at the wrong height) would otherwise be quietly re-based at the next
/// contact change and could pass; and the simulated motors have no speed limit, so a reference that
/// asks a joint for more speed than its motor has would be followed by lagging behind it.

#include <vector>

#include "retarget/sim/violations.hpp"

namespace rt {

class ReferenceSignal;
class RobotData;
class RobotModel;

/// `stance-off-floor` violations: spans of frames where a foot labelled in contact has its sole
/// centre more than `tolerance_m` above or below the reference's own floor, the median height of
/// all its labelled stance sole centres (so that a reference exported over a floor at another
/// constant height is not charged for it). Times are clip times: frame time minus `lead_s` (the
/// standing lead-in prepended to the signal, the check's own motion: its frames are not judged).
std::vector<Violation> stance_off_floor(const ReferenceSignal& signal, double lead_s, double tolerance_m);

/// `joint-velocity` violations of the reference itself: spans of frames where it moves a joint
/// faster than the joint's URDF velocity limit (central differences of the frames; joints without a
/// limit are not judged), from the clip's start on (the standing lead-in of `lead_s` is the check's
/// own motion). A robot that tracks such a reference only by lagging behind it performs
/// another motion, and one retimed too fast (a walk played 3x) asks for speeds no motor has.
std::vector<Violation> reference_joint_speed(const RobotModel& model, const ReferenceSignal& signal, double lead_s);

/// `reference-torque` violations: spans of frames where the reference asks a joint with no foot
/// below it (waist, arms, head) for more torque than its effort limit (model/torque_demand.hpp:
/// inverse dynamics of the frames), from the clip's start on. They do not fail the check by
/// themselves: how much the saturated joint's lag matters is what the simulation finds out.
std::vector<Violation> reference_torque_demand(const RobotModel& model, RobotData& data, const ReferenceSignal& signal, double lead_s);

}  // namespace rt
