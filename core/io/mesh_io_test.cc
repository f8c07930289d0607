#include "core/io/mesh_io.h"

#include <gtest/gtest.h>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_mesh_io_test";
  fs::create_directories(dir);
  return dir;
}

// Two materials, interleaved, with coordinates that need all float digits.
TriangleMesh TwoMaterialMesh() {
  TriangleMesh mesh;
  const int bark = mesh.AddMaterial({"bark", Eigen::Vector3f(0.35f, 0.25f, 0.17f), false});
  const int leaves = mesh.AddMaterial({"leaves", Eigen::Vector3f(0.2f, 0.45f, 0.12f), true});
  for (int i = 0; i < 6; ++i) {
    mesh.AddVertex(Eigen::Vector3f(0.1f * i + 1e-7f, 1.0f / 3.0f * i, -123.456789f + i));
  }
  mesh.AddTriangle(0, 1, 2, bark);
  mesh.AddTriangle(3, 4, 5, leaves);
  mesh.AddTriangle(0, 2, 4, bark);
  return mesh;
}

TEST(MeshIoTest, ObjRoundTripIsExact) {
  const TriangleMesh mesh = TwoMaterialMesh();
  const fs::path path = TestDir() / "round_trip.obj";
  WriteObj(path, mesh);
  EXPECT_TRUE(fs::exists(TestDir() / "round_trip.mtl"));
  const TriangleMesh back = ReadObj(path);
  ASSERT_EQ(back.NumVertices(), mesh.NumVertices());
  ASSERT_EQ(back.NumTriangles(), mesh.NumTriangles());
  EXPECT_EQ(back.vertices, mesh.vertices);
  EXPECT_EQ(back.triangles, mesh.triangles);
  EXPECT_EQ(back.triangle_materials, mesh.triangle_materials);
  ASSERT_EQ(back.materials.size(), 2u);
  for (int m = 0; m < 2; ++m) {
    EXPECT_EQ(back.materials[m].name, mesh.materials[m].name);
    EXPECT_EQ(back.materials[m].diffuse_color, mesh.materials[m].diffuse_color);
    EXPECT_EQ(back.materials[m].double_sided, mesh.materials[m].double_sided);
  }
}

TEST(MeshIoTest, ReadsPolygonsAndIndexForms) {
  const fs::path path = TestDir() / "forms.obj";
  AtomicWriteString(path,
                    "# a quad and a triangle\r\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                    "vn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3//1 4\nusemtl red\nf -3 -2 -1\n");
  const TriangleMesh mesh = ReadObj(path);
  EXPECT_EQ(mesh.NumVertices(), 4);
  ASSERT_EQ(mesh.NumTriangles(), 3);
  EXPECT_EQ(mesh.triangles[1], Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(mesh.triangles[2], Eigen::Vector3i(1, 2, 3));
  ASSERT_EQ(mesh.materials.size(), 2u);  // "default" and "red" (no .mtl)
  EXPECT_EQ(mesh.materials[mesh.triangle_materials[2]].name, "red");
}

TEST(MeshIoTest, ErrorsNameFileAndLine) {
  const fs::path path = TestDir() / "bad.obj";
  AtomicWriteString(path, "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n");
  try {
    ReadObj(path);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), path.string() + ":4");
  }
  AtomicWriteString(path, "v 0 zero 0\n");
  EXPECT_THROW(ReadObj(path), InputError);
  AtomicWriteString(path, "v 0 0 0\nf 1 1\n");
  EXPECT_THROW(ReadObj(path), InputError);
  AtomicWriteString(path, "mtllib missing.mtl\n");
  EXPECT_THROW(ReadObj(path), InputError);
  EXPECT_THROW(ReadObj(TestDir() / "does_not_exist.obj"), InputError);
}

}  // namespace
}  // namespace sylva
