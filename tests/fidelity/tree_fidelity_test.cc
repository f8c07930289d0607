// Golden-metric test of the whole tree (issue 3's targets) on synthetic trees
// with known ground truth: density -> particle-flow skeleton -> mesh, then
//   - per-view IoU of the mesh's rendered silhouette against the exact mattes,
//     on input views and on held-out views;
//   - Chamfer distance between the reconstructed and the true skeleton, both
//     sampled along their edges, relative to the tree height;
//   - distance of the skeleton's root from the true base (the origin).
#include <gtest/gtest.h>

#include <cstdio>

#include "datasets/eval/point_metrics.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "mesh/tree_metrics.h"
#include "reconstruct/density/density_reconstruction.h"
#include "ui/pipeline/report.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {
namespace {

struct TreeResult {
  FidelityReport report;
  TreeMetricsReport metrics;  // as the mesh stage computes them
  double true_crown_base = 0;
  double true_crown_volume = 0;  // the union of the leaf clusters
  double true_dbh = 0;
  double chamfer_over_height = 0;
  double root_error_over_height = 0;
  double height = 0;
};

TreeResult ReconstructTree(uint64_t seed) {
  SyntheticDatasetOptions synth;
  synth.seed = seed;
  synth.num_views = 8;
  synth.num_held_out = 2;
  const SyntheticDataset data = MakeSyntheticDataset(synth);
  const ImageSet inputs = data.InputImageSet();
  const std::vector<FloatImage> input_mattes = data.InputMattes();
  const PipelineOptions options;
  const DensityGrid density =
      ReconstructDensity(inputs, input_mattes, options.density, nullptr, nullptr);
  const BuiltSkeleton built = BuildSkeleton(density, inputs, input_mattes, {}, options, nullptr);
  std::string mesh_brief;
  const TriangleMesh mesh =
      BuildTreeMesh(built.skeleton, density, inputs, input_mattes, options, &mesh_brief);
  std::printf("seed %d: %s\n  %s\n", static_cast<int>(seed), built.brief.c_str(),
              mesh_brief.c_str());

  TreeResult result;
  ReportOptions report_options;
  report_options.write_images = false;
  result.report =
      ComputeFidelity(density, data.image_set, data.mattes, data.HeldOutFlags(), report_options);
  AddMeshFidelity(mesh, data.image_set, report_options, &result.report);
  result.metrics = ComputeTreeMetrics(built.skeleton, &density, "m", TreeMetricsOptions(),
                                      SkeletonSources::Reconstruction());
  const TreeMetricsReport truth = ComputeTreeMetrics(data.tree.skeleton, nullptr, "m");
  result.true_crown_base = truth.crown_base_height;
  result.true_dbh = truth.dbh.value_or(0);
  result.true_crown_volume = LeafClustersUnionVolume(data.tree.clusters, 1000, seed);
  result.height = data.tree.mesh.Bounds().max().z();  // the true base is at z = 0
  const double spacing = 0.005 * result.height;
  const PointSetDistances distances = ComparePointSets(built.skeleton.SamplePoints(spacing),
                                                       data.tree.skeleton.SamplePoints(spacing));
  result.chamfer_over_height = distances.chamfer / result.height;
  result.root_error_over_height =
      built.skeleton.nodes[built.skeleton.RootIdx()].position.norm() / result.height;
  return result;
}

class TreeFidelity : public ::testing::TestWithParam<uint64_t> {};

TEST_P(TreeFidelity, MeshSilhouettesSkeletonAndRoot) {
  const TreeResult result = ReconstructTree(GetParam());
  const TreeMetricsReport& tree = result.metrics;
  std::printf(
      "  true height %.3f; reconstructed height %.3f, crown base %.3f (true %.3f), crown "
      "width %.3f, crown volume %.2f (hull %.2f, leaf clusters %.2f), DBH %.4f (true %.4f), "
      "branch length %.1f\n"
      "  skeleton Chamfer %.2f %% of height, root %.2f %% of height from the true base\n",
      result.height, tree.height, tree.crown_base_height, result.true_crown_base, tree.crown_width,
      tree.crown_volume_density.value_or(0), tree.crown_volume_hull, result.true_crown_volume,
      tree.dbh.value_or(0), result.true_dbh, tree.total_length, 100 * result.chamfer_over_height,
      100 * result.root_error_over_height);
  for (const ViewFidelity& view : result.report.views) {
    std::printf("  %-16s %s mesh IoU %.3f precision %.3f recall %.3f | density IoU %.3f\n",
                view.name.c_str(), view.held_out ? "held-out" : "input   ", view.mesh_scores.iou,
                view.mesh_scores.precision, view.mesh_scores.recall, view.scores.iou);
    ASSERT_TRUE(view.has_mesh);
    EXPECT_GE(view.mesh_scores.iou, view.held_out ? 0.7 : 0.8) << view.name;
  }
  EXPECT_LE(result.chamfer_over_height, 0.05);
  EXPECT_LE(result.root_error_over_height, 0.02);
  // Metrics against the generator's (mesh/tree_metrics.h; measured: height
  // within 0.6 %, crown base 0.34-0.35 m off, density crown volume 1.13-1.24
  // x the leaf clusters' union, which it holds with the gaps between them).
  EXPECT_NEAR(tree.height, result.height, 0.02 * result.height);
  EXPECT_NEAR(tree.crown_base_height, result.true_crown_base, 0.1 * result.height);
  ASSERT_TRUE(tree.crown_volume_density.has_value());
  EXPECT_NEAR(*tree.crown_volume_density, result.true_crown_volume,
              0.35 * result.true_crown_volume);
}

INSTANTIATE_TEST_SUITE_P(Seeds, TreeFidelity, ::testing::Values(1, 2, 3));

}  // namespace
}  // namespace sylva
