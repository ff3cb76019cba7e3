#pragma once
/// RobotModel: the immutable description of a robot, built once from robot.yaml + URDF, and the
/// MuJoCo model we generate from it (design.md §2, §3.5). Per-evaluation state lives in RobotData
/// (robot_data.hpp), so one RobotModel can serve many threads.
///
/// Generalised coordinates follow MuJoCo: q = [p_W_root (3), quat_W_root (w x y z), joints (nu)]
/// where "root" is the root body: the URDF root link turned to face +X with +Z up by robot.yaml's
/// base_orientation (identity by default; root_link_orientation() converts),
/// v = [v_W_root (3, world frame), ω_root (3, root link frame), joint rates (nu)]; nq = 7 + nu,
/// nv = 6 + nu. Joints appear in "model order" (depth-first order of the kinematic tree, which is
/// MuJoCo's order); `export_joint_order()` maps to the CSV column order.
///
/// The generated MuJoCo model (mj()): one body per link with a movable parent joint (links on
/// fixed joints are merged into their parent's body: Link::body, Link::X_B_L), a free joint on the
/// root body, hinge/slide joints with the URDF ranges, armature, damping and frictionloss, a floor
/// plane, one torque motor per movable joint (actuator i drives movable_joints()[i], ctrl and force
/// clamped to the URDF effort), a sole box per foot, and the other links' collision geometry.
/// Only robot-vs-floor contacts exist: MuJoCo tests predefined floor-geom pairs only (the
/// contype/conaffinity bits say the same); every robot geom collides with the floor, so a non-sole
/// contact means a fall. Visual geometry is not part of the model.

#include <memory>
#include <string>
#include <vector>

#include "retarget/core/diagnostics.hpp"
#include "retarget/core/types.hpp"
#include "retarget/model/collision_hull.hpp"
#include "retarget/model/robot_config.hpp"

struct mjModel_;
typedef struct mjModel_ mjModel;

namespace rt {

enum class JointType { Revolute, Continuous, Prismatic, Fixed, Floating };

struct Inertial {
  double mass_kg = 0;
  Vec3 p_L_com = Vec3::Zero();         ///< [m] centre of mass in the link frame
  Mat3 I_com = Mat3::Zero();           ///< [kg m^2] about the COM, in link-frame axes
};

struct Geometry {
  enum class Kind { Box, Cylinder, Sphere, Mesh };
  Kind kind = Kind::Box;
  Iso3 X_L_G = Iso3::Identity();  ///< geometry frame in the link frame
  Vec3 box_size_m = Vec3::Zero(); ///< full extents (box)
  double radius_m = 0;            ///< cylinder, sphere
  double length_m = 0;            ///< cylinder (along z)
  std::string mesh_path;          ///< resolved absolute path (mesh)
  Vec3 mesh_scale = Vec3::Ones(); ///< may be negative (mirrored mesh)
};

struct Link {
  std::string name;
  int parent_joint = -1;              ///< index into joints(), -1 for the root
  std::vector<int> child_joints;
  bool has_inertial = false;
  Inertial inertial;
  std::vector<Geometry> collisions;
  std::vector<Geometry> visuals;
  /// MuJoCo body the link belongs to (merged fixed children share their parent's body). An empty
  /// URDF root above a floating joint (a "world" link) maps to the world body 0.
  int body = -1;
  Iso3 X_B_L = Iso3::Identity();      ///< link frame in that body's frame
};

struct Joint {
  std::string name;
  JointType type = JointType::Fixed;
  int parent_link = -1;
  int child_link = -1;
  Iso3 X_P_J = Iso3::Identity();      ///< joint frame in the parent link frame (URDF <origin>)
  Vec3 axis = Vec3::UnitZ();          ///< unit axis in the joint frame
  bool has_position_limits = false;
  double lower = 0, upper = 0;        ///< [rad] or [m]
  double velocity_limit = 0;          ///< [rad/s] or [m/s]; 0 = none given
  double effort_limit = 0;            ///< [N m] or [N]; 0 = none given
  double damping = 0;                 ///< URDF <dynamics damping>
  double friction = 0;                ///< URDF <dynamics friction>
  int qpos_index = -1;                ///< index in q (movable joints), else -1
  int dof_index = -1;                 ///< index in v (movable joints), else -1
};

/// A foot's sole, resolved against the model.
struct Sole {
  int link = -1;
  Vec3 p_L_center = Vec3::Zero();  ///< [m] centre of the bottom face, foot link frame
  /// Sole frame S in the foot link frame: x forward (length), y left (width), z the sole normal
  /// into the foot. Identity for a sole given in robot.yaml (link axes); a derived sole's frame
  /// comes from the standing pose (sole_fit.hpp), so any foot-link orientation works.
  Mat3 R_L_S = Mat3::Identity();
  Vec2 size_m = Vec2::Zero();      ///< [m] length (sole x), width (sole y)
  int geom = -1;                   ///< MuJoCo geom id of the sole box
  /// Corners of the bottom face in the link frame (counter-clockwise seen from above).
  std::array<Vec3, 4> corners_L() const;
};

struct RobotLoadOptions {
  /// Keep the converted collision meshes (binary STL bytes) after compiling, for write_mjcf().
  /// Off by default: they are only needed to export the model.
  bool keep_mjcf_assets = false;
};

class RobotModel {
 public:
  /// Builds the model: parses and validates the URDF (formats/urdf), resolves soles, generates
  /// the MJCF with converted meshes and compiles it. Throws InputError for bad input.
  static std::unique_ptr<RobotModel> load(const RobotConfig& config, const RobotLoadOptions& options = {});
  /// Convenience: load_robot_config + load.
  static std::unique_ptr<RobotModel> load(const std::string& robot,
                                          const std::vector<std::string>& extra_package_paths = {});
  ~RobotModel();
  RobotModel(const RobotModel&) = delete;
  RobotModel& operator=(const RobotModel&) = delete;

  const RobotConfig& config() const { return config_; }
  const std::string& name() const { return config_.name; }

  const std::vector<Link>& links() const { return links_; }
  const std::vector<Joint>& joints() const { return joints_; }
  int root_link() const { return root_link_; }
  /// Index of a link / joint by name, or -1.
  int find_link(const std::string& name) const;
  int find_joint(const std::string& name) const;
  /// As find_*, but throws InputError("<robot.yaml>: unknown link 'x'") when missing.
  int link_index(const std::string& name) const;
  int joint_index(const std::string& name) const;

  int nq() const { return 7 + nu(); }
  int nv() const { return 6 + nu(); }
  /// Number of movable (1-DOF) joints.
  int nu() const { return static_cast<int>(movable_joints_.size()); }
  /// Movable joints (indices into joints()) in model order: movable_joints()[i] has
  /// qpos_index 7 + i and dof_index 6 + i.
  const std::vector<int>& movable_joints() const { return movable_joints_; }
  /// Export (CSV column) order: export_joint_order()[k] is the index into movable_joints() of the
  /// k-th exported joint.
  const std::vector<int>& export_joint_order() const { return export_order_; }

  /// Lower/upper position limits and velocity/effort limits of the movable joints in model order
  /// (±infinity / 0 where the URDF gives none).
  const VecX& q_lower() const { return q_lower_; }
  const VecX& q_upper() const { return q_upper_; }
  const VecX& velocity_limits() const { return velocity_limits_; }
  const VecX& effort_limits() const { return effort_limits_; }

  double total_mass_kg() const { return total_mass_kg_; }
  const std::array<Sole, 2>& soles() const { return soles_; }  ///< [0] left, [1] right
  /// Support points of every link's URDF collision geometry, feet included, and of each sole
  /// rectangle (collision_hull.hpp), grouped by link.
  const std::vector<CollisionHull>& collision_hulls() const { return collision_hulls_; }
  /// Which foot's sole a MuJoCo geom is: kLeftFoot, kRightFoot, or -1 (floor or other geometry).
  int sole_side(int geom) const;
  /// MuJoCo geom id of the floor plane.
  int floor_geom() const { return floor_geom_; }
  /// MuJoCo geom groups: sole boxes, and the other (fall-detecting) collision geometry, whose
  /// names are "col_<link>_<k>".
  static constexpr int kSoleGeomGroup = 2;
  static constexpr int kCollisionGeomGroup = 3;

  /// MuJoCo body id of the root link (the body with the free joint).
  int root_body() const { return root_body_; }
  /// The root body's frame is F, the forward-x/left-y/up-z frame of robot.yaml's base_orientation
  /// (the root link's own frame when none is given): q[3..6] is F's orientation. References (CSV,
  /// NPZ) carry the URDF root link's orientation; these convert between the two (the origins are
  /// the same point).
  Quat root_link_orientation(const Quat& quat_W_F) const;
  Quat root_body_orientation(const Quat& quat_W_root) const;
  /// Link whose frame is the frame of MuJoCo body b (the link that created it), -1 for the world.
  int body_link(int body) const { return body_links_.at(static_cast<std::size_t>(body)); }
  /// URDF link whose geometry MuJoCo geom g is (a fixed child merged into its parent's body keeps
  /// its own name here: the foot, not the ankle body it was merged into), -1 for the floor.
  int geom_link(int geom) const { return geom_links_.at(static_cast<std::size_t>(geom)); }

  /// Standing configuration (size nq): standing joints from robot.yaml, root upright at the origin
  /// facing +X, root height so the lowest sole touches z = 0 (or robot.yaml's root_height).
  const VecX& standing_q() const { return standing_q_; }
  /// COM height of the standing pose [m] (z_c of the balance model).
  double standing_com_height_m() const { return standing_com_height_m_; }

  /// Non-fatal findings of loading (URDF warnings, mimic joints, massless bodies given a tiny
  /// mass, inertias fixed up, meshes simplified, ...).
  const Diagnostics& diagnostics() const { return diagnostics_; }

  /// The compiled MuJoCo model (owned). Treat as read-only: share it across threads.
  /// mjModel::qpos0 has the root at the standing height (joints at 0): use standing_q() for the
  /// full standing pose.
  const mjModel* mj() const { return mj_; }
  /// The generated MJCF text (meshes referenced by file names of the in-memory VFS it was
  /// compiled with, so it cannot be reloaded from disk as is).
  const std::string& mjcf() const { return mjcf_; }
  /// Writes the generated model so that MuJoCo (simulate, mj_loadXML) can load it from disk: the
  /// MJCF at `path` and its collision meshes as mesh<k>.stl in the same folder (files of those
  /// names are replaced). Needs RobotLoadOptions::keep_mjcf_assets when the model has meshes;
  /// throws InputError(path) when a file cannot be written.
  void write_mjcf(const std::string& path) const;

 private:
  RobotModel() = default;
  friend class RobotModelBuilder;

  RobotConfig config_;
  std::vector<Link> links_;
  std::vector<Joint> joints_;
  int root_link_ = -1;
  std::vector<int> movable_joints_;
  std::vector<int> export_order_;
  VecX q_lower_, q_upper_, velocity_limits_, effort_limits_;
  double total_mass_kg_ = 0;
  std::array<Sole, 2> soles_;
  std::vector<CollisionHull> collision_hulls_;
  VecX standing_q_;
  double standing_com_height_m_ = 0;
  int floor_geom_ = -1;
  int root_body_ = -1;
  std::vector<int> body_links_;
  std::vector<int> geom_links_;
  Diagnostics diagnostics_;
  mjModel* mj_ = nullptr;
  std::string mjcf_;
  std::vector<std::pair<std::string, std::string>> mjcf_assets_;  ///< file name, bytes (if kept)
  bool mjcf_assets_kept_ = false;
};

}  // namespace rt
