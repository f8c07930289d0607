// Benchmark of the branch MRF (sketch/branch_mrf.h, Chen et al. 2008): the
// drawing of a synthetic tree's trunk and main branches (its depths
// dropped) -> depths by the MRF with the parameters of another tree of the
// same species, then self-similar propagation to 4,291 segments (the tree
// Chen 2008 reports 50 s for). Beside it, in the same process, the same
// inference with the interaction term summed over the whole 25^3 grid for
// every candidate, as the paper writes it (MrfOptions::crowding_reach = 0).
// Both print their median error of the drawn segments' parent-child angles
// against the truth; the program fails when the fast one is more than
// kMaxExtraErrorDeg worse than the reference, or exceeds the 0.5 s
// (full run only).
//
// usage: sylva_mrf_benchmark [--quick]   (--quick: 1,000 segments)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <queue>
#include <vector>

#include "datasets/synthetic/synthetic_tree.h"
#include "sketch/branch_mrf.h"

namespace sylva {
namespace {

constexpr double kGoalSeconds = 0.5;
constexpr double kMaxExtraErrorDeg = 3.0;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The synthetic tree's trunk and first-order branches.
SkeletonGraph MainBranches(const SkeletonGraph& skeleton) {
  SkeletonGraph main;
  const std::vector<std::vector<int>> children = skeleton.Children();
  std::vector<int> index(skeleton.nodes.size(), -1);
  std::queue<int> queue;
  const int root = skeleton.RootIdx();
  index[root] = main.AddNode(skeleton.nodes[root].position, 0.1, -1, 0);
  queue.push(root);
  while (!queue.empty()) {
    const int node = queue.front();
    queue.pop();
    for (int child : children[node]) {
      if (skeleton.nodes[child].order > 1) continue;
      index[child] = main.AddNode(skeleton.nodes[child].position, 0.1, index[node],
                                  skeleton.nodes[child].order);
      queue.push(child);
    }
  }
  return main;
}

double MedianAngleError(const SegmentTree& truth, const SegmentTree& result) {
  auto angle = [](const SegmentTree& t, int i) {
    const int p = t.parent[i];
    const Eigen::Vector3d vc = t.points[i] - t.points[p], vp = t.points[p] - t.points[t.parent[p]];
    return std::atan2(vc.cross(vp).norm(), vc.dot(vp)) / kDeg;
  };
  std::vector<double> errors;
  for (int i = 0; i < truth.Size(); ++i) {
    const int p = truth.parent[i];
    if (p >= 0 && truth.parent[p] >= 0)
      errors.push_back(std::abs(angle(truth, i) - angle(result, i)));
  }
  std::sort(errors.begin(), errors.end());
  return errors.empty() ? 0.0 : errors[errors.size() / 2];
}

struct Run {
  double infer_seconds = 0, propagate_seconds = 0, error_deg = 0;
  int segments = 0;
};

Run Time(const SegmentTree& truth, const SegmentTree& drawn, const TreeExemplar& exemplar,
         const MrfOptions& options) {
  Run run;
  auto start = std::chrono::steady_clock::now();
  MrfResult result =
      InferBranchDepths(drawn, Eigen::Vector3d::UnitY(), exemplar.parameters, options);
  run.infer_seconds = Seconds(start);
  run.error_deg = MedianAngleError(truth, result.tree);
  start = std::chrono::steady_clock::now();
  PropagateBranches(exemplar.tree, nullptr, options, &result);
  run.propagate_seconds = Seconds(start);
  run.segments = result.tree.Size() - 1;
  return run;
}

int Main(bool quick) {
  const SyntheticTreeOptions species;
  const SkeletonGraph skeleton = GenerateSyntheticSkeleton(species, 11);
  const SegmentTree truth =
      SegmentTreeOfSkeleton(MainBranches(skeleton), std::numeric_limits<double>::infinity());
  SegmentTree drawn = truth;
  for (Eigen::Vector3d& p : drawn.points) p.y() = 0.0;
  const TreeExemplar exemplar =
      MakeExemplar("same species", GenerateSyntheticSkeleton(species, 12));
  MrfOptions options;
  options.generations = 20;
  options.max_segments = quick ? 1001 : 4292;  // segments + the root point
  const Run fast = Time(truth, drawn, exemplar, options);
  MrfOptions reference_options = options;
  reference_options.crowding_reach = 0;
  const Run reference = Time(truth, drawn, exemplar, reference_options);
  std::printf(
      "branch MRF: %d drawn segments -> %d segments (the flat drawing's median angle "
      "error: %.1f deg)\n",
      drawn.Size() - 1, fast.segments, MedianAngleError(truth, drawn));
  std::printf(
      "  sylva:     infer %.3f s + propagate %.3f s = %.3f s (goal < %.1f s); median angle "
      "error %.1f deg\n",
      fast.infer_seconds, fast.propagate_seconds, fast.infer_seconds + fast.propagate_seconds,
      kGoalSeconds, fast.error_deg);
  std::printf(
      "  reference: infer %.3f s + propagate %.3f s = %.3f s (whole-grid interaction); "
      "median angle error %.1f deg\n",
      reference.infer_seconds, reference.propagate_seconds,
      reference.infer_seconds + reference.propagate_seconds, reference.error_deg);
  std::printf("  speed-up %.1fx\n", (reference.infer_seconds + reference.propagate_seconds) /
                                        (fast.infer_seconds + fast.propagate_seconds));
  bool ok = fast.error_deg <= reference.error_deg + kMaxExtraErrorDeg;
  if (!ok) std::printf("FAIL: the truncated interaction loses accuracy\n");
  if (!quick && fast.infer_seconds + fast.propagate_seconds > kGoalSeconds) {
    std::printf("FAIL: slower than the goal\n");
    ok = false;
  }
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  return sylva::Main(quick);
}
