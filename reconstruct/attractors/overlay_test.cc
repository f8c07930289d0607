#include "reconstruct/attractors/overlay.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/check.h"

namespace sylva {
namespace {

TEST(DrawAttractorOverlayTest, DrawsOnTheGraphAndNowhereElse) {
  const FloatImage photo(120, 100, 3, 0.5f);
  AttractorGraph2D graph;
  graph.width = 120;
  graph.height = 100;
  graph.root = graph.AddNode({20.5, 50.5}, -1);
  graph.AddNode({90.5, 50.5}, graph.root);
  const FloatImage overlay = DrawAttractorOverlay(photo, graph);
  ASSERT_EQ(overlay.width(), 120);
  ASSERT_EQ(overlay.height(), 100);
  ASSERT_EQ(overlay.channels(), 3);
  // On the edge (pixel 60, 50): magenta, far from grey.
  EXPECT_GT(overlay.at(60, 50, 0), 0.8f);
  EXPECT_LT(overlay.at(60, 50, 1), 0.4f);
  // At the root: red.
  EXPECT_GT(overlay.at(20, 50, 0), 0.8f);
  EXPECT_LT(overlay.at(20, 50, 2), 0.3f);
  // Away from the drawing: exactly the photo.
  int changed_far = 0;
  for (int y = 0; y < 100; ++y) {
    for (int x = 0; x < 120; ++x) {
      if (std::abs(y - 50) <= 8) continue;
      for (int c = 0; c < 3; ++c) changed_far += overlay.at(x, y, c) != 0.5f;
    }
  }
  EXPECT_EQ(changed_far, 0);
}

TEST(DrawAttractorOverlayTest, RgbaIsCompositedOverWhiteAndSizesMustMatch) {
  FloatImage photo(40, 40, 4, 0.0f);  // transparent black
  AttractorGraph2D graph;
  graph.width = graph.height = 40;
  graph.root = graph.AddNode({20, 20}, -1);
  const FloatImage overlay = DrawAttractorOverlay(photo, graph);
  EXPECT_EQ(overlay.at(2, 2, 1), 1.0f);
  graph.width = 41;
  EXPECT_THROW(DrawAttractorOverlay(photo, graph), InputError);
}

}  // namespace
}  // namespace sylva
