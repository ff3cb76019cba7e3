#pragma once
/// Skeleton profiles: which joint (or End Site) of a BVH skeleton gives each canonical landmark
/// (landmarks.hpp). Built-in profiles cover the common conventions; a user profile (YAML) covers
/// any other skeleton.
///
/// User profile file (`--skeleton-profile FILE.yaml`):
///
///     name: my_rig                 # required; reported as the profile name
///     base: mixamo                 # optional: start from a built-in profile and override it
///     landmarks:                   # landmark name -> joint reference, or a list of alternatives
///       left_knee: LeftLeg                          # the joint's origin
///       head: {joint: Head, point: midpoint}        # midpoint of the joint and its End Site
///       left_toe: [LeftToeBase, {joint: LeftFoot, point: end_site}]   # first one found wins
///       left_hand: null                             # drop a landmark inherited from `base`
///
/// `point` is `joint` (default), `end_site` (the joint's End Site) or `midpoint` (halfway between
/// the joint and its End Site, the joint alone when it has none). Joint names match
/// case-insensitively and ignore a namespace prefix (`mixamorig:Hips` matches `Hips`).
/// `pelvis` may be given; otherwise it is the midpoint of the two hip landmarks. Landmark names
/// are those of landmarks.hpp (`left_knee`, `right_toe`, ...). Unknown keys, unknown landmark or
/// point names, and joints that are not in the clip are errors with the YAML file and line.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/bvh/bvh_file.hpp"
#include "retarget/core/yaml_view.hpp"
#include "retarget/motion/landmarks.hpp"

namespace rt {

/// Which point of a joint a landmark reads.
enum class JointPoint : std::uint8_t {
  Joint,     ///< the joint's origin
  EndSite,   ///< the joint's first End Site with a non-zero OFFSET (unresolved when there is none)
  Midpoint,  ///< halfway between the joint and that End Site; the joint alone when it has none
};

/// "joint", "end_site", "midpoint".
std::string_view joint_point_name(JointPoint point);

struct JointRef {
  std::string joint;  ///< joint name (case-insensitive, namespace prefix ignored)
  JointPoint point = JointPoint::Joint;
};

struct SkeletonProfile {
  std::string name;
  std::string origin = "built-in";  ///< "built-in" or the YAML file path
  /// Per landmark, alternatives in order of preference (the first that resolves is used); an
  /// empty list means the profile does not provide the landmark. An empty pelvis list means
  /// "midpoint of the hip landmarks".
  std::array<std::vector<JointRef>, kLandmarkCount> landmarks;
  /// YAML location ("file:line") of each landmark entry of a user profile; empty for built-ins.
  std::array<std::string, kLandmarkCount> locations;
  /// Joint names characteristic of this convention; they rank profiles that all resolve the
  /// required landmarks (e.g. CMU MotionBuilder vs Mixamo, which share most names).
  std::vector<std::string> signature;
};

/// Landmarks a profile must resolve for a skeleton to count as recognised: hips, knees, ankles,
/// toes, shoulders, elbows, wrists and head (the pelvis follows from the hips).
const std::vector<Landmark>& required_skeleton_landmarks();

/// The built-in profiles: cmu_motionbuilder_2008, cmu_motionbuilder_2010, cmu_3dsmax, cmu_daz,
/// iclone_cc_base, bandai_namco, games105, mixamo (PyMO / Mixamo naming).
const std::vector<SkeletonProfile>& builtin_skeleton_profiles();

/// Parses a user profile (format above). InputError with `file:line: key.path: message`.
SkeletonProfile load_skeleton_profile(const std::string& path);
SkeletonProfile parse_skeleton_profile(const YamlView& root);

/// Where a landmark is read in one particular skeleton.
struct LandmarkSource {
  int joint = -1;     ///< BvhFile joint index; -1 when the landmark is not available
  int end_site = -1;  ///< BvhFile End Site index for EndSite / Midpoint points; -1 for none
  JointPoint point = JointPoint::Joint;
  bool available() const { return joint >= 0; }
};

/// A profile resolved against a skeleton.
struct SkeletonBinding {
  std::string profile;  ///< profile name
  std::string origin;   ///< "built-in" or the YAML path
  std::array<LandmarkSource, kLandmarkCount> sources;
  bool pelvis_from_hips = true;  ///< pelvis = midpoint of the hip landmarks (sources[Pelvis] unused)
  int signature_hits = 0;        ///< how many of the profile's signature names the skeleton has
  std::vector<Landmark> missing_required;  ///< required landmarks that did not resolve

  bool has(Landmark l) const {
    return l == Landmark::Pelvis && pelvis_from_hips
               ? sources[static_cast<std::size_t>(index(Landmark::LeftHip))].available() &&
                     sources[static_cast<std::size_t>(index(Landmark::RightHip))].available()
               : sources[static_cast<std::size_t>(index(l))].available();
  }
};

/// Resolves `profile` against the skeleton of `file`. For a user profile (origin != "built-in")
/// an entry none of whose joints exists is an InputError at the entry's YAML line; required
/// landmarks that the profile does not give end up in missing_required.
SkeletonBinding bind_skeleton_profile(const SkeletonProfile& profile, const BvhFile& file);

/// The built-in profile that fits `file` best: among those resolving every required landmark,
/// the one with the most signature names, then the most landmarks. InputError (location: the
/// file) naming the landmarks the closest profile misses and how to pass a profile otherwise.
SkeletonBinding recognise_skeleton(const BvhFile& file);

}  // namespace rt
