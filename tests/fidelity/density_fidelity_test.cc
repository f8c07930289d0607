// Golden-metric test of the density stage on synthetic trees with known
// ground truth: per-view silhouette IoU of the projected density against the
// exact mattes, on input views and on held-out views (issue 2's targets).
#include <gtest/gtest.h>

#include <cstdio>

#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/density/density_reconstruction.h"
#include "ui/pipeline/report.h"

namespace sylva {
namespace {

struct Case {
  SyntheticCameraKind camera;
  int num_views;
  uint64_t seed;
};

FidelityReport ReconstructAndReport(const Case& c) {
  SyntheticDatasetOptions synth;
  synth.seed = c.seed;
  synth.camera = c.camera;
  synth.num_views = c.num_views;
  synth.num_held_out = 2;
  const SyntheticDataset data = MakeSyntheticDataset(synth);
  DensitySummary summary;
  const DensityGrid grid = ReconstructDensity(data.InputImageSet(), data.InputMattes(),
                                              DensityOptions(), nullptr, &summary);
  std::printf("%s\n", summary.BriefReport().c_str());
  return ComputeFidelity(grid, data.image_set, data.mattes, data.HeldOutFlags(), ReportOptions());
}

void ExpectFidelity(const Case& c, double min_input_iou, double min_held_out_iou) {
  const FidelityReport report = ReconstructAndReport(c);
  std::printf("seed %d, %d %s views:\n", static_cast<int>(c.seed), c.num_views,
              c.camera == SyntheticCameraKind::kPinhole ? "pinhole" : "orthographic");
  for (const ViewFidelity& view : report.views) {
    std::printf("  %-16s %s IoU %.3f precision %.3f recall %.3f (%dx%d)\n", view.name.c_str(),
                view.held_out ? "held-out" : "input   ", view.scores.iou, view.scores.precision,
                view.scores.recall, view.width, view.height);
    EXPECT_GE(view.scores.iou, view.held_out ? min_held_out_iou : min_input_iou) << view.name;
  }
  EXPECT_EQ(report.input.num_views, c.num_views);
  EXPECT_EQ(report.held_out.num_views, 2);
}

class PinholeFidelity : public ::testing::TestWithParam<uint64_t> {};
TEST_P(PinholeFidelity, EightViews) {
  ExpectFidelity({SyntheticCameraKind::kPinhole, 8, GetParam()}, 0.9, 0.75);
}
INSTANTIATE_TEST_SUITE_P(Seeds, PinholeFidelity, ::testing::Values(1, 2, 3));

class OrthographicFidelity : public ::testing::TestWithParam<uint64_t> {};
TEST_P(OrthographicFidelity, TwoViewsAtRightAngles) {
  ExpectFidelity({SyntheticCameraKind::kOrthographic, 2, GetParam()}, 0.9, 0.75);
}
INSTANTIATE_TEST_SUITE_P(Seeds, OrthographicFidelity, ::testing::Values(1, 2, 3));

}  // namespace
}  // namespace sylva
