#include "datasets/eval/graph_metrics.h"

#include "core/util/check.h"

namespace sylva {
namespace {

std::vector<Eigen::Vector3d> Lift(const std::vector<Eigen::Vector2d>& points) {
  std::vector<Eigen::Vector3d> lifted;
  lifted.reserve(points.size());
  for (const Eigen::Vector2d& p : points) lifted.emplace_back(p.x(), p.y(), 0.0);
  return lifted;
}

}  // namespace

AttractorGraph2D ProjectSkeleton(const SkeletonGraph& skeleton, const ImageSet& image_set,
                                 int view_idx, int max_order) {
  SYLVA_CHECK(view_idx >= 0 && view_idx < image_set.NumViews()) << "view " << view_idx;
  const Camera& camera = image_set.CameraOf(view_idx);
  AttractorGraph2D graph;
  graph.width = camera.width();
  graph.height = camera.height();
  graph.source = "ground truth";
  // Nodes first, then parent links: skeleton parents may come after their children.
  std::vector<int> index_of(skeleton.nodes.size(), -1);
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if (skeleton.nodes[i].order > max_order) continue;
    Eigen::Vector2d point_in_image;
    SYLVA_CHECK_INPUT(image_set.Project(view_idx, skeleton.nodes[i].position, &point_in_image),
                      image_set.views[view_idx].name)
        << "skeleton node " << i << " lies behind the camera";
    index_of[i] = graph.AddNode(point_in_image, -1);
  }
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    const int parent = skeleton.nodes[i].parent_idx;
    if (index_of[i] >= 0 && parent >= 0) graph.nodes[index_of[i]].parent_idx = index_of[parent];
  }
  const int root = skeleton.RootIdx();
  graph.root = root >= 0 ? index_of[root] : -1;
  return graph;
}

PointSetDistances CompareGraphs2D(const AttractorGraph2D& a, const AttractorGraph2D& b,
                                  double spacing_px) {
  return CompareGraphs2D(a, b.SamplePoints(spacing_px), spacing_px);
}

PointSetDistances CompareGraphs2D(const AttractorGraph2D& a, const std::vector<Eigen::Vector2d>& b,
                                  double spacing_px) {
  SYLVA_CHECK(!a.IsEmpty() && !b.empty()) << "comparing an empty attractor graph";
  return ComparePointSets(Lift(a.SamplePoints(spacing_px)), Lift(b));
}

}  // namespace sylva
