#pragma once
/// robot.yaml: how a URDF robot is retargeted to and simulated (design.md §4).
///
/// Schema (every key is checked; unknown keys are errors naming their path and line; links and
/// joints are checked against the URDF by RobotModel::load, again with their robot.yaml line):
///
///   name: g1                                  # required
///   urdf: package://unitree_g1/g1.urdf        # required: relative to this file, absolute, or package://
///   package_paths: [../../../shared/data/robots]  # optional roots for package://<pkg>/ (relative to this file)
///   feet:                                     # required: both sides
///     left:  {link: left_ankle_roll_link, sole: derive}   # the lowest flat face of the link's
///                                             #   collision (else visual) geometry in the standing
///                                             #   pose, any link orientation (sole_fit.hpp)
///     right: {link: right_ankle_roll_link, sole: {center: [0.035, 0, -0.035], size: [0.22, 0.08]}}
///   landmarks:                                # human landmark -> robot link (landmarks.hpp names)
///     pelvis:    {link: pelvis, weight: 1.0, orientation_weight: 1.0, offset: [0, 0, 0]}
///     left_knee: {link: left_knee_link}       # weight 1, orientation_weight 0, offset 0 by default
///     right_knee: right_knee_link             # shorthand for {link: right_knee_link}
///                                             # orientation_weight > 0 only for pelvis, chest,
///                                             #   left_ankle, right_ankle (the oriented landmarks)
///   base_orientation: {forward: -x, up: z}    # optional: the URDF root link's axes that point
///                                             #   forward and up when the robot stands (default
///                                             #   {forward: x, up: z}); or {rpy: [r, p, y]} [rad]:
///                                             #   the forward-x/left-y/up-z frame in root axes
///   joint_limits:                             # optional overrides of URDF <limit> values
///     left_knee_joint: {velocity: 12, effort: 150}   # [rad/s] (m/s), [N m] (N); > 0
///   export_joints: [left_hip_pitch_joint, ...]   # optional CSV column order (default: URDF order);
///                                             #   must list every movable joint exactly once
///   npz_layout: names:mjlab_order.yaml         # optional body/joint order of the NPZ: urdf (default),
///                                             #   mjcf:FILE or names:FILE (npz_layout.hpp); FILE
///                                             #   relative to this file, absolute or package://
///   standing_pose:                            # optional
///     joints: {left_knee_joint: 0.3}          # [rad] (or m); within limits; unlisted joints are 0,
///                                             #   or just inside the range when 0 is outside it
///     root_height: 0.79                       # [m] optional; default puts the soles on the floor
///   controller:                               # optional (tracking controller, paper eq. 2)
///     kp: 36                                  # [1/s^2]
///     kd: 12                                  # [1/s]
///     joint_gains: {left_knee_joint: {kp: 49, kd: 14}}
///   simulation:                               # optional
///     timestep: 0.001                         # [s] MuJoCo step of the dynamics check
///     armature: 0.01                          # [kg m^2] reflected rotor inertia added to every joint
///     joint_armature: {left_knee_joint: 0.05}
///     damping: 0.0                            # [N m s/rad] added to the URDF damping
///     friction: 1.0                           # sliding friction coefficient sole/floor
///     hold_kp: 300                            # [N m/rad] PD gains of the standing hold that
///     hold_kd: 10                             # [N m s/rad]   `retarget inspect` runs (standing_hold.hpp)

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/motion/landmarks.hpp"

namespace rt {

/// Sole rectangle of a foot link. The sole plane is the bottom face of the foot; contact is
/// simulated with a thin box whose bottom face is this rectangle.
struct SoleConfig {
  bool derive = false;     ///< derive from the link's geometry (its lowest face, sole_fit.hpp) instead
  Vec3 p_L_center = Vec3::Zero();  ///< [m] centre of the sole's bottom face in the foot link frame
  Vec2 size_m = Vec2::Zero();      ///< [m] length along link x, width along link y
};

struct FootConfig {
  std::string link;
  SoleConfig sole;
};

/// Foot sides, as indices into RobotConfig::feet and RobotModel::soles().
inline constexpr int kLeftFoot = 0;
inline constexpr int kRightFoot = 1;

/// A human landmark tracked by a point (and optionally the orientation) of a robot link.
struct LandmarkTarget {
  Landmark landmark = Landmark::Pelvis;
  std::string link;
  Vec3 p_L_offset = Vec3::Zero();  ///< [m] tracked point in the link frame
  double weight = 1.0;               ///< position weight (dimensionless, relative)
  double orientation_weight = 0.0;   ///< orientation weight; > 0 only for landmarks with orientation
};

struct JointGains {
  double kp = 0;  ///< [1/s^2]
  double kd = 0;  ///< [1/s]
};

struct ControllerConfig {
  double kp = 36.0;  ///< [1/s^2] default position gain of eq. (2)
  double kd = 12.0;  ///< [1/s] default velocity gain of eq. (2)
  /// Per joint group: "legs" (joints that move a sole), "arms" (joints that move a hand or wrist
  /// landmark but not the head/chest), "torso" (the rest). Override kp/kd for that group.
  std::map<std::string, JointGains> group_gains;
  std::map<std::string, JointGains> joint_gains;  ///< per-joint overrides (above the groups)
  /// Task-space gains of the feet (the tracking controller's r̈̂, eq. 4) under the walking
  /// controller; kp = 0 keeps its default (WalkingControllerOptions::foot_kp/foot_kd).
  JointGains foot_gains;
};

struct SimulationConfig {
  double timestep_s = 0.001;
  double armature = 0.01;  ///< [kg m^2]; explicit PD on light links is unstable without it
  std::map<std::string, double> joint_armature;
  double extra_damping = 0.0;  ///< [N m s/rad]
  double friction = 1.0;
  double hold_kp = 300.0;  ///< [N m/rad]
  double hold_kd = 10.0;   ///< [N m s/rad]
};

/// URDF limit overrides of one joint; 0 keeps the URDF value.
struct JointLimitOverride {
  double velocity = 0;  ///< [rad/s] or [m/s]
  double effort = 0;    ///< [N m] or [N]
};

struct RobotConfig {
  std::string name;
  std::string config_path;  ///< the robot.yaml that was read
  std::string urdf_path;    ///< resolved absolute path of the URDF
  std::vector<std::string> package_paths;  ///< resolved roots, in search order
  std::array<FootConfig, 2> feet;          ///< [0] left, [1] right
  std::vector<LandmarkTarget> landmarks;
  /// Orientation of the pipeline's body frame F (x forward, y left, z up when the robot stands)
  /// in URDF root-link axes: v_root = R_root_F v_F. Identity for a URDF whose root already faces
  /// +X with +Z up. The CSV/NPZ root pose stays the URDF root link's (RobotModel converts).
  Mat3 R_root_F = Mat3::Identity();
  std::map<std::string, JointLimitOverride> joint_limits;
  std::vector<std::string> export_joints;  ///< empty: URDF order of movable joints
  /// NPZ body/joint order: "urdf", or "mjcf:<absolute path>" / "names:<absolute path>"
  /// (resolved when the config is read; npz_layout.hpp interprets it).
  std::string npz_layout = "urdf";
  std::map<std::string, double> standing_joints;
  std::optional<double> standing_root_height_m;
  ControllerConfig controller;
  SimulationConfig simulation;

  /// "file:line" where a key path was written ("feet.left.link", "export_joints[3]",
  /// "standing_pose.joints.left_knee_joint", "landmarks.pelvis.link"); the file alone when the
  /// key was not written there (defaults, or a config built in code). Used for errors found later
  /// against the URDF (unknown links and joints).
  std::string where(const std::string& key_path) const;
  std::map<std::string, std::string> key_locations;  ///< key path -> "file:line"
};

/// Folders searched for robot names: $RETARGET_ROBOTS_PATH (colon-separated), then the project's
/// robots/ folder.
std::vector<std::string> robot_search_path();

/// Loads a robot config. `robot` is a path to a robot.yaml, a folder holding one, or the name of
/// a folder in robot_search_path(). `extra_package_paths` (from --package-path) are searched
/// before the config's own package_paths, then $ROS_PACKAGE_PATH. Throws InputError with
/// file:line and key path on any schema error, and when the URDF cannot be found.
RobotConfig load_robot_config(const std::string& robot, const std::vector<std::string>& extra_package_paths = {});

/// Parses robot.yaml text as if read from `config_path` (used in messages and as the base of
/// relative paths; the file itself is not read). Same checks as load_robot_config.
RobotConfig parse_robot_config(const std::string& yaml_text, const std::string& config_path,
                               const std::vector<std::string>& extra_package_paths = {});

/// Resolves a URDF/mesh reference: "package://pkg/rel" or "package:///pkg/rel" against the package
/// search path (package:///abs is taken as an absolute path when that file exists) (a package `pkg` is the folder <root>/pkg or <root>/*/pkg), relative paths against
/// `base_dir`. Returns the absolute path of an existing file, or "" when not found.
std::string resolve_resource(const std::string& uri, const std::string& base_dir,
                             const std::vector<std::string>& package_paths);

}  // namespace rt
