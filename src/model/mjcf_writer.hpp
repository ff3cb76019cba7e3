#pragma once
/// Internal to rt_model: the MuJoCo model as plain data, its MJCF text, and compilation from an
/// in-memory virtual file system (nothing is written to disk).

#include <string>
#include <vector>

#include "retarget/core/types.hpp"

struct mjModel_;
typedef struct mjModel_ mjModel;

namespace rt::detail {

struct MjcfGeom {
  enum class Kind { Box, Sphere, Cylinder, Mesh };
  Kind kind = Kind::Box;
  std::string name;
  Iso3 X_B_G = Iso3::Identity();
  Vec3 half_size = Vec3::Zero();  ///< box: half extents; sphere: x = radius; cylinder: x = radius, y = half length
  std::string mesh;               ///< mesh asset name (Kind::Mesh)
  int group = 0;
};

struct MjcfJoint {
  std::string name;
  bool slide = false;  ///< prismatic; otherwise hinge
  Vec3 axis = Vec3::UnitZ();
  bool limited = false;
  double lower = 0, upper = 0;
  double armature = 0, damping = 0, frictionloss = 0;
};

struct MjcfBody {
  std::string name;
  int parent = -1;                  ///< index into MjcfModel::bodies, -1 for the root body
  Iso3 X_P_B = Iso3::Identity();    ///< body frame in the parent body frame (root: in the world)
  MjcfJoint joint;                  ///< the body's joint (not used for the root, which is free)
  double mass_kg = 0;
  Vec3 p_B_com = Vec3::Zero();
  Mat3 I_com = Mat3::Identity();    ///< about the COM, body axes
  std::vector<MjcfGeom> geoms;
  std::vector<int> children;        ///< in emission order
};

struct MjcfMotor {
  std::string joint;
  double effort_limit = 0;  ///< [N m] or [N]; 0 = unlimited
};

struct MjcfFile {
  std::string name;   ///< VFS file name (no folders)
  std::string bytes;
};

struct MjcfModel {
  std::string model_name;
  std::string free_joint_name;
  double timestep_s = 0.001;
  double friction = 1.0;
  std::vector<MjcfBody> bodies;       ///< [0] is the root body; parents precede children
  std::vector<std::string> mesh_assets;  ///< asset name i reads VFS file "<name>.stl"
  std::vector<MjcfMotor> motors;
  /// Robot geoms never collide with each other but always with the floor. MuJoCo runs on the
  /// predefined floor pairs the writer emits; the bits say the same for tools that read the MJCF.
  int robot_contype = 2, robot_conaffinity = 1;
  int floor_contype = 1, floor_conaffinity = 2;
};

/// MJCF text of the model (bodies emitted depth-first in `children` order, which is the body and
/// joint numbering MuJoCo uses).
std::string write_mjcf(const MjcfModel& model);

/// Compiles MJCF text with the given in-memory files (mesh STL bytes). MuJoCo's XML loader and
/// its error/warning hooks are process-wide state, so compilation is serialised by a global mutex.
/// Throws InputError(location, "MuJoCo rejected the generated model: ...") on failure. A warning
/// MuJoCo's compiler reports for an accepted model is returned in `warning` (empty if none).
mjModel* compile_mjcf(const std::string& xml, const std::vector<MjcfFile>& files, const std::string& location,
                      std::string& warning);

/// Installs MuJoCo error/warning hooks once per process, if the application has set none:
/// warnings are dropped (MuJoCo still counts them in mjData::warning) instead of printed and
/// logged to MUJOCO_LOG.TXT, and errors throw rt::InternalError instead of exiting the process.
void install_mujoco_hooks();

}  // namespace rt::detail
