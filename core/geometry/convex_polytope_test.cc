#include "core/geometry/convex_polytope.h"

#include <gtest/gtest.h>

#include "core/util/random.h"

namespace sylva {
namespace {

TEST(ConvexPolytopeTest, ClipCubeToOctahedronLikeShape) {
  ConvexPolytope polytope(Box3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)));
  // x + y + z <= 1 cuts off one corner.
  polytope.Clip(Eigen::Vector3d(-1, -1, -1), 1.0);
  const Box3d box = polytope.Bounds();
  EXPECT_TRUE(box.min().isApprox(Eigen::Vector3d(-1, -1, -1)));
  EXPECT_TRUE(box.max().isApprox(Eigen::Vector3d(1, 1, 1)));  // (1,1,-1) survives
  for (const auto& v : polytope.Vertices()) EXPECT_LE(v.sum(), 1 + 1e-9);
  // x >= 0.5 then x <= 0.25: empty.
  polytope.Clip(Eigen::Vector3d(1, 0, 0), -0.5);
  EXPECT_FALSE(polytope.IsEmpty());
  EXPECT_NEAR(polytope.Bounds().min().x(), 0.5, 1e-12);
  polytope.Clip(Eigen::Vector3d(-1, 0, 0), 0.25);
  EXPECT_TRUE(polytope.IsEmpty());
}

TEST(ConvexPolytopeTest, ManyRandomTangentPlanesApproachTheBall) {
  ConvexPolytope polytope(Box3d(Eigen::Vector3d::Constant(-5), Eigen::Vector3d::Constant(5)));
  RandomEngine rng(5);
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d n =
        Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
    polytope.Clip(-n, 1.0);  // keep n . p <= 1
  }
  const Box3d box = polytope.Bounds();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(box.max()[a], 1.0, 0.1);
    EXPECT_NEAR(box.min()[a], -1.0, 0.1);
  }
}

}  // namespace
}  // namespace sylva
