#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>

#include "formats/urdf/package_uri.hpp"
#include "formats/urdf/urdf_description.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

// ---- console_bridge capture ---------------------------------------------------------------------

// urdfdom reports problems only through console_bridge (and still returns a model for some broken
// files), so its log is captured and inspected. The output handler and log level are process-wide
// state of console_bridge: one capture at a time, and the previous handler is restored afterwards.
// The mutex is a function-local static because the state it guards is itself global.
std::mutex& console_bridge_mutex() {
  static std::mutex m;
  return m;
}

class ConsoleCapture : public console_bridge::OutputHandler {
 public:
  ConsoleCapture() : lock_(console_bridge_mutex()) {
    previous_handler_ = console_bridge::getOutputHandler();
    previous_level_ = console_bridge::getLogLevel();
    console_bridge::useOutputHandler(this);
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
  }
  ~ConsoleCapture() override {
    console_bridge::useOutputHandler(previous_handler_);
    console_bridge::setLogLevel(previous_level_);
  }
  ConsoleCapture(const ConsoleCapture&) = delete;
  ConsoleCapture& operator=(const ConsoleCapture&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    // Messages may span lines; keep one line.
    std::string one_line;
    for (const auto& piece : split(text, "\r\n")) {
      const auto t = trim(piece);
      if (t.empty()) continue;
      if (!one_line.empty()) one_line += ' ';
      one_line.append(t.data(), t.size());
    }
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR)
      errors.push_back(one_line);
    else if (level == console_bridge::CONSOLE_BRIDGE_LOG_WARN)
      warnings.push_back(one_line);
  }

  std::vector<std::string> errors;
  std::vector<std::string> warnings;

 private:
  std::lock_guard<std::mutex> lock_;
  console_bridge::OutputHandler* previous_handler_ = nullptr;
  console_bridge::LogLevel previous_level_ = console_bridge::CONSOLE_BRIDGE_LOG_WARN;
};

// ---- structural pass over the XML (tinyxml) -----------------------------------------------------

struct XmlGeometry {
  int line = 0;
  std::string kind;  // box, cylinder, sphere, mesh
};

struct XmlLink {
  std::string name;
  int line = 0;
  std::vector<XmlGeometry> collisions, visuals;
};

struct XmlJoint {
  std::string name;
  std::string type;
  int line = 0;
  std::string parent, child;
  bool has_limit = false;
};

struct XmlIndex {
  int robot_line = 0;
  std::vector<XmlLink> links;
  std::vector<XmlJoint> joints;
  std::map<std::string, int> link_by_name, joint_by_name;
};

class Reader {
 public:
  Reader(std::string name, std::string base_dir, const UrdfReadOptions& options)
      : name_(std::move(name)), base_dir_(std::move(base_dir)), options_(options) {}

  UrdfRobot read(const std::string& xml);

 private:
  [[noreturn]] void fail(int line, const std::string& message) const {
    throw InputError(line > 0 ? name_ + ":" + std::to_string(line) : name_, message);
  }
  std::string where(int line) const { return line > 0 ? name_ + ":" + std::to_string(line) : name_; }

  void index_xml(const std::string& xml);
  void check_numbers(const TiXmlElement* e, const std::string& owner) const;
  void check_structure();
  void parse_with_urdfdom(const std::string& xml);
  void fill_link(const XmlLink& x, UrdfLink& link) const;
  void fill_joint(const XmlJoint& x, UrdfJoint& joint) const;
  UrdfGeometry convert_geometry(const urdf::GeometrySharedPtr& g, const urdf::Pose& origin, const XmlGeometry& x,
                                const std::string& link) const;
  int line_for_message(const std::string& message) const;

  std::string name_;
  std::string base_dir_;
  const UrdfReadOptions& options_;
  XmlIndex index_;
  urdf::ModelInterfaceSharedPtr model_;
  Diagnostics diagnostics_;
};

const char* attribute(const TiXmlElement* e, const char* name) {
  const char* v = e->Attribute(name);
  return v ? v : "";
}

// Parses whitespace-separated finite numbers (locale-independent). False on anything else.
bool parse_numbers(const std::string& text, std::size_t count, std::vector<double>& out) {
  out.clear();
  const char* p = text.data();
  const char* end = p + text.size();
  while (true) {
    while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    if (p == end) break;
    if (*p == '+') ++p;
    double v = 0;
    const auto r = std::from_chars(p, end, v);
    if (r.ec != std::errc() || !std::isfinite(v)) return false;
    if (r.ptr < end && !std::isspace(static_cast<unsigned char>(*r.ptr))) return false;
    out.push_back(v);
    p = r.ptr;
  }
  return out.size() == count;
}

// urdfdom logs malformed numbers without saying where they are (and half-parses the element), so
// every numeric attribute is checked here first, with its line.
void Reader::check_numbers(const TiXmlElement* e, const std::string& owner) const {
  if (!e) return;
  // max_abs bounds geometry and mass (a robot is metres and kilograms; 1e300 is a typo that would
  // otherwise reach the simulation); limits and gains stay free (URDFs use 1e16 for "none").
  constexpr double kFree = std::numeric_limits<double>::infinity();
  struct Rule {
    const char* element;
    const char* attribute;
    std::size_t count;
    double max_abs;
  };
  static constexpr Rule kRules[] = {
      {"origin", "xyz", 3, 1e3},       {"origin", "rpy", 3, 1e3},      {"mass", "value", 1, 1e6},
      {"inertia", "ixx", 1, 1e6},      {"inertia", "ixy", 1, 1e6},     {"inertia", "ixz", 1, 1e6},
      {"inertia", "iyy", 1, 1e6},      {"inertia", "iyz", 1, 1e6},     {"inertia", "izz", 1, 1e6},
      {"box", "size", 3, 1e3},         {"cylinder", "radius", 1, 1e3}, {"cylinder", "length", 1, 1e3},
      {"sphere", "radius", 1, 1e3},    {"mesh", "scale", 3, 1e3},      {"axis", "xyz", 3, 1e3},
      {"limit", "lower", 1, kFree},    {"limit", "upper", 1, kFree},   {"limit", "effort", 1, kFree},
      {"limit", "velocity", 1, kFree}, {"dynamics", "damping", 1, kFree}, {"dynamics", "friction", 1, kFree},
      {"mimic", "multiplier", 1, kFree}, {"mimic", "offset", 1, kFree}};
  std::vector<double> values;
  for (const Rule& rule : kRules) {
    if (e->ValueStr() != rule.element) continue;
    const char* v = e->Attribute(rule.attribute);
    if (!v) continue;
    const std::string what = "<" + e->ValueStr() + " " + rule.attribute + "=\"" + std::string(v).substr(0, 80) + "\"> in " + owner;
    if (!parse_numbers(v, rule.count, values))
      fail(e->Row(), what + ": expected " +
                         (rule.count == 1 ? std::string("a finite number") : std::to_string(rule.count) + " finite numbers"));
    for (double x : values)
      if (std::abs(x) > rule.max_abs)
        fail(e->Row(), what + ": " + format("%g is not between -%g and %g", x, rule.max_abs, rule.max_abs));
  }
  for (const TiXmlElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) check_numbers(c, owner);
}

// What the pre-scan of an XML text finds (comments, CDATA, declarations and quoted attribute
// values skipped). tinyxml parses recursively, so absurd nesting must be refused before parsing,
// and its attribute handling is quadratic in the attributes of one element (200,000 took minutes).
struct XmlShape {
  int deepest = 0;         // element nesting
  int most_attributes = 0;  // in one element (quoted values counted)
};

XmlShape xml_shape(const std::string& xml) {
  int depth = 0, deepest = 0, most_attributes = 0;
  const std::size_t n = xml.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (xml[i] != '<') continue;
    if (xml.compare(i, 4, "<!--") == 0) {
      const auto e = xml.find("-->", i + 4);
      if (e == std::string::npos) break;
      i = e + 2;
    } else if (xml.compare(i, 9, "<![CDATA[") == 0) {
      const auto e = xml.find("]]>", i + 9);
      if (e == std::string::npos) break;
      i = e + 2;
    } else if (i + 1 < n && (xml[i + 1] == '?' || xml[i + 1] == '!')) {
      const auto e = xml.find('>', i + 2);
      if (e == std::string::npos) break;
      i = e;
    } else if (i + 1 < n && xml[i + 1] == '/') {
      --depth;
    } else {
      // An opening tag: find its end outside quotes; "/>" closes it at once.
      char quote = 0;
      int values = 0;
      std::size_t j = i + 1;
      for (; j < n; ++j) {
        if (quote) {
          if (xml[j] == quote) quote = 0;
        } else if (xml[j] == '"' || xml[j] == '\'') {
          quote = xml[j];
          ++values;
        } else if (xml[j] == '>') {
          break;
        }
      }
      most_attributes = std::max(most_attributes, values);
      if (j >= n) break;
      if (xml[j - 1] != '/') deepest = std::max(deepest, ++depth);
      i = j;
    }
  }
  return {deepest, most_attributes};
}

void Reader::index_xml(const std::string& xml) {
  constexpr int kMaxNesting = 200;      // URDFs nest 5 or 6 deep
  constexpr int kMaxAttributes = 1000;  // URDF elements have at most a handful
  // tinyxml reads UTF-8 only; a UTF-16 file (byte-order mark FF FE or FE FF, or NUL bytes in
  // "<?xml") otherwise fails with a message about the first odd byte.
  if (xml.size() >= 2 && ((xml[0] == '\xff' && xml[1] == '\xfe') || (xml[0] == '\xfe' && xml[1] == '\xff') ||
                          (xml[0] == '<' && xml[1] == '\0') || (xml[0] == '\0' && xml[1] == '<')))
    fail(1, "the file is UTF-16 encoded; save it as UTF-8");
  // tinyxml steps over a multi-byte sequence by its lead byte alone, so a lead byte near the end
  // of the text would make it read past it.
  if (const std::size_t bad = first_invalid_utf8(xml); bad != std::string::npos) {
    const TextPosition at = text_position(xml, bad);
    fail(at.line, format("byte 0x%02X at column %d is not UTF-8; save the file as UTF-8", static_cast<unsigned char>(xml[bad]), at.column));
  }
  const XmlShape shape = xml_shape(xml);
  if (shape.deepest > kMaxNesting)
    fail(0, "XML elements nested more than " + std::to_string(kMaxNesting) + " deep: not a URDF");
  if (shape.most_attributes > kMaxAttributes)
    fail(0, "an XML element has more than " + std::to_string(kMaxAttributes) + " attributes: not a URDF");
  TiXmlDocument doc;
  doc.Parse(xml.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (trim(xml).empty()) fail(0, "empty file");
  if (doc.Error()) {
    if (doc.ErrorId() == TiXmlBase::TIXML_ERROR_DOCUMENT_EMPTY) fail(0, "not an XML document (no element found)");
    fail(doc.ErrorRow(), std::string("not a valid XML document: ") + doc.ErrorDesc());
  }
  const TiXmlElement* robot = doc.RootElement();
  if (!robot || robot->ValueStr() != "robot")
    fail(robot ? robot->Row() : 0, "not a URDF: the document has no <robot> element");
  index_.robot_line = robot->Row();

  for (const TiXmlElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = e->ValueStr();
    if (tag == "link") {
      XmlLink link;
      link.name = attribute(e, "name");
      link.line = e->Row();
      if (link.name.empty()) fail(link.line, "<link> without a name");
      check_numbers(e, "link '" + link.name + "'");
      if (const TiXmlElement* in = e->FirstChildElement("inertial")) {
        const TiXmlElement* mass = in->FirstChildElement("mass");
        if (!mass || !mass->Attribute("value"))
          fail(in->Row(), "<inertial> of link '" + link.name + "' has no <mass value=...>");
      }
      if (index_.link_by_name.count(link.name))
        fail(link.line, "duplicate link '" + link.name + "' (first defined at line " +
                            std::to_string(index_.links[static_cast<std::size_t>(index_.link_by_name[link.name])].line) + ")");
      for (const char* group : {"collision", "visual"}) {
        for (const TiXmlElement* c = e->FirstChildElement(group); c; c = c->NextSiblingElement(group)) {
          const TiXmlElement* g = c->FirstChildElement("geometry");
          if (!g) fail(c->Row(), "<" + std::string(group) + "> of link '" + link.name + "' has no <geometry>");
          const TiXmlElement* shape = g->FirstChildElement();
          if (!shape) fail(g->Row(), "empty <geometry> in link '" + link.name + "'");
          const std::string kind = shape->ValueStr();
          if (kind != "box" && kind != "cylinder" && kind != "sphere" && kind != "mesh")
            fail(shape->Row(), "unsupported geometry <" + kind + "> in link '" + link.name +
                                   "' (supported: box, cylinder, sphere, mesh)");
          if (kind == "mesh" && std::string(attribute(shape, "filename")).empty())
            fail(shape->Row(), "<mesh> without filename in link '" + link.name + "'");
          (std::string(group) == "collision" ? link.collisions : link.visuals).push_back({g->Row(), kind});
        }
      }
      index_.link_by_name[link.name] = static_cast<int>(index_.links.size());
      index_.links.push_back(std::move(link));
    } else if (tag == "joint") {
      XmlJoint joint;
      joint.name = attribute(e, "name");
      joint.type = attribute(e, "type");
      joint.line = e->Row();
      if (joint.name.empty()) fail(joint.line, "<joint> without a name");
      check_numbers(e, "joint '" + joint.name + "'");
      if (index_.joint_by_name.count(joint.name))
        fail(joint.line, "duplicate joint '" + joint.name + "' (first defined at line " +
                             std::to_string(index_.joints[static_cast<std::size_t>(index_.joint_by_name[joint.name])].line) + ")");
      if (joint.type == "planar")
        fail(joint.line, "joint '" + joint.name +
                             "' is planar: planar joints are not supported (use revolute, continuous, prismatic, fixed or floating)");
      if (joint.type != "revolute" && joint.type != "continuous" && joint.type != "prismatic" &&
          joint.type != "fixed" && joint.type != "floating")
        fail(joint.line, "joint '" + joint.name + "' has unknown type '" + joint.type +
                             "' (expected revolute, continuous, prismatic, fixed or floating)");
      const TiXmlElement* parent = e->FirstChildElement("parent");
      const TiXmlElement* child = e->FirstChildElement("child");
      if (!parent || std::string(attribute(parent, "link")).empty())
        fail(joint.line, "joint '" + joint.name + "' has no <parent link=...>");
      if (!child || std::string(attribute(child, "link")).empty())
        fail(joint.line, "joint '" + joint.name + "' has no <child link=...>");
      joint.parent = attribute(parent, "link");
      joint.child = attribute(child, "link");
      joint.has_limit = e->FirstChildElement("limit") != nullptr;
      if ((joint.type == "revolute" || joint.type == "prismatic") && !joint.has_limit)
        fail(joint.line, "joint '" + joint.name + "' is " + joint.type + " but has no <limit> (use type continuous for an unlimited revolute joint)");
      index_.joint_by_name[joint.name] = static_cast<int>(index_.joints.size());
      index_.joints.push_back(std::move(joint));
    }
  }
  if (index_.links.empty()) fail(index_.robot_line, "the robot has no links");
}

void Reader::check_structure() {
  const std::size_t n = index_.links.size();
  // Each link becomes a MuJoCo body with its meshes; humanoids have well under 100.
  constexpr std::size_t kMaxLinks = 1000;
  if (n > kMaxLinks)
    fail(index_.links[kMaxLinks].line, "more than " + std::to_string(kMaxLinks) + " links: not a robot this tool can simulate");
  std::vector<int> parent_joint(n, -1);
  for (std::size_t j = 0; j < index_.joints.size(); ++j) {
    const XmlJoint& x = index_.joints[j];
    for (const std::string* l : {&x.parent, &x.child}) {
      if (!index_.link_by_name.count(*l))
        fail(x.line, "joint '" + x.name + "' references link '" + *l + "', which does not exist");
    }
    if (x.parent == x.child) fail(x.line, "joint '" + x.name + "' connects link '" + x.parent + "' to itself");
    const int c = index_.link_by_name.at(x.child);
    int& pj = parent_joint[static_cast<std::size_t>(c)];
    if (pj >= 0)
      fail(x.line, "link '" + x.child + "' is the child of two joints: '" + index_.joints[static_cast<std::size_t>(pj)].name +
                       "' (line " + std::to_string(index_.joints[static_cast<std::size_t>(pj)].line) + ") and '" + x.name + "'");
    pj = static_cast<int>(j);
  }
  std::vector<int> roots;
  for (std::size_t l = 0; l < n; ++l)
    if (parent_joint[l] < 0) roots.push_back(static_cast<int>(l));
  if (roots.empty())
    fail(index_.robot_line, "no root link: every link has a parent joint, so the joints form a cycle");
  if (roots.size() > 1) {
    const XmlLink& a = index_.links[static_cast<std::size_t>(roots[0])];
    const XmlLink& b = index_.links[static_cast<std::size_t>(roots[1])];
    fail(b.line, "two root links: '" + a.name + "' (line " + std::to_string(a.line) + ") and '" + b.name +
                     "' (a link that is not connected to the rest of the tree?)");
  }
  // Every link must be reachable from the root; with one parent per link and a single root, an
  // unreachable link lies on a cycle.
  std::vector<std::vector<int>> children(n);
  for (const XmlJoint& x : index_.joints)
    children[static_cast<std::size_t>(index_.link_by_name.at(x.parent))].push_back(index_.link_by_name.at(x.child));
  // The tree's depth is bounded too: the MJCF writer and MuJoCo's compiler recurse per body (a
  // 20,000-link chain overflowed the stack), and MuJoCo refuses deep trees anyway. Humanoids are
  // about 10 links deep.
  constexpr int kMaxTreeDepth = 100;
  std::vector<char> reached(n, 0);
  std::vector<std::pair<int, int>> stack{{roots[0], 1}};  // link, depth in links
  reached[static_cast<std::size_t>(roots[0])] = 1;
  while (!stack.empty()) {
    const auto [l, depth] = stack.back();
    stack.pop_back();
    for (int c : children[static_cast<std::size_t>(l)]) {
      if (!reached[static_cast<std::size_t>(c)]) {
        reached[static_cast<std::size_t>(c)] = 1;
        if (depth + 1 > kMaxTreeDepth) {
          const XmlJoint& x = index_.joints[static_cast<std::size_t>(parent_joint[static_cast<std::size_t>(c)])];
          fail(x.line, "the kinematic tree is more than " + std::to_string(kMaxTreeDepth) + " links deep at link '" +
                           index_.links[static_cast<std::size_t>(c)].name + "' (joint '" + x.name +
                           "'); a robot is about 10 deep");
        }
        stack.push_back({c, depth + 1});
      }
    }
  }
  for (std::size_t l = 0; l < n; ++l) {
    if (reached[l]) continue;
    const XmlJoint& x = index_.joints[static_cast<std::size_t>(parent_joint[l])];
    fail(x.line, "cycle in the kinematic tree: link '" + index_.links[l].name + "' (child of joint '" + x.name +
                     "') is not reachable from the root link '" + index_.links[static_cast<std::size_t>(roots[0])].name + "'");
  }
}

// Line of the first element whose name appears in brackets in a urdfdom message ("Joint [j] ...").
int Reader::line_for_message(const std::string& message) const {
  std::size_t pos = 0;
  while ((pos = message.find('[', pos)) != std::string::npos) {
    const auto end = message.find(']', pos);
    if (end == std::string::npos) break;
    const std::string name = message.substr(pos + 1, end - pos - 1);
    if (auto it = index_.joint_by_name.find(name); it != index_.joint_by_name.end())
      return index_.joints[static_cast<std::size_t>(it->second)].line;
    if (auto it = index_.link_by_name.find(name); it != index_.link_by_name.end())
      return index_.links[static_cast<std::size_t>(it->second)].line;
    pos = end + 1;
  }
  return index_.robot_line;
}

void Reader::parse_with_urdfdom(const std::string& xml) {
  std::vector<std::string> errors, warnings;
  {
    ConsoleCapture capture;
    try {
      model_ = urdf::parseURDF(xml);
    } catch (const std::exception& e) {
      capture.errors.push_back(e.what());
      model_.reset();
    }
    errors = std::move(capture.errors);
    warnings = std::move(capture.warnings);
  }
  for (const auto& w : warnings) diagnostics_.warn(where(line_for_message(w)), "urdfdom: " + w);
  if (!errors.empty()) fail(line_for_message(errors.front()), "invalid URDF: " + errors.front());
  if (!model_) fail(index_.robot_line, "invalid URDF (urdfdom rejected it without a message)");
}

Iso3 to_iso(const urdf::Pose& p) {
  Iso3 X = Iso3::Identity();
  X.translation() = Vec3(p.position.x, p.position.y, p.position.z);
  Quat q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  if (q.norm() > 0) X.linear() = q.normalized().toRotationMatrix();
  return X;
}

bool finite(const Iso3& X) { return X.matrix().allFinite(); }

UrdfGeometry Reader::convert_geometry(const urdf::GeometrySharedPtr& g, const urdf::Pose& origin,
                                      const XmlGeometry& x, const std::string& link) const {
  UrdfGeometry out;
  out.line = x.line;
  out.X_L_G = to_iso(origin);
  if (!finite(out.X_L_G)) fail(x.line, "non-finite <origin> of a geometry in link '" + link + "'");
  if (!g) fail(x.line, "geometry of link '" + link + "' could not be parsed");
  auto positive = [&](double v, const char* what) {
    if (!std::isfinite(v) || v <= 0)
      fail(x.line, std::string("geometry of link '") + link + "': " + what + " must be a positive number, got " + format("%g", v));
  };
  switch (g->type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(*g);
      out.kind = UrdfGeometry::Kind::Box;
      out.box_size_m = Vec3(b.dim.x, b.dim.y, b.dim.z);
      for (int i = 0; i < 3; ++i) positive(out.box_size_m[i], "box size");
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(*g);
      out.kind = UrdfGeometry::Kind::Cylinder;
      out.radius_m = c.radius;
      out.length_m = c.length;
      positive(out.radius_m, "cylinder radius");
      positive(out.length_m, "cylinder length");
      break;
    }
    case urdf::Geometry::SPHERE: {
      out.kind = UrdfGeometry::Kind::Sphere;
      out.radius_m = static_cast<const urdf::Sphere&>(*g).radius;
      positive(out.radius_m, "sphere radius");
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(*g);
      out.kind = UrdfGeometry::Kind::Mesh;
      out.mesh_uri = m.filename;
      out.mesh_scale = Vec3(m.scale.x, m.scale.y, m.scale.z);
      if (!out.mesh_scale.allFinite() || (out.mesh_scale.array() == 0).any())
        fail(x.line, "mesh scale of link '" + link + "' must be finite and non-zero");
      const ResolvedResource r = resolve_package_uri(out.mesh_uri, base_dir_, options_.package_paths);
      if (r.path.empty() && options_.require_mesh_files) fail(x.line, "mesh of link '" + link + "': " + r.error);
      out.mesh_path = r.path;
      break;
    }
  }
  return out;
}

void Reader::fill_link(const XmlLink& x, UrdfLink& link) const {
  link.name = x.name;
  link.line = x.line;
  const urdf::LinkConstSharedPtr l = model_->getLink(x.name);
  if (!l) fail(x.line, "link '" + x.name + "' was dropped by urdfdom");
  if (l->inertial) {
    const urdf::Inertial& in = *l->inertial;
    link.has_inertial = true;
    if (!std::isfinite(in.mass)) fail(x.line, "link '" + x.name + "' has a non-finite mass");
    if (in.mass < 0) fail(x.line, "link '" + x.name + "' has a negative mass (" + format("%g", in.mass) + " kg)");
    Mat3 I;
    I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    if (!I.allFinite()) fail(x.line, "link '" + x.name + "' has a non-finite inertia");
    const Iso3 X = to_iso(in.origin);
    if (!finite(X)) fail(x.line, "link '" + x.name + "' has a non-finite inertial <origin>");
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
    const double scale = I.diagonal().cwiseAbs().sum();
    if (eig.eigenvalues().minCoeff() < -1e-9 * scale - 1e-12)
      fail(x.line, "link '" + x.name + "' has an inertia matrix that is not positive semi-definite (principal moments " +
                       format("%g %g %g", eig.eigenvalues()[0], eig.eigenvalues()[1], eig.eigenvalues()[2]) + ")");
    link.inertial.mass_kg = in.mass;
    link.inertial.p_L_com = X.translation();
    link.inertial.I_com = X.linear() * I * X.linear().transpose();
  }
  // urdfdom silently drops some broken <collision>/<visual> entries: insist on a one-to-one match.
  if (l->collision_array.size() != x.collisions.size() || l->visual_array.size() != x.visuals.size())
    fail(x.line, "a <collision> or <visual> of link '" + x.name + "' could not be parsed");
  for (std::size_t i = 0; i < x.collisions.size(); ++i) {
    const auto& c = l->collision_array[i];
    link.collisions.push_back(convert_geometry(c->geometry, c->origin, x.collisions[i], x.name));
  }
  for (std::size_t i = 0; i < x.visuals.size(); ++i) {
    const auto& v = l->visual_array[i];
    link.visuals.push_back(convert_geometry(v->geometry, v->origin, x.visuals[i], x.name));
  }
}

void Reader::fill_joint(const XmlJoint& x, UrdfJoint& joint) const {
  joint.name = x.name;
  joint.line = x.line;
  const urdf::JointConstSharedPtr j = model_->getJoint(x.name);
  if (!j) fail(x.line, "joint '" + x.name + "' was dropped by urdfdom");
  switch (j->type) {
    case urdf::Joint::REVOLUTE: joint.type = UrdfJointType::Revolute; break;
    case urdf::Joint::CONTINUOUS: joint.type = UrdfJointType::Continuous; break;
    case urdf::Joint::PRISMATIC: joint.type = UrdfJointType::Prismatic; break;
    case urdf::Joint::FIXED: joint.type = UrdfJointType::Fixed; break;
    case urdf::Joint::FLOATING: joint.type = UrdfJointType::Floating; break;
    default: fail(x.line, "joint '" + x.name + "' has an unsupported type");
  }
  joint.parent_link = index_.link_by_name.at(x.parent);
  joint.child_link = index_.link_by_name.at(x.child);
  joint.X_P_J = to_iso(j->parent_to_joint_origin_transform);
  if (!finite(joint.X_P_J)) fail(x.line, "joint '" + x.name + "' has a non-finite <origin>");
  const bool movable = joint.type == UrdfJointType::Revolute || joint.type == UrdfJointType::Continuous ||
                       joint.type == UrdfJointType::Prismatic;
  if (movable) {
    const Vec3 axis(j->axis.x, j->axis.y, j->axis.z);
    if (!axis.allFinite() || axis.norm() < 1e-9) fail(x.line, "joint '" + x.name + "' has a zero or non-finite <axis>");
    joint.axis = axis.normalized();
  }
  if (j->limits) {
    const urdf::JointLimits& lim = *j->limits;
    if (!std::isfinite(lim.lower) || !std::isfinite(lim.upper) || !std::isfinite(lim.effort) || !std::isfinite(lim.velocity))
      fail(x.line, "joint '" + x.name + "' has a non-finite <limit>");
    if (lim.effort < 0 || lim.velocity < 0)
      fail(x.line, "joint '" + x.name + "' has a negative effort or velocity limit");
    joint.velocity_limit = lim.velocity;
    joint.effort_limit = lim.effort;
    if (joint.type == UrdfJointType::Revolute || joint.type == UrdfJointType::Prismatic) {
      if (lim.lower > lim.upper)
        fail(x.line, "joint '" + x.name + "' has lower limit " + format("%g", lim.lower) + " > upper limit " + format("%g", lim.upper));
      joint.has_position_limits = true;
      joint.lower = lim.lower;
      joint.upper = lim.upper;
    }
  }
  if (j->dynamics) {
    if (!std::isfinite(j->dynamics->damping) || !std::isfinite(j->dynamics->friction) || j->dynamics->damping < 0 ||
        j->dynamics->friction < 0)
      fail(x.line, "joint '" + x.name + "' has a negative or non-finite <dynamics> damping/friction");
    joint.damping = j->dynamics->damping;
    joint.friction = j->dynamics->friction;
  }
  if (j->mimic) {
    joint.mimic_joint = j->mimic->joint_name;
    joint.mimic_multiplier = j->mimic->multiplier;
    joint.mimic_offset = j->mimic->offset;
  }
}

UrdfRobot Reader::read(const std::string& xml) {
  index_xml(xml);
  check_structure();
  parse_with_urdfdom(xml);

  UrdfRobot robot;
  robot.name = model_->getName();
  robot.path = name_;
  robot.links.resize(index_.links.size());
  robot.joints.resize(index_.joints.size());
  for (std::size_t i = 0; i < index_.links.size(); ++i) fill_link(index_.links[i], robot.links[i]);
  for (std::size_t i = 0; i < index_.joints.size(); ++i) {
    UrdfJoint& j = robot.joints[i];
    fill_joint(index_.joints[i], j);
    robot.links[static_cast<std::size_t>(j.child_link)].parent_joint = static_cast<int>(i);
    robot.links[static_cast<std::size_t>(j.parent_link)].child_joints.push_back(static_cast<int>(i));
  }
  for (std::size_t i = 0; i < robot.links.size(); ++i)
    if (robot.links[i].parent_joint < 0) robot.root_link = static_cast<int>(i);
  for (const UrdfJoint& j : robot.joints) {
    if (j.mimic_joint.empty()) continue;
    if (!index_.joint_by_name.count(j.mimic_joint))
      fail(j.line, "joint '" + j.name + "' mimics joint '" + j.mimic_joint + "', which does not exist");
    diagnostics_.note(where(j.line), "joint '" + j.name + "' mimics '" + j.mimic_joint +
                                         "'; the coupling is not enforced (the joint is treated as independent)");
  }
  robot.diagnostics = std::move(diagnostics_);
  return robot;
}

}  // namespace

int UrdfRobot::find_link(const std::string& n) const {
  for (std::size_t i = 0; i < links.size(); ++i)
    if (links[i].name == n) return static_cast<int>(i);
  return -1;
}

int UrdfRobot::find_joint(const std::string& n) const {
  for (std::size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == n) return static_cast<int>(i);
  return -1;
}

std::string UrdfRobot::link_location(int link) const {
  return path + ":" + std::to_string(links.at(static_cast<std::size_t>(link)).line);
}

std::string UrdfRobot::joint_location(int joint) const {
  return path + ":" + std::to_string(joints.at(static_cast<std::size_t>(joint)).line);
}

UrdfRobot read_urdf_string(const std::string& xml, const std::string& name, const std::string& base_dir,
                           const UrdfReadOptions& options) {
  return Reader(name, base_dir, options).read(xml);
}

UrdfRobot read_urdf_file(const std::string& path, const UrdfReadOptions& options) {
  const std::string xml = read_file(path, 64ull << 20);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return read_urdf_string(xml, path, dir.empty() ? "." : dir, options);
}

}  // namespace rt
