#include "sketch/scan_skeleton.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <set>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "core/util/thinning.h"

namespace sylva::scan {
namespace {

// Edge-adjacent neighbours first (core/util/thinning.h numbers them): a
// chain walked this way takes the corner pixel of a staircase instead of
// cutting it, so no pixel is left behind.
constexpr int kWalkOrder[8] = {0, 2, 4, 6, 1, 3, 5, 7};

// Union-find root with path halving.
int Root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Groups junction pixels (x, y) closer than `radius` (Euclidean).
std::vector<int> ClusterPixels(const std::vector<cv::Point>& pixels, double radius) {
  std::vector<int> order(pixels.size()), parent(pixels.size());
  std::iota(order.begin(), order.end(), 0);
  std::iota(parent.begin(), parent.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return pixels[a].y < pixels[b].y; });
  for (size_t i = 0; i < order.size(); ++i) {
    const cv::Point p = pixels[order[i]];
    for (size_t j = i + 1; j < order.size() && pixels[order[j]].y - p.y <= radius; ++j) {
      const cv::Point d = pixels[order[j]] - p;
      if (d.x * d.x + d.y * d.y <= radius * radius) {
        parent[Root(parent, order[i])] = Root(parent, order[j]);
      }
    }
  }
  for (size_t i = 0; i < pixels.size(); ++i) parent[i] = Root(parent, static_cast<int>(i));
  return parent;
}

// Walks the skeleton (padded by one zero pixel, so neighbours never leave it)
// into nodes and edges.
class SkeletonTracer {
 public:
  SkeletonTracer(const cv::Mat& skeleton, double junction_cluster_px)
      : cluster_px_(junction_cluster_px) {
    cv::copyMakeBorder(skeleton != 0, padded_, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
    offsets_ = NeighbourOffsets(padded_.step);
    node_of_.assign(padded_.total(), -1);
    visited_.assign(padded_.total(), false);
  }

  SkeletonGraph Trace() {
    FindNodes();
    for (size_t i = 0; i < node_pixels_.size(); ++i) WalkFromNodePixel(node_pixels_[i]);
    TraceLeftoverLoops();
    return std::move(graph_);
  }

 private:
  const uchar* data() const { return padded_.ptr<uchar>(); }
  int Code(int index) const { return NeighbourCode(data(), index, offsets_); }
  Eigen::Vector2d Position(int index) const {
    const int step = static_cast<int>(padded_.step);
    return Eigen::Vector2d(index % step - 1, index / step - 1);
  }

  // End points become nodes of their own; junction pixels are clustered.
  void FindNodes() {
    std::vector<int> junction_indices;
    std::vector<cv::Point> junction_pixels;
    const int total = static_cast<int>(padded_.total());
    for (int index = 0; index < total; ++index) {
      if (!data()[index]) continue;
      const int crossings = CrossingNumber(Code(index));
      if (crossings == 1) {
        AddNodePixel(index, AddNode(Position(index), false));
      } else if (crossings >= 3) {
        junction_indices.push_back(index);
        const Eigen::Vector2d p = Position(index);
        junction_pixels.emplace_back(static_cast<int>(p.x()), static_cast<int>(p.y()));
      }
    }
    const std::vector<int> cluster = ClusterPixels(junction_pixels, cluster_px_);
    std::vector<int> node_of_cluster(cluster.size(), -1);
    std::vector<int> count(cluster.size(), 0);
    for (size_t i = 0; i < cluster.size(); ++i) {
      int& node = node_of_cluster[cluster[i]];
      if (node < 0) node = AddNode(Eigen::Vector2d::Zero(), true);
      graph_.nodes[node].position += Position(junction_indices[i]);
      ++count[cluster[i]];
      AddNodePixel(junction_indices[i], node);
    }
    for (size_t c = 0; c < cluster.size(); ++c) {
      if (count[c] > 0) graph_.nodes[node_of_cluster[c]].position /= count[c];
    }
  }

  int AddNode(const Eigen::Vector2d& position, bool junction) {
    graph_.nodes.push_back({position, junction});
    return static_cast<int>(graph_.nodes.size()) - 1;
  }
  void AddNodePixel(int index, int node) {
    node_of_[index] = node;
    node_pixels_.push_back(index);
  }

  void WalkFromNodePixel(int start) {
    const int node = node_of_[start];
    for (int k = 0; k < 8; ++k) {
      const int next = start + offsets_[k];
      if (!data()[next]) continue;
      const int other = node_of_[next];
      if (other > node && direct_edges_.insert({node, other}).second) {
        graph_.edges.push_back({node, other, {Position(start), Position(next)}, false});
      } else if (other < 0 && !visited_[next]) {
        WalkChain(node, start, next);
      }
    }
  }

  // Follows the chain start -> first ... until it reaches a node pixel (its
  // own start node only after a loop longer than a junction cluster).
  void WalkChain(int node, int start, int first) {
    SkeletonEdge edge{node, -1, {graph_.nodes[node].position, Position(first)}, false};
    visited_[first] = true;
    int current = first;
    const int min_loop_steps = static_cast<int>(2 * cluster_px_) + 3;
    for (int steps = 1;; ++steps) {
      const int end_node = AdjacentNode(current, start, node, steps >= min_loop_steps);
      if (end_node >= 0) {
        edge.node_b = end_node;
        edge.points.push_back(graph_.nodes[end_node].position);
        break;
      }
      const int next = UnvisitedNeighbour(current);
      if (next < 0) {  // a dead end the crossing numbers missed
        edge.node_b = AddNode(Position(current), false);
        node_of_[current] = edge.node_b;
        break;
      }
      visited_[next] = true;
      edge.points.push_back(Position(next));
      current = next;
    }
    graph_.edges.push_back(std::move(edge));
  }

  int AdjacentNode(int index, int start, int start_node, bool allow_start_node) const {
    int same = -1;
    for (int k = 0; k < 8; ++k) {
      const int neighbour = index + offsets_[k];
      const int n = node_of_[neighbour];
      if (n < 0 || neighbour == start) continue;
      if (n != start_node) return n;
      same = n;
    }
    return allow_start_node ? same : -1;
  }

  int UnvisitedNeighbour(int index) const {
    for (int k : kWalkOrder) {
      const int neighbour = index + offsets_[k];
      if (data()[neighbour] && node_of_[neighbour] < 0 && !visited_[neighbour]) return neighbour;
    }
    return -1;
  }

  // Closed curves with no junction or end (a crown drawn as one loop) are
  // not reached from any node.
  void TraceLeftoverLoops() {
    const int total = static_cast<int>(padded_.total());
    for (int index = 0; index < total; ++index) {
      if (!data()[index] || node_of_[index] >= 0 || visited_[index]) continue;
      SkeletonEdge loop{-1, -1, {Position(index)}, true};
      visited_[index] = true;
      for (int current = UnvisitedNeighbour(index); current >= 0;
           current = UnvisitedNeighbour(current)) {
        visited_[current] = true;
        loop.points.push_back(Position(current));
      }
      // Fewer points are pixels a chain walk stepped past.
      if (loop.points.size() >= 2 * cluster_px_ + 3) graph_.edges.push_back(std::move(loop));
    }
  }

  double cluster_px_;
  cv::Mat padded_;
  std::array<int, 8> offsets_;
  std::vector<int> node_of_;
  std::vector<bool> visited_;
  std::vector<int> node_pixels_;
  std::set<std::pair<int, int>> direct_edges_;
  SkeletonGraph graph_;
};

// The edge's points ordered to end at `node` (reversed if it starts there).
std::vector<Eigen::Vector2d> PointsEndingAt(const SkeletonEdge& edge, int node) {
  std::vector<Eigen::Vector2d> points = edge.points;
  if (edge.node_b != node) std::reverse(points.begin(), points.end());
  return points;
}

// Joins the two edges at two-way node `node`; false if it has a self-loop
// that becomes a closed loop instead.
void MergeAt(int node, std::vector<std::vector<int>>& incident, std::vector<SkeletonEdge>& edges,
             std::vector<bool>& dead) {
  const int e1 = incident[node][0], e2 = incident[node][1];
  incident[node].clear();
  if (e1 == e2) {  // a loop from the node back to itself
    SkeletonEdge& loop = edges[e1];
    loop.points.pop_back();
    loop.node_a = loop.node_b = -1;
    loop.closed = true;
    return;
  }
  std::vector<Eigen::Vector2d> points = PointsEndingAt(edges[e1], node);
  std::vector<Eigen::Vector2d> tail = PointsEndingAt(edges[e2], node);
  std::reverse(tail.begin(), tail.end());
  points.insert(points.end(), tail.begin() + 1, tail.end());
  const int a = edges[e1].node_a == node ? edges[e1].node_b : edges[e1].node_a;
  const int b = edges[e2].node_a == node ? edges[e2].node_b : edges[e2].node_a;
  edges[e1] = SkeletonEdge{a, b, std::move(points), false};
  dead[e2] = true;
  std::replace(incident[b].begin(), incident[b].end(), e2, e1);
}

// Drops the dead edges and the nodes no edge uses; renumbers the rest.
void Compact(const std::vector<bool>& dead, SkeletonGraph& graph) {
  std::vector<SkeletonEdge> edges;
  std::vector<int> new_index(graph.nodes.size(), -1);
  std::vector<SkeletonNode> nodes;
  const auto renumber = [&](int node) {
    if (node < 0) return node;
    if (new_index[node] < 0) {
      new_index[node] = static_cast<int>(nodes.size());
      nodes.push_back(graph.nodes[node]);
    }
    return new_index[node];
  };
  for (size_t e = 0; e < graph.edges.size(); ++e) {
    if (dead[e]) continue;
    SkeletonEdge edge = std::move(graph.edges[e]);
    edge.node_a = renumber(edge.node_a);
    edge.node_b = renumber(edge.node_b);
    edges.push_back(std::move(edge));
  }
  graph.nodes = std::move(nodes);
  graph.edges = std::move(edges);
}

// The unit direction in which the edge leaves the drawing at end `node`,
// from the point `look_back_px` (along the chain) before the end.
Eigen::Vector2d EndDirection(const SkeletonEdge& edge, int node, double look_back_px) {
  const std::vector<Eigen::Vector2d> points = PointsEndingAt(edge, node);
  const Eigen::Vector2d end = points.back();
  Eigen::Vector2d back = points.front();
  double length = 0;
  for (size_t i = points.size() - 1; i > 0; --i) {
    length += (points[i] - points[i - 1]).norm();
    if (length >= look_back_px) {
      back = points[i - 1];
      break;
    }
  }
  const Eigen::Vector2d direction = end - back;
  return direction.norm() > 0 ? Eigen::Vector2d(direction.normalized()) : Eigen::Vector2d::Zero();
}

}  // namespace

cv::Mat SauvolaInk(const cv::Mat& grey, int window, double k, double range) {
  const cv::Size box(window, window);
  cv::Mat mean, square_mean, deviation;
  cv::boxFilter(grey, mean, CV_32F, box, cv::Point(-1, -1), true, cv::BORDER_REPLICATE);
  cv::sqrBoxFilter(grey, square_mean, CV_32F, box, cv::Point(-1, -1), true, cv::BORDER_REPLICATE);
  cv::sqrt(square_mean - mean.mul(mean), deviation);
  cv::Mat threshold = mean.mul(1.0 + static_cast<float>(k) * (deviation / range - 1.0));
  threshold.convertTo(threshold, grey.depth());
  cv::Mat ink;
  cv::compare(grey, threshold, ink, cv::CMP_LE);
  return ink;
}

cv::Mat ThinZhangSuen(const cv::Mat& ink) {
  cv::Mat image = (ink != 0);  // a fresh continuous CV_8U copy, 255 on ink
  sylva::ThinZhangSuen(image.cols, image.rows, image.step, image.ptr<uchar>());
  return image;
}

std::vector<int> SkeletonGraph::Degrees() const {
  std::vector<int> degrees(nodes.size(), 0);
  for (const SkeletonEdge& edge : edges) {
    if (edge.node_a >= 0) ++degrees[edge.node_a];
    if (edge.node_b >= 0) ++degrees[edge.node_b];
  }
  return degrees;
}

SkeletonGraph TraceSkeleton(const cv::Mat& skeleton, double junction_cluster_px) {
  return SkeletonTracer(skeleton, junction_cluster_px).Trace();
}

double EdgeLength(const SkeletonEdge& edge) {
  double length = 0;
  for (size_t i = 1; i < edge.points.size(); ++i) {
    length += (edge.points[i] - edge.points[i - 1]).norm();
  }
  if (edge.closed && edge.points.size() > 1) {
    length += (edge.points.front() - edge.points.back()).norm();
  }
  return length;
}

void MergeThroughTwoWayNodes(SkeletonGraph& graph) {
  std::vector<std::vector<int>> incident(graph.nodes.size());
  for (size_t e = 0; e < graph.edges.size(); ++e) {
    if (graph.edges[e].node_a >= 0) incident[graph.edges[e].node_a].push_back(static_cast<int>(e));
    if (graph.edges[e].node_b >= 0) incident[graph.edges[e].node_b].push_back(static_cast<int>(e));
  }
  std::vector<bool> dead(graph.edges.size(), false);
  for (size_t node = 0; node < graph.nodes.size(); ++node) {
    if (incident[node].size() == 2) MergeAt(static_cast<int>(node), incident, graph.edges, dead);
  }
  Compact(dead, graph);
}

int PruneSpurs(double min_length_px, SkeletonGraph& graph) {
  int removed = 0;
  // A few rounds: pruning a spur can leave a shorter one behind a merge.
  for (int round = 0; round < 3; ++round) {
    const std::vector<int> degree = graph.Degrees();
    std::vector<bool> dead(graph.edges.size(), false);
    int removed_now = 0;
    for (size_t e = 0; e < graph.edges.size(); ++e) {
      const SkeletonEdge& edge = graph.edges[e];
      if (edge.closed || EdgeLength(edge) >= min_length_px) continue;
      const int da = degree[edge.node_a], db = degree[edge.node_b];
      if ((da == 1 && db != 2) || (db == 1 && da != 2)) {
        dead[e] = true;
        ++removed_now;
      }
    }
    if (removed_now == 0) break;
    removed += removed_now;
    Compact(dead, graph);
    MergeThroughTwoWayNodes(graph);
  }
  return removed;
}

int CloseGaps(double max_gap_px, double max_angle_rad, SkeletonGraph& graph) {
  const std::vector<int> degree = graph.Degrees();
  std::vector<int> edge_of(graph.nodes.size(), -1);
  for (size_t e = 0; e < graph.edges.size(); ++e) {
    for (int node : {graph.edges[e].node_a, graph.edges[e].node_b}) {
      if (node >= 0) edge_of[node] = static_cast<int>(e);
    }
  }
  struct Gap {
    double length;
    int a, b;
  };
  std::vector<Gap> gaps;
  const double min_cos = std::cos(max_angle_rad);
  for (size_t a = 0; a < graph.nodes.size(); ++a) {
    if (degree[a] != 1) continue;
    const Eigen::Vector2d dir_a = EndDirection(graph.edges[edge_of[a]], a, max_gap_px);
    for (size_t b = a + 1; b < graph.nodes.size(); ++b) {
      if (degree[b] != 1) continue;
      const Eigen::Vector2d ab = graph.nodes[b].position - graph.nodes[a].position;
      const double length = ab.norm();
      if (length == 0 || length > max_gap_px) continue;
      const Eigen::Vector2d dir_b = EndDirection(graph.edges[edge_of[b]], b, max_gap_px);
      if (dir_a.dot(ab) >= min_cos * length && dir_b.dot(-ab) >= min_cos * length) {
        gaps.push_back({length, static_cast<int>(a), static_cast<int>(b)});
      }
    }
  }
  std::sort(gaps.begin(), gaps.end(),
            [](const Gap& x, const Gap& y) { return x.length < y.length; });
  std::vector<bool> joined(graph.nodes.size(), false);
  int closed = 0;
  for (const Gap& gap : gaps) {
    if (joined[gap.a] || joined[gap.b]) continue;
    joined[gap.a] = joined[gap.b] = true;
    graph.edges.push_back(SkeletonEdge{
        gap.a, gap.b, {graph.nodes[gap.a].position, graph.nodes[gap.b].position}, false});
    ++closed;
  }
  if (closed > 0) MergeThroughTwoWayNodes(graph);
  return closed;
}

}  // namespace sylva::scan
