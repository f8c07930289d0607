// Golden-metric test of the skeleton's wood (issue 12, item 5) on leafless
// synthetic trees with known skeletons: density -> particle flow -> matte
// pruning -> consolidation, steered by livewire attractor graphs as the
// pipeline's attract stage traces them, then CompareSkeletons against the generator's
// skeleton. Without the consolidation the skeleton carried 1.8-1.9 x the
// true branch length (every particle's trace a twig); the by-hand probe
// tests/bench/skeleton_probe.cc prints the same figures on more trees, leafy
// ones too. The second test does the same on laser-scanned trees (ITSMe's
// TreeQSM tables, bundled in datasets/itsme-qsm) rendered to photos.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "datasets/eval/skeleton_metrics.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/density/density_reconstruction.h"
#include "tests/fidelity/qsm_photos.h"
#include "tests/fidelity/synthetic_livewire.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {
namespace {

// The skeleton the stages build from `data`'s input views (density,
// livewire graphs, particle flow, pruning, consolidation) against its truth.
SkeletonComparison ReconstructAndCompare(const SyntheticDataset& data,
                                         const PipelineOptions& options, BuiltSkeleton* built) {
  const ImageSet inputs = data.InputImageSet();
  const std::vector<FloatImage> mattes = data.InputMattes();
  const DensityGrid density = ReconstructDensity(inputs, mattes, options.density, nullptr, nullptr);
  *built = BuildSkeleton(density, inputs, mattes,
                         SyntheticLivewireGraphs(data, inputs, mattes, density, options), options,
                         nullptr);
  const SkeletonGraph& truth = data.tree.skeleton;
  return CompareSkeletons(built->skeleton, truth, truth.Height());
}

class SkeletonFidelity : public ::testing::TestWithParam<uint64_t> {};

TEST_P(SkeletonFidelity, LeaflessTreeLengthAndPrecision) {
  SyntheticDatasetOptions synth;
  synth.seed = GetParam();
  synth.num_views = 8;
  synth.num_held_out = 0;
  synth.tree.leaves_per_cluster = 0;
  BuiltSkeleton built;
  const SkeletonComparison c =
      ReconstructAndCompare(MakeSyntheticDataset(synth), PipelineOptions(), &built);
  std::printf("seed %d: %s\n  %s\n", static_cast<int>(GetParam()), c.BriefReport().c_str(),
              built.brief.c_str());
  // Measured (seeds 1, 2): length 1.07 / 1.10 x, precision 0.822 / 0.825,
  // Chamfer 2.08 / 1.78 % of the height (without the consolidation:
  // 1.90 / 1.89 x, 0.838 / 0.849, 1.89 / 1.63 %).
  EXPECT_NEAR(c.length_ratio, 1.0, 0.3);
  EXPECT_GE(c.precision, 0.8);
  EXPECT_LE(c.chamfer_fraction, 0.022);
  // No thin branch leaves the trunk's foot.
  const std::vector<std::vector<int>> children = built.skeleton.Children();
  EXPECT_EQ(children[built.skeleton.RootIdx()].size(), 1u);
}

INSTANTIATE_TEST_SUITE_P(Seeds, SkeletonFidelity, ::testing::Values(1, 2));

class ScannedTreeFidelity : public ::testing::TestWithParam<const char*> {};

// Slender real trees (17-24 m, trunk radius 6-9 cm, 8 views at 512 px: the
// branches are a pixel or less wide) where strands that did not merge ran
// beside the trunk: 1.55 / 1.62 x the true length before the trunk's own
// top could be trimmed as redundant (skeleton_consolidation.h).
TEST_P(ScannedTreeFidelity, LengthAndPrecision) {
  SyntheticDatasetOptions views;
  views.num_views = 8;
  views.num_held_out = 0;
  const PipelineOptions options;
  BuiltSkeleton built;
  const SkeletonComparison c = ReconstructAndCompare(
      QsmPhotoDataset(std::string(SYLVA_SOURCE_DIR) + "/datasets/itsme-qsm/" + GetParam(), views,
                      options),
      options, &built);
  std::printf("%s: %s\n", GetParam(), c.BriefReport().c_str());
  // Measured: tree_1 length 1.02 x, precision 1.000; tree_2 1.23 x, 0.966.
  EXPECT_NEAR(c.length_ratio, 1.0, 0.3);
  EXPECT_GE(c.precision, 0.9);
  EXPECT_LE(c.chamfer_fraction, 0.015);
}

INSTANTIATE_TEST_SUITE_P(Itsme, ScannedTreeFidelity,
                         ::testing::Values("tree_1_qsm.csv", "tree_2_qsm.csv"));

}  // namespace
}  // namespace sylva
