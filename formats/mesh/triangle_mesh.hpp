#pragma once
/// Triangle meshes for collision geometry: loading any format assimp reads (STL binary/ASCII,
/// COLLADA, OBJ, ...) into plain vertex/face arrays in the mesh file's frame (URDF convention),
/// and writing them in a form MuJoCo 2.2.2 reads (binary STL; it cannot read DAE or ASCII STL).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "retarget/core/types.hpp"

namespace rt {

struct TriangleMesh {
  std::vector<Vec3> vertices;             ///< [m] in the mesh frame
  std::vector<std::array<int, 3>> faces;  ///< counter-clockwise seen from outside

  /// Axis-aligned bounds of the vertices; (+inf, -inf) when empty.
  Vec3 min_corner() const;
  Vec3 max_corner() const;
};

struct MeshLoadOptions {
  /// Per-axis scale baked into the vertices (URDF <mesh scale>). A mirrored scale (negative
  /// determinant) flips every triangle's winding so that normals stay outward.
  Vec3 scale = Vec3::Ones();
  /// More faces than this are reduced by vertex clustering (simplify_mesh). MuJoCo 2.2.2 rejects
  /// STL files with more than 200000 faces; collision only uses the convex hull, so clustering on
  /// a fine grid changes the contact geometry by at most the cell size.
  int max_faces = 200000;
  /// [bytes] Larger files are refused before they are read (a 2 GB sparse STL, a 10M-vertex OBJ
  /// polygon): robot collision meshes are at most a few MB.
  std::uint64_t max_file_bytes = 128ull << 20;
};

/// Loads a mesh file with assimp: triangulated, node transforms applied (PreTransformVertices),
/// COLLADA <unit> and <up_axis> applied (a Y_UP file's +Y becomes +Z; Z_UP files are kept as
/// written), then the URDF <mesh scale>. Points and lines
/// are dropped. Throws InputError("<path>: ...") when the file cannot be read or has no triangles.
TriangleMesh load_mesh(const std::string& path, const MeshLoadOptions& options = {});

/// Reduces the mesh to at most `max_faces` triangles by merging vertices on a uniform grid whose
/// cell grows until the bound holds; degenerate and duplicate triangles are removed. Returns the
/// mesh unchanged when it is already small enough.
TriangleMesh simplify_mesh(const TriangleMesh& mesh, int max_faces);

/// Binary STL bytes (80-byte header, little-endian float32), the form MuJoCo 2.2.2 reads.
std::string to_binary_stl(const TriangleMesh& mesh);

}  // namespace rt
