#include "retarget/report/motion_viewer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

#include "formats/mesh/triangle_mesh.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/json_document.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt {

// The page's script (src/report/motion_viewer.js), embedded at build time.
extern const char kMotionViewerJs[];

namespace {

using json = nlohmann::ordered_json;

constexpr const char* kDataBlockOpen = "<script type=\"application/json\" id=\"rt-viewer-data\">";
constexpr const char* kFormat = "retarget-viewer";
constexpr int kFormatVersion = 1;

static_assert(sizeof(float) == 4, "float32 arrays");

bool little_endian_host() {
  const std::uint32_t one = 1;
  unsigned char b = 0;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

// ---- geometry ----------------------------------------------------------------------------------

TriangleMesh box_mesh(const Vec3& size) {
  TriangleMesh m;
  const Vec3 h = 0.5 * size;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  // Two outward triangles per face (counter-clockwise seen from outside).
  m.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
             {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

TriangleMesh cylinder_mesh(double r, double length, int segments = 24) {
  TriangleMesh m;
  const double h = 0.5 * length;
  for (int i = 0; i < segments; ++i) {
    const double a = 2 * M_PI * i / segments;
    m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), -h);
    m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), h);
  }
  const int bottom = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, -h);
  m.vertices.emplace_back(0, 0, h);
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % segments;
    const int b0 = 2 * i, t0 = 2 * i + 1, b1 = 2 * j, t1 = 2 * j + 1;
    m.faces.push_back({b0, b1, t1});
    m.faces.push_back({b0, t1, t0});
    m.faces.push_back({bottom, b1, b0});
    m.faces.push_back({bottom + 1, t0, t1});
  }
  return m;
}

TriangleMesh sphere_mesh(double r, int rings = 8, int segments = 16) {
  TriangleMesh m;
  for (int i = 0; i <= rings; ++i) {
    const double t = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double a = 2 * M_PI * j / segments;
      m.vertices.emplace_back(r * std::sin(t) * std::cos(a), r * std::sin(t) * std::sin(a), r * std::cos(t));
    }
  }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      const int c = a + segments, d = b + segments;
      if (i > 0) m.faces.push_back({a, c, b});
      if (i + 1 < rings) m.faces.push_back({b, c, d});
    }
  return m;
}

// The geometry's triangles in its own frame G.
TriangleMesh geometry_mesh(const Geometry& g) {
  switch (g.kind) {
    case Geometry::Kind::Box: return box_mesh(g.box_size_m);
    case Geometry::Kind::Cylinder: return cylinder_mesh(g.radius_m, g.length_m);
    case Geometry::Kind::Sphere: return sphere_mesh(g.radius_m);
    case Geometry::Kind::Mesh: {
      MeshLoadOptions o;
      o.scale = g.mesh_scale;
      return load_mesh(g.mesh_path, o);
    }
  }
  return {};
}

struct LinkMesh {
  int model_link = -1;
  TriangleMesh mesh;  ///< link frame
};

void append_in_link(const Geometry& g, TriangleMesh&& in_G, TriangleMesh& out_L) {
  const int base = static_cast<int>(out_L.vertices.size());
  for (const Vec3& v : in_G.vertices) out_L.vertices.push_back(g.X_L_G * v);
  for (const auto& f : in_G.faces) out_L.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
}

// One mesh per link from its visual (else collision) geometry; `source` says which were used.
std::vector<LinkMesh> link_meshes(const RobotModel& model, const ViewerOptions& options, std::vector<std::string>& notes,
                                  std::string& source) {
  std::vector<LinkMesh> out;
  bool used_visual = false, used_collision = false;
  for (std::size_t li = 0; li < model.links().size(); ++li) {
    const Link& link = model.links()[li];
    const bool visual = !options.collision_meshes && !link.visuals.empty();
    LinkMesh lm;
    lm.model_link = static_cast<int>(li);
    bool fell_back = false;
    if (visual) {
      try {
        for (const Geometry& g : link.visuals) append_in_link(g, geometry_mesh(g), lm.mesh);
        used_visual = true;
      } catch (const InputError& e) {
        // A visual mesh assimp cannot read (or a missing file): the collision geometry, which
        // loaded with the model, still shows the link.
        notes.push_back("link " + link.name + ": visual mesh not shown (" + e.what() + "), collision geometry instead");
        lm.mesh = TriangleMesh{};
        fell_back = true;
      }
    }
    if (!visual || fell_back) {
      for (const Geometry& g : link.collisions) append_in_link(g, geometry_mesh(g), lm.mesh);
      if (!link.collisions.empty()) used_collision = true;
    }
    if (!lm.mesh.faces.empty()) out.push_back(std::move(lm));
  }
  source = used_visual && used_collision ? "visual+collision" : used_visual ? "visual" : "collision";
  // Decimation: each mesh keeps its share of the budget (at least a box's 12 triangles).
  std::size_t total = 0;
  for (const LinkMesh& m : out) total += m.mesh.faces.size();
  const std::size_t budget = static_cast<std::size_t>(std::max(12, options.max_triangles));
  if (total > budget) {
    for (LinkMesh& m : out) {
      const double share = static_cast<double>(m.mesh.faces.size()) * static_cast<double>(budget) / static_cast<double>(total);
      const int max_faces = std::max(12, static_cast<int>(share));
      m.mesh = simplify_mesh(m.mesh, max_faces);
    }
    std::size_t after = 0;
    for (const LinkMesh& m : out) after += m.mesh.faces.size();
    notes.push_back(format("meshes decimated from %zu to %zu triangles (vertex clustering)", total, after));
  }
  return out;
}

void put_vec(std::vector<float>& out, const Vec3& v) {
  out.push_back(static_cast<float>(v.x()));
  out.push_back(static_cast<float>(v.y()));
  out.push_back(static_cast<float>(v.z()));
}

// Links, meshes and colours: the part of a scene that does not depend on the frames.
void scene_robot(const RobotModel& model, const ViewerOptions& options, ViewerScene& s, std::vector<int>& model_links) {
  s.robot = model.name();
  std::vector<LinkMesh> meshes = link_meshes(model, options, s.notes, s.mesh_source);
  std::map<int, int> viewer_index;
  auto index_of = [&](int model_link) {
    auto it = viewer_index.find(model_link);
    if (it != viewer_index.end()) return it->second;
    const int k = static_cast<int>(model_links.size());
    viewer_index[model_link] = k;
    model_links.push_back(model_link);
    s.link_names.push_back(model.links()[static_cast<std::size_t>(model_link)].name);
    return k;
  };
  // Side tints from the standing pose: left links bluish, right links warm, so mirrored limbs
  // can be told apart at a glance.
  RobotData data(model);
  update_kinematics(model, data, model.standing_q());
  const Iso3 X_W_root = link_pose(model, data, model.root_link());
  for (LinkMesh& m : meshes) {
    ViewerMesh vm;
    vm.link = index_of(m.model_link);
    vm.positions_L.reserve(3 * m.mesh.vertices.size());
    for (const Vec3& v : m.mesh.vertices) put_vec(vm.positions_L, v);
    vm.indices.reserve(3 * m.mesh.faces.size());
    for (const auto& f : m.mesh.faces)
      for (int i : f) vm.indices.push_back(static_cast<std::uint32_t>(i));
    const Vec3 p_root = X_W_root.inverse() * link_pose(model, data, m.model_link).translation();
    const double lateral = std::isfinite(p_root.y()) ? p_root.y() : 0.0;
    if (lateral > 0.02) vm.color = {0.62f, 0.68f, 0.80f};
    else if (lateral < -0.02) vm.color = {0.80f, 0.68f, 0.60f};
    else vm.color = {0.72f, 0.72f, 0.74f};
    s.meshes.push_back(std::move(vm));
  }
  for (int side = 0; side < 2; ++side) s.foot_links[static_cast<std::size_t>(side)] = index_of(model.soles()[static_cast<std::size_t>(side)].link);
}

// Poses, soles and COM of frame f (after update_kinematics).
void scene_frame(const RobotModel& model, const RobotData& data, const std::vector<int>& model_links, ViewerScene& s) {
  for (int l : model_links) {
    const Iso3 X = link_pose(model, data, l);
    put_vec(s.link_poses, X.translation());
    Quat q(X.linear());
    q.normalize();
    s.link_poses.push_back(static_cast<float>(q.x()));
    s.link_poses.push_back(static_cast<float>(q.y()));
    s.link_poses.push_back(static_cast<float>(q.z()));
    s.link_poses.push_back(static_cast<float>(q.w()));
  }
  for (const Sole& sole : model.soles())
    for (const Vec3& c : sole.corners_L()) put_vec(s.sole_corners_W, link_point(model, data, sole.link, c));
  put_vec(s.com_W, com_position(model, data));
}

// ---- bones of the landmark set ----------------------------------------------------------------

const std::vector<std::array<Landmark, 2>>& skeleton_bones() {
  using L = Landmark;
  static const std::vector<std::array<Landmark, 2>> bones = {
      {L::Pelvis, L::Spine},          {L::Spine, L::Chest},           {L::Chest, L::Neck},
      {L::Neck, L::Head},             {L::Pelvis, L::LeftHip},        {L::LeftHip, L::LeftKnee},
      {L::LeftKnee, L::LeftAnkle},    {L::LeftAnkle, L::LeftHeel},    {L::LeftAnkle, L::LeftToe},
      {L::LeftHeel, L::LeftToe},      {L::Neck, L::LeftShoulder},     {L::LeftShoulder, L::LeftElbow},
      {L::LeftElbow, L::LeftWrist},   {L::LeftWrist, L::LeftHand},    {L::Pelvis, L::RightHip},
      {L::RightHip, L::RightKnee},    {L::RightKnee, L::RightAnkle},  {L::RightAnkle, L::RightHeel},
      {L::RightAnkle, L::RightToe},   {L::RightHeel, L::RightToe},    {L::Neck, L::RightShoulder},
      {L::RightShoulder, L::RightElbow}, {L::RightElbow, L::RightWrist}, {L::RightWrist, L::RightHand},
      {L::Chest, L::LeftShoulder},    {L::Chest, L::RightShoulder}};
  return bones;
}

// ---- JSON --------------------------------------------------------------------------------------

template <class T>
std::string b64(const std::vector<T>& v) {
  return base64_encode(v.data(), v.size() * sizeof(T));
}

template <class T>
std::vector<T> unb64(const json& j, const std::string& file, const std::string& key, std::size_t expected_count) {
  if (!j.is_string()) throw InputError(file + " [" + key + "]", "expected a base64 string");
  const std::string bytes = base64_decode(j.get<std::string>(), file + " [" + key + "]");
  if (bytes.size() % sizeof(T) != 0 || (expected_count != SIZE_MAX && bytes.size() != expected_count * sizeof(T)))
    throw InputError(file + " [" + key + "]",
                     format("expected %zu values, got %zu bytes", expected_count, bytes.size()));
  std::vector<T> v(bytes.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
  return v;
}

json points_json(const ViewerPoints& p) {
  json j;
  j["names"] = p.names;
  json bones = json::array();
  for (const auto& b : p.bones) bones.push_back({b[0], b[1]});
  j["bones"] = bones;
  j["p_W"] = b64(p.p_W);
  j["valid"] = b64(p.valid);
  return j;
}

ViewerPoints points_from_json(const json& j, const std::string& file, const std::string& key, int T) {
  ViewerPoints p;
  if (!j.is_object() || !j.contains("names") || !j["names"].is_array())
    throw InputError(file + " [" + key + "]", "expected an object with names, bones, p_W, valid");
  for (const json& n : j["names"]) p.names.push_back(n.get<std::string>());
  const std::size_t N = p.names.size();
  for (const json& b : j.value("bones", json::array())) {
    const int a = b.at(0).get<int>(), c = b.at(1).get<int>();
    if (a < 0 || c < 0 || static_cast<std::size_t>(a) >= N || static_cast<std::size_t>(c) >= N)
      throw InputError(file + " [" + key + ".bones]", format("bone (%d, %d) outside the %zu points", a, c, N));
    p.bones.push_back({a, c});
  }
  p.p_W = unb64<float>(j.at("p_W"), file, key + ".p_W", static_cast<std::size_t>(T) * N * 3);
  p.valid = unb64<std::uint8_t>(j.at("valid"), file, key + ".valid", static_cast<std::size_t>(T) * N);
  return p;
}

json scene_json(const ViewerScene& s) {
  json j;
  j["format"] = kFormat;
  j["format_version"] = kFormatVersion;
  j["mode"] = s.mode;
  j["title"] = s.title;
  j["robot"] = s.robot;
  j["fps"] = s.fps;
  j["num_frames"] = s.num_frames;
  j["link_names"] = s.link_names;
  j["link_poses"] = b64(s.link_poses);
  j["mesh_source"] = s.mesh_source;
  json meshes = json::array();
  for (const ViewerMesh& m : s.meshes)
    meshes.push_back({{"link", m.link},
                      {"color", {m.color[0], m.color[1], m.color[2]}},
                      {"num_vertices", m.positions_L.size() / 3},
                      {"num_triangles", m.num_triangles()},
                      {"positions_L", b64(m.positions_L)},
                      {"indices", b64(m.indices)}});
  j["meshes"] = meshes;
  j["foot_links"] = {s.foot_links[0], s.foot_links[1]};
  j["sole_corners_W"] = b64(s.sole_corners_W);
  j["contact"] = s.contact[0].empty() ? json(nullptr) : json::array({b64(s.contact[0]), b64(s.contact[1])});
  j["com_W"] = b64(s.com_W);
  j["com_planned_W"] = s.com_planned_W.empty() ? json(nullptr) : json(b64(s.com_planned_W));
  j["cop_planned_W"] = s.cop_planned_W.empty() ? json(nullptr) : json(b64(s.cop_planned_W));
  j["skeleton"] = s.skeleton.empty() ? json(nullptr) : points_json(s.skeleton);
  j["landmarks"] = s.landmarks.empty() ? json(nullptr) : points_json(s.landmarks);
  j["notes"] = s.notes;
  return j;
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// Text placed inside <script>: a "</script" (any case) would end the element early; "<\/" means
// the same inside JavaScript strings, regular expressions and JSON.
std::string script_safe(std::string text) {
  for (std::size_t i = 0; (i = text.find("</", i)) != std::string::npos; i += 3) text.replace(i, 2, "<\\/");
  return text;
}

std::string read_library(const std::string& path, bool required) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    if (!required) return {};
    throw InputError(path, std::string("not found; the viewer inlines three.js from the Debian package ") +
                               kThreeJsPackage + " (apt-get install " + kThreeJsPackage + ")");
  }
  return read_file(path, 64ull << 20);
}

}  // namespace

int ViewerScene::num_triangles() const {
  int n = 0;
  for (const ViewerMesh& m : meshes) n += m.num_triangles();
  return n;
}

// ---- base64 ------------------------------------------------------------------------------------

std::string base64_encode(const void* data, std::size_t bytes) {
  static const char* a = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes; i += 3) {
    const std::uint32_t v = (std::uint32_t(p[i]) << 16) | (std::uint32_t(p[i + 1]) << 8) | p[i + 2];
    out += a[v >> 18];
    out += a[(v >> 12) & 63];
    out += a[(v >> 6) & 63];
    out += a[v & 63];
  }
  if (i < bytes) {
    std::uint32_t v = std::uint32_t(p[i]) << 16;
    if (i + 1 < bytes) v |= std::uint32_t(p[i + 1]) << 8;
    out += a[v >> 18];
    out += a[(v >> 12) & 63];
    out += i + 1 < bytes ? a[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string base64_decode(const std::string& text, const std::string& where) {
  if (text.size() % 4 != 0) throw InputError(where, format("base64 length %zu is not a multiple of 4", text.size()));
  auto value = [&](char c, std::size_t at) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    throw InputError(where, format("character %zu is not base64", at));
  };
  std::string out;
  out.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    const bool last = i + 4 == text.size();
    const int pad = last ? (text[i + 3] == '=') + (text[i + 2] == '=') : 0;
    if (pad == 1 && text[i + 2] == '=') throw InputError(where, format("character %zu is not base64", i + 2));
    std::uint32_t v = 0;
    for (int k = 0; k < 4 - pad; ++k) v |= std::uint32_t(value(text[i + k], i + k)) << (18 - 6 * k);
    out += static_cast<char>(v >> 16);
    if (pad < 2) out += static_cast<char>((v >> 8) & 255);
    if (pad < 1) out += static_cast<char>(v & 255);
  }
  return out;
}

// ---- scenes ------------------------------------------------------------------------------------

ViewerPoints skeleton_points(const std::array<LandmarkTrack, kLandmarkCount>& tracks, double fps_tracks,
                             const ViewerScene& scene) {
  ViewerPoints p;
  const int T = scene.num_frames;
  std::array<int, kLandmarkCount> point_of{};
  point_of.fill(-1);
  std::vector<const LandmarkTrack*> present;
  for (Landmark l : all_landmarks()) {
    const LandmarkTrack& t = tracks[static_cast<std::size_t>(index(l))];
    if (!t.present || t.p_W.cols() == 0) continue;
    point_of[static_cast<std::size_t>(index(l))] = static_cast<int>(p.names.size());
    p.names.emplace_back(landmark_name(l));
    present.push_back(&t);
  }
  if (p.names.empty() || T == 0 || !(fps_tracks > 0) || !(scene.fps > 0)) return {};
  for (const auto& b : skeleton_bones()) {
    const int a = point_of[static_cast<std::size_t>(index(b[0]))], c = point_of[static_cast<std::size_t>(index(b[1]))];
    if (a >= 0 && c >= 0) p.bones.push_back({a, c});
  }
  const std::size_t N = present.size();
  p.p_W.reserve(static_cast<std::size_t>(T) * N * 3);
  p.valid.reserve(static_cast<std::size_t>(T) * N);
  for (int f = 0; f < T; ++f) {
    const double x = f / scene.fps * fps_tracks;  // source frame of this scene frame
    for (const LandmarkTrack* t : present) {
      const int n = static_cast<int>(t->p_W.cols());
      const int i0 = std::clamp(static_cast<int>(std::floor(x)), 0, n - 1), i1 = std::min(i0 + 1, n - 1);
      const double w = std::clamp(x - i0, 0.0, 1.0);
      put_vec(p.p_W, (1 - w) * t->p_W.col(i0) + w * t->p_W.col(i1));
      p.valid.push_back(t->valid(i0) && t->valid(i1) ? 1 : 0);
    }
  }
  return p;
}

ViewerScene motion_scene(const RobotModel& model, const Reference& reference, const std::string& where,
                         const ViewerOptions& options) {
  const int T = reference.num_frames();
  require_input(T >= 1, where, "the reference has no frames");
  require_input(std::isfinite(reference.fps) && reference.fps > 0, where, "the reference has no frame rate");
  const ReferenceRobotMap map(model, reference, where);  // checks the joint set first
  // Frames shown: every stride-th, so that the page plays at most max_fps.
  const double max_fps = options.max_fps > 0 ? options.max_fps : reference.fps;
  const int stride = std::max(1, static_cast<int>(std::ceil(reference.fps / max_fps - 1e-9)));
  std::vector<int> frames;
  for (int f = 0; f < T; f += stride) frames.push_back(f);
  ViewerScene s;
  s.mode = "motion";
  s.fps = reference.fps / stride;
  s.num_frames = static_cast<int>(frames.size());
  std::vector<int> model_links;
  scene_robot(model, options, s, model_links);
  s.title = options.title.empty() ? model.name() + ": " + base_name(where) : options.title;
  if (stride > 1)
    s.notes.push_back(format("shown at %g Hz: every %d%s frame of the %g Hz reference", s.fps, stride,
                             stride == 2 ? "nd" : stride == 3 ? "rd" : "th", reference.fps));
  RobotData data(model);
  const std::size_t L = model_links.size();
  s.link_poses.reserve(frames.size() * L * 7);
  for (int f : frames) {
    update_kinematics(model, data, map.q(reference, f));
    scene_frame(model, data, model_links, s);
  }
  if (reference.has_contacts())
    for (std::size_t side = 0; side < 2; ++side)
      for (int f : frames) s.contact[side].push_back(reference.contact[side][static_cast<std::size_t>(f)]);
  if (reference.com_W.cols() == T)
    for (int f : frames) put_vec(s.com_planned_W, reference.com_W.col(f));
  if (reference.cop_W.cols() == T)
    for (int f : frames) {
      s.cop_planned_W.push_back(static_cast<float>(reference.cop_W(0, f)));
      s.cop_planned_W.push_back(static_cast<float>(reference.cop_W(1, f)));
    }
  return s;
}

ViewerScene robot_scene(const RobotModel& model, const ViewerOptions& options) {
  ViewerScene s;
  s.mode = "robot";
  s.fps = 30;
  s.num_frames = 1;
  std::vector<int> model_links;
  scene_robot(model, options, s, model_links);
  s.title = options.title.empty() ? model.name() + ": standing pose" : options.title;
  RobotData data(model);
  update_kinematics(model, data, model.standing_q());
  scene_frame(model, data, model_links, s);
  s.contact = {std::vector<std::uint8_t>{1}, std::vector<std::uint8_t>{1}};
  for (const LandmarkTarget& t : model.config().landmarks) {
    s.landmarks.names.push_back(std::string(landmark_name(t.landmark)) + " (" + t.link + ")");
    put_vec(s.landmarks.p_W, link_point(model, data, model.link_index(t.link), t.p_L_offset));
    s.landmarks.valid.push_back(1);
  }
  return s;
}

// ---- page --------------------------------------------------------------------------------------

void require_three_js(const ViewerOptions& options) { (void)read_library(options.three_js_dir + "/three.min.js", true); }

std::string viewer_page_html(const ViewerScene& s, const ViewerOptions& options) {
  RT_DEMAND(little_endian_host(), "the viewer's float32 arrays are written little-endian");
  const std::string three = read_library(options.three_js_dir + "/three.min.js", true);
  const std::string orbit = read_library(options.three_js_dir + "/examples/js/controls/OrbitControls.js", false);
  std::string h;
  h.reserve(three.size() + 4096);
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<meta name=\"generator\" content=\"retarget motion viewer\">\n";
  h += "<title>" + html_escape(s.title) + "</title>\n";
  h += "<style>\n"
       "html,body{margin:0;height:100%;overflow:hidden;font:13px system-ui,sans-serif;color:#222;background:#f4f4f2}\n"
       "#view{position:absolute;inset:0 0 92px 0}\n"
       "#bar{position:absolute;left:0;right:0;bottom:0;height:92px;background:#fff;border-top:1px solid #ccc;"
       "padding:4px 8px;box-sizing:border-box}\n"
       "#bar .row{display:flex;align-items:center;gap:8px;margin:2px 0}\n"
       "#scrub{flex:1}#timeline{width:100%;height:28px;display:block;cursor:pointer}\n"
       "#layers{flex-wrap:wrap;row-gap:0}#layers label{white-space:nowrap}\n"
       "#info{position:absolute;left:8px;top:8px;background:rgba(255,255,255,.85);padding:4px 8px;"
       "border-radius:4px;max-width:46em}\n"
       "#info h1{font-size:14px;margin:0 0 2px}#info .notes{color:#666;font-size:11px}\n"
       ".key{display:inline-block;width:10px;height:10px;border-radius:2px;margin:0 3px 0 8px;vertical-align:middle}\n"
       "#rt-status{position:absolute;right:8px;top:8px;font-size:11px;color:#666}\n"
       "#rt-status[data-status=error]{color:#a00;background:#fff;padding:4px;white-space:pre-wrap;max-width:40em}\n"
       "</style>\n</head>\n<body>\n";
  // The error hook comes first, so that a failure in any later script leaves a mark in the DOM
  // (the headless-browser test reads it; a user sees it in the corner).
  h += "<div id=\"rt-status\" data-status=\"loading\">loading</div>\n";
  h += "<script>(function(){var st=document.getElementById('rt-status');window.rtViewerFail=function(m){"
       "st.setAttribute('data-status','error');st.textContent=(st.textContent.indexOf('error')===0?st.textContent+'\\n':'error: ')+m;};"
       "window.addEventListener('error',function(e){window.rtViewerFail((e.message||'script error')+"
       "(e.lineno?' (line '+e.lineno+')':''));});"
       "var ce=console.error;console.error=function(){window.rtViewerFail(Array.prototype.join.call(arguments,' '));"
       "ce.apply(console,arguments);};})();</script>\n";
  h += "<div id=\"view\"></div>\n<div id=\"info\"></div>\n";
  h += "<div id=\"bar\"><div class=\"row\"><button id=\"play\">pause</button>"
       "<input id=\"scrub\" type=\"range\" min=\"0\" max=\"0\" value=\"0\"><span id=\"time\">0.00 s</span>"
       "<label>speed <select id=\"speed\"><option>0.1</option><option>0.25</option><option>0.5</option>"
       "<option selected>1</option><option>2</option></select></label></div>"
       "<div class=\"row\" id=\"layers\"></div><canvas id=\"timeline\"></canvas></div>\n";
  h += kDataBlockOpen + script_safe(scene_json(s).dump()) + "</script>\n";
  h += "<script>\n" + script_safe(three) + "\n</script>\n";
  if (!orbit.empty()) h += "<script>\n" + script_safe(orbit) + "\n</script>\n";
  h += "<script>\n" + script_safe(kMotionViewerJs) + "\n</script>\n</body>\n</html>\n";
  return h;
}

ViewerScene parse_viewer_page(const std::string& html, const std::string& file) {
  const std::size_t open = html.find(kDataBlockOpen);
  if (open == std::string::npos) throw InputError(file, "no viewer data block (not a page of retarget view)");
  const std::size_t begin = open + std::strlen(kDataBlockOpen);
  const std::size_t end = html.find("</script>", begin);
  if (end == std::string::npos) throw InputError(file, "the viewer data block is not closed");
  const json j = parse_json_object(std::string_view(html).substr(begin, end - begin), file, "viewer data", 16);
  auto need = [&](const char* key) -> const json& {
    if (!j.contains(key)) throw InputError(file + " [" + key + "]", "missing");
    return j[key];
  };
  try {
    if (need("format") != kFormat) throw InputError(file + " [format]", std::string("expected \"") + kFormat + "\"");
    ViewerScene s;
    s.mode = need("mode").get<std::string>();
    s.title = need("title").get<std::string>();
    s.robot = need("robot").get<std::string>();
    s.fps = need("fps").get<double>();
    s.num_frames = need("num_frames").get<int>();
    if (s.num_frames < 1) throw InputError(file + " [num_frames]", "expected at least 1");
    const std::size_t T = static_cast<std::size_t>(s.num_frames);
    for (const json& n : need("link_names")) s.link_names.push_back(n.get<std::string>());
    const std::size_t L = s.link_names.size();
    s.link_poses = unb64<float>(need("link_poses"), file, "link_poses", T * L * 7);
    s.mesh_source = need("mesh_source").get<std::string>();
    std::size_t k = 0;
    for (const json& m : need("meshes")) {
      const std::string key = format("meshes[%zu]", k++);
      ViewerMesh vm;
      vm.link = m.at("link").get<int>();
      if (vm.link < 0 || static_cast<std::size_t>(vm.link) >= L)
        throw InputError(file + " [" + key + ".link]", format("link %d outside the %zu links", vm.link, L));
      for (int c = 0; c < 3; ++c) vm.color[static_cast<std::size_t>(c)] = m.at("color").at(static_cast<std::size_t>(c)).get<float>();
      const std::size_t nv = m.at("num_vertices").get<std::size_t>();
      vm.positions_L = unb64<float>(m.at("positions_L"), file, key + ".positions_L", nv * 3);
      vm.indices = unb64<std::uint32_t>(m.at("indices"), file, key + ".indices", m.at("num_triangles").get<std::size_t>() * 3);
      for (std::uint32_t i : vm.indices)
        if (i >= nv) throw InputError(file + " [" + key + ".indices]", format("vertex %u of %zu", i, nv));
      s.meshes.push_back(std::move(vm));
    }
    const json& feet = need("foot_links");
    for (std::size_t side = 0; side < 2; ++side) {
      s.foot_links[side] = feet.at(side).get<int>();
      if (s.foot_links[side] < 0 || static_cast<std::size_t>(s.foot_links[side]) >= L)
        throw InputError(file + " [foot_links]", format("link %d outside the %zu links", s.foot_links[side], L));
    }
    s.sole_corners_W = unb64<float>(need("sole_corners_W"), file, "sole_corners_W", T * 24);
    if (!need("contact").is_null())
      for (std::size_t side = 0; side < 2; ++side)
        s.contact[side] = unb64<std::uint8_t>(j["contact"].at(side), file, format("contact[%zu]", side), T);
    s.com_W = unb64<float>(need("com_W"), file, "com_W", T * 3);
    if (!need("com_planned_W").is_null()) s.com_planned_W = unb64<float>(j["com_planned_W"], file, "com_planned_W", T * 3);
    if (!need("cop_planned_W").is_null()) s.cop_planned_W = unb64<float>(j["cop_planned_W"], file, "cop_planned_W", T * 2);
    if (!need("skeleton").is_null()) s.skeleton = points_from_json(j["skeleton"], file, "skeleton", s.num_frames);
    if (!need("landmarks").is_null()) s.landmarks = points_from_json(j["landmarks"], file, "landmarks", 1);
    for (const json& n : need("notes")) s.notes.push_back(n.get<std::string>());
    return s;
  } catch (const json::exception& e) {
    throw InputError(file, std::string("malformed viewer data: ") + e.what());
  }
}

}  // namespace rt
