#include "formats/mesh/triangle_mesh.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <unordered_map>
#include <utility>

#include "retarget/core/error.hpp"
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

TriangleMesh load_mesh(const std::string& path, const MeshLoadOptions& options) {
  if (!options.scale.allFinite() || (options.scale.array() == 0).any())
    throw InputError(path, "mesh scale must be finite and non-zero");
  Assimp::Importer importer;
  // Keep URDF/ROS coordinates: by default assimp rotates Z_UP COLLADA files to Y up.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_JoinIdenticalVertices |
                                  aiProcess_SortByPType);
  if (!scene) throw InputError(path, std::string("cannot read mesh: ") + importer.GetErrorString());

  TriangleMesh mesh;
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* m = scene->mMeshes[mi];
    if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const int base = static_cast<int>(mesh.vertices.size());
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      const aiVector3D& p = m->mVertices[v];
      const Vec3 x = Vec3(p.x, p.y, p.z).cwiseProduct(options.scale);
      if (!x.allFinite()) throw InputError(path, "mesh has a non-finite vertex");
      mesh.vertices.push_back(x);
    }
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;
      std::array<int, 3> t{};
      for (int k = 0; k < 3; ++k) t[static_cast<std::size_t>(k)] = base + static_cast<int>(face.mIndices[k]);
      mesh.faces.push_back(t);
    }
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
  double cell = extent / 2048.0;
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
    std::set<std::array<int, 3>> seen;
    for (const auto& f : mesh.faces) {
      std::array<int, 3> g{remap[static_cast<std::size_t>(f[0])], remap[static_cast<std::size_t>(f[1])],
                           remap[static_cast<std::size_t>(f[2])]};
      if (g[0] == g[1] || g[1] == g[2] || g[0] == g[2]) continue;
      // Rotate so the smallest index leads: the same triangle with the same winding dedupes.
      while (g[0] > g[1] || g[0] > g[2]) g = {g[1], g[2], g[0]};
      if (seen.insert(g).second) out.faces.push_back(g);
    }
    if (static_cast<long>(out.faces.size()) <= max_faces || out.vertices.size() <= 4) return out;
    cell *= 1.5;
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
