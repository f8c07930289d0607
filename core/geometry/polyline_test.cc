#include "core/geometry/polyline.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

namespace sylva {
namespace {

using Eigen::Vector3d;

TEST(PolylineTest, SegmentSegmentDistanceOfCrossingParallelAndDegenerateSegments) {
  Vector3d cp, cq;
  // Skew segments 1 apart, closest at their middles.
  EXPECT_DOUBLE_EQ(
      SegmentSegmentDistance2<Vector3d>({-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}, &cp, &cq),
      1.0);
  EXPECT_TRUE(cp.isApprox(Vector3d(0, 0, 0)));
  EXPECT_TRUE(cq.isApprox(Vector3d(0, 0, 1)));
  // Closest at an end of one segment: the other's end is past it.
  EXPECT_DOUBLE_EQ(
      SegmentSegmentDistance2<Vector3d>({0, 0, 0}, {1, 0, 0}, {2, -1, 0}, {2, 1, 0}, &cp, &cq),
      1.0);
  EXPECT_TRUE(cp.isApprox(Vector3d(1, 0, 0)));
  EXPECT_TRUE(cq.isApprox(Vector3d(2, 0, 0)));
  // Parallel, overlapping: the distance between the lines.
  EXPECT_DOUBLE_EQ(SegmentSegmentDistance2<Vector3d>({0, 0, 0}, {2, 0, 0}, {1, 3, 0}, {3, 3, 0}),
                   9.0);
  // A point and a segment; two points.
  EXPECT_DOUBLE_EQ(SegmentSegmentDistance2<Vector3d>({1, 2, 0}, {1, 2, 0}, {0, 0, 0}, {2, 0, 0}),
                   4.0);
  EXPECT_DOUBLE_EQ(SegmentSegmentDistance2<Vector3d>({0, 0, 0}, {0, 0, 0}, {0, 0, 3}, {0, 0, 3}),
                   9.0);
}

}  // namespace
}  // namespace sylva
