#include "formats/mesh/triangle_mesh.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <limits>
#include <unordered_map>
#include <utility>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

Vec3 TriangleMesh::min_corner() const {
  Vec3 m = Vec3::Constant(std::numeric_limits<double>::infinity());
  for (const Vec3& v : vertices) m = m.cwiseMin(v);
  return m;
}

Vec3 TriangleMesh::max_corner() const {
  Vec3 m = Vec3::Constant(-std::numeric_limits<double>::infinity());
  for (const Vec3& v : vertices) m = m.cwiseMax(v);
  return m;
}

namespace {

std::uint32_t get_u32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

float get_f32(const unsigned char* p) {
  const std::uint32_t u = get_u32(p);
  float f = 0;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

// Adds a vertex, merging exact duplicates (STL stores every corner of every triangle; assimp's
// JoinIdenticalVertices keeps them apart when their face normals differ, and is slow).
class VertexPool {
 public:
  explicit VertexPool(TriangleMesh& mesh) : mesh_(mesh) {}
  int add(const Vec3& v) {
    std::uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; ++k) {
      std::uint64_t bits = 0;
      const double x = v[k] == 0 ? 0.0 : v[k];  // +0 and -0 are the same point
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
    }
    auto range = index_.equal_range(h);
    for (auto it = range.first; it != range.second; ++it)
      if (mesh_.vertices[static_cast<std::size_t>(it->second)] == v) return it->second;
    const int id = static_cast<int>(mesh_.vertices.size());
    mesh_.vertices.push_back(v);
    index_.emplace(h, id);
    return id;
  }

 private:
  TriangleMesh& mesh_;
  std::unordered_multimap<std::uint64_t, int> index_;
};

void add_triangle(TriangleMesh& mesh, VertexPool& pool, const Vec3& a, const Vec3& b, const Vec3& c) {
  const std::array<int, 3> t{pool.add(a), pool.add(b), pool.add(c)};
  if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) mesh.faces.push_back(t);
}

// Binary STL, recognised by its exact size (84 + 50 n bytes); most robot packages ship these, and
// reading them directly is an order of magnitude faster than through assimp. False otherwise.
bool read_binary_stl(const std::string& path, const Vec3& scale, TriangleMesh& mesh) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size < 84 || size > (std::uintmax_t{1} << 32)) return false;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return false;
  unsigned char header[84];
  if (std::fread(header, 1, 84, f.get()) != 84) return false;
  const std::uint64_t count = get_u32(header + 80);
  if (count == 0 || 84 + 50 * count != size) return false;
  std::string bytes(static_cast<std::size_t>(50 * count), '\0');
  if (std::fread(bytes.data(), 1, bytes.size(), f.get()) != bytes.size()) return false;
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  VertexPool pool(mesh);
  for (std::uint64_t i = 0; i < count; ++i) {
    const unsigned char* t = p + 50 * i + 12;  // skip the stored normal
    Vec3 v[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = Vec3(get_f32(t + 12 * k), get_f32(t + 12 * k + 4), get_f32(t + 12 * k + 8)).cwiseProduct(scale);
      if (!v[k].allFinite()) throw InputError(path, "mesh has a non-finite vertex (triangle " + std::to_string(i) + ")");
    }
    add_triangle(mesh, pool, v[0], v[1], v[2]);
  }
  return true;
}

// assimp triangulates a polygon in time quadratic in its corners (an OBJ face of 10M vertices ran
// for minutes): OBJ faces are counted first. Mesh faces have 3-4 corners, CAD exports a few dozen.
void check_obj_polygons(const std::string& path) {
  constexpr std::size_t kMaxCorners = 1000;
  std::string lower = path;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower.size() < 4 || lower.compare(lower.size() - 4, 4, ".obj") != 0) return;
  const std::string text = read_file(path);
  std::size_t line = 1;
  for (std::size_t i = 0; i < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', i), text.size());
    if (end - i > 2 && text[i] == 'f' && (text[i + 1] == ' ' || text[i + 1] == '\t')) {
      std::size_t corners = 0;
      for (std::size_t k = i + 1; k < end; ++k)
        if (text[k] != ' ' && text[k] != '\t' && text[k] != '\r' && (text[k - 1] == ' ' || text[k - 1] == '\t')) ++corners;
      if (corners > kMaxCorners)
        throw InputError(path + ":" + std::to_string(line),
                         format("a face with %zu corners (at most %zu): not a robot mesh", corners, kMaxCorners));
    }
    i = end + 1;
  }
}

void read_with_assimp(const std::string& path, const Vec3& scale, TriangleMesh& mesh) {
  check_obj_polygons(path);
  Assimp::Importer importer;
  // COLLADA files declare their up axis (<up_axis>, Z_UP for most robot meshes, Y_UP for many
  // exported from modelling tools) and units (<unit meter>): assimp applies both, turning every
  // file to its own Y-up convention, so the Y-up result is turned back to Z up below. A Z_UP file
  // comes out as written, a Y_UP one with its +Y along +Z (as ROS tools display it).
  const bool collada = ends_with(to_lower(path), ".dae");
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (!scene) throw InputError(path, std::string("cannot read mesh: ") + importer.GetErrorString());
  VertexPool pool(mesh);
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;
      Vec3 v[3];
      for (int k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= m->mNumVertices) throw InputError(path, "mesh has a face with a bad vertex index");
        const aiVector3D& p = m->mVertices[face.mIndices[k]];
        const Vec3 p_file = collada ? Vec3(p.x, -p.z, p.y) : Vec3(p.x, p.y, p.z);  // Y up -> Z up
        v[k] = p_file.cwiseProduct(scale);
        if (!v[k].allFinite()) throw InputError(path, "mesh has a non-finite vertex");
      }
      add_triangle(mesh, pool, v[0], v[1], v[2]);
    }
  }
}

}  // namespace

TriangleMesh load_mesh(const std::string& path, const MeshLoadOptions& options) {
  if (!options.scale.allFinite() || (options.scale.array() == 0).any())
    throw InputError(path, "mesh scale must be finite and non-zero");
  require_regular_file(path);
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes > options.max_file_bytes)
    throw InputError(path, format("mesh file of %.0f bytes is larger than the limit of %.0f MB", static_cast<double>(bytes),
                                  static_cast<double>(options.max_file_bytes) / (1 << 20)));
  TriangleMesh mesh;
  if (!read_binary_stl(path, options.scale, mesh)) {
    mesh = TriangleMesh();
    read_with_assimp(path, options.scale, mesh);
  }
  if (mesh.faces.empty()) throw InputError(path, "mesh has no triangles");
  // A mirroring scale turns counter-clockwise triangles clockwise: swap two corners to keep
  // normals (and MuJoCo's volume and inertia of the mesh) positive.
  if (options.scale.prod() < 0)
    for (auto& f : mesh.faces) std::swap(f[1], f[2]);
  if (options.max_faces > 0 && static_cast<long>(mesh.faces.size()) > options.max_faces)
    mesh = simplify_mesh(mesh, options.max_faces);
  return mesh;
}

TriangleMesh simplify_mesh(const TriangleMesh& mesh, int max_faces) {
  if (max_faces <= 0 || static_cast<long>(mesh.faces.size()) <= max_faces || mesh.vertices.empty()) return mesh;
  const Vec3 lo = mesh.min_corner();
  const double extent = (mesh.max_corner() - lo).maxCoeff();
  if (!(extent > 0)) return mesh;
  // A closed surface clustered on a grid of cell h keeps about 4 (extent / h)^2 triangles: start
  // a little finer than that and coarsen until the bound holds.
  double cell = extent / std::sqrt(static_cast<double>(max_faces));
  for (;;) {
    std::unordered_map<std::uint64_t, int> cell_vertex;
    std::vector<Vec3> sum;
    std::vector<int> count;
    std::vector<int> remap(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      const Vec3 c = ((mesh.vertices[i] - lo) / cell).array().floor();
      const std::uint64_t key = (static_cast<std::uint64_t>(c.x()) << 42) ^ (static_cast<std::uint64_t>(c.y()) << 21) ^
                                static_cast<std::uint64_t>(c.z());
      auto [it, inserted] = cell_vertex.emplace(key, static_cast<int>(sum.size()));
      if (inserted) {
        sum.push_back(Vec3::Zero());
        count.push_back(0);
      }
      sum[static_cast<std::size_t>(it->second)] += mesh.vertices[i];
      ++count[static_cast<std::size_t>(it->second)];
      remap[i] = it->second;
    }
    TriangleMesh out;
    out.vertices.resize(sum.size());
    for (std::size_t i = 0; i < sum.size(); ++i) out.vertices[i] = sum[i] / count[i];
    for (const auto& f : mesh.faces) {
      std::array<int, 3> g{remap[static_cast<std::size_t>(f[0])], remap[static_cast<std::size_t>(f[1])],
                           remap[static_cast<std::size_t>(f[2])]};
      if (g[0] == g[1] || g[1] == g[2] || g[0] == g[2]) continue;
      // Rotate so the smallest index leads: the same triangle with the same winding dedupes.
      while (g[0] > g[1] || g[0] > g[2]) g = {g[1], g[2], g[0]};
      out.faces.push_back(g);
    }
    std::sort(out.faces.begin(), out.faces.end());
    out.faces.erase(std::unique(out.faces.begin(), out.faces.end()), out.faces.end());
    if (static_cast<long>(out.faces.size()) <= max_faces || out.vertices.size() <= 4) return out;
    cell *= 1.25;
  }
}

namespace {
void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_f32(std::string& s, double v) {
  const float f = static_cast<float>(v);
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof u);
  put_u32(s, u);
}
}  // namespace

std::string to_binary_stl(const TriangleMesh& mesh) {
  std::string out;
  out.reserve(84 + 50 * mesh.faces.size());
  std::string header = "binary STL written by retarget";
  header.resize(80, ' ');
  out += header;
  put_u32(out, static_cast<std::uint32_t>(mesh.faces.size()));
  for (const auto& f : mesh.faces) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(f[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(f[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(f[2])];
    Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    n = len > 0 ? Vec3(n / len) : Vec3::Zero();
    for (const Vec3* v : {static_cast<const Vec3*>(&n), &a, &b, &c})
      for (int k = 0; k < 3; ++k) put_f32(out, (*v)[k]);
    out.push_back(0);
    out.push_back(0);
  }
  return out;
}

}  // namespace rt
