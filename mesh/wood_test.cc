#include "mesh/wood.h"

#include <gtest/gtest.h>

#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/mesh_checks.h"

namespace sylva {
namespace {

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Without twigs: the watertight bark keeps mesh/bark_mesh.h's promise (one
// solid plus the laterals counted as unattached); the tubes are one closed
// tube per branch axis. The skeleton comes back as it went in.
TEST(WoodTest, WatertightBarkOrTubes) {
  const SkeletonGraph skeleton = GenerateSyntheticSkeleton(SyntheticTreeOptions(), 1);
  WoodOptions options;
  const Wood watertight = MeshWood(skeleton, DensityGrid(), options);
  EXPECT_EQ(watertight.skeleton.NumNodes(), skeleton.NumNodes());
  EXPECT_EQ(watertight.twigs.NumTriangles(), 0);
  const MeshCheck bark = CheckMesh(watertight.bark, "", false);
  EXPECT_TRUE(Contains(watertight.brief, "Watertight bark:")) << watertight.brief;
  EXPECT_EQ(watertight.bark_summary.failed_joints, 0) << watertight.brief;
  EXPECT_EQ(bark.boundary_edges + bark.nonmanifold_edges + bark.misoriented_edges, 0);
  EXPECT_EQ(bark.components, 1 + watertight.bark_summary.unattached) << watertight.brief;
  EXPECT_EQ(watertight.bark_summary.triangles, watertight.bark.NumTriangles());

  options.watertight_bark = false;
  const Wood tubes = MeshWood(skeleton, DensityGrid(), options);
  EXPECT_TRUE(Contains(tubes.brief, "Branch mesh:")) << tubes.brief;
  EXPECT_EQ(tubes.bark_summary.triangles, 0);  // no watertight bark
  EXPECT_EQ(CheckMesh(tubes.bark, "", false).components,
            static_cast<int>(skeleton.BranchAxes().size()));
}

// With twigs: the skeleton comes back with them (the leaves grow on it);
// separate twigs are tubes of their own material beside a bark without
// them, joined ones are part of the bark.
TEST(WoodTest, TwigsJoinedOrSeparate) {
  const SkeletonGraph skeleton = GenerateSyntheticSkeleton(SyntheticTreeOptions(), 1);
  WoodOptions options;
  options.twigs = true;
  options.twig.twigs_per_length = 0.15;
  options.twig_mesh.mode = "separate";
  const Wood separate = MeshWood(skeleton, DensityGrid(), options);
  EXPECT_GT(separate.skeleton.NumNodes(), skeleton.NumNodes());
  EXPECT_GT(separate.twigs.NumTriangles(), 0);
  ASSERT_EQ(separate.twigs.materials.size(), 1u);
  EXPECT_EQ(separate.twigs.materials[0].name, options.twig_mesh.material.name);
  EXPECT_TRUE(Contains(separate.brief, "Twigs meshed apart (Twigs.mesh=separate)"))
      << separate.brief;
  options.twig_mesh.mode = "joined";
  const Wood joined = MeshWood(skeleton, DensityGrid(), options);
  EXPECT_EQ(joined.skeleton.NumNodes(), separate.skeleton.NumNodes());
  EXPECT_EQ(joined.twigs.NumTriangles(), 0);
  EXPECT_GT(joined.bark.NumTriangles(), separate.bark.NumTriangles());
  EXPECT_EQ(CheckMesh(joined.bark, "", false).components, 1 + joined.bark_summary.unattached)
      << joined.brief;
}

}  // namespace
}  // namespace sylva
