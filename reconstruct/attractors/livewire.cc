#include "reconstruct/attractors/livewire.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/imgproc/segmentation.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "core/util/check.h"
#include "reconstruct/attractors/livewire_features.h"
#include "reconstruct/attractors/livewire_seeds.h"

namespace sylva {
namespace {

// Margin of the window that SnapGraphToImage traces one edge in, as a share
// of the edge's length, and at least this many traced pixels.
constexpr double kEdgeWindowShare = 0.5;
constexpr int kMinEdgeWindowMargin = 16;

void CheckInImage(const Eigen::Vector2d& point, int width, int height, const std::string& what) {
  SYLVA_CHECK_INPUT(point.allFinite() && point.x() >= 0 && point.y() >= 0 && point.x() < width &&
                        point.y() < height,
                    what)
      << "(" << point.x() << ", " << point.y() << ") lies outside the " << width << " x " << height
      << " image";
}

cv::segmentation::IntelligentScissorsMB MakeScissors(const LivewireFeatures& features,
                                                     const cv::Rect& window,
                                                     const LivewireOptions& options) {
  cv::segmentation::IntelligentScissorsMB scissors;
  scissors.setWeights(static_cast<float>(options.weight_outside),
                      static_cast<float>(options.weight_direction),
                      static_cast<float>(options.weight_centerline));
  scissors.applyImageFeatures(features.outside(window).clone(), features.direction(window).clone(),
                              features.centerline(window).clone());
  return scissors;
}

// Merges paths (each from a seed to the map's source, which `owner` already
// marks) into `graph`: a path's pixels up to the first owned one become a
// chain of nodes hanging from that pixel's node.
class PathMerger {
 public:
  PathMerger(const LivewireFeatures& features, AttractorGraph2D* graph)
      : features_(features),
        graph_(graph),
        owner_(static_cast<size_t>(features.mask.cols) * features.mask.rows, -1) {}

  void Own(const cv::Point& pixel, int node) { owner_[Index(pixel)] = node; }

  // Returns true if the path added nodes.
  bool Add(const std::vector<cv::Point>& path) {
    size_t joint = 0;
    while (joint < path.size() && owner_[Index(path[joint])] < 0) ++joint;
    if (joint == 0 || joint == path.size()) return false;
    int parent = owner_[Index(path[joint])];
    for (size_t k = joint; k-- > 0;) {
      parent = graph_->AddNode(features_.ToFull(path[k]), parent);
      Own(path[k], parent);
    }
    return true;
  }

 private:
  size_t Index(const cv::Point& p) const {
    return static_cast<size_t>(p.y) * features_.mask.cols + p.x;
  }

  const LivewireFeatures& features_;
  AttractorGraph2D* graph_;
  std::vector<int> owner_;
};

// The traced pixel of lowest centre-line cost within `radius` traced pixels
// of `pixel` (nearest, then first in row order, on ties).
cv::Point CheapestPixelNear(const LivewireFeatures& features, const cv::Point& pixel,
                            double radius) {
  const int r = static_cast<int>(std::floor(radius));
  cv::Point best = pixel;
  float best_cost = features.centerline.at<float>(pixel);
  int best_d2 = 0;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const cv::Point q(pixel.x + dx, pixel.y + dy);
      const int d2 = dx * dx + dy * dy;
      if (d2 > radius * radius || !q.inside(cv::Rect(0, 0, features.mask.cols, features.mask.rows)))
        continue;
      const float cost = features.centerline.at<float>(q);
      if (cost < best_cost || (cost == best_cost && d2 < best_d2))
        best = q, best_cost = cost, best_d2 = d2;
    }
  }
  return best;
}

// The livewire path from `from` to `to` (traced pixels, both included),
// searched in a window around the two.
std::vector<cv::Point> PathInWindow(const LivewireFeatures& features, const cv::Point& from,
                                    const cv::Point& to, const LivewireOptions& options) {
  const double length = std::hypot(from.x - to.x, from.y - to.y);
  const int margin =
      std::max(kMinEdgeWindowMargin, static_cast<int>(std::ceil(kEdgeWindowShare * length)));
  cv::Rect window(
      cv::Point(std::min(from.x, to.x) - margin, std::min(from.y, to.y) - margin),
      cv::Point(std::max(from.x, to.x) + margin + 1, std::max(from.y, to.y) + margin + 1));
  window &= cv::Rect(0, 0, features.mask.cols, features.mask.rows);
  cv::segmentation::IntelligentScissorsMB scissors = MakeScissors(features, window, options);
  scissors.buildMap(to - window.tl());
  std::vector<cv::Point> path;
  scissors.getContour(from - window.tl(), path, /*backward=*/true);
  for (cv::Point& p : path) p += window.tl();
  return path;
}

}  // namespace

std::string LivewireSummary::BriefReport() const {
  std::ostringstream out;
  out << "livewire: " << seeds << " seeds, " << paths << " paths, " << nodes << " nodes, "
      << megapixels << " MP in " << seconds << " s";
  return out.str();
}

AttractorGraph2D TraceAttractorGraph(const FloatImage& photo, const FloatImage& matte,
                                     const Eigen::Vector2d& target,
                                     const std::vector<Eigen::Vector2d>& user_seeds,
                                     const LivewireOptions& options, LivewireSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  options.Check();
  const LivewireFeatures features = ComputeLivewireFeatures(photo, matte, options);
  CheckInImage(target, photo.width(), photo.height(), "livewire target");
  for (const Eigen::Vector2d& seed : user_seeds) {
    CheckInImage(seed, photo.width(), photo.height(), "livewire seed");
  }
  const cv::Point target_pixel = features.ToTraced(target);
  std::vector<cv::Point> seeds;
  for (const Eigen::Vector2d& seed : user_seeds) seeds.push_back(features.ToTraced(seed));
  if (seeds.empty()) seeds = AutomaticSeeds(features.mask, target_pixel, options);

  cv::segmentation::IntelligentScissorsMB scissors =
      MakeScissors(features, cv::Rect(0, 0, features.mask.cols, features.mask.rows), options);
  scissors.buildMap(target_pixel);
  AttractorGraph2D graph;
  graph.width = photo.width();
  graph.height = photo.height();
  graph.source = "livewire";
  graph.root = graph.AddNode(target, -1);
  PathMerger merger(features, &graph);
  merger.Own(target_pixel, graph.root);
  int paths = 0;
  std::vector<cv::Point> path;
  for (const cv::Point& seed : seeds) {
    scissors.getContour(seed, path, /*backward=*/true);
    paths += merger.Add(path);
  }
  graph = graph.Simplified(options.simplify_tolerance);
  if (options.min_twig_length > 0) {
    graph = graph.WithoutTwigs(options.min_twig_length * std::max(photo.width(), photo.height()));
  }
  if (summary != nullptr) {
    summary->seeds = static_cast<int>(seeds.size());
    summary->paths = paths;
    summary->nodes = graph.NumNodes();
    summary->megapixels = photo.NumPixels() / 1e6;
    summary->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return graph;
}

AttractorGraph2D SnapGraphToImage(const AttractorGraph2D& drawn, const FloatImage& photo,
                                  const FloatImage& matte, const LivewireOptions& options) {
  options.Check();
  drawn.Check("drawn attractor graph");
  const LivewireFeatures features = ComputeLivewireFeatures(photo, matte, options);
  SYLVA_CHECK_INPUT(drawn.width == photo.width() && drawn.height == photo.height(),
                    "drawn attractor graph")
      << "drawn on a " << drawn.width << " x " << drawn.height << " image, the photo is "
      << photo.width() << " x " << photo.height();
  const double radius = options.snap_radius * std::min(features.scale_x, features.scale_y);
  std::vector<cv::Point> pixels;
  AttractorGraph2D snapped = drawn;
  snapped.source = "strokes+livewire";
  for (AttractorNode& node : snapped.nodes) {
    pixels.push_back(CheapestPixelNear(features, features.ToTraced(node.position), radius));
    if (pixels.back() != features.ToTraced(node.position))
      node.position = features.ToFull(pixels.back());
  }
  for (int i = 0; i < drawn.NumNodes(); ++i) {
    const int parent = drawn.nodes[i].parent_idx;
    if (parent < 0) continue;
    const std::vector<cv::Point> path = PathInWindow(features, pixels[i], pixels[parent], options);
    int below = parent;  // path runs from node i to its parent; add its interior from the parent up
    for (size_t k = path.size() - 1; k-- > 1;)
      below = snapped.AddNode(features.ToFull(path[k]), below);
    snapped.nodes[i].parent_idx = below;
  }
  return snapped.Simplified(options.simplify_tolerance);
}

Eigen::Vector2d MatteFootPoint(const FloatImage& matte, double threshold) {
  SYLVA_CHECK_INPUT(matte.channels() == 1 && !matte.empty(), "matte")
      << "expected a non-empty one-channel matte";
  for (int y = matte.height() - 1; y >= 0; --y) {
    int best_start = -1, best_length = 0;
    for (int x = 0; x < matte.width();) {
      if (matte.at(x, y) < threshold) {
        ++x;
        continue;
      }
      const int run_start = x;
      while (x < matte.width() && matte.at(x, y) >= threshold) ++x;
      if (x - run_start > best_length) best_length = x - run_start, best_start = run_start;
    }
    if (best_length > 0) return Eigen::Vector2d(best_start + 0.5 * best_length, y + 0.5);
  }
  SYLVA_CHECK_INPUT(false, "matte")
      << "no pixel reaches the threshold " << threshold << ": no foot point";
  return Eigen::Vector2d::Zero();
}

}  // namespace sylva
