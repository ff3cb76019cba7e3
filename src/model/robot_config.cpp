#include "retarget/model/robot_config.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "formats/urdf/package_uri.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/core/yaml_view.hpp"

namespace fs = std::filesystem;

namespace rt {

namespace {

// Absolute, normalised folder path without a trailing separator.
std::string normal_dir(const fs::path& p) {
  fs::path n = fs::absolute(p).lexically_normal();
  if (n.filename().empty() && n.has_parent_path() && n != n.root_path()) n = n.parent_path();
  return n.string();
}

// Landmarks whose human data carries an orientation (human_motion.hpp: pelvis, chest, feet).
bool has_orientation(Landmark l) {
  return l == Landmark::Pelvis || l == Landmark::Chest || l == Landmark::LeftAnkle || l == Landmark::RightAnkle;
}

class ConfigParser {
 public:
  ConfigParser(RobotConfig& config, const std::string& config_dir) : c_(config), dir_(config_dir) {}

  void parse(const YamlView& doc, const std::vector<std::string>& extra_package_paths);

 private:
  // Records where a key was written, for errors found later against the URDF.
  const YamlView& mark(const YamlView& v) {
    c_.key_locations[v.path()] = v.location();
    return v;
  }
  double number(const YamlView& v, double lo, double hi, const char* what) {
    const double x = mark(v).as_double();
    if (x < lo || x > hi) v.fail(std::string(what) + " must be in [" + format("%g", lo) + ", " + format("%g", hi) + "], got " + format("%g", x));
    return x;
  }
  double number_or(const YamlView& parent, const char* key, double fallback, double lo, double hi, const char* what) {
    auto v = parent.find(key);
    return v ? number(*v, lo, hi, what) : fallback;
  }
  // A point or size on a link [m]: a robot is a few metres, so 1e300 is a typo, not a pose.
  Vec3 vec3(const YamlView& v) {
    constexpr double kMaxLength_m = 100;
    const auto xs = mark(v).as_doubles();
    if (xs.size() != 3) v.fail("expected a list of 3 numbers, got " + std::to_string(xs.size()));
    for (double x : xs)
      if (!(std::abs(x) <= kMaxLength_m)) v.fail(format("%g m is not between -100 and 100 m", x));
    return Vec3(xs[0], xs[1], xs[2]);
  }
  std::string name_string(const YamlView& v) {
    const std::string s = mark(v).as_string();
    if (s.empty()) v.fail("expected a non-empty name");
    return s;
  }

  void parse_feet(const YamlView& feet);
  void parse_base_orientation(const YamlView& v);
  void parse_npz_layout(const YamlView& layout);
  void parse_landmarks(const YamlView& landmarks);
  void parse_standing(const YamlView& standing);
  void parse_controller(const YamlView& controller);
  void parse_simulation(const YamlView& simulation);

  RobotConfig& c_;
  std::string dir_;
};

void ConfigParser::parse(const YamlView& doc, const std::vector<std::string>& extra_package_paths) {
  doc.expect_map();
  doc.check_keys({"name", "urdf", "package_paths", "feet", "landmarks", "base_orientation", "joint_limits",
                  "export_joints", "npz_layout", "standing_pose", "controller", "simulation"});
  c_.name = name_string(doc.at("name"));

  // Search order: --package-path, then the config's own roots, then $ROS_PACKAGE_PATH.
  for (const auto& p : extra_package_paths) c_.package_paths.push_back(normal_dir(p));
  if (auto pp = doc.find("package_paths")) {
    mark(*pp);
    for (const auto& p : pp->as_strings()) {
      fs::path path(p);
      if (path.is_relative()) path = fs::path(dir_) / path;
      c_.package_paths.push_back(normal_dir(path));
    }
  }
  if (const char* ros = std::getenv("ROS_PACKAGE_PATH"))
    for (const auto& p : split_path_list(ros)) c_.package_paths.push_back(p);

  const YamlView urdf = doc.at("urdf");
  const std::string uri = name_string(urdf);
  const ResolvedResource r = resolve_package_uri(uri, dir_, c_.package_paths);
  if (r.path.empty()) urdf.fail("URDF not found: " + r.error + " (add its folder with --package-path)");
  c_.urdf_path = r.path;

  parse_feet(doc.at("feet"));
  if (auto lm = doc.find("landmarks")) parse_landmarks(*lm);
  if (auto bo = doc.find("base_orientation")) parse_base_orientation(*bo);
  if (auto jl = doc.find("joint_limits")) {
    mark(*jl).expect_map();
    for (const auto& name : jl->keys()) {
      const YamlView entry = mark(jl->at(name));
      entry.check_keys({"velocity", "effort"});
      JointLimitOverride o;
      o.velocity = number_or(entry, "velocity", 0, 1e-6, 1e6, "velocity limit");
      o.effort = number_or(entry, "effort", 0, 1e-6, 1e7, "effort limit");
      c_.joint_limits[name] = o;
    }
  }
  if (auto ej = doc.find("export_joints")) {
    mark(*ej).expect_sequence();
    std::set<std::string> seen;
    for (std::size_t i = 0; i < ej->size(); ++i) {
      const YamlView item = ej->at(i);
      const std::string name = name_string(item);
      if (!seen.insert(name).second) item.fail("joint '" + name + "' is listed twice");
      c_.export_joints.push_back(name);
    }
  }
  if (auto layout = doc.find("npz_layout")) parse_npz_layout(*layout);
  if (auto sp = doc.find("standing_pose")) parse_standing(*sp);
  if (auto ctl = doc.find("controller")) parse_controller(*ctl);
  if (auto sim = doc.find("simulation")) parse_simulation(*sim);
}

// "urdf", or "mjcf:FILE" / "names:FILE" with FILE resolved as the URDF is (relative to this file,
// absolute or package://); the file's content is checked against the URDF when it is used.
void ConfigParser::parse_npz_layout(const YamlView& layout) {
  const std::string spec = name_string(layout);
  if (spec == "urdf") {
    c_.npz_layout = spec;
    return;
  }
  const auto colon = spec.find(':');
  const std::string kind = colon == std::string::npos ? spec : spec.substr(0, colon);
  if (colon == std::string::npos || (kind != "mjcf" && kind != "names") || colon + 1 == spec.size())
    layout.fail("expected urdf, mjcf:FILE or names:FILE, got '" + spec + "'");
  const ResolvedResource r = resolve_package_uri(spec.substr(colon + 1), dir_, c_.package_paths);
  if (r.path.empty()) layout.fail(kind + " file not found: " + r.error);
  c_.npz_layout = kind + ":" + r.path;
}

void ConfigParser::parse_feet(const YamlView& feet) {
  mark(feet).check_keys({"left", "right"});
  const char* sides[2] = {"left", "right"};
  for (int s = 0; s < 2; ++s) {
    const YamlView foot = feet.at(sides[s]);
    foot.check_keys({"link", "sole"});
    FootConfig& f = c_.feet[static_cast<std::size_t>(s)];
    f.link = name_string(foot.at("link"));
    const YamlView sole = mark(foot.at("sole"));
    if (sole.is_scalar()) {
      if (sole.as_string() != "derive") sole.fail("expected 'derive' or a map {center: [x, y, z], size: [length, width]}");
      f.sole.derive = true;
    } else {
      sole.check_keys({"center", "size"});
      f.sole.p_L_center = vec3(sole.at("center"));
      const YamlView size = sole.at("size");
      const auto xs = mark(size).as_doubles();
      if (xs.size() != 2) size.fail("expected [length, width]");
      if (!(xs[0] > 0 && xs[1] > 0)) size.fail("sole length and width must be positive");
      f.sole.size_m = Vec2(xs[0], xs[1]);
    }
  }
  if (c_.feet[0].link == c_.feet[1].link) feet.at("right").at("link").fail("left and right feet use the same link");
}

// A signed axis name ("x", "-y", "+z") as a unit vector.
Vec3 axis_vector(const YamlView& v) {
  std::string a = to_lower(v.as_string());
  double sign = 1;
  if (!a.empty() && (a[0] == '-' || a[0] == '+')) {
    sign = a[0] == '-' ? -1 : 1;
    a = a.substr(1);
  }
  if (a == "x") return sign * Vec3::UnitX();
  if (a == "y") return sign * Vec3::UnitY();
  if (a == "z") return sign * Vec3::UnitZ();
  v.fail("expected an axis of the root link: x, y, z, -x, -y or -z");
}

void ConfigParser::parse_base_orientation(const YamlView& v) {
  mark(v).check_keys({"forward", "up", "rpy"});
  if (auto rpy = v.find("rpy")) {
    if (v.find("forward") || v.find("up")) rpy->fail("give either rpy or forward/up, not both");
    const Vec3 a = vec3(*rpy);
    // URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll).
    c_.R_root_F = (AngleAxis(a.z(), Vec3::UnitZ()) * AngleAxis(a.y(), Vec3::UnitY()) * AngleAxis(a.x(), Vec3::UnitX()))
                      .toRotationMatrix();
    return;
  }
  const Vec3 forward = v.find("forward") ? axis_vector(mark(v.at("forward"))) : Vec3::UnitX();
  const Vec3 up = v.find("up") ? axis_vector(mark(v.at("up"))) : Vec3::UnitZ();
  if (std::abs(forward.dot(up)) > 0.5) v.fail("forward and up must be different, perpendicular axes");
  c_.R_root_F.col(0) = forward;
  c_.R_root_F.col(1) = up.cross(forward);
  c_.R_root_F.col(2) = up;
}

void ConfigParser::parse_landmarks(const YamlView& landmarks) {
  mark(landmarks).expect_map();
  std::set<std::string> seen;
  for (const auto& key : landmarks.keys()) {
    const YamlView entry = mark(landmarks.at(key));
    if (!seen.insert(key).second) entry.fail("landmark '" + key + "' is listed twice");
    const auto lm = landmark_from_name(key);
    if (!lm) {
      std::vector<std::string> names;
      for (Landmark l : all_landmarks()) names.emplace_back(landmark_name(l));
      entry.fail("unknown landmark '" + key + "' (known: " + join(names, ", ") + ")");
    }
    LandmarkTarget t;
    t.landmark = *lm;
    if (entry.is_scalar()) {
      t.link = name_string(entry);
      c_.key_locations[entry.path() + ".link"] = entry.location();
    } else {
      entry.check_keys({"link", "weight", "orientation_weight", "offset"});
      t.link = name_string(entry.at("link"));
      t.weight = number_or(entry, "weight", 1.0, 0, 1e6, "weight");
      t.orientation_weight = number_or(entry, "orientation_weight", 0.0, 0, 1e6, "orientation_weight");
      if (t.orientation_weight > 0 && !has_orientation(*lm))
        entry.at("orientation_weight")
            .fail("landmark '" + key + "' carries no orientation (only pelvis, chest, left_ankle and right_ankle do)");
      if (auto off = entry.find("offset")) t.p_L_offset = vec3(*off);
    }
    c_.landmarks.push_back(t);
  }
}

void ConfigParser::parse_standing(const YamlView& standing) {
  mark(standing).check_keys({"joints", "root_height"});
  if (auto joints = standing.find("joints")) {
    mark(*joints).expect_map();
    for (const auto& name : joints->keys()) c_.standing_joints[name] = number(joints->at(name), -1e3, 1e3, "joint position");
  }
  if (auto h = standing.find("root_height")) c_.standing_root_height_m = number(*h, 1e-3, 100, "root_height");
}

void ConfigParser::parse_controller(const YamlView& controller) {
  mark(controller).check_keys({"kp", "kd", "group_gains", "joint_gains", "foot_gains"});
  ControllerConfig& k = c_.controller;
  k.kp = number_or(controller, "kp", k.kp, 0, 1e6, "kp");
  k.kd = number_or(controller, "kd", k.kd, 0, 1e6, "kd");
  // A map of {kp, kd} entries, each defaulting to the section's kp/kd.
  auto gains_map = [&](const YamlView& map, std::map<std::string, JointGains>& out) {
    mark(map).expect_map();
    for (const auto& name : map.keys()) {
      const YamlView g = mark(map.at(name));
      g.check_keys({"kp", "kd"});
      out[name] = JointGains{number_or(g, "kp", k.kp, 0, 1e6, "kp"), number_or(g, "kd", k.kd, 0, 1e6, "kd")};
    }
  };
  if (auto gg = controller.find("group_gains")) {
    mark(*gg).check_keys({"legs", "torso", "arms"});
    gains_map(*gg, k.group_gains);
  }
  if (auto jg = controller.find("joint_gains")) gains_map(*jg, k.joint_gains);
  if (auto fg = controller.find("foot_gains")) {
    const YamlView g = mark(*fg);
    g.check_keys({"kp", "kd"});
    k.foot_gains.kp = number(g.at("kp"), 1e-3, 1e6, "foot_gains kp");
    k.foot_gains.kd = number_or(g, "kd", 2 * std::sqrt(k.foot_gains.kp), 0, 1e6, "foot_gains kd");
  }
}

void ConfigParser::parse_simulation(const YamlView& simulation) {
  mark(simulation).check_keys(
      {"timestep", "armature", "joint_armature", "damping", "friction", "hold_kp", "hold_kd"});
  SimulationConfig& s = c_.simulation;
  s.timestep_s = number_or(simulation, "timestep", s.timestep_s, 1e-5, 0.05, "timestep");
  s.armature = number_or(simulation, "armature", s.armature, 0, 1e3, "armature");
  s.extra_damping = number_or(simulation, "damping", s.extra_damping, 0, 1e6, "damping");
  s.friction = number_or(simulation, "friction", s.friction, 1e-3, 10, "friction");
  s.hold_kp = number_or(simulation, "hold_kp", s.hold_kp, 0, 1e7, "hold_kp");
  s.hold_kd = number_or(simulation, "hold_kd", s.hold_kd, 0, 1e6, "hold_kd");
  if (auto ja = simulation.find("joint_armature")) {
    mark(*ja).expect_map();
    for (const auto& name : ja->keys()) s.joint_armature[name] = number(ja->at(name), 0, 1e3, "armature");
  }
}

std::string config_dir(const std::string& config_path) { return normal_dir(fs::absolute(config_path).parent_path()); }

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

}  // namespace

std::string RobotConfig::where(const std::string& key_path) const {
  auto it = key_locations.find(key_path);
  if (it != key_locations.end()) return it->second;
  return config_path;
}

std::vector<std::string> robot_search_path() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("RETARGET_ROBOTS_PATH"))
    for (const auto& p : split_path_list(env)) out.push_back(p);
  out.push_back(RT_PROJECT_ROBOTS_DIR);
  return out;
}

RobotConfig parse_robot_config(const std::string& yaml_text, const std::string& config_path,
                               const std::vector<std::string>& extra_package_paths) {
  RobotConfig c;
  c.config_path = config_path;
  ConfigParser(c, config_dir(config_path)).parse(YamlView::load_string(yaml_text, config_path), extra_package_paths);
  return c;
}

RobotConfig load_robot_config(const std::string& robot, const std::vector<std::string>& extra_package_paths) {
  fs::path path(robot);
  std::error_code ec;
  const bool folder = fs::is_directory(path, ec);
  if (folder) path /= "robot.yaml";
  // Something that exists but is no regular file (a FIFO would block the read, a device never
  // ends): say what it is rather than "not found".
  if (fs::exists(path, ec) && !is_file(path)) require_regular_file(path.string());
  if (folder && !is_file(path)) throw InputError(robot, "robot not found: the folder holds no robot.yaml");
  if (!is_file(path)) {
    // A bare name: look for <root>/<name>/robot.yaml along the robot search path.
    const bool bare_name = robot.find('/') == std::string::npos && !ends_with(robot, ".yaml") && !robot.empty();
    path.clear();
    if (bare_name)
      for (const auto& root : robot_search_path())
        if (is_file(fs::path(root) / robot / "robot.yaml")) {
          path = fs::path(root) / robot / "robot.yaml";
          break;
        }
    if (path.empty())
      throw InputError(robot, "robot not found: not a robot.yaml, a folder holding one, or a robot name in " +
                                  join(robot_search_path(), ":"));
  }
  return parse_robot_config(read_file(path.string(), 4ull << 20), path.lexically_normal().string(), extra_package_paths);
}

std::string resolve_resource(const std::string& uri, const std::string& base_dir,
                             const std::vector<std::string>& package_paths) {
  return resolve_package_uri(uri, base_dir, package_paths).path;
}

}  // namespace rt
