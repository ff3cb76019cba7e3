#pragma once
/// Acclaim ASF (skeleton) and AMC (motion) files as written, the CMU motion library's original
/// format: no unit conversion and no recognition of the skeleton.
///
/// ASF: `:units` (mass, length, angle deg|rad), `:root` (order of the AMC root values, axis order,
/// position, orientation), `:bonedata` (begin/end blocks: id, name, direction, length,
/// `axis ax ay az ORDER`, dof, limits, ...), `:hierarchy` (begin/end, "parent child ..." lines).
/// AMC: `:FULLY-SPECIFIED`, `:DEGREES` / `:RADIANS`, then frames: a frame number on its own line
/// (consecutive), then one "bone v1 v2 ..." line per bone with dofs, values in its dof order.
///
/// Bad input (same policy as the BVH reader): InputError "<file>:<line>:<col>: ..." for malformed
/// text, unknown keywords, bones or dofs, wrong value counts, non-finite numbers, a hierarchy that
/// is not a tree from the root, missing or repeated bones in a frame; sizes are bounded (at most
/// 1000 bones, files up to 1 GiB).

#include <array>
#include <string>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

/// One dof of a bone or the root: rotation about or translation along a local axis.
struct AsfDof {
  bool rotation = true;
  int axis = 0;  ///< 0 = x, 1 = y, 2 = z
};

struct AsfBone {
  std::string name;
  int parent = -1;               ///< index into AsfSkeleton::bones; -1 = child of the root
  Vec3 direction = Vec3::UnitX();  ///< unit direction in the global rest frame
  double length = 0;             ///< [length units]
  Vec3 axis_angles = Vec3::Zero();  ///< [angle units] the bone frame's orientation
  std::array<int, 3> axis_order{0, 1, 2};  ///< axes of axis_angles in the order applied (XYZ = 0,1,2)
  std::vector<AsfDof> dofs;      ///< in the order of the AMC values
  int line = 0;                  ///< line of the bone's `begin`
};

struct AsfSkeleton {
  std::string file;              ///< name used in messages
  double length_unit = 1;        ///< `:units length` (CMU: 0.45, i.e. a unit is 1/0.45 inch)
  bool angles_in_degrees = true; ///< `:units angle`
  std::vector<AsfDof> root_order;              ///< the AMC root values (TX TY TZ RX RY RZ in CMU files)
  std::array<int, 3> root_axis_order{0, 1, 2}; ///< order in which the root rotations are applied
  Vec3 root_position = Vec3::Zero();
  Vec3 root_orientation = Vec3::Zero();        ///< [angle units]
  /// Bones in an order where a parent precedes its children (the hierarchy's, depth-first).
  std::vector<AsfBone> bones;

  int find_bone(const std::string& name) const;
};

struct AmcMotion {
  std::string file;
  bool has_angle_unit = false;   ///< :DEGREES or :RADIANS given
  bool angles_in_degrees = true;
  int num_frames = 0;
  /// Per frame: the root values (skeleton.root_order) then every bone's dof values, in bone order.
  int values_per_frame = 0;
  std::vector<double> values;    ///< num_frames x values_per_frame, row-major
  std::vector<int> frame_lines;  ///< line of each frame's number
  /// Column of bone b's first value (-1 for bones without dofs).
  std::vector<int> bone_column;

  const double* frame(int f) const { return values.data() + static_cast<std::size_t>(f) * static_cast<std::size_t>(values_per_frame); }
};

/// Parses ASF text; `file` names it in messages.
AsfSkeleton parse_asf(const std::string& text, const std::string& file);
AsfSkeleton read_asf(const std::string& path);

/// Parses AMC text for `skeleton`.
AmcMotion parse_amc(const std::string& text, const std::string& file, const AsfSkeleton& skeleton);
AmcMotion read_amc(const std::string& path, const AsfSkeleton& skeleton);

}  // namespace rt
