#include "retarget/model/robot_model.hpp"

#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <tuple>

#include "formats/mesh/triangle_mesh.hpp"
#include "formats/urdf/urdf_description.hpp"
#include "mjcf_writer.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/sole_fit.hpp"

namespace rt {

namespace {

constexpr double kSoleThickness_m = 0.01;  // thin enough to sit under the foot, thick enough for stable contact
constexpr double kTinyMass_kg = 1e-3;      // given to massless moving bodies (MuJoCo rejects them)
constexpr double kTinyInertia = 1e-7;      // [kg m^2] floor for principal moments of moving bodies
// Collision meshes only serve fall detection through their convex hulls (MuJoCo collides meshes as
// hulls), so they are clustered down to this many triangles: compiling 50k-triangle meshes costs
// MuJoCo (hull, mesh inertia) far more than the centimetre-level detail is worth. Also well under
// MuJoCo 2.2.2's 200000-face STL limit.
constexpr int kCollisionFaceBudget = 4000;

bool is_movable(JointType t) {
  return t == JointType::Revolute || t == JointType::Continuous || t == JointType::Prismatic;
}

JointType to_joint_type(UrdfJointType t) {
  switch (t) {
    case UrdfJointType::Revolute: return JointType::Revolute;
    case UrdfJointType::Continuous: return JointType::Continuous;
    case UrdfJointType::Prismatic: return JointType::Prismatic;
    case UrdfJointType::Fixed: return JointType::Fixed;
    case UrdfJointType::Floating: return JointType::Floating;
  }
  return JointType::Fixed;
}

Geometry to_geometry(const UrdfGeometry& g) {
  Geometry out;
  switch (g.kind) {
    case UrdfGeometry::Kind::Box: out.kind = Geometry::Kind::Box; break;
    case UrdfGeometry::Kind::Cylinder: out.kind = Geometry::Kind::Cylinder; break;
    case UrdfGeometry::Kind::Sphere: out.kind = Geometry::Kind::Sphere; break;
    case UrdfGeometry::Kind::Mesh: out.kind = Geometry::Kind::Mesh; break;
  }
  out.X_L_G = g.X_L_G;
  out.box_size_m = g.box_size_m;
  out.radius_m = g.radius_m;
  out.length_m = g.length_m;
  out.mesh_path = g.mesh_path;
  out.mesh_scale = g.mesh_scale;
  return out;
}

// Motion of a 1-DOF joint at position q, in the joint frame.
Iso3 joint_motion(const Joint& j, double q) {
  Iso3 X = Iso3::Identity();
  if (j.type == JointType::Revolute || j.type == JointType::Continuous)
    X.linear() = AngleAxis(q, j.axis).toRotationMatrix();
  else if (j.type == JointType::Prismatic)
    X.translation() = j.axis * q;
  return X;
}

// True when the mesh is (nearly) flat or degenerate; then X_G_box and half are the pose (in the
// mesh frame) and half extents of its oriented bounding box along the principal axes.
bool is_flat(const TriangleMesh& m, Iso3& X_G_box, Vec3& half) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& v : m.vertices) mean += v;
  mean /= static_cast<double>(m.vertices.size());
  Mat3 cov = Mat3::Zero();
  for (const Vec3& v : m.vertices) cov += (v - mean) * (v - mean).transpose();
  Mat3 axes = Eigen::SelfAdjointEigenSolver<Mat3>(cov).eigenvectors();
  if (axes.determinant() < 0) axes.col(0) *= -1;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& v : m.vertices) {
    const Vec3 p = axes.transpose() * (v - mean);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 extent = hi - lo;
  if (extent.minCoeff() > std::max(1e-4, 1e-3 * extent.maxCoeff())) return false;
  X_G_box = Iso3::Identity();
  X_G_box.linear() = axes;
  X_G_box.translation() = mean + axes * (0.5 * (lo + hi));
  half = 0.5 * extent;
  return true;
}

}  // namespace

Quat RobotModel::root_link_orientation(const Quat& quat_W_F) const {
  return (quat_W_F * Quat(Mat3(config_.R_root_F.transpose()))).normalized();
}

Quat RobotModel::root_body_orientation(const Quat& quat_W_root) const {
  return (quat_W_root * Quat(config_.R_root_F)).normalized();
}

std::array<Vec3, 4> Sole::corners_L() const {
  const double hx = 0.5 * size_m.x(), hy = 0.5 * size_m.y();
  return {p_L_center + R_L_S * Vec3(-hx, -hy, 0), p_L_center + R_L_S * Vec3(hx, -hy, 0),
          p_L_center + R_L_S * Vec3(hx, hy, 0), p_L_center + R_L_S * Vec3(-hx, hy, 0)};
}

class RobotModelBuilder {
 public:
  RobotModelBuilder(const RobotConfig& config, const RobotLoadOptions& options)
      : cfg_(config), options_(options), m_(new RobotModel()) {
    m_->config_ = config;
  }

  std::unique_ptr<RobotModel> build();

 private:
  [[noreturn]] void config_error(const std::string& key_path, const std::string& message) const {
    throw InputError(cfg_.where(key_path), key_path + ": " + message);
  }
  std::string urdf_name() const { return base_name(cfg_.urdf_path); }
  int config_link(const std::string& key_path, const std::string& name) const;
  int config_joint(const std::string& key_path, const std::string& name) const;

  void copy_description();
  void find_root();
  void build_bodies();
  void merge_inertias();
  void resolve_standing_joints();
  std::vector<Iso3> link_poses(const VecX& q) const;
  void append_surface(const Geometry& g, const Iso3& X_W_L, const std::string& where, FootSurface& out);
  void resolve_soles();
  void add_geometry();
  void build_collision_hulls();
  void resolve_joint_settings();
  void compute_standing_height();
  void compile();
  void finish_with_mujoco();

  const TriangleMesh& mesh(const std::string& path, const Vec3& scale, const std::string& where);

  const RobotConfig& cfg_;
  RobotLoadOptions options_;
  std::unique_ptr<RobotModel> m_;
  UrdfRobot urdf_;
  int world_link_ = -1;  // empty URDF root above a floating joint, or -1
  detail::MjcfModel mjcf_;
  std::vector<int> body_of_mjcf_;  // MjcfModel body index -> MuJoCo body id (index + 1)
  std::map<std::tuple<std::string, double, double, double>, TriangleMesh> meshes_;
  std::map<std::tuple<std::string, double, double, double>, std::string> mesh_assets_;
  std::vector<detail::MjcfFile> files_;
  std::array<std::string, 2> sole_geom_names_{"sole_left", "sole_right"};
  double root_height_m_ = 0;
  std::map<std::string, int> geom_owner_;  // generated geom name -> URDF link
  VecX q_stand_;  // standing configuration, root upright at the origin (height set later)
};

int RobotModelBuilder::config_link(const std::string& key_path, const std::string& name) const {
  const int l = m_->find_link(name);
  if (l < 0) config_error(key_path, "unknown link '" + name + "' (not in " + urdf_name() + ")");
  if (l == world_link_) config_error(key_path, "link '" + name + "' is the empty world link above the floating joint");
  return l;
}

int RobotModelBuilder::config_joint(const std::string& key_path, const std::string& name) const {
  const int j = m_->find_joint(name);
  if (j < 0) config_error(key_path, "unknown joint '" + name + "' (not in " + urdf_name() + ")");
  if (!is_movable(m_->joints_[static_cast<std::size_t>(j)].type))
    config_error(key_path, "joint '" + name + "' is not a movable (revolute, continuous or prismatic) joint");
  return j;
}

void RobotModelBuilder::copy_description() {
  UrdfReadOptions options;
  options.package_paths = cfg_.package_paths;
  urdf_ = read_urdf_file(cfg_.urdf_path, options);
  m_->diagnostics_.append(urdf_.diagnostics);
  for (const UrdfLink& u : urdf_.links) {
    Link l;
    l.name = u.name;
    l.parent_joint = u.parent_joint;
    l.child_joints = u.child_joints;
    l.has_inertial = u.has_inertial;
    l.inertial.mass_kg = u.inertial.mass_kg;
    l.inertial.p_L_com = u.inertial.p_L_com;
    l.inertial.I_com = u.inertial.I_com;
    for (const auto& g : u.collisions) l.collisions.push_back(to_geometry(g));
    for (const auto& g : u.visuals) l.visuals.push_back(to_geometry(g));
    m_->links_.push_back(std::move(l));
  }
  for (const UrdfJoint& u : urdf_.joints) {
    Joint j;
    j.name = u.name;
    j.type = to_joint_type(u.type);
    j.parent_link = u.parent_link;
    j.child_link = u.child_link;
    j.X_P_J = u.X_P_J;
    j.axis = u.axis;
    j.has_position_limits = u.has_position_limits;
    j.lower = u.lower;
    j.upper = u.upper;
    j.velocity_limit = u.velocity_limit;
    j.effort_limit = u.effort_limit;
    j.damping = u.damping;
    j.friction = u.friction;
    m_->joints_.push_back(j);
  }
  m_->total_mass_kg_ = 0;
  for (const Link& l : m_->links_) m_->total_mass_kg_ += l.inertial.mass_kg;
  if (!(m_->total_mass_kg_ > 0)) throw InputError(cfg_.urdf_path, "the robot has no mass (no link has an <inertial> mass > 0)");
}

void RobotModelBuilder::find_root() {
  int root = urdf_.root_link;
  for (std::size_t j = 0; j < m_->joints_.size(); ++j) {
    const Joint& joint = m_->joints_[j];
    if (joint.type != JointType::Floating) continue;
    const Link& parent = m_->links_[static_cast<std::size_t>(joint.parent_link)];
    const bool empty_root = joint.parent_link == urdf_.root_link && parent.child_joints.size() == 1 &&
                            parent.inertial.mass_kg == 0 && parent.collisions.empty();
    if (!empty_root)
      throw InputError(urdf_.joint_location(static_cast<int>(j)),
                       "floating joint '" + joint.name +
                           "' is supported only as the single joint below an empty root link (a 'world' link); the "
                           "generated model gives the root a free joint anyway");
    world_link_ = joint.parent_link;
    root = joint.child_link;
  }
  m_->root_link_ = root;
}

void RobotModelBuilder::build_bodies() {
  auto& links = m_->links_;
  const auto& joints = m_->joints_;
  m_->body_links_ = {-1, m_->root_link_};
  m_->root_body_ = 1;
  if (world_link_ >= 0) {
    links[static_cast<std::size_t>(world_link_)].body = 0;
    links[static_cast<std::size_t>(world_link_)].X_B_L = Iso3::Identity();
  }
  Link& root = links[static_cast<std::size_t>(m_->root_link_)];
  root.body = 1;
  // The root body's frame is the forward-x/left-y/up-z frame F (robot.yaml base_orientation): the
  // whole pipeline sees a robot that faces +X; the root link hangs in it turned by R_F_root.
  root.X_B_L = Iso3::Identity();
  root.X_B_L.linear() = cfg_.R_root_F.transpose();

  // Free joint name that no URDF joint uses.
  mjcf_.free_joint_name = "root";
  while (m_->find_joint(mjcf_.free_joint_name) >= 0) mjcf_.free_joint_name += "_";
  auto body_name = [&](const std::string& link) {
    std::string n = link;
    while (n == "world") n += "_";  // MuJoCo's world body owns that name
    return n;
  };
  detail::MjcfBody root_body;
  root_body.name = body_name(root.name);
  mjcf_.bodies.push_back(root_body);

  // Pre-order depth-first walk, children in URDF document order: bodies are created in the order
  // MuJoCo numbers them, and movable joints in qpos order (checked after compilation).
  std::vector<int> stack;
  auto push_children = [&](int link) {
    const auto& cj = links[static_cast<std::size_t>(link)].child_joints;
    for (auto it = cj.rbegin(); it != cj.rend(); ++it) stack.push_back(joints[static_cast<std::size_t>(*it)].child_link);
  };
  push_children(m_->root_link_);
  while (!stack.empty()) {
    const int li = stack.back();
    stack.pop_back();
    Link& link = links[static_cast<std::size_t>(li)];
    const int ji = link.parent_joint;
    const Joint& joint = joints[static_cast<std::size_t>(ji)];
    const Link& parent = links[static_cast<std::size_t>(joint.parent_link)];
    if (is_movable(joint.type)) {
      const int body = static_cast<int>(m_->body_links_.size());
      detail::MjcfBody b;
      b.name = body_name(link.name);
      b.parent = parent.body - 1;
      b.X_P_B = parent.X_B_L * joint.X_P_J;
      b.joint.name = joint.name;
      b.joint.slide = joint.type == JointType::Prismatic;
      b.joint.axis = joint.axis;
      b.joint.limited = joint.has_position_limits;
      b.joint.lower = joint.lower;
      b.joint.upper = joint.upper;
      mjcf_.bodies[static_cast<std::size_t>(b.parent)].children.push_back(body - 1);
      mjcf_.bodies.push_back(b);
      m_->body_links_.push_back(li);
      link.body = body;
      link.X_B_L = Iso3::Identity();
      m_->movable_joints_.push_back(ji);
    } else {
      link.body = parent.body;
      link.X_B_L = parent.X_B_L * joint.X_P_J;
    }
    push_children(li);
  }
  for (std::size_t k = 0; k < m_->movable_joints_.size(); ++k) {
    Joint& j = m_->joints_[static_cast<std::size_t>(m_->movable_joints_[k])];
    j.qpos_index = 7 + static_cast<int>(k);
    j.dof_index = 6 + static_cast<int>(k);
  }
}

void RobotModelBuilder::merge_inertias() {
  // Parts of each body: a link's inertia about its COM, rotated into body axes, plus the
  // parallel-axis term about the combined COM.
  std::vector<std::vector<const Link*>> parts(mjcf_.bodies.size());
  for (const Link& l : m_->links_)
    if (l.body >= 1) parts[static_cast<std::size_t>(l.body - 1)].push_back(&l);
  for (std::size_t b = 0; b < mjcf_.bodies.size(); ++b) {
    const int body = static_cast<int>(b) + 1;
    double mass = 0;
    Vec3 first_moment = Vec3::Zero();
    for (const Link* l : parts[b]) {
      mass += l->inertial.mass_kg;
      first_moment += l->inertial.mass_kg * (l->X_B_L * l->inertial.p_L_com);
    }
    detail::MjcfBody& mb = mjcf_.bodies[b];
    const std::string& link_name = m_->links_[static_cast<std::size_t>(m_->body_links_[static_cast<std::size_t>(body)])].name;
    if (mass <= 0) {
      mb.mass_kg = kTinyMass_kg;
      mb.p_B_com = Vec3::Zero();
      mb.I_com = Mat3::Identity() * kTinyInertia;
      m_->diagnostics_.warn(cfg_.urdf_path, "link '" + link_name + "' moves but has no mass: given " +
                                                format("%g", kTinyMass_kg) + " kg so that MuJoCo accepts it");
      continue;
    }
    const Vec3 com = first_moment / mass;
    Mat3 I = Mat3::Zero();
    for (const Link* l : parts[b]) {
      const Mat3 R = l->X_B_L.linear();
      const Vec3 d = l->X_B_L * l->inertial.p_L_com - com;
      I += R * l->inertial.I_com * R.transpose() +
           l->inertial.mass_kg * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
    }
    I = 0.5 * (I + I.transpose());
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
    Vec3 moments = eig.eigenvalues();
    bool fixed = false;
    for (int k = 0; k < 3; ++k)
      if (moments[k] < kTinyInertia) {
        moments[k] = kTinyInertia;
        fixed = true;
      }
    if (fixed) {
      I = eig.eigenvectors() * moments.asDiagonal() * eig.eigenvectors().transpose();
      m_->diagnostics_.warn(cfg_.urdf_path, "body of link '" + link_name + "' has a (near) zero principal inertia: raised to " +
                                                format("%g", kTinyInertia) + " kg m^2");
    }
    const Vec3 s = moments;
    if (s[0] + s[1] < s[2] * (1 - 1e-9) || s[0] + s[2] < s[1] * (1 - 1e-9) || s[1] + s[2] < s[0] * (1 - 1e-9))
      m_->diagnostics_.warn(cfg_.urdf_path, "body of link '" + link_name +
                                                "' has principal inertias that violate the triangle inequality; MuJoCo balances them");
    mb.mass_kg = mass;
    mb.p_B_com = com;
    mb.I_com = I;
  }
}

const TriangleMesh& RobotModelBuilder::mesh(const std::string& path, const Vec3& scale, const std::string& where) {
  const auto key = std::make_tuple(path, scale.x(), scale.y(), scale.z());
  auto it = meshes_.find(key);
  if (it != meshes_.end()) return it->second;
  MeshLoadOptions options;
  options.scale = scale;
  options.max_faces = 0;
  TriangleMesh tm;
  try {
    tm = load_mesh(path, options);
  } catch (const InputError& e) {
    throw InputError(where, e.what());
  }
  return meshes_.emplace(key, std::move(tm)).first->second;
}

void RobotModelBuilder::resolve_standing_joints() {
  const int nu = m_->nu();
  q_stand_ = VecX::Zero(7 + nu);
  q_stand_[3] = 1;  // identity quaternion (w x y z)
  std::vector<char> listed(static_cast<std::size_t>(nu), 0);
  for (const auto& [name, value] : cfg_.standing_joints) {
    const std::string key = "standing_pose.joints." + name;
    const int j = config_joint(key, name);
    const Joint& joint = m_->joints_[static_cast<std::size_t>(j)];
    if (joint.has_position_limits && (value < joint.lower || value > joint.upper))
      config_error(key, format("%g is outside the joint range [%g, %g]", value, joint.lower, joint.upper));
    q_stand_[joint.qpos_index] = value;
    listed[static_cast<std::size_t>(joint.qpos_index - 7)] = 1;
  }
  // An unlisted joint stands at 0 when 0 is in its range, else just inside the nearer limit (a
  // joint held at its limit would show as a joint-limit violation in every check).
  for (int k = 0; k < nu; ++k) {
    const Joint& joint = m_->joints_[static_cast<std::size_t>(m_->movable_joints_[static_cast<std::size_t>(k)])];
    if (listed[static_cast<std::size_t>(k)] || !joint.has_position_limits || (joint.lower <= 0 && 0 <= joint.upper)) continue;
    const double margin = std::min(0.05, 0.1 * (joint.upper - joint.lower));
    const double value = joint.lower > 0 ? joint.lower + margin : joint.upper - margin;
    q_stand_[7 + k] = value;
    m_->diagnostics_.note(cfg_.where("standing_pose"),
                          format("standing_pose: joint '%s' is not listed and 0 is outside its range [%g, %g]: it stands at %g",
                                 joint.name.c_str(), joint.lower, joint.upper, value));
  }
}

std::vector<Iso3> RobotModelBuilder::link_poses(const VecX& q) const {
  // Forward kinematics of the URDF tree with the root body at the origin, upright (facing +X).
  std::vector<Iso3> X_W_L(m_->links_.size(), Iso3::Identity());
  X_W_L[static_cast<std::size_t>(m_->root_link_)] = m_->links_[static_cast<std::size_t>(m_->root_link_)].X_B_L;
  std::vector<int> stack{m_->root_link_};
  while (!stack.empty()) {
    const int li = stack.back();
    stack.pop_back();
    for (int ji : m_->links_[static_cast<std::size_t>(li)].child_joints) {
      const Joint& j = m_->joints_[static_cast<std::size_t>(ji)];
      const double qj = j.qpos_index >= 0 ? q[j.qpos_index] : 0.0;
      X_W_L[static_cast<std::size_t>(j.child_link)] = X_W_L[static_cast<std::size_t>(li)] * j.X_P_J * joint_motion(j, qj);
      stack.push_back(j.child_link);
    }
  }
  return X_W_L;
}

void RobotModelBuilder::append_surface(const Geometry& g, const Iso3& X_W_L, const std::string& where, FootSurface& out) {
  const Iso3 X_W_G = X_W_L * g.X_L_G;
  const int base = static_cast<int>(out.vertices_F.size());
  auto tri = [&](int a, int b, int c) { out.triangles.push_back({base + a, base + b, base + c}); };
  switch (g.kind) {
    case Geometry::Kind::Box: {
      for (int k = 0; k < 8; ++k)
        out.vertices_F.push_back(X_W_G * (0.5 * g.box_size_m.cwiseProduct(Vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1))));
      // Two triangles per face (corner k has bit 0 = +x, bit 1 = +y, bit 2 = +z).
      const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
      for (const auto& f : faces) {
        tri(f[0], f[1], f[2]);
        tri(f[0], f[2], f[3]);
      }
      break;
    }
    case Geometry::Kind::Cylinder: {
      constexpr int n = 32;
      for (int k = 0; k < n; ++k) {
        const double a = 2 * M_PI * k / n;
        for (const double z : {-0.5 * g.length_m, 0.5 * g.length_m})
          out.vertices_F.push_back(X_W_G * Vec3(g.radius_m * std::cos(a), g.radius_m * std::sin(a), z));
      }
      for (int k = 0; k < n; ++k) {
        const int k1 = (k + 1) % n;
        tri(2 * k, 2 * k1, 2 * k1 + 1);
        tri(2 * k, 2 * k1 + 1, 2 * k + 1);
        if (k >= 2) {
          tri(0, 2 * k1, 2 * k);              // bottom cap fan
          tri(1, 2 * k + 1, 2 * k1 + 1);      // top cap fan
        }
      }
      break;
    }
    case Geometry::Kind::Sphere: {
      constexpr int rings = 8, segments = 16;
      for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < segments; ++j) {
          const double th = M_PI * i / rings, ph = 2 * M_PI * j / segments;
          out.vertices_F.push_back(X_W_G * (g.radius_m * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th))));
        }
      for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
          const int j1 = (j + 1) % segments;
          tri(i * segments + j, (i + 1) * segments + j, (i + 1) * segments + j1);
          tri(i * segments + j, (i + 1) * segments + j1, i * segments + j1);
        }
      break;
    }
    case Geometry::Kind::Mesh: {
      const TriangleMesh& tm = mesh(g.mesh_path, g.mesh_scale, where);
      for (const Vec3& v : tm.vertices) out.vertices_F.push_back(X_W_G * v);
      for (const auto& f : tm.faces) tri(f[0], f[1], f[2]);
      break;
    }
  }
}

void RobotModelBuilder::resolve_soles() {
  const char* sides[2] = {"left", "right"};
  std::vector<Iso3> X_W_L;  // standing pose, computed when a sole is derived
  for (int s = 0; s < 2; ++s) {
    const FootConfig& f = cfg_.feet[static_cast<std::size_t>(s)];
    const std::string key = std::string("feet.") + sides[s];
    Sole& sole = m_->soles_[static_cast<std::size_t>(s)];
    sole.link = config_link(key + ".link", f.link);
    if (!f.sole.derive) {
      sole.p_L_center = f.sole.p_L_center;
      sole.size_m = f.sole.size_m;
      continue;
    }
    // The lowest flat face of the foot's collision geometry (else its visual geometry) in the
    // standing pose, measured with world axes: the link's own axes need not point up or forward.
    const Link& link = m_->links_[static_cast<std::size_t>(sole.link)];
    // Collision geometry made of spheres only is a set of contact points (G1: four 5 mm spheres
    // inside the sole's outline), not the foot's shape: then the visual geometry has the sole.
    const bool contact_points = !link.collisions.empty() && !link.visuals.empty() &&
                                std::all_of(link.collisions.begin(), link.collisions.end(),
                                            [](const Geometry& g) { return g.kind == Geometry::Kind::Sphere; });
    const std::vector<Geometry>& geometry = link.collisions.empty() || contact_points ? link.visuals : link.collisions;
    if (geometry.empty())
      config_error(key + ".sole", "cannot derive the sole: link '" + f.link +
                                      "' has no collision or visual geometry (give {center: [x, y, z], size: [length, width]})");
    if (X_W_L.empty()) X_W_L = link_poses(q_stand_);
    const Iso3& X = X_W_L[static_cast<std::size_t>(sole.link)];
    FootSurface surface;
    for (const Geometry& g : geometry) append_surface(g, X, urdf_.link_location(sole.link), surface);
    const SoleFit fit = fit_sole(surface);
    if (!(fit.size_m.minCoeff() > 1e-3))
      config_error(key + ".sole", "the derived sole of link '" + f.link + "' is degenerate (" +
                                      format("%g x %g m", fit.size_m.x(), fit.size_m.y()) +
                                      "): its lowest part is not a flat face; give {center: [x, y, z], size: [length, width]}");
    sole.p_L_center = X.inverse() * fit.p_F_center;
    sole.R_L_S = X.linear().transpose() * fit.R_F_S;
    sole.size_m = fit.size_m;
  }
}

void RobotModelBuilder::add_geometry() {
  mjcf_.friction = cfg_.simulation.friction;
  const int left_foot = m_->soles_[0].link, right_foot = m_->soles_[1].link;
  for (std::size_t li = 0; li < m_->links_.size(); ++li) {
    const Link& link = m_->links_[li];
    if (link.body <= 0 || static_cast<int>(li) == left_foot || static_cast<int>(li) == right_foot) continue;
    detail::MjcfBody& body = mjcf_.bodies[static_cast<std::size_t>(link.body - 1)];
    for (std::size_t k = 0; k < link.collisions.size(); ++k) {
      const Geometry& g = link.collisions[k];
      detail::MjcfGeom mg;
      mg.name = "col_" + link.name + "_" + std::to_string(k);
      geom_owner_[mg.name] = static_cast<int>(li);
      mg.group = RobotModel::kCollisionGeomGroup;
      mg.X_B_G = link.X_B_L * g.X_L_G;
      switch (g.kind) {
        case Geometry::Kind::Box:
          mg.kind = detail::MjcfGeom::Kind::Box;
          mg.half_size = 0.5 * g.box_size_m;
          break;
        case Geometry::Kind::Sphere:
          mg.kind = detail::MjcfGeom::Kind::Sphere;
          mg.half_size = Vec3(g.radius_m, 0, 0);
          break;
        case Geometry::Kind::Cylinder:
          mg.kind = detail::MjcfGeom::Kind::Cylinder;
          mg.half_size = Vec3(g.radius_m, 0.5 * g.length_m, 0);
          break;
        case Geometry::Kind::Mesh: {
          const std::string where = urdf_.link_location(static_cast<int>(li));
          const TriangleMesh& tm = mesh(g.mesh_path, g.mesh_scale, where);
          // MuJoCo builds the convex hull of every mesh with qhull, which fails (and prints) on
          // flat meshes: give those a thin box over their oriented bounds instead.
          Iso3 X_G_box;
          Vec3 half;
          if (is_flat(tm, X_G_box, half)) {
            mg.kind = detail::MjcfGeom::Kind::Box;
            mg.X_B_G = mg.X_B_G * X_G_box;
            mg.half_size = half.cwiseMax(Vec3::Constant(0.0005));
            m_->diagnostics_.note(where, "collision mesh " + base_name(g.mesh_path) + " of link '" + link.name +
                                             "' is flat: simulated as a thin box");
            break;
          }
          mg.kind = detail::MjcfGeom::Kind::Mesh;
          const auto key = std::make_tuple(g.mesh_path, g.mesh_scale.x(), g.mesh_scale.y(), g.mesh_scale.z());
          auto it = mesh_assets_.find(key);
          if (it == mesh_assets_.end()) {
            const std::string name = "mesh" + std::to_string(mesh_assets_.size());
            files_.push_back({name + ".stl", to_binary_stl(simplify_mesh(tm, kCollisionFaceBudget))});
            mjcf_.mesh_assets.push_back(name);
            it = mesh_assets_.emplace(key, name).first;
          }
          mg.mesh = it->second;
          break;
        }
      }
      body.geoms.push_back(mg);
    }
  }
  for (int s = 0; s < 2; ++s) {
    const Sole& sole = m_->soles_[static_cast<std::size_t>(s)];
    const Link& link = m_->links_[static_cast<std::size_t>(sole.link)];
    detail::MjcfGeom mg;
    mg.name = sole_geom_names_[static_cast<std::size_t>(s)];
    geom_owner_[mg.name] = sole.link;
    mg.kind = detail::MjcfGeom::Kind::Box;
    mg.group = RobotModel::kSoleGeomGroup;
    mg.half_size = Vec3(0.5 * sole.size_m.x(), 0.5 * sole.size_m.y(), 0.5 * kSoleThickness_m);
    Iso3 X_L_G = Iso3::Identity();
    X_L_G.linear() = sole.R_L_S;
    X_L_G.translation() = sole.p_L_center + sole.R_L_S * Vec3(0, 0, 0.5 * kSoleThickness_m);
    mg.X_B_G = link.X_B_L * X_L_G;
    mjcf_.bodies[static_cast<std::size_t>(link.body - 1)].geoms.push_back(mg);
  }
}

void RobotModelBuilder::build_collision_hulls() {
  for (std::size_t li = 0; li < m_->links_.size(); ++li) {
    const Link& link = m_->links_[li];
    // A foot's sole rectangle is collision geometry too (the simulation's sole box).
    for (const Sole& sole : m_->soles_)
      if (sole.link == static_cast<int>(li)) {
        const auto corners = sole.corners_L();
        m_->collision_hulls_.push_back(make_hull(static_cast<int>(li), std::vector<Vec3>(corners.begin(), corners.end())));
      }
    for (const Geometry& g : link.collisions) {
      const Mat3 R = g.X_L_G.linear();
      const Vec3 c = g.X_L_G.translation();
      std::vector<Vec3> points;
      switch (g.kind) {
        case Geometry::Kind::Box:
          for (int k = 0; k < 8; ++k)
            points.push_back(g.X_L_G * (0.5 * g.box_size_m.cwiseProduct(Vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1))));
          break;
        case Geometry::Kind::Sphere:
          m_->collision_hulls_.push_back(make_hull(static_cast<int>(li), {c}, g.radius_m));
          continue;
        case Geometry::Kind::Cylinder:
          for (int k = 0; k < 32; ++k) {
            const double a = 2 * M_PI * k / 32;
            for (const double z : {-0.5 * g.length_m, 0.5 * g.length_m})
              points.push_back(c + R * Vec3(g.radius_m * std::cos(a), g.radius_m * std::sin(a), z));
          }
          break;
        case Geometry::Kind::Mesh: {
          const TriangleMesh& tm = mesh(g.mesh_path, g.mesh_scale, urdf_.link_location(static_cast<int>(li)));
          points.reserve(tm.vertices.size());
          for (const Vec3& v : tm.vertices) points.push_back(g.X_L_G * v);
          points = convex_hull_vertices(points);
          // A finely tessellated curved part has thousands of hull vertices; its support points
          // are within r (1 − cos 4.5°) of them and keep the floor terms cheap.
          if (points.size() > kMaxHullPoints) points = support_points(points);
          break;
        }
      }
      m_->collision_hulls_.push_back(make_hull(static_cast<int>(li), std::move(points)));
    }
  }
}

void RobotModelBuilder::resolve_joint_settings() {
  for (const auto& [name, a] : cfg_.simulation.joint_armature) config_joint("simulation.joint_armature." + name, name);
  for (const auto& [name, g] : cfg_.controller.joint_gains) config_joint("controller.joint_gains." + name, name);
  for (const auto& lm : cfg_.landmarks)
    config_link("landmarks." + std::string(landmark_name(lm.landmark)) + ".link", lm.link);
  for (const auto& [name, o] : cfg_.joint_limits) {
    Joint& j = m_->joints_[static_cast<std::size_t>(config_joint("joint_limits." + name, name))];
    if (o.velocity > 0) j.velocity_limit = o.velocity;
    if (o.effort > 0) j.effort_limit = o.effort;
  }

  const int nu = m_->nu();
  m_->q_lower_.resize(nu);
  m_->q_upper_.resize(nu);
  m_->velocity_limits_.resize(nu);
  m_->effort_limits_.resize(nu);
  const double inf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < nu; ++k) {
    const Joint& j = m_->joints_[static_cast<std::size_t>(m_->movable_joints_[static_cast<std::size_t>(k)])];
    m_->q_lower_[k] = j.has_position_limits ? j.lower : -inf;
    m_->q_upper_[k] = j.has_position_limits ? j.upper : inf;
    m_->velocity_limits_[k] = j.velocity_limit;
    m_->effort_limits_[k] = j.effort_limit;
    detail::MjcfBody& b = mjcf_.bodies[static_cast<std::size_t>(m_->links_[static_cast<std::size_t>(j.child_link)].body - 1)];
    auto arm = cfg_.simulation.joint_armature.find(j.name);
    b.joint.armature = arm != cfg_.simulation.joint_armature.end() ? arm->second : cfg_.simulation.armature;
    b.joint.damping = j.damping + cfg_.simulation.extra_damping;
    b.joint.frictionloss = j.friction;
    mjcf_.motors.push_back({j.name, j.effort_limit});
  }

  // Export order: robot.yaml's list (a permutation of the movable joints) or URDF document order.
  std::vector<int> model_pos(m_->joints_.size(), -1);
  for (int k = 0; k < nu; ++k) model_pos[static_cast<std::size_t>(m_->movable_joints_[static_cast<std::size_t>(k)])] = k;
  if (cfg_.export_joints.empty()) {
    for (std::size_t j = 0; j < m_->joints_.size(); ++j)
      if (model_pos[j] >= 0) m_->export_order_.push_back(model_pos[j]);
  } else {
    std::vector<char> listed(static_cast<std::size_t>(nu), 0);
    for (std::size_t i = 0; i < cfg_.export_joints.size(); ++i) {
      const std::string key = "export_joints[" + std::to_string(i) + "]";
      const int j = config_joint(key, cfg_.export_joints[i]);
      const int k = model_pos[static_cast<std::size_t>(j)];
      if (listed[static_cast<std::size_t>(k)]) config_error(key, "joint '" + cfg_.export_joints[i] + "' is listed twice");
      listed[static_cast<std::size_t>(k)] = 1;
      m_->export_order_.push_back(k);
    }
    std::vector<std::string> missing;
    for (int k = 0; k < nu; ++k)
      if (!listed[static_cast<std::size_t>(k)])
        missing.push_back(m_->joints_[static_cast<std::size_t>(m_->movable_joints_[static_cast<std::size_t>(k)])].name);
    if (!missing.empty()) config_error("export_joints", "must list every movable joint; missing: " + join(missing, ", "));
  }
}

void RobotModelBuilder::compute_standing_height() {
  VecX q = q_stand_;
  const std::vector<Iso3> X_W_L = link_poses(q);
  double lowest = std::numeric_limits<double>::infinity();
  for (const Sole& s : m_->soles_)
    for (const Vec3& c : s.corners_L()) lowest = std::min(lowest, (X_W_L[static_cast<std::size_t>(s.link)] * c).z());
  root_height_m_ = cfg_.standing_root_height_m ? *cfg_.standing_root_height_m : -lowest;
  q[2] = root_height_m_;
  m_->standing_q_ = q;
  mjcf_.bodies[0].X_P_B = Iso3::Identity();
  mjcf_.bodies[0].X_P_B.translation() = Vec3(0, 0, root_height_m_);
}

void RobotModelBuilder::compile() {
  mjcf_.model_name = cfg_.name.empty() ? urdf_.name : cfg_.name;
  mjcf_.timestep_s = cfg_.simulation.timestep_s;
  m_->mjcf_ = detail::write_mjcf(mjcf_);
  std::string warning;
  m_->mj_ = detail::compile_mjcf(m_->mjcf_, files_, cfg_.urdf_path, warning);
  if (!warning.empty()) m_->diagnostics_.warn(cfg_.urdf_path, "MuJoCo: " + warning);
  m_->mjcf_assets_kept_ = options_.keep_mjcf_assets;
  if (options_.keep_mjcf_assets)
    for (auto& f : files_) m_->mjcf_assets_.emplace_back(f.name, std::move(f.bytes));
  files_.clear();
  meshes_.clear();
}

void RobotModelBuilder::finish_with_mujoco() {
  const mjModel* mj = m_->mj_;
  const int nu = m_->nu();
  RT_DEMAND(mj->nq == 7 + nu && mj->nv == 6 + nu && mj->nu == nu, "generated MuJoCo model has unexpected sizes");
  RT_DEMAND(mj->nbody == static_cast<int>(mjcf_.bodies.size()) + 1, "MuJoCo body count differs from the generated bodies");
  for (std::size_t b = 0; b < mjcf_.bodies.size(); ++b)
    RT_DEMAND(mj_name2id(mj, mjOBJ_BODY, mjcf_.bodies[b].name.c_str()) == static_cast<int>(b) + 1,
              "MuJoCo body order differs from the generated order");
  for (int k = 0; k < nu; ++k) {
    const Joint& j = m_->joints_[static_cast<std::size_t>(m_->movable_joints_[static_cast<std::size_t>(k)])];
    const int id = mj_name2id(mj, mjOBJ_JOINT, j.name.c_str());
    RT_DEMAND(id >= 0 && mj->jnt_qposadr[id] == j.qpos_index && mj->jnt_dofadr[id] == j.dof_index,
              "MuJoCo qpos order differs from the model order at joint " + j.name);
    RT_DEMAND(mj->actuator_trnid[2 * k] == id, "actuator order differs from the model order");
  }
  m_->floor_geom_ = mj_name2id(mj, mjOBJ_GEOM, "floor");
  RT_DEMAND(m_->floor_geom_ >= 0, "no floor geom");
  for (int s = 0; s < 2; ++s) {
    m_->soles_[static_cast<std::size_t>(s)].geom = mj_name2id(mj, mjOBJ_GEOM, sole_geom_names_[static_cast<std::size_t>(s)].c_str());
    RT_DEMAND(m_->soles_[static_cast<std::size_t>(s)].geom >= 0, "no sole geom");
  }

  m_->geom_links_.assign(static_cast<std::size_t>(mj->ngeom), -1);
  for (const auto& [name, link] : geom_owner_) {
    const int id = mj_name2id(mj, mjOBJ_GEOM, name.c_str());
    RT_DEMAND(id >= 0, "generated geom " + name + " is missing from the MuJoCo model");
    m_->geom_links_[static_cast<std::size_t>(id)] = link;
  }

  const double mj_mass = mj_getTotalmass(mj);
  if (std::abs(mj_mass - m_->total_mass_kg_) > 1e-9 * std::max(1.0, m_->total_mass_kg_))
    m_->diagnostics_.note(cfg_.urdf_path, format("simulated mass %.6f kg differs from the URDF's %.6f kg (tiny masses added to massless bodies)",
                                                 mj_mass, m_->total_mass_kg_));

  mjData* d = mj_makeData(mj);
  RT_DEMAND(d != nullptr, "mj_makeData failed");
  mju_copy(d->qpos, m_->standing_q_.data(), mj->nq);
  mj_kinematics(mj, d);
  mj_comPos(mj, d);
  m_->standing_com_height_m_ = d->subtree_com[3 * m_->root_body_ + 2];
  mj_deleteData(d);
}

std::unique_ptr<RobotModel> RobotModelBuilder::build() {
  copy_description();
  find_root();
  build_bodies();
  merge_inertias();
  resolve_standing_joints();
  resolve_soles();
  resolve_joint_settings();
  add_geometry();
  build_collision_hulls();
  compute_standing_height();
  compile();
  finish_with_mujoco();
  return std::move(m_);
}

std::unique_ptr<RobotModel> RobotModel::load(const RobotConfig& config, const RobotLoadOptions& options) {
  return RobotModelBuilder(config, options).build();
}

void RobotModel::write_mjcf(const std::string& path) const {
  if (!mjcf_assets_kept_ && mj_->nmesh > 0)
    throw InputError(path, "the model was loaded without its mesh files (RobotLoadOptions::keep_mjcf_assets)");
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (const auto& [name, bytes] : mjcf_assets_) write_file_atomic((dir / name).string(), bytes);
  write_file_atomic(path, mjcf_);
}

std::unique_ptr<RobotModel> RobotModel::load(const std::string& robot, const std::vector<std::string>& extra_package_paths) {
  return load(load_robot_config(robot, extra_package_paths));
}

RobotModel::~RobotModel() {
  if (mj_) mj_deleteModel(mj_);
}

int RobotModel::find_link(const std::string& name) const {
  for (std::size_t i = 0; i < links_.size(); ++i)
    if (links_[i].name == name) return static_cast<int>(i);
  return -1;
}

int RobotModel::find_joint(const std::string& name) const {
  for (std::size_t i = 0; i < joints_.size(); ++i)
    if (joints_[i].name == name) return static_cast<int>(i);
  return -1;
}

int RobotModel::link_index(const std::string& name) const {
  const int i = find_link(name);
  if (i < 0) throw InputError(config_.config_path, "unknown link '" + name + "' (robot " + config_.name + ")");
  return i;
}

int RobotModel::joint_index(const std::string& name) const {
  const int i = find_joint(name);
  if (i < 0) throw InputError(config_.config_path, "unknown joint '" + name + "' (robot " + config_.name + ")");
  return i;
}

int RobotModel::sole_side(int geom) const {
  for (int s = 0; s < 2; ++s)
    if (soles_[static_cast<std::size_t>(s)].geom == geom) return s;
  return -1;
}

}  // namespace rt
