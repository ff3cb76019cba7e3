// Mesh conversion (formats/mesh): ASCII STL and COLLADA (unit, up axis, node transforms) to
// triangles, mirrored scales keep outward normals, binary STL output MuJoCo reads, simplification.

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "formats/mesh/triangle_mesh.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

std::string mesh_file(const std::string& name) { return test::source_path("tests/data/urdf/mini_biped/meshes/" + name); }

// Signed volume by the divergence theorem: positive when the triangles wind counter-clockwise seen
// from outside (outward normals).
double signed_volume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& f : m.faces)
    v += m.vertices[static_cast<std::size_t>(f[0])].dot(
             m.vertices[static_cast<std::size_t>(f[1])].cross(m.vertices[static_cast<std::size_t>(f[2])])) / 6.0;
  return v;
}

TEST(Mesh, AsciiStlBox) {
  const TriangleMesh m = load_mesh(mesh_file("torso.stl"));
  EXPECT_EQ(m.faces.size(), 12u);
  EXPECT_EQ(m.vertices.size(), 8u);  // corners shared between triangles are merged
  EXPECT_TRUE(m.min_corner().isApprox(Vec3(-0.1, -0.15, 0.0), 1e-6));  // float32 in the file
  EXPECT_TRUE(m.max_corner().isApprox(Vec3(0.1, 0.15, 0.4), 1e-6));
  EXPECT_NEAR(signed_volume(m), 0.2 * 0.3 * 0.4, 1e-8);
}

TEST(Mesh, ColladaKeepsUrdfAxesAppliesUnitAndNodeTransform) {
  // The file is Z_UP in centimetres: a 5 x 5 x 30 cm box below its node, which is moved 1 cm down.
  const TriangleMesh m = load_mesh(mesh_file("arm.dae"));
  EXPECT_EQ(m.faces.size(), 12u);
  EXPECT_TRUE(m.min_corner().isApprox(Vec3(-0.025, -0.025, -0.31), 1e-6)) << m.min_corner().transpose();
  EXPECT_TRUE(m.max_corner().isApprox(Vec3(0.025, 0.025, -0.01), 1e-6)) << m.max_corner().transpose();
  EXPECT_NEAR(signed_volume(m), 0.05 * 0.05 * 0.3, 1e-8);
}

// arm.dae with another <up_axis> and <unit>, written to the scratch folder.
std::string collada_variant(const std::string& name, const std::string& up_axis, const std::string& unit) {
  std::string text = read_file(mesh_file("arm.dae"), 1 << 20);
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    if (at == std::string::npos) throw std::runtime_error("arm.dae lacks " + from);
    text.replace(at, from.size(), to);
  };
  replace("<up_axis>Z_UP</up_axis>", "<up_axis>" + up_axis + "</up_axis>");
  replace("<unit name=\"centimeter\" meter=\"0.01\"/>", unit);
  const std::string path = test::scratch_dir() + "/" + name;
  write_file_atomic(path, text);
  return path;
}

TEST(Mesh, ColladaUpAxisAndUnitAreHonoured) {
  // The same numbers in a Y_UP file: its +Y is up, so the file's z (-31..-1 cm) becomes -y and
  // its y becomes z.
  const TriangleMesh y_up = load_mesh(collada_variant("arm_y_up.dae", "Y_UP", "<unit name=\"centimeter\" meter=\"0.01\"/>"));
  EXPECT_TRUE(y_up.min_corner().isApprox(Vec3(-0.025, 0.01, -0.025), 1e-6)) << y_up.min_corner().transpose();
  EXPECT_TRUE(y_up.max_corner().isApprox(Vec3(0.025, 0.31, 0.025), 1e-6)) << y_up.max_corner().transpose();
  EXPECT_NEAR(signed_volume(y_up), 0.05 * 0.05 * 0.3, 1e-8);  // a rotation: normals stay outward

  // X_UP: the file's +X is up.
  const TriangleMesh x_up = load_mesh(collada_variant("arm_x_up.dae", "X_UP", "<unit name=\"centimeter\" meter=\"0.01\"/>"));
  EXPECT_NEAR(x_up.max_corner().z() - x_up.min_corner().z(), 0.05, 1e-6);  // file x extent
  EXPECT_NEAR(x_up.max_corner().x() - x_up.min_corner().x(), 0.05, 1e-6);
  EXPECT_NEAR(x_up.max_corner().y() - x_up.min_corner().y(), 0.30, 1e-6);  // file z extent
  EXPECT_NEAR(signed_volume(x_up), 0.05 * 0.05 * 0.3, 1e-8);

  // Millimetres, Z_UP: the numbers are read as mm.
  const TriangleMesh mm = load_mesh(collada_variant("arm_mm.dae", "Z_UP", "<unit name=\"millimeter\" meter=\"0.001\"/>"));
  EXPECT_TRUE(mm.min_corner().isApprox(Vec3(-0.0025, -0.0025, -0.031), 1e-6)) << mm.min_corner().transpose();
}

TEST(Mesh, ScaleIsBakedAndMirroringKeepsNormalsOutward) {
  MeshLoadOptions options;
  options.scale = Vec3(2, -1, 0.5);  // determinant < 0: a mirror
  const TriangleMesh m = load_mesh(mesh_file("torso.stl"), options);
  EXPECT_TRUE(m.min_corner().isApprox(Vec3(-0.2, -0.15, 0.0), 1e-6));
  EXPECT_TRUE(m.max_corner().isApprox(Vec3(0.2, 0.15, 0.2), 1e-6));
  EXPECT_NEAR(signed_volume(m), 0.4 * 0.3 * 0.2, 1e-8);  // positive: outward normals
  options.scale = Vec3(-1, -1, 1);  // a rotation, not a mirror: no flip needed
  EXPECT_NEAR(signed_volume(load_mesh(mesh_file("torso.stl"), options)), 0.2 * 0.3 * 0.4, 1e-8);
  options.scale = Vec3(1, 0, 1);
  EXPECT_THROW(load_mesh(mesh_file("torso.stl"), options), InputError);
}

TEST(Mesh, BinaryStlRoundTripAndMuJoCoReadsIt) {
  const TriangleMesh m = load_mesh(mesh_file("arm.dae"));
  const std::string stl = to_binary_stl(m);
  ASSERT_EQ(stl.size(), 84 + 50 * m.faces.size());
  const std::string path = test::scratch_dir() + "/arm.stl";
  write_file_atomic(path, stl);
  const TriangleMesh back = load_mesh(path);
  EXPECT_EQ(back.faces.size(), m.faces.size());
  EXPECT_TRUE(back.min_corner().isApprox(m.min_corner(), 1e-6));
  EXPECT_NEAR(signed_volume(back), signed_volume(m), 1e-8);

  // MuJoCo 2.2.2 compiles a model using the bytes from memory.
  mjVFS* vfs = new mjVFS;
  mj_defaultVFS(vfs);
  const std::string xml =
      "<mujoco><asset><mesh name='arm' file='arm.stl'/></asset><worldbody><body><freejoint/>"
      "<geom type='mesh' mesh='arm' mass='1'/></body></worldbody></mujoco>";
  for (const auto& [name, bytes] : {std::make_pair(std::string("m.xml"), xml), std::make_pair(std::string("arm.stl"), stl)}) {
    ASSERT_EQ(mj_makeEmptyFileVFS(vfs, name.c_str(), static_cast<int>(bytes.size())), 0);
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs, name.c_str())], bytes.data(), bytes.size());
  }
  char error[1000] = "";
  mjModel* model = mj_loadXML("m.xml", vfs, error, sizeof error);
  EXPECT_NE(model, nullptr) << error;
  if (model) {
    EXPECT_EQ(model->nmesh, 1);
    EXPECT_EQ(model->mesh_facenum[0], 12);
    mj_deleteModel(model);
  }
  mj_deleteVFS(vfs);
  delete vfs;
}

TEST(Mesh, SimplifyBoundsTrianglesAndKeepsTheShape) {
  // A finely tessellated sphere (about 20k triangles).
  TriangleMesh sphere;
  const int n = 100;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double th = M_PI * i / n, ph = M_PI * j / n;
      sphere.vertices.emplace_back(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  auto id = [&](int i, int j) { return i * 2 * n + (j % (2 * n)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      sphere.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      sphere.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  const TriangleMesh small = simplify_mesh(sphere, 2000);
  EXPECT_LE(small.faces.size(), 2000u);
  EXPECT_GT(small.faces.size(), 200u);
  for (const Vec3& v : small.vertices) EXPECT_NEAR(v.norm(), 1.0, 0.1);
  EXPECT_TRUE(small.min_corner().isApprox(Vec3(-1, -1, -1), 0.1));
  // Already small enough: unchanged.
  EXPECT_EQ(simplify_mesh(small, 2000).faces.size(), small.faces.size());
}

TEST(Mesh, UnreadableFilesAreInputErrors) {
  EXPECT_THROW(load_mesh(test::source_path("tests/data/urdf/mini_biped/robot.yaml")), InputError);
  EXPECT_THROW(load_mesh("/nonexistent/mesh.stl"), InputError);
  // A truncated binary STL is not mistaken for one (its size does not match the count) and
  // assimp then rejects it.
  const std::string stl = to_binary_stl(load_mesh(mesh_file("torso.stl")));
  const std::string path = test::scratch_dir() + "/truncated.stl";
  write_file_atomic(path, stl.substr(0, stl.size() - 30));
  try {
    load_mesh(path);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), path);
  }
}

// Issue 18 item 11: meshes have a size cap (a 2 GB sparse STL was read whole) and a FIFO is refused.
TEST(Mesh, OversizedAndNonRegularFilesAreRefusedUnread) {
  const std::string dir = test::scratch_dir();
  const std::string sparse = dir + "/huge.stl";
  {
    std::FILE* f = std::fopen(sparse.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(std::fseek(f, (3ll << 30) - 1, SEEK_SET), 0);  // 3 GB, sparse: nothing written
    std::fputc(0, f);
    std::fclose(f);
  }
  try {
    load_mesh(sparse);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("larger than the limit of 128 MB"), std::string::npos) << e.what();
  }
  MeshLoadOptions small;
  small.max_file_bytes = 100;
  EXPECT_THROW(load_mesh(mesh_file("torso.stl"), small), InputError);
  // An OBJ face of 2000 corners (assimp's triangulation is quadratic in them): refused at its line.
  std::string obj = "# a polygon\n";
  for (int i = 0; i < 2000; ++i) obj += "v " + std::to_string(std::cos(i * 0.00314)) + " " + std::to_string(std::sin(i * 0.00314)) + " 0\n";
  obj += "f";
  for (int i = 1; i <= 2000; ++i) obj += " " + std::to_string(i);
  write_file_atomic(dir + "/polygon.obj", obj + "\n");
  try {
    load_mesh(dir + "/polygon.obj");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/polygon.obj:2002: a face with 2000 corners (at most 1000): not a robot mesh");
  }
  const std::string fifo = dir + "/pipe.stl";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  EXPECT_THROW(load_mesh(fifo), InputError);
}

TEST(Mesh, RealColladaMeshesLoad) {
  RT_REQUIRE_SHARED(dae, "robots/jvrc1/jvrc_description/meshes/R_ANKLE_P_S.dae");
  const TriangleMesh m = load_mesh(dae);
  EXPECT_GT(m.faces.size(), 100u);
  // The JVRC foot in its mesh frame (Z_UP kept): 10 cm wide, bottom 10.8 cm below the ankle.
  EXPECT_NEAR(m.max_corner().x() - m.min_corner().x(), 0.10, 1e-3);
  EXPECT_NEAR(m.min_corner().z(), -0.1077, 1e-3);
  EXPECT_GT(signed_volume(m), 0);
}

}  // namespace
}  // namespace rt
