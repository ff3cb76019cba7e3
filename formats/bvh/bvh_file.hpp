#pragma once
/// BvhFile: an in-memory mirror of a BVH (Biovision Hierarchy) file. It holds the hierarchy as
/// declared (joints, OFFSETs, per-joint CHANNELS in their declared order, End Sites) and the motion
/// matrix, in the file's own units and axes, with no interpretation: no unit or axis conversion,
/// no recognition of the skeleton. Forward kinematics is in bvh_kinematics.hpp.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

/// One motion channel of a joint. The order of the enumerators is used for axis arithmetic:
/// `axis = value % 3` (0 = X, 1 = Y, 2 = Z), rotations are the last three.
enum class BvhChannel : std::uint8_t { Xposition, Yposition, Zposition, Xrotation, Yrotation, Zrotation };

/// "Xposition", ..., "Zrotation" (the spelling used in files).
std::string_view bvh_channel_name(BvhChannel channel);
/// 0, 1, 2 for X, Y, Z.
inline int bvh_channel_axis(BvhChannel channel) { return static_cast<int>(channel) % 3; }
inline bool bvh_is_rotation(BvhChannel channel) { return static_cast<int>(channel) >= 3; }

/// A ROOT or JOINT block.
struct BvhJoint {
  std::string name;
  int parent = -1;                   ///< index into BvhFile::joints; -1 for a ROOT
  Vec3 offset = Vec3::Zero();        ///< OFFSET [file units], in the parent joint's frame
  std::vector<BvhChannel> channels;  ///< CHANNELS in declared order (may be empty)
  int first_column = 0;              ///< column of channels[0] in the motion matrix
  int line = 0;                      ///< 1-based line of the ROOT / JOINT keyword
};

/// An `End Site` block: a leaf point without channels, fixed in its parent joint's frame.
struct BvhEndSite {
  int parent = -1;             ///< index into BvhFile::joints
  Vec3 offset = Vec3::Zero();  ///< OFFSET [file units], in the parent joint's frame
  int line = 0;                ///< 1-based line of the `End Site` keyword
};

struct BvhFile {
  std::string name;  ///< path (or name) used in messages
  /// Joints in declaration (depth-first) order: a parent always precedes its children.
  std::vector<BvhJoint> joints;
  std::vector<BvhEndSite> end_sites;
  int num_channels = 0;     ///< columns of the motion matrix (sum of the joints' channel counts)
  int num_frames = 0;       ///< rows in `values`
  int declared_frames = 0;  ///< the `Frames:` value
  double frame_time_s = 0;  ///< [s] the `Frame Time:` value as written (may be 0 in broken files)
  int frame_time_decimals = -1;  ///< digits written after its decimal point (-1: exponent notation)
  /// Motion matrix, num_frames x num_channels, row-major; columns in declaration order.
  std::vector<double> values;

  int frames_line = 0;      ///< line of `Frames:`
  int frame_time_line = 0;  ///< line of `Frame Time:`
  int first_row_line = 0;   ///< line of the first motion row (0 when there is none)

  /// The channel values of frame `f` (num_channels of them).
  const double* frame(int f) const { return values.data() + static_cast<std::size_t>(f) * static_cast<std::size_t>(num_channels); }
  double value(int f, int column) const { return frame(f)[column]; }
  /// Index of the first joint with exactly this name, or -1.
  int find_joint(std::string_view joint_name) const;
  /// Joint that owns motion column `column`, or -1 if out of range.
  int joint_of_column(int column) const;
};

}  // namespace rt
