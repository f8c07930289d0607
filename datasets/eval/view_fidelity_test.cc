#include "datasets/eval/view_fidelity.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

ViewFidelity View(bool held_out, double iou, double precision, double recall) {
  ViewFidelity view;
  view.held_out = held_out;
  view.scores.iou = iou;
  view.scores.precision = precision;
  view.scores.recall = recall;
  return view;
}

TEST(ViewFidelityTest, GroupsAverageTheirOwnViewsAndAreAbsentWhenEmpty) {
  std::vector<ViewFidelity> views = {View(false, 0.8, 0.9, 0.7), View(true, 0.5, 0.6, 0.4),
                                     View(false, 0.6, 0.7, 0.9)};
  views[2].has_mesh = true;
  views[2].mesh_scores.iou = 0.3;

  const FidelityGroup input = SummariseViews(views, /*held_out=*/false, /*mesh=*/false);
  EXPECT_EQ(input.num_views, 2);
  EXPECT_NEAR(*input.mean_iou, 0.7, 1e-12);
  EXPECT_EQ(*input.min_iou, 0.6);
  EXPECT_NEAR(*input.mean_precision, 0.8, 1e-12);
  EXPECT_NEAR(*input.mean_recall, 0.8, 1e-12);

  const FidelityGroup held_out = SummariseViews(views, true, false);
  EXPECT_EQ(held_out.num_views, 1);
  EXPECT_EQ(*held_out.mean_iou, 0.5);

  // The mesh groups count only the views the mesh was compared in.
  const FidelityGroup mesh_input = SummariseViews(views, false, true);
  EXPECT_EQ(mesh_input.num_views, 1);
  EXPECT_EQ(*mesh_input.mean_iou, 0.3);
  const FidelityGroup mesh_held_out = SummariseViews(views, true, true);
  EXPECT_EQ(mesh_held_out.num_views, 0);
  EXPECT_FALSE(mesh_held_out.mean_iou || mesh_held_out.min_iou || mesh_held_out.mean_precision ||
               mesh_held_out.mean_recall);
}

TEST(ViewFidelityTest, PriorViewsAreInNeitherGroup) {
  std::vector<ViewFidelity> views = {View(false, 0.8, 0.9, 0.7), View(false, 0.2, 0.3, 0.1),
                                     View(true, 0.5, 0.6, 0.4)};
  views[1].prior = true;
  const FidelityGroup input = SummariseViews(views, false, false);
  EXPECT_EQ(input.num_views, 1);
  EXPECT_EQ(*input.mean_iou, 0.8);
  EXPECT_EQ(*input.min_iou, 0.8);
  EXPECT_EQ(SummariseViews(views, true, false).num_views, 1);
}

}  // namespace
}  // namespace sylva
