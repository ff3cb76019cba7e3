#pragma once
/// ASF/AMC skeleton motion (the CMU library's original format) -> HumanMotion.
///
/// The ASF/AMC forward kinematics (Acclaim convention, as CMU's own viewer): a bone's rotation in
/// the world is A = A_parent C M C^-1, where C is the bone's `axis` rotation (its three angles
/// applied in the stated order, e.g. XYZ = x first, about fixed axes) and M the frame's dof
/// rotations applied in the bone's `dof` order; the bone runs from its parent's end to
/// start + length A direction. The root: position from the AMC root values in the `:root order`,
/// rotation C_root M C_root^-1 with the rotations applied in the root's `axis` order and C_root the
/// root `orientation`. Angles in the AMC's `:DEGREES`/`:RADIANS` (else the ASF's `:units angle`).
///
/// This is expressed exactly as a BVH skeleton (a joint at every bone's start, the bone's rotation
/// as that joint's rotation, decomposed into Z Y X channels per frame; End Sites at the leaf
/// bones' ends) and converted by bvh_to_human_motion, so units, up axis, T-pose, floor and
/// landmarks follow the BVH rules (bvh_motion.hpp) with the built-in `cmu_asf` profile (CMU bone
/// names: lfemur, ltibia, lfoot, ltoes, lhumerus, lradius, lwrist, ...), or a user profile naming
/// ASF bones (a bone's joint is its start, its End Site the end of a leaf bone).
///
/// AMC files state no frame rate: 120 Hz (the CMU library's) is assumed with a note, unless
/// `options.source_fps`.

#include <string>

#include "formats/asf/asf_amc.hpp"
#include "formats/bvh/bvh_file.hpp"
#include "retarget/motion/human_motion.hpp"
#include "retarget/motion/load_motion.hpp"

namespace rt {

/// The ASF beside an AMC: `options_asf` when given, else by CMU naming (`01_01.amc` -> `01.asf`),
/// the same stem (`walk.amc` -> `walk.asf`), or the only .asf in the folder. InputError naming the
/// candidates when none exists.
std::string find_asf_for(const std::string& amc_path, const std::string& options_asf);

/// The skeleton and motion as an equivalent BVH (see above); `name` is used in messages.
BvhFile asf_amc_to_bvh(const AsfSkeleton& skeleton, const AmcMotion& motion, double frame_time_s, const std::string& name);

/// Loads an AMC clip with its ASF. Throws InputError (file:line:col for malformed text).
HumanMotion load_asf_amc_motion(const std::string& amc_path, const MotionLoadOptions& options = {});

}  // namespace rt
