#pragma once
/// A URDF file as a plain, validated description (formats layer: no MuJoCo, no robot.yaml).
///
/// Reading goes through urdfdom (values) plus a tinyxml pass over the same text for what urdfdom
/// does not give: document order, line numbers, and the structural checks urdfdom skips or only
/// logs (dependencies.md §5 "urdfdom"). Every rejection is an InputError "<file>:<line>: <message>".
///
/// Frames follow URDF: a joint frame is given in its parent link frame (<origin>), and the child
/// link frame coincides with the joint frame. Units: metres, radians, kilograms.

#include <string>
#include <vector>

#include "retarget/core/diagnostics.hpp"
#include "retarget/core/types.hpp"

namespace rt {

enum class UrdfJointType { Revolute, Continuous, Prismatic, Fixed, Floating };

struct UrdfInertial {
  double mass_kg = 0;
  Vec3 p_L_com = Vec3::Zero();  ///< [m] centre of mass in the link frame
  Mat3 I_com = Mat3::Zero();    ///< [kg m^2] about the COM, in link-frame axes (origin rpy applied)
};

struct UrdfGeometry {
  enum class Kind { Box, Cylinder, Sphere, Mesh };
  Kind kind = Kind::Box;
  Iso3 X_L_G = Iso3::Identity();  ///< geometry frame in the link frame
  Vec3 box_size_m = Vec3::Zero(); ///< full extents (box)
  double radius_m = 0;            ///< cylinder, sphere
  double length_m = 0;            ///< cylinder (along its z axis)
  std::string mesh_uri;           ///< as written in the file (mesh)
  std::string mesh_path;          ///< resolved absolute path (mesh)
  Vec3 mesh_scale = Vec3::Ones(); ///< may be negative (mirrored mesh)
  int line = 0;                   ///< line of the <geometry> element
};

struct UrdfLink {
  std::string name;
  int line = 0;
  bool has_inertial = false;
  UrdfInertial inertial;
  std::vector<UrdfGeometry> collisions;
  std::vector<UrdfGeometry> visuals;
  int parent_joint = -1;          ///< index into UrdfRobot::joints, -1 for the root
  std::vector<int> child_joints;  ///< in document order
};

struct UrdfJoint {
  std::string name;
  int line = 0;
  UrdfJointType type = UrdfJointType::Fixed;
  int parent_link = -1;  ///< index into UrdfRobot::links
  int child_link = -1;
  Iso3 X_P_J = Iso3::Identity();  ///< joint frame in the parent link frame
  Vec3 axis = Vec3::UnitX();      ///< unit axis in the joint frame (URDF default 1 0 0)
  bool has_position_limits = false;  ///< revolute, prismatic
  double lower = 0, upper = 0;       ///< [rad] or [m]
  double velocity_limit = 0;         ///< [rad/s] or [m/s]; 0 = not given
  double effort_limit = 0;           ///< [N m] or [N]; 0 = not given
  double damping = 0;
  double friction = 0;
  std::string mimic_joint;           ///< <mimic joint=...>, empty if none (not enforced by us)
  double mimic_multiplier = 1, mimic_offset = 0;
};

struct UrdfRobot {
  std::string name;
  std::string path;  ///< the file read (or the name given for a string)
  std::vector<UrdfLink> links;    ///< document order
  std::vector<UrdfJoint> joints;  ///< document order
  int root_link = -1;
  Diagnostics diagnostics;        ///< non-fatal findings (urdfdom warnings, mimic joints, ...)

  int find_link(const std::string& name) const;
  int find_joint(const std::string& name) const;
  /// "<file>:<line>" of a link / joint element.
  std::string link_location(int link) const;
  std::string joint_location(int joint) const;
};

struct UrdfReadOptions {
  /// Roots searched for package://<pkg>/ URIs (see package_uri.hpp), in order.
  std::vector<std::string> package_paths;
  /// Require every mesh file (collision and visual) to exist. On by default: a missing mesh means
  /// a broken robot package.
  bool require_mesh_files = true;
};

/// Reads and validates a URDF file. Throws InputError "<file>:<line>: <message>" for a file that
/// is not XML, has no <robot>, an error logged by urdfdom, no root or several roots, a cycle, a
/// joint naming a missing link, a link with two parents, a planar or unknown joint type, a
/// revolute/prismatic joint without <limit>, lower > upper, a zero axis, a negative or
/// non-finite mass or inertia, a <mesh> without filename, or a mesh file that does not exist.
UrdfRobot read_urdf_file(const std::string& path, const UrdfReadOptions& options = {});

/// As read_urdf_file for URDF text; `name` stands for the file in messages, and relative mesh
/// paths resolve against `base_dir`.
UrdfRobot read_urdf_string(const std::string& xml, const std::string& name, const std::string& base_dir,
                           const UrdfReadOptions& options = {});

}  // namespace rt
