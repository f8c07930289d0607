#include "ui/pipeline/tree_building.h"

#include <gtest/gtest.h>

#include <sstream>

#include "core/util/check.h"

namespace sylva {
namespace {

// A closed tetrahedron, outward triangles.
TriangleMesh Tetrahedron() {
  TriangleMesh mesh;
  const int bark = mesh.AddMaterial(Material{"bark"});
  mesh.AddVertex(Eigen::Vector3f(0, 0, 0));
  mesh.AddVertex(Eigen::Vector3f(1, 0, 0));
  mesh.AddVertex(Eigen::Vector3f(0, 1, 0));
  mesh.AddVertex(Eigen::Vector3f(0, 0, 1));
  mesh.AddTriangle(0, 2, 1, bark);
  mesh.AddTriangle(0, 1, 3, bark);
  mesh.AddTriangle(0, 3, 2, bark);
  mesh.AddTriangle(1, 2, 3, bark);
  return mesh;
}

TEST(TreeBuildingTest, SubdivideBarkFollowsTheOption) {
  TreeGeometryOptions options;
  TriangleMesh bark = Tetrahedron();
  std::ostringstream brief;
  SubdivideBark(options, &bark, &brief);  // 0 = off
  EXPECT_EQ(bark.NumTriangles(), 4);
  EXPECT_TRUE(brief.str().empty());
  options.bark_subdivision = 2;
  SubdivideBark(options, &bark, &brief);
  EXPECT_EQ(bark.NumTriangles(), 64);
  EXPECT_NE(brief.str().find("Loop subdivision: 2 level(s), 4 -> 64 triangles"), std::string::npos)
      << brief.str();
}

// A bark that is not closed (as after a failed joint) is refused naming the
// option that asked for subdivision.
TEST(TreeBuildingTest, SubdivideBarkRefusesAnOpenBark) {
  TreeGeometryOptions options;
  options.bark_subdivision = 1;
  TriangleMesh bark = Tetrahedron();
  bark.triangles.pop_back();
  bark.triangle_materials.pop_back();
  std::ostringstream brief;
  try {
    SubdivideBark(options, &bark, &brief);
    FAIL() << "an open bark was subdivided";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "BranchMesh.subdivision");
    EXPECT_NE(error.message().find("3 boundary half-edges"), std::string::npos) << error.message();
  }
}

}  // namespace
}  // namespace sylva
