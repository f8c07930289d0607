// Shared by the L-Py and MTG tests: a tiny hand-checkable skeleton, the
// skeletons of the bundled data, and a node-by-node comparison.
#ifndef SYLVA_CORE_IO_PLANT_EXPORT_TEST_UTIL_H_
#define SYLVA_CORE_IO_PLANT_EXPORT_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/qsm_io.h"
#include "core/io/skeleton_io.h"
#include "core/types/skeleton_graph.h"

namespace sylva {
namespace testing_util {

inline const std::filesystem::path kSourceDir = SYLVA_SOURCE_DIR;
inline const std::filesystem::path kTestData = kSourceDir / "core" / "io" / "testdata";

// A trunk of 3 segments up +Z, two branches of order 1 and one of order 2:
// the golden files' tree (testdata/tiny_tree.*). Radii in m.
inline SkeletonGraph TinyTree() {
  SkeletonGraph s;
  s.radius_source = "ground truth";
  const int root = s.AddNode({0, 0, 0}, 0.2, -1, 0);
  const int n1 = s.AddNode({0, 0, 1}, 0.15, root, 0);
  const int n2 = s.AddNode({0, 0, 2}, 0.1, n1, 0);
  s.AddNode({0, 0, 3}, 0.05, n2, 0);
  const int b1 = s.AddNode({1, 0, 1.5}, 0.05, n1, 1);
  s.AddNode({1.5, 0, 2.5}, 0.02, b1, 1);
  s.AddNode({0, -1, 2.5}, 0.04, n2, 1);
  s.AddNode({1, 0.5, 2}, 0.01, b1, 2);
  return s;
}

// Every skeleton of the bundled data: the demo's ground truth and each part
// of the four ITSMe QSMs (exact conversion, merge_fraction 0).
inline std::vector<std::pair<std::string, SkeletonGraph>> BundledSkeletons() {
  std::vector<std::pair<std::string, SkeletonGraph>> skeletons;
  skeletons.emplace_back("demo", ReadSkeletonJson(kSourceDir / "datasets" / "demo" /
                                                  "ground_truth" / "skeleton.json"));
  for (const char* name : {"tree_1_qsm.csv", "tree_2_qsm.csv", "buttressed_tree_1_qsm_1.csv",
                           "buttressed_tree_2_qsm_1.csv"}) {
    const QsmModel qsm = ReadQsmCsv(kSourceDir / "datasets" / "itsme-qsm" / name);
    int k = 0;
    for (const QsmSkeleton& part : SkeletonsFromQsm(qsm)) {
      skeletons.emplace_back(std::string(name) + " part " + std::to_string(k++), part.skeleton);
    }
  }
  return skeletons;
}

// Largest distance between corresponding positions and radii of `expected`
// and `actual`, whose node k is expected node order[k]; fails unless
// parents correspond too.
inline double MaxNodeError(const SkeletonGraph& expected, const SkeletonGraph& actual,
                           const std::vector<int>& order) {
  EXPECT_EQ(actual.NumNodes(), static_cast<int>(order.size()));
  EXPECT_EQ(expected.NumNodes(), static_cast<int>(order.size()));
  std::vector<int> actual_of(expected.nodes.size(), -1);
  for (size_t k = 0; k < order.size(); ++k) actual_of[order[k]] = static_cast<int>(k);
  double error = 0.0;
  const int n = std::min<int>(actual.NumNodes(), static_cast<int>(order.size()));
  for (int k = 0; k < n; ++k) {
    const SkeletonNode& e = expected.nodes[order[k]];
    const SkeletonNode& a = actual.nodes[k];
    const int parent = e.parent_idx < 0 ? -1 : actual_of[e.parent_idx];
    EXPECT_EQ(a.parent_idx, parent) << "node " << k;
    error = std::max({error, (a.position - e.position).norm(), std::abs(a.radius - e.radius)});
  }
  return error;
}

}  // namespace testing_util
}  // namespace sylva

#endif  // SYLVA_CORE_IO_PLANT_EXPORT_TEST_UTIL_H_
