#pragma once
/// BVH skeleton motion -> HumanMotion (design.md §3.1).
///
/// Steps: read the file (formats/bvh), recognise the skeleton (built-in name profiles or the
/// user profile `options.profile_path`, skeleton_profile.hpp), forward kinematics of every frame,
/// landmark positions, units (detected from the skeleton size unless `options.source_units`),
/// up axis (detected from the head-over-feet direction unless `options.up_axis`), conversion to
/// metres / Z up, synthetic T-pose leading frames dropped (unless `options.drop_tpose` is false),
/// frame rate from `Frame Time` (unless `options.source_fps`), and finally
/// rt::normalize_motion(motion, options.normalize).
///
/// Landmarks: every landmark the profile resolves is present with all samples Measured. The pelvis
/// is the midpoint of the hip joint centres; the head the midpoint of the head joint and its top
/// End Site when there is one; the toe the toe joint or, without one, the foot End Site; the hand
/// the finger base or the hand End Site. Heels are not part of BVH skeletons and stay absent.
///
/// Detection rules (all reported in motion.diagnostics and motion.source.details):
///  * units: the candidate (m, cm, mm, inch, cmu = 1/0.45 inch) that makes the skeleton's
///    segment-length size closest to a 1.75 m adult's (size = thigh + shank + pelvis-to-head
///    length, which is pose-independent); the guess is wrong for skeletons far from adult size
///    (children, scaled rigs): override with `--source-units`.
///  * up axis: the axis (with sign) closest to the mean head-above-ankles direction over the clip.
///  * synthetic T-pose: up to 10 leading frames whose arms are straight and horizontal, followed
///    by a jump of the root-relative pose of at least 0.15 m and 8x the clip's median
///    frame-to-frame change.
///
/// motion.source.details keys: joints, channels, end_sites, root, frame_time_s, declared_frames,
/// profile_origin, skeleton_size_m, up_axis (signed, e.g. "-y"), up_axis_confidence (detected
/// only), tpose_frames (when a lead-in was found), head_joint_height_m and stature_m. The stature
/// estimate is the head joint's height above the floor at the first kept frame / 0.87 (the head
/// joint sits at the skull base in every built-in convention; head height is ~0.13 of stature);
/// a value outside 1.0-2.5 m is reported as a warning that units or up axis are likely wrong.

#include <string>

#include "formats/bvh/bvh_file.hpp"
#include "retarget/motion/human_motion.hpp"
#include "retarget/motion/load_motion.hpp"

namespace rt {

/// Loads a BVH clip. Throws InputError (with `file:line:col` for malformed text, `file` for an
/// unrecognised skeleton, `file frame N joint J` for numerically unusable data).
HumanMotion load_bvh_motion(const std::string& path, const MotionLoadOptions& options = {});

/// Converts an already-read BVH file (`file.name` is used as the path in messages and in
/// motion.source.path).
HumanMotion bvh_to_human_motion(const BvhFile& file, const MotionLoadOptions& options = {});

}  // namespace rt
