#pragma once
/// `retarget init-robot`: a robot.yaml guessed from a humanoid URDF (design: issue 17). The body
/// parts are found from the kinematic tree at q = 0, not from names:
///   legs     the two leaves farthest from the root whose branches (from their common ancestor,
///            the pelvis) have >= 3 movable joints each; the foot is the lowest link of a leg
///            with geometry (collision, else visual);
///   up       from the feet towards the hips; forward: the long axis of the feet's lowest faces,
///            towards the toes (the sole lies ahead of the ankle); left = up x forward. Written
///            as base_orientation (axis names when both are within 10 deg of root axes, else rpy);
///   arms     the pair of leaves on opposite sides whose common ancestor (the chest link) has
///            >= 3 movable joints down to each; fingers end at their common ancestor (the hand);
///   joints   hip / shoulder: the first joint cluster of the limb (joints within 15 % of its
///            length); knee / elbow: the joint nearest the middle of the limb; ankle / wrist: the
///            last joint; the head: the highest link with geometry above the chest outside the arms.
/// Standing pose: an SRDF group state (half_sitting, standing, stand, home, ready, default, the
/// first that exists) when an SRDF is given, else knees bent by `knee_bend_rad` with the hips
/// pitched so that the COM is over the feet and the ankles keeping the soles flat.
/// Gains, armature and hold gains follow documented rules of the robot's mass and joint efforts.

#include <string>
#include <vector>

namespace rt {

struct InitRobotOptions {
  std::string urdf_path;
  std::string srdf_path;                   ///< optional: standing pose from a group state
  std::string name;                        ///< default: the URDF's robot name
  std::vector<std::string> package_paths;  ///< roots for package:// (absolute paths are written)
  double knee_bend_rad = 0.35;             ///< knee flexion of the guessed standing pose
};

struct InitRobotResult {
  std::string yaml;                 ///< robot.yaml text, with comments saying where values came from
  std::vector<std::string> report;  ///< what was guessed, one line each, with the numbers to check
};

/// Guesses the config. Throws InputError (the URDF's location) when no two legs can be found or
/// the URDF cannot be read.
InitRobotResult guess_robot_config(const InitRobotOptions& options);

}  // namespace rt
