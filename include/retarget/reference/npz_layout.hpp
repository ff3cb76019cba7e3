#pragma once
/// Which bodies and joints an NPZ carries, and in which order (README "Files out"). Simulator
/// loaders such as mjlab's and BeyondMimic's index the NPZ's body axis by their own body ids and
/// ignore `body_names`, so the order must be the simulator's:
///
///   urdf        body 0 the root link, then every other URDF link in URDF order (fixed links
///               included); joints in the robot's export (CSV) order
///   mjcf:FILE   the MJCF's bodies in document order (MuJoCo body ids 1, 2, ...; the world body is
///               not a body here), each matched by name to a URDF link: a body is the URDF link of
///               its name, whose frame it carries, and URDF links without a body are fixed links
///               the MJCF merged into their parents. Joints in the MJCF's document order (qpos
///               order). Every movable URDF joint must be in the MJCF and sit in the body of its
///               child link; the first body must be the URDF root (it carries the free joint)
///   names:FILE  YAML `{bodies: [link, ...], joints: [joint, ...]}`: bodies any URDF links (at least
///               one), joints every movable joint once; either key may be left out (bodies: the
///               urdf layout's, joints: the export order)
///
/// Errors are InputError with the file and line (or key path) of the offending name.

#include <string>
#include <vector>

#include "retarget/model/robot_data.hpp"
#include "retarget/reference/npz_body_arrays.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

struct NpzLayout {
  std::string spec;                      ///< "urdf", "mjcf:<path>" or "names:<path>" (meta.json records it)
  std::vector<int> body_links;           ///< NPZ body b is link body_links[b] (index into model.links())
  std::vector<std::string> joint_order;  ///< joint_pos / joint_vel column order
};

/// Resolves a layout spec ("urdf", "mjcf:FILE", "names:FILE"; FILE as given, relative to the
/// working directory) against the robot. `where` names the spec in messages ("--npz-layout").
NpzLayout resolve_npz_layout(const RobotModel& model, const std::string& spec, const std::string& where);

/// The joint order stated by FILE for an NPZ that does not name its joints (`validate
/// --joint-order`): an MJCF (.xml: its joint document order), or YAML, either a list of joint
/// names or a names-layout mapping with `joints`. Every movable joint of the robot, once.
std::vector<std::string> read_joint_order(const RobotModel& model, const std::string& path);

/// World pose and velocity of the layout's bodies over a reference; velocities by central
/// differences at the reference rate (one-sided at the ends). `joint_order` is copied from the
/// layout, so the NPZ writer puts the joint columns in that order.
NpzBodyArrays compute_body_arrays(const RobotModel& model, RobotData& data, const Reference& reference,
                                  const NpzLayout& layout);

}  // namespace rt
