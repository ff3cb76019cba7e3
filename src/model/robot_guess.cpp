#include "retarget/model/robot_guess.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include "formats/mesh/triangle_mesh.hpp"
#include "formats/urdf/srdf_reader.hpp"
#include "formats/urdf/urdf_description.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace fs = std::filesystem;

namespace rt {

namespace {

constexpr double kSnapCos = 0.984807753012208;  // cos 10 deg: a guessed axis this close to a root axis is that axis
constexpr double kClusterFraction = 0.15;       // joints within this fraction of a limb's length form one joint
constexpr double kSoleBand_m = 0.005;           // lowest foot points within this band are the sole

bool movable(UrdfJointType t) {
  return t == UrdfJointType::Revolute || t == UrdfJointType::Continuous || t == UrdfJointType::Prismatic;
}

std::string num(double v) {
  if (std::abs(v) < 5e-5) v = 0;
  std::string s = format("%.4f", v);
  while (s.size() > 1 && s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

// A URDF name as a YAML scalar: plain when it is a simple identifier, else double-quoted.
std::string yaml_name(const std::string& n) {
  const bool plain = !n.empty() && std::all_of(n.begin(), n.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '/';
  }) && !std::isdigit(static_cast<unsigned char>(n[0])) && n[0] != '-';
  if (plain) return n;
  std::string q = "\"";
  for (char c : n) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

std::string vec(const Vec3& v) { return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]"; }

// The URDF tree with forward kinematics in the root link frame R.
class Tree {
 public:
  explicit Tree(const UrdfRobot& u) : u_(u) {
    root_ = u.root_link;
    // A floating joint below an empty world link: the robot's root is its child (as RobotModel).
    for (const UrdfJoint& j : u.joints)
      if (j.type == UrdfJointType::Floating && j.parent_link == u.root_link) root_ = j.child_link;
  }
  const UrdfRobot& urdf() const { return u_; }
  int root() const { return root_; }

  // Link poses in R for joint values q (by joint index; missing = 0).
  std::vector<Iso3> poses(const std::map<int, double>& q = {}) const {
    std::vector<Iso3> X(u_.links.size(), Iso3::Identity());
    std::vector<int> stack{root_};
    while (!stack.empty()) {
      const int l = stack.back();
      stack.pop_back();
      for (int ji : u_.links[static_cast<std::size_t>(l)].child_joints) {
        const UrdfJoint& j = u_.joints[static_cast<std::size_t>(ji)];
        const auto it = q.find(ji);
        const double v = it == q.end() ? 0.0 : it->second;
        Iso3 M = Iso3::Identity();
        if (j.type == UrdfJointType::Revolute || j.type == UrdfJointType::Continuous)
          M.linear() = AngleAxis(v, j.axis).toRotationMatrix();
        else if (j.type == UrdfJointType::Prismatic)
          M.translation() = j.axis * v;
        X[static_cast<std::size_t>(j.child_link)] = X[static_cast<std::size_t>(l)] * j.X_P_J * M;
        stack.push_back(j.child_link);
      }
    }
    return X;
  }

  int parent(int link) const {
    const int j = u_.links[static_cast<std::size_t>(link)].parent_joint;
    return j < 0 || link == root_ ? -1 : u_.joints[static_cast<std::size_t>(j)].parent_link;
  }
  // Links from the root down to `link`, both included.
  std::vector<int> path(int link) const {
    std::vector<int> p;
    for (int l = link; l >= 0; l = parent(l)) p.push_back(l);
    std::reverse(p.begin(), p.end());
    return p;
  }
  int lca(int a, int b) const {
    const auto pa = path(a), pb = path(b);
    int c = root_;
    for (std::size_t i = 0; i < std::min(pa.size(), pb.size()) && pa[i] == pb[i]; ++i) c = pa[i];
    return c;
  }
  // Movable joints on the way from `ancestor` down to `link`, top first.
  std::vector<int> movable_joints(int ancestor, int link) const {
    std::vector<int> out;
    for (int l = link; l >= 0 && l != ancestor; l = parent(l)) {
      const int j = u_.links[static_cast<std::size_t>(l)].parent_joint;
      if (j >= 0 && movable(u_.joints[static_cast<std::size_t>(j)].type)) out.push_back(j);
    }
    std::reverse(out.begin(), out.end());
    return out;
  }
  bool descends(int link, int ancestor) const {
    for (int l = link; l >= 0; l = parent(l))
      if (l == ancestor) return true;
    return false;
  }
  std::vector<int> leaves() const {
    std::vector<int> out;
    for (std::size_t l = 0; l < u_.links.size(); ++l)
      if (u_.links[l].child_joints.empty() && descends(static_cast<int>(l), root_)) out.push_back(static_cast<int>(l));
    return out;
  }
  bool has_geometry(int l) const {
    const UrdfLink& k = u_.links[static_cast<std::size_t>(l)];
    return !k.collisions.empty() || !k.visuals.empty();
  }
  const std::string& name(int l) const { return u_.links[static_cast<std::size_t>(l)].name; }
  const UrdfJoint& joint(int j) const { return u_.joints[static_cast<std::size_t>(j)]; }

 private:
  const UrdfRobot& u_;
  int root_ = -1;
};

// Points of a link's collision geometry (else visual) in R, for a link pose X_R_L. Collision
// spheres alone are contact points, not the link's shape: then the visual geometry (as RobotModel
// does for derived soles).
std::vector<Vec3> geometry_points(const UrdfLink& link, const Iso3& X_R_L) {
  std::vector<Vec3> out;
  const bool contact_points = !link.collisions.empty() && !link.visuals.empty() &&
                              std::all_of(link.collisions.begin(), link.collisions.end(),
                                          [](const UrdfGeometry& g) { return g.kind == UrdfGeometry::Kind::Sphere; });
  const auto& geometry = link.collisions.empty() || contact_points ? link.visuals : link.collisions;
  for (const UrdfGeometry& g : geometry) {
    const Iso3 X = X_R_L * g.X_L_G;
    switch (g.kind) {
      case UrdfGeometry::Kind::Box:
        for (int k = 0; k < 8; ++k) out.push_back(X * (0.5 * g.box_size_m.cwiseProduct(Vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1))));
        break;
      case UrdfGeometry::Kind::Cylinder:
        for (int k = 0; k < 32; ++k) {
          const double a = 2 * M_PI * k / 32;
          for (const double z : {-0.5 * g.length_m, 0.5 * g.length_m})
            out.push_back(X * Vec3(g.radius_m * std::cos(a), g.radius_m * std::sin(a), z));
        }
        break;
      case UrdfGeometry::Kind::Sphere:
        for (int k = 0; k < 6; ++k) {
          Vec3 d = Vec3::Zero();
          d[k / 2] = k % 2 ? 1 : -1;
          out.push_back(X * (g.radius_m * d));
        }
        break;
      case UrdfGeometry::Kind::Mesh: {
        MeshLoadOptions o;
        o.scale = g.mesh_scale;
        o.max_faces = 20000;  // the shape's extent is all that is used here
        for (const Vec3& v : load_mesh(g.mesh_path, o).vertices) out.push_back(X * v);
        break;
      }
    }
  }
  return out;
}

struct FootGuess {
  int leaf = -1, link = -1;
  std::vector<int> joints;  // movable joints from the pelvis down
  std::vector<Vec3> sole_R;  // lowest geometry points in R at q = 0
  Vec3 ankle_R = Vec3::Zero();
};

// A limb: its joints from the branching link down, and the landmark joints picked from them.
struct Limb {
  std::vector<int> joints;
  int top = -1, middle = -1, end = -1;  // joint indices
};

Limb pick_limb_joints(const Tree& t, const std::vector<Iso3>& X, const std::vector<int>& joints) {
  Limb limb;
  limb.joints = joints;
  auto pos = [&](int j) { return X[static_cast<std::size_t>(t.joint(j).child_link)].translation(); };
  const Vec3 first = pos(joints.front()), last = pos(joints.back());
  const double length = (last - first).norm();
  limb.top = joints.front();
  for (int j : joints)
    if ((pos(j) - first).norm() <= kClusterFraction * length) limb.top = j;
  limb.end = joints.back();
  int end_cluster_first = joints.back();
  for (auto it = joints.rbegin(); it != joints.rend(); ++it)
    if ((pos(*it) - last).norm() <= kClusterFraction * length) end_cluster_first = *it;
  const Vec3 mid = 0.5 * (pos(limb.top) + pos(end_cluster_first));
  const Vec3 along = length > 0 ? Vec3((last - first) / length) : Vec3::UnitZ();
  double best = std::numeric_limits<double>::infinity();
  bool inside = false;
  for (int j : joints) {
    if (j == limb.top) inside = true;
    if (j == end_cluster_first) break;
    if (!inside || j == limb.top) continue;
    // A knee or elbow bends the limb: its axis is across it (a roll or yaw joint along the limb
    // is not one).
    const UrdfJoint& jt = t.joint(j);
    const Vec3 axis = X[static_cast<std::size_t>(jt.child_link)].linear() * jt.axis;
    if (std::abs(axis.dot(along)) > 0.7) continue;
    const double d = (pos(j) - mid).norm();
    if (d < best) best = d, limb.middle = j;
  }
  if (limb.middle < 0) limb.middle = joints[joints.size() / 2];
  // The limb's top (hip, shoulder) is the joint above the middle one in line with it: where the
  // limb turns from (H1's hip pitch sits 11.5 cm outside its roll joint, over the knee).
  double nearest = std::numeric_limits<double>::infinity();
  for (int j : joints) {
    if (j == limb.middle) break;
    Vec3 d = pos(j) - pos(limb.middle);
    d -= along * along.dot(d);
    if (d.norm() <= nearest + 1e-3) nearest = std::min(nearest, d.norm()), limb.top = j;
  }
  return limb;
}

}  // namespace

InitRobotResult guess_robot_config(const InitRobotOptions& o) {
  InitRobotResult out;
  auto say = [&](const std::string& line) { out.report.push_back(line); };

  // Read the URDF; without package paths, try the folders above it (<root>/<pkg>/urdf/x.urdf).
  std::vector<std::string> package_paths;
  for (const auto& p : o.package_paths) package_paths.push_back(fs::absolute(p).lexically_normal().string());
  const std::string urdf_abs = fs::absolute(o.urdf_path).lexically_normal().string();
  UrdfReadOptions ro;
  ro.package_paths = package_paths;
  UrdfRobot urdf;
  try {
    urdf = read_urdf_file(urdf_abs, ro);
  } catch (const InputError&) {
    if (!package_paths.empty()) throw;
    fs::path up = fs::path(urdf_abs).parent_path();
    for (int k = 0; k < 3 && up.has_parent_path() && up != up.root_path(); ++k) {
      up = up.parent_path();
      ro.package_paths.push_back(up.string());
    }
    urdf = read_urdf_file(urdf_abs, ro);  // throws the real problem if these do not help either
    package_paths = ro.package_paths;
    say("package path  guessed from the URDF's folders: " + join(package_paths, ":"));
  }
  const Tree t(urdf);
  const std::vector<Iso3> X0 = t.poses();
  auto p0 = [&](int link) { return X0[static_cast<std::size_t>(link)].translation(); };
  auto jpos0 = [&](int j) { return p0(t.joint(j).child_link); };

  // ---- legs -------------------------------------------------------------------------------------
  const std::vector<int> leaves = t.leaves();
  int leaf1 = -1;
  for (int l : leaves)
    if (t.movable_joints(t.root(), l).size() >= 3 && (leaf1 < 0 || p0(l).norm() > p0(leaf1).norm())) leaf1 = l;
  int leaf2 = -1;
  for (int l : leaves) {
    if (l == leaf1 || leaf1 < 0) continue;
    const int c = t.lca(leaf1, l);
    if (t.movable_joints(c, leaf1).size() < 3 || t.movable_joints(c, l).size() < 3) continue;
    if (leaf2 < 0 || p0(l).norm() > p0(leaf2).norm()) leaf2 = l;
  }
  if (leaf1 < 0 || leaf2 < 0)
    throw InputError(urdf_abs, "cannot find two legs: no two branches with 3 or more movable joints each end far from the root");
  const int pelvis = t.lca(leaf1, leaf2);
  std::array<FootGuess, 2> feet;
  for (int k = 0; k < 2; ++k) {
    FootGuess& f = feet[static_cast<std::size_t>(k)];
    f.leaf = k == 0 ? leaf1 : leaf2;
    for (int l = f.leaf; l >= 0 && l != pelvis; l = t.parent(l))
      if (t.has_geometry(l)) {
        f.link = l;
        break;
      }
    if (f.link < 0) throw InputError(urdf_abs, "leg ending in link '" + t.name(f.leaf) + "' has no link with geometry for a foot");
    f.joints = t.movable_joints(pelvis, f.link);
    if (f.joints.size() < 3) throw InputError(urdf_abs, "leg to foot '" + t.name(f.link) + "' has fewer than 3 movable joints");
    f.ankle_R = jpos0(f.joints.back());
  }
  const Vec3 hips_R = 0.5 * (jpos0(feet[0].joints.front()) + jpos0(feet[1].joints.front()));
  const Vec3 ankles_R = 0.5 * (feet[0].ankle_R + feet[1].ankle_R);
  Vec3 up = hips_R - ankles_R;
  if (up.norm() < 1e-3) throw InputError(urdf_abs, "the legs have no length at q = 0");
  up.normalize();
  // Snap to the root's axes when close: URDFs are usually axis-aligned, and hips a little ahead
  // of the ankles tilt the hip-ankle line a few degrees (H1: 2.8 deg).
  auto snap = [](Vec3& v, std::string& axis_name) {
    for (int i = 0; i < 3; ++i)
      if (std::abs(v[i]) >= kSnapCos) {
        const double s = v[i] > 0 ? 1 : -1;
        v = Vec3::Zero();
        v[i] = s;
        axis_name = std::string(s > 0 ? "" : "-") + "xyz"[i];
        return true;
      }
    return false;
  };
  std::string up_name;
  const bool up_snapped = snap(up, up_name);

  // ---- facing: the feet's long axis, towards where the sole lies ahead of the ankle -------------
  Vec3 forward_sum = Vec3::Zero();
  for (FootGuess& f : feet) {
    const std::vector<Vec3> pts = geometry_points(urdf.links[static_cast<std::size_t>(f.link)], X0[static_cast<std::size_t>(f.link)]);
    double low = std::numeric_limits<double>::infinity();
    for (const Vec3& p : pts) low = std::min(low, up.dot(p));
    Vec3 c = Vec3::Zero();
    for (const Vec3& p : pts)
      if (up.dot(p) <= low + kSoleBand_m) f.sole_R.push_back(p), c += p;
    c /= static_cast<double>(f.sole_R.size());
    Mat3 cov = Mat3::Zero();
    for (const Vec3& p : f.sole_R) {
      const Vec3 d = (p - c) - up * up.dot(p - c);
      cov += d * d.transpose();
    }
    Vec3 axis = Eigen::SelfAdjointEigenSolver<Mat3>(cov).eigenvectors().col(2);
    axis = (axis - up * up.dot(axis)).normalized();
    // The bounds' midpoint, not the mean (tessellation density), decides where the toes are.
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Vec3& p : f.sole_R) lo = std::min(lo, axis.dot(p)), hi = std::max(hi, axis.dot(p));
    const double ahead = 0.5 * (lo + hi) - axis.dot(f.ankle_R);
    forward_sum += (ahead >= 0 ? 1.0 : -1.0) * axis;
  }
  Vec3 forward = forward_sum - up * up.dot(forward_sum);
  if (forward.norm() < 1e-6) forward = Vec3::UnitX() - up * up.x();
  forward.normalize();
  std::string forward_name;
  const bool snapped = up_snapped && snap(forward, forward_name) && std::abs(up.dot(forward)) < 1e-9;
  Mat3 R_root_F;
  R_root_F.col(0) = forward;
  R_root_F.col(2) = up;
  R_root_F.col(1) = up.cross(forward).normalized();
  R_root_F.col(0) = R_root_F.col(1).cross(up);
  const Vec3 left = R_root_F.col(1);
  // F coordinates of a root-frame point.
  auto F = [&](const Vec3& p_R) -> Vec3 { return R_root_F.transpose() * p_R; };
  if (left.dot(feet[0].ankle_R) < left.dot(feet[1].ankle_R)) std::swap(feet[0], feet[1]);  // [0] is the left leg

  // ---- arms, chest and head ----------------------------------------------------------------------
  auto in_legs = [&](int l) {
    for (const FootGuess& f : feet)
      if (t.descends(l, t.joint(f.joints.front()).child_link)) return true;
    return false;
  };
  int hand_l = -1, hand_r = -1;
  double best_arm = 0;
  for (int a : leaves) {
    if (in_legs(a) || F(p0(a)).y() <= 0.03) continue;
    for (int b : leaves) {
      if (in_legs(b) || F(p0(b)).y() >= -0.03) continue;
      const int c = t.lca(a, b);
      if (t.movable_joints(c, a).size() < 3 || t.movable_joints(c, b).size() < 3) continue;
      const double score = (p0(a) - p0(c)).norm() + (p0(b) - p0(c)).norm();
      if (score > best_arm) best_arm = score, hand_l = a, hand_r = b;
    }
  }
  int chest = -1;
  std::array<Limb, 2> arms;
  std::array<int, 2> hand_link{-1, -1};
  if (hand_l >= 0) {
    chest = t.lca(hand_l, hand_r);
    for (int k = 0; k < 2; ++k) {
      // The hand: the common ancestor of every leaf on this side below the arm's first link.
      const int leaf = k == 0 ? hand_l : hand_r;
      const int arm_top = t.path(leaf)[t.path(chest).size()];
      int hand = leaf;
      for (int l : leaves)
        if (t.descends(l, arm_top) && l != leaf) hand = t.lca(hand, l);
      std::vector<int> joints = t.movable_joints(chest, hand);
      if (joints.size() < 3) joints = t.movable_joints(chest, leaf);
      arms[static_cast<std::size_t>(k)] = pick_limb_joints(t, X0, joints);
      hand_link[static_cast<std::size_t>(k)] = hand;
    }
  }
  std::array<Limb, 2> legs{pick_limb_joints(t, X0, feet[0].joints), pick_limb_joints(t, X0, feet[1].joints)};

  const double leg_length = (hips_R - ankles_R).norm();
  const Vec3 hip_mid_F = 0.5 * (F(jpos0(legs[0].top)) + F(jpos0(legs[1].top)));
  Vec3 shoulder_mid_F = hip_mid_F + Vec3(0, 0, 0.9 * leg_length);
  if (chest >= 0) shoulder_mid_F = 0.5 * (F(jpos0(arms[0].top)) + F(jpos0(arms[1].top)));
  // Head: the highest link with geometry above the shoulders, outside the arms and legs.
  int head = -1;
  double head_z = shoulder_mid_F.z();
  Vec3 head_F = Vec3::Zero();
  for (std::size_t l = 0; l < urdf.links.size(); ++l) {
    const int li = static_cast<int>(l);
    if (!t.descends(li, t.root()) || in_legs(li) || !t.has_geometry(li)) continue;
    if (chest >= 0 && (t.descends(li, t.path(hand_l)[t.path(chest).size()]) || t.descends(li, t.path(hand_r)[t.path(chest).size()])))
      continue;
    const std::vector<Vec3> pts = geometry_points(urdf.links[l], X0[l]);
    if (pts.empty()) continue;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Vec3& p : pts) lo = lo.cwiseMin(F(p)), hi = hi.cwiseMax(F(p));
    const Vec3 centre = 0.5 * (lo + hi);
    // A head is a part whose middle is above the shoulders (a torso mesh reaching up is not) and
    // at least 5 % of the leg length across in every direction (a camera or IMU board is not).
    if ((hi - lo).minCoeff() < 0.05 * leg_length) continue;
    if (centre.z() > head_z + 0.02 && lo.z() > shoulder_mid_F.z() - 0.1 * leg_length) head = li, head_z = centre.z(), head_F = centre;
  }

  // ---- landmarks ---------------------------------------------------------------------------------
  struct Mapped {
    std::string landmark;
    int link;
    Vec3 p_F;  // the landmark point at q = 0, in F
    double weight, orientation_weight;
    std::string why;
  };
  std::vector<Mapped> marks;
  auto add = [&](const std::string& lm, int link, const Vec3& p_F, double w, double ow, const std::string& why) {
    marks.push_back({lm, link, p_F, w, ow, why});
  };
  add("pelvis", pelvis, hip_mid_F, 1.0, 1.0, "the legs' common link; the point between the hip joints");
  const int torso = chest >= 0 ? chest : pelvis;
  const Vec3 spine_F = hip_mid_F + 0.35 * (shoulder_mid_F - hip_mid_F);
  // The spine point rides on the last link of the pelvis-chest chain that starts below it.
  int spine_link = pelvis;
  for (int l : t.path(torso))
    if (t.descends(l, pelvis) && F(p0(l)).z() <= spine_F.z() + 1e-9) spine_link = l;
  add("spine", spine_link, spine_F, 0.5, 0, "35 % of the way from the hips to the shoulders");
  add("chest", torso, hip_mid_F + 0.8 * (shoulder_mid_F - hip_mid_F), 1.0, 1.0,
      chest >= 0 ? "the arms' common link, 80 % of the way from the hips to the shoulders" : "no arms found: on the pelvis");
  const Vec3 neck_F = shoulder_mid_F + Vec3(0, 0, 0.06 * leg_length);
  if (head >= 0) {
    const std::vector<int> head_joints = t.movable_joints(torso, head);
    const int neck_link = head_joints.empty() ? torso : t.joint(head_joints.front()).child_link;
    add("neck", neck_link, head_joints.empty() ? neck_F : F(jpos0(head_joints.front())), 0.5, 0,
        head_joints.empty() ? "above the shoulders" : "the first neck joint");
    add("head", head, head_F, 0.5, 0, "the middle of the head's geometry");
  } else {
    add("neck", torso, neck_F, 0.5, 0, "above the shoulders (no head link found)");
  }
  const char* sides[2] = {"left", "right"};
  for (int k = 0; k < 2; ++k) {
    const std::string s = sides[k];
    const Limb& leg = legs[static_cast<std::size_t>(k)];
    const FootGuess& foot = feet[static_cast<std::size_t>(k)];
    add(s + "_hip", t.joint(leg.top).child_link, F(jpos0(leg.top)), 1.0, 0, "the hip joint in line with the knee");
    add(s + "_knee", t.joint(leg.middle).child_link, F(jpos0(leg.middle)), 1.0, 0, "the leg joint nearest the leg's middle");
    add(s + "_ankle", foot.link, F(foot.ankle_R), 1.0, 1.0, "the last leg joint, on the foot link");
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, low = lo, y = 0;
    for (const Vec3& p : foot.sole_R) {
      const Vec3 q = F(p);
      lo = std::min(lo, q.x()), hi = std::max(hi, q.x()), low = std::min(low, q.z()), y += q.y();
    }
    y /= static_cast<double>(foot.sole_R.size());
    const double mid = 0.5 * (lo + hi), len = hi - lo;
    add(s + "_toe", foot.link, Vec3(mid + 0.4 * len, y, low + 0.01), 0.5, 0, "on the sole, 40 % of its length ahead of its middle");
    add(s + "_heel", foot.link, Vec3(mid - 0.4 * len, y, low + 0.01), 0.5, 0, "on the sole, 40 % of its length behind its middle");
    if (chest < 0) continue;
    const Limb& arm = arms[static_cast<std::size_t>(k)];
    const int end_link = t.joint(arm.end).child_link;
    const Vec3 shoulder_F = F(jpos0(arm.top)), end_F = F(jpos0(arm.end));
    add(s + "_shoulder", t.joint(arm.top).child_link, shoulder_F, 1.0, 0, "the shoulder joint in line with the elbow");
    // The geometry below the last arm joint: its far end from the shoulder, and its middle.
    Vec3 lo3 = Vec3::Constant(std::numeric_limits<double>::infinity()), hi3 = -lo3, tip_F = end_F;
    bool any = false;
    for (std::size_t l = 0; l < urdf.links.size(); ++l)
      if (t.descends(static_cast<int>(l), end_link))
        for (const Vec3& p : geometry_points(urdf.links[l], X0[l])) {
          lo3 = lo3.cwiseMin(F(p)), hi3 = hi3.cwiseMax(F(p)), any = true;
          if ((F(p) - shoulder_F).norm() > (tip_F - shoulder_F).norm()) tip_F = F(p);
        }
    if ((tip_F - end_F).norm() > 0.3 * (end_F - shoulder_F).norm()) {
      // An arm that ends in a forearm (no wrist joint): the last joint is the elbow, the wrist and
      // hand are points on the forearm towards its far end.
      add(s + "_elbow", end_link, end_F, 1.0, 0, "the last arm joint (the arm ends in a forearm)");
      add(s + "_wrist", end_link, end_F + 0.8 * (tip_F - end_F), 1.0, 0, "80 % of the way along the forearm");
      add(s + "_hand", end_link, tip_F, 0.5, 0, "the far end of the forearm");
      continue;
    }
    add(s + "_elbow", t.joint(arm.middle).child_link, F(jpos0(arm.middle)), 1.0, 0, "the bending arm joint nearest the arm's middle");
    add(s + "_wrist", end_link, end_F, 1.0, 0, "the last arm joint");
    // The hand: the middle of the geometry below the wrist, else a third of the forearm beyond it.
    const Vec3 elbow_F = F(jpos0(arm.middle));
    const Vec3 hand_F = any ? Vec3(0.5 * (lo3 + hi3)) : Vec3(end_F + 0.33 * (end_F - elbow_F));
    add(s + "_hand", end_link, hand_F, 0.5, 0, any ? "the middle of the hand's geometry" : "a third of the forearm beyond the wrist");
  }

  // ---- standing pose -----------------------------------------------------------------------------
  std::map<std::string, double> standing;
  std::string standing_source;
  if (!o.srdf_path.empty()) {
    const auto states = read_srdf_group_states(o.srdf_path);
    for (const char* want : {"half_sitting", "standing", "stand", "home", "ready", "default"}) {
      for (const auto& s : states)
        if (to_lower(s.name) == want) {
          for (const auto& [name, v] : s.joints) {
            const int j = urdf.find_joint(name);
            if (j >= 0 && movable(urdf.joints[static_cast<std::size_t>(j)].type)) standing[name] = v;
          }
          standing_source = "SRDF group state '" + s.name + "' (" + o.srdf_path + ":" + std::to_string(s.line) + ")";
          break;
        }
      if (!standing_source.empty()) break;
    }
    if (standing_source.empty()) say("standing      the SRDF has no half_sitting/standing/home/ready/default group state");
  }
  auto clamp_joint = [&](int j, double v) {
    const UrdfJoint& jt = t.joint(j);
    if (!jt.has_position_limits) return v;
    const double m = std::min(0.02, 0.1 * (jt.upper - jt.lower));
    return std::clamp(v, jt.lower + m, jt.upper - m);
  };
  if (standing_source.empty()) {
    // Knees bent, hips pitched so the COM is over the feet, ankles keeping the soles flat. Pitch
    // joints turn about the left axis; s is each one's sign (+1 when its axis points left).
    std::array<std::vector<std::pair<int, double>>, 2> pitch;  // (joint, sign)
    for (int k = 0; k < 2; ++k)
      for (int j : feet[static_cast<std::size_t>(k)].joints) {
        const UrdfJoint& jt = t.joint(j);
        if (jt.type == UrdfJointType::Prismatic) continue;
        const Vec3 axis_F = F(X0[static_cast<std::size_t>(jt.child_link)].linear() * jt.axis);
        if (std::abs(axis_F.y()) > 0.9) pitch[static_cast<std::size_t>(k)].push_back({j, axis_F.y() > 0 ? 1.0 : -1.0});
      }
    const bool can_bend = pitch[0].size() >= 3 && pitch[1].size() >= 3;
    if (!can_bend) {
      standing_source = "legs straight: fewer than 3 pitch joints (hip, knee, ankle) per leg";
    } else {
      // The knee is the pitch joint nearest the leg's middle joint.
      auto pose = [&](double hip_angle) {
        std::map<int, double> q;
        for (int k = 0; k < 2; ++k) {
          const auto& p = pitch[static_cast<std::size_t>(k)];
          const int knee_j = legs[static_cast<std::size_t>(k)].middle;
          std::size_t knee = p.size() / 2;
          for (std::size_t i = 0; i < p.size(); ++i)
            if (p[i].first == knee_j) knee = i;
          if (knee == 0 || knee + 1 >= p.size()) knee = p.size() / 2;
          const double a_hip = hip_angle, a_knee = o.knee_bend_rad, a_ankle = -(hip_angle + o.knee_bend_rad);
          q[p.front().first] = clamp_joint(p.front().first, a_hip / p.front().second);
          q[p[knee].first] = clamp_joint(p[knee].first, a_knee / p[knee].second);
          q[p.back().first] = clamp_joint(p.back().first, a_ankle / p.back().second);
        }
        return q;
      };
      // COM minus the soles' middle along forward, as a function of the hip angle.
      auto com_ahead = [&](double hip_angle) {
        const auto q = pose(hip_angle);
        const std::vector<Iso3> X = t.poses(q);
        Vec3 com = Vec3::Zero();
        double mass = 0;
        for (std::size_t l = 0; l < urdf.links.size(); ++l) {
          if (!t.descends(static_cast<int>(l), t.root())) continue;
          const double m = urdf.links[l].inertial.mass_kg;
          com += m * (X[l] * urdf.links[l].inertial.p_L_com);
          mass += m;
        }
        com /= std::max(mass, 1e-9);
        double sole = 0;
        for (const FootGuess& f : feet) {
          // The sole points move with the foot link.
          const Iso3 d = X[static_cast<std::size_t>(f.link)] * X0[static_cast<std::size_t>(f.link)].inverse();
          double lo = std::numeric_limits<double>::infinity(), hi = -lo;
          for (const Vec3& p : f.sole_R) lo = std::min(lo, F(d * p).x()), hi = std::max(hi, F(d * p).x());
          sole += 0.25 * (lo + hi);
        }
        return F(com).x() - sole;
      };
      double a = -o.knee_bend_rad - 0.3, b = 0.3;
      const double fa = com_ahead(a), fb = com_ahead(b);
      double hip = -0.5 * o.knee_bend_rad;
      if (fa * fb < 0) {
        for (int it = 0; it < 50; ++it) {
          const double m = 0.5 * (a + b);
          ((com_ahead(m) > 0) == (fa > 0) ? a : b) = m;
        }
        hip = 0.5 * (a + b);
      }
      for (const auto& [j, v] : pose(hip)) standing[t.joint(j).name] = v;
      standing_source = format("knees bent %.2f rad, hips %.3f rad so the COM is over the soles (COM %.1f mm ahead of "
                               "their middle), ankles keeping the soles flat",
                               o.knee_bend_rad, hip, com_ahead(hip) * 1e3);
    }
  }
  // Joints whose 0 is outside their range stand just inside it (RobotModel does the same; written
  // here so that the file says so).
  for (std::size_t j = 0; j < urdf.joints.size(); ++j) {
    const UrdfJoint& jt = urdf.joints[j];
    if (!movable(jt.type) || standing.count(jt.name) || !jt.has_position_limits || (jt.lower <= 0 && 0 <= jt.upper)) continue;
    standing[jt.name] = clamp_joint(static_cast<int>(j), 0.0);
  }

  // ---- gains -------------------------------------------------------------------------------------
  double mass = 0;
  for (const UrdfLink& l : urdf.links) mass += l.inertial.mass_kg;
  // Tracking gains [1/s^2]: 36 (kd 12) holds the example robots up to 60 kg; a 90 kg robot needed
  // about 100 (kd 20) on slow steps: kp = 36 max(1, (m / 60 kg)^2.5), critically damped kd = 2 sqrt(kp).
  const double kp = 36 * std::max(1.0, std::pow(mass / 60.0, 2.5));
  const double kd = 2 * std::sqrt(kp);
  // Standing hold [N m/rad]: 30 per kg of robot (1000 for the 33 kg G1), kd a fiftieth.
  const double hold_kp = 10 * std::round(3 * mass), hold_kd = hold_kp / 50;

  // ---- the YAML ----------------------------------------------------------------------------------
  const std::string name = !o.name.empty() ? o.name : urdf.name;
  std::string y;
  y += "# Written by `retarget init-robot` from " + urdf_abs + ".\n";
  y += "# Every value below is a guess from the kinematic tree; the comments say where each came from.\n";
  y += "# Check with `retarget inspect <this folder>` (warnings, standing hold) and a converted clip.\n";
  y += "name: " + yaml_name(name) + "\n";
  y += "urdf: " + yaml_name(urdf_abs) + "\n";
  std::vector<std::string> quoted_paths;
  for (const auto& p : package_paths) quoted_paths.push_back(yaml_name(p));
  if (!package_paths.empty()) y += "package_paths: [" + join(quoted_paths, ", ") + "]\n";
  y += "\n# The root link's axes that point forward and up: from the feet (up: feet to hips; forward: the\n";
  y += "# feet's long axis, towards the toes). The CSV root stays the URDF root link.\n";
  if (snapped) {
    y += "base_orientation: {forward: " + forward_name + ", up: " + up_name + "}\n";
  } else {
    const Mat3& R = R_root_F;
    const Vec3 rpy(std::atan2(R(2, 1), R(2, 2)), -std::asin(std::clamp(R(2, 0), -1.0, 1.0)), std::atan2(R(1, 0), R(0, 0)));
    y += "base_orientation: {rpy: " + vec(rpy) + "}   # not aligned with the root's axes\n";
  }
  y += "\n# Feet: the lowest link with geometry of each leg; the sole is its lowest face in the standing pose.\n";
  y += "feet:\n";
  for (int k = 0; k < 2; ++k)
    y += std::string("  ") + sides[k] + ":" + (k == 0 ? "  " : " ") + "{link: " + yaml_name(t.name(feet[static_cast<std::size_t>(k)].link)) +
         ", sole: derive}\n";
  y += "\n# Human landmark -> robot link point; offsets in the link frame [m].\n";
  y += "landmarks:\n";
  for (const Mapped& m : marks) {
    const Vec3 p_L = X0[static_cast<std::size_t>(m.link)].inverse() * (R_root_F * m.p_F);
    std::string entry = "{link: " + yaml_name(t.name(m.link));
    if (p_L.norm() > 5e-4) entry += ", offset: " + vec(p_L);
    entry += ", weight: " + num(m.weight);
    if (m.orientation_weight > 0) entry += ", orientation_weight: " + num(m.orientation_weight);
    entry += "}";
    y += format("  %-15s %s   # %s\n", (m.landmark + ":").c_str(), entry.c_str(), m.why.c_str());
  }
  y += "\n# CSV column order: the URDF order of the movable joints (export_joints not given).\n";
  y += "\n# Standing pose: " + standing_source + ".\n";
  std::string joints_text;
  for (std::size_t j = 0; j < urdf.joints.size(); ++j) {
    const auto it = standing.find(urdf.joints[j].name);
    if (it != standing.end()) joints_text += "    " + yaml_name(it->first) + ": " + num(it->second) + "\n";
  }
  y += joints_text.empty() ? "standing_pose:\n  joints: {}\n" : "standing_pose:\n  joints:\n" + joints_text;
  y += "\n# Tracking gains scaled to the mass (" + format("%.1f kg", mass) + "): kp = 36 max(1, (m / 60 kg)^2.5), kd = 2 sqrt(kp).\n";
  y += "controller: {kp: " + num(kp) + ", kd: " + num(kd) + "}\n";
  y += "\n# Armature (reflected rotor inertia) from each joint's effort limit: 2e-4 kg m^2 per N m, in\n";
  y += "# [0.01, 0.2] (the URDF has none; without it an explicit PD on light links is unstable at 1 ms).\n";
  y += "# Standing hold (retarget inspect): 30 N m/rad per kg, kd a fiftieth.\n";
  y += "simulation:\n  armature: 0.01\n";
  std::string arm;
  for (const UrdfJoint& j : urdf.joints) {
    if (!movable(j.type)) continue;
    const double a = std::clamp(2e-4 * j.effort_limit, 0.01, 0.2);
    if (a > 0.01 + 1e-9) arm += "    " + yaml_name(j.name) + ": " + num(a) + "\n";
  }
  if (!arm.empty()) y += "  joint_armature:\n" + arm;
  y += "  hold_kp: " + num(hold_kp) + "\n  hold_kd: " + num(hold_kd) + "\n";
  out.yaml = y;

  // ---- report ------------------------------------------------------------------------------------
  say(format("root          %s; forward = root %s, up = root %s%s", t.name(t.root()).c_str(),
             snapped ? forward_name.c_str() : vec(forward).c_str(), snapped ? up_name.c_str() : vec(up).c_str(),
             snapped ? "" : " (not axis-aligned: written as rpy)"));
  say(format("legs          pelvis %s; feet %s (left), %s (right); %zu and %zu joints; leg length %.3f m", t.name(pelvis).c_str(),
             t.name(feet[0].link).c_str(), t.name(feet[1].link).c_str(), feet[0].joints.size(), feet[1].joints.size(), leg_length));
  if (chest >= 0)
    say(format("arms          chest %s; hands %s (left), %s (right); %zu and %zu joints", t.name(chest).c_str(),
               t.name(hand_link[0]).c_str(), t.name(hand_link[1]).c_str(), arms[0].joints.size(), arms[1].joints.size()));
  else
    say("arms          none found (no pair of branches with 3+ joints on opposite sides): arm landmarks not mapped");
  say("head          " + (head >= 0 ? t.name(head) : std::string("none found (not tracked)")));
  say("standing      " + standing_source);
  say(format("mass          %.2f kg -> controller kp %.1f, kd %.1f; hold_kp %.0f, hold_kd %.1f", mass, kp, kd, hold_kp, hold_kd));
  return out;
}

}  // namespace rt
