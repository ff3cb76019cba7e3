#pragma once
/// Forward kinematics of a BVH skeleton (BvhFile): global joint frames and End Site positions per
/// frame, in the file's world frame F and the file's units.
///
/// Conventions (the de-facto BVH semantics of Biovision, MotionBuilder, Blender and assimp):
///  * angles are degrees; a joint's rotation is the product of its rotation channels in the
///    declared order, each about the joint's own already-rotated axes (intrinsic), so channels
///    `Zrotation Xrotation Yrotation` give R = Rz(z) * Rx(x) * Ry(y);
///  * a joint's origin in its parent's frame is its OFFSET, except that each position channel
///    replaces the matching OFFSET component (root translation channels and position channels on
///    non-root joints alike);
///  * X_F_joint = X_F_parent * Translation(t) * Rotation(R); an End Site is the point OFFSET in its
///    parent joint's frame.

#include <vector>

#include "formats/bvh/bvh_file.hpp"
#include "retarget/core/types.hpp"

namespace rt {

/// Global pose of one frame. Reusable workspace: bvh_forward_kinematics resizes it once and
/// then only overwrites it.
struct BvhPose {
  std::vector<Mat3> R_F_joint;  ///< orientation of each joint frame in F
  Mat3X p_F_joint;              ///< [file units] origin of each joint in F, 3 x joints
  Mat3X p_F_end_site;           ///< [file units] each End Site in F, 3 x end sites
};

/// Rotation of `joint` relative to its parent from one frame's channel values (a row of
/// BvhFile::values).
Mat3 bvh_local_rotation(const BvhJoint& joint, const double* frame_values);

/// Origin of `joint` in its parent's frame [file units]: OFFSET with position channels substituted.
Vec3 bvh_local_translation(const BvhJoint& joint, const double* frame_values);

/// Computes the pose of frame `frame` (0 <= frame < file.num_frames). With `joint_mask` (one entry
/// per joint, non-zero = compute) only the masked joints and their End Sites are computed and the
/// rest of `pose` is left untouched; the mask must include every ancestor of a masked joint
/// (bvh_ancestor_closure builds such a mask).
void bvh_forward_kinematics(const BvhFile& file, int frame, BvhPose& pose,
                            const std::vector<char>* joint_mask = nullptr);

/// Mask (one entry per joint) of `joints` and all their ancestors; out-of-range indices are ignored.
std::vector<char> bvh_ancestor_closure(const BvhFile& file, const std::vector<int>& joints);

}  // namespace rt
