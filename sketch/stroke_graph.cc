#include "sketch/stroke_graph.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <set>

#include "core/geometry/polyline.h"
#include "core/util/check.h"

namespace sylva {
namespace {

// A point this close to a segment's end (pixels) is that end: no split.
constexpr double kSameNodeDistance = 1e-6;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The strokes as chains of shared nodes while ends are joined. Joining
// merges node classes (union-find); a class takes the position of the node
// it was merged into.
class StrokeNetwork {
 public:
  StrokeNetwork(const StrokeSet& strokes, double simplify_tolerance) {
    for (const Stroke& stroke : strokes.strokes) {
      const int count = static_cast<int>(stroke.points.size());
      std::vector<char> keep(count, simplify_tolerance > 0 ? 0 : 1);
      DouglasPeucker(
          count, [&](int k) { return stroke.points[k]; }, simplify_tolerance, &keep);
      chains_.emplace_back();
      for (int k = 0; k < count; ++k) {
        if (keep[k]) chains_.back().push_back(NewNode(stroke.points[k]));
      }
    }
  }

  int NumNodes() const { return static_cast<int>(positions_.size()); }
  const std::vector<std::vector<int>>& chains() const { return chains_; }
  const Eigen::Vector2d& Position(int node) const { return positions_[node]; }
  int Find(int node) const {
    while (merged_into_[node] != node) node = merged_into_[node];
    return node;
  }

  // Step 2 of stroke_graph.h: joins every stroke end within snap_distance
  // of another stroke.
  void JoinEnds(double snap_distance) {
    for (int s = 0; s < static_cast<int>(chains_.size()); ++s) {
      for (const bool front : {true, false}) {
        const int end = Find(front ? chains_[s].front() : chains_[s].back());
        if (joined_[end]) continue;
        const int target = JoinTarget(s, end, snap_distance);
        if (target < 0) continue;
        merged_into_[end] = target;
        joined_[target] = 1;
      }
    }
  }

 private:
  int NewNode(const Eigen::Vector2d& position) {
    positions_.push_back(position);
    merged_into_.push_back(NumNodes() - 1);
    joined_.push_back(0);
    return NumNodes() - 1;
  }

  // Whether a node class is a stroke end or a junction.
  bool IsEndOrJunction(int node) const {
    if (joined_[node]) return true;
    for (const std::vector<int>& chain : chains_) {
      if (Find(chain.front()) == node || Find(chain.back()) == node) return true;
    }
    return false;
  }

  // Where the end `end` of stroke `s` joins another stroke: the nearest end
  // or junction of another stroke within snap_distance, else the nearest
  // point on another stroke's segments (a new node splitting the segment),
  // else -1. Nodes already on stroke s are never targets.
  int JoinTarget(int s, int end, double snap_distance) {
    std::set<int> own;
    for (const int node : chains_[s]) own.insert(Find(node));
    const Eigen::Vector2d& p = positions_[end];
    const double snap2 = snap_distance * snap_distance;
    int best_node = -1;
    double best_node2 = snap2;
    int best_chain = -1, best_segment = -1;
    double best_segment2 = snap2, best_t = 0;
    for (int c = 0; c < static_cast<int>(chains_.size()); ++c) {
      if (c == s) continue;
      const std::vector<int>& chain = chains_[c];
      for (size_t k = 0; k < chain.size(); ++k) {
        const int a = Find(chain[k]);
        if (own.count(a)) continue;
        const double d2 = (positions_[a] - p).squaredNorm();
        if (d2 <= best_node2 && (best_node < 0 || d2 < best_node2) && IsEndOrJunction(a)) {
          best_node = a, best_node2 = d2;
        }
        if (k + 1 == chain.size() || own.count(Find(chain[k + 1]))) continue;
        double t = 0;
        const double s2 = SegmentDistance2(p, positions_[a], positions_[Find(chain[k + 1])], &t);
        if (s2 <= best_segment2 && (best_chain < 0 || s2 < best_segment2)) {
          best_chain = c, best_segment = static_cast<int>(k), best_segment2 = s2, best_t = t;
        }
      }
    }
    if (best_node >= 0) return best_node;
    if (best_chain < 0) return -1;
    return NodeOnSegment(best_chain, best_segment, best_t);
  }

  // The node at parameter t of segment k of chain c: an end of the segment
  // if the point is (almost) there, else a new node inserted into the chain.
  int NodeOnSegment(int c, int k, double t) {
    std::vector<int>& chain = chains_[c];
    const int a = Find(chain[k]), b = Find(chain[k + 1]);
    const Eigen::Vector2d q = positions_[a] + t * (positions_[b] - positions_[a]);
    if ((q - positions_[a]).norm() <= kSameNodeDistance) return a;
    if ((q - positions_[b]).norm() <= kSameNodeDistance) return b;
    const int node = NewNode(q);
    chain.insert(chain.begin() + k + 1, node);
    return node;
  }

  std::vector<Eigen::Vector2d> positions_;
  std::vector<int> merged_into_;
  std::vector<char> joined_;
  std::vector<std::vector<int>> chains_;
};

// The joined strokes as an undirected graph with dense node indices.
struct UndirectedGraph {
  std::vector<Eigen::Vector2d> positions;
  std::vector<std::pair<int, int>> edges;  // undirected, no repeats

  int AddNode(const Eigen::Vector2d& p) {
    positions.push_back(p);
    return static_cast<int>(positions.size()) - 1;
  }
  double Length(const std::pair<int, int>& e) const {
    return (positions[e.second] - positions[e.first]).norm();
  }
  std::vector<std::vector<int>> Adjacency() const {
    std::vector<std::vector<int>> neighbours(positions.size());
    for (const auto& [a, b] : edges) neighbours[a].push_back(b), neighbours[b].push_back(a);
    for (std::vector<int>& list : neighbours) std::sort(list.begin(), list.end());
    return neighbours;
  }
};

UndirectedGraph GraphFromNetwork(const StrokeNetwork& network) {
  UndirectedGraph graph;
  std::vector<int> index_of(network.NumNodes(), -1);
  std::set<std::pair<int, int>> edges;
  for (const std::vector<int>& chain : network.chains()) {
    int previous = -1;
    for (const int raw : chain) {
      const int node = network.Find(raw);
      if (index_of[node] < 0) index_of[node] = graph.AddNode(network.Position(node));
      const int current = index_of[node];
      if (previous >= 0 && previous != current) {
        edges.insert({std::min(previous, current), std::max(previous, current)});
      }
      previous = current;
    }
  }
  graph.edges.assign(edges.begin(), edges.end());
  return graph;
}

// Splits edge `e` at new node `node` (which lies on it).
void SplitEdge(UndirectedGraph* graph, size_t e, int node) {
  const auto [a, b] = graph->edges[e];
  graph->edges[e] = {a, node};
  graph->edges.push_back({b, node});
}

// Step 3: splits every edge longer than `spacing` into equal pieces.
void Resample(UndirectedGraph* graph, double spacing) {
  const size_t num_edges = graph->edges.size();
  for (size_t e = 0; e < num_edges; ++e) {
    const auto [a, b] = graph->edges[e];
    const double pieces = std::ceil(graph->Length(graph->edges[e]) / spacing);
    if (!(pieces > 1)) continue;
    const Eigen::Vector2d pa = graph->positions[a], pb = graph->positions[b];
    int previous = a;
    for (int k = 1; k < pieces; ++k) {
      const int node = graph->AddNode(pa + (pb - pa) * (k / pieces));
      if (previous == a) {
        graph->edges[e] = {a, node};
      } else {
        graph->edges.push_back({previous, node});
      }
      previous = node;
    }
    graph->edges.push_back({previous, b});
  }
}

// Step 4, given root point: the node nearest to `point` on the graph,
// splitting the nearest edge if needed.
int NodeNearest(UndirectedGraph* graph, const Eigen::Vector2d& point) {
  size_t best_edge = 0;
  double best2 = kInfinity, best_t = 0;
  for (size_t e = 0; e < graph->edges.size(); ++e) {
    double t = 0;
    const double d2 = SegmentDistance2(point, graph->positions[graph->edges[e].first],
                                       graph->positions[graph->edges[e].second], &t);
    if (d2 < best2) best2 = d2, best_edge = e, best_t = t;
  }
  const auto [a, b] = graph->edges[best_edge];
  const Eigen::Vector2d q =
      graph->positions[a] + best_t * (graph->positions[b] - graph->positions[a]);
  if ((q - graph->positions[a]).norm() <= kSameNodeDistance) return a;
  if ((q - graph->positions[b]).norm() <= kSameNodeDistance) return b;
  const int node = graph->AddNode(q);
  SplitEdge(graph, best_edge, node);
  return node;
}

// Connected components: component index per node, numbered by their lowest
// node.
std::vector<int> Components(const std::vector<std::vector<int>>& adjacency, int* count) {
  std::vector<int> component(adjacency.size(), -1);
  *count = 0;
  for (size_t start = 0; start < adjacency.size(); ++start) {
    if (component[start] >= 0) continue;
    std::vector<int> stack = {static_cast<int>(start)};
    component[start] = *count;
    while (!stack.empty()) {
      const int node = stack.back();
      stack.pop_back();
      for (const int next : adjacency[node]) {
        if (component[next] < 0) component[next] = *count, stack.push_back(next);
      }
    }
    ++*count;
  }
  return component;
}

// Step 4: one root per component, the main root first.
std::vector<int> ComponentRoots(UndirectedGraph* graph,
                                const std::optional<Eigen::Vector2d>& root) {
  const int main_root = root ? NodeNearest(graph, *root) : -1;
  int count = 0;
  const std::vector<int> component = Components(graph->Adjacency(), &count);
  std::vector<int> lowest(count, -1);
  std::vector<double> length(count, 0);
  for (int n = 0; n < static_cast<int>(graph->positions.size()); ++n) {
    int& best = lowest[component[n]];
    if (best < 0 || graph->positions[n].y() > graph->positions[best].y()) best = n;
  }
  for (const auto& edge : graph->edges) length[component[edge.first]] += graph->Length(edge);
  const int main_component = main_root >= 0
                                 ? component[main_root]
                                 : static_cast<int>(std::max_element(length.begin(), length.end()) -
                                                    length.begin());  // the first of equals
  std::vector<int> roots = {main_root >= 0 ? main_root : lowest[main_component]};
  for (int c = 0; c < count; ++c) {
    if (c != main_component) roots.push_back(lowest[c]);
  }
  return roots;
}

// Step 5: Dijkstra from each root; appends the nodes in settle order to
// `order` and sets their parents (-1 for the roots).
void OrientTowardsRoots(const UndirectedGraph& graph, const std::vector<int>& roots,
                        std::vector<int>* order, std::vector<int>* parent,
                        std::vector<double>* distance) {
  const std::vector<std::vector<int>> adjacency = graph.Adjacency();
  parent->assign(graph.positions.size(), -1);
  distance->assign(graph.positions.size(), kInfinity);
  std::vector<char> settled(graph.positions.size(), 0);
  using Entry = std::pair<double, int>;
  for (const int root : roots) {
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    (*distance)[root] = 0;
    queue.push({0.0, root});
    while (!queue.empty()) {
      const auto [d, node] = queue.top();
      queue.pop();
      if (settled[node]) continue;
      settled[node] = 1;
      order->push_back(node);
      for (const int next : adjacency[node]) {
        const double through = d + (graph.positions[next] - graph.positions[node]).norm();
        if (!settled[next] && through < (*distance)[next]) {
          (*distance)[next] = through, (*parent)[next] = node;
          queue.push({through, next});
        }
      }
    }
  }
}

}  // namespace

AttractorGraph2D GraphFromStrokes(const StrokeSet& strokes, const StrokeGraphOptions& options) {
  options.Check();
  strokes.Check("the stroke set");
  StrokeNetwork network(strokes, options.simplify_tolerance);
  network.JoinEnds(options.snap_distance);
  UndirectedGraph graph = GraphFromNetwork(network);
  if (std::isfinite(options.resample_spacing)) Resample(&graph, options.resample_spacing);
  const std::vector<int> roots = ComponentRoots(&graph, strokes.root);
  std::vector<int> order, parent;
  std::vector<double> distance;
  OrientTowardsRoots(graph, roots, &order, &parent, &distance);

  AttractorGraph2D result;
  result.width = strokes.width;
  result.height = strokes.height;
  result.source = "strokes";
  std::vector<int> index_of(graph.positions.size(), -1);
  for (const int node : order) {
    const int up = parent[node] < 0 ? -1 : index_of[parent[node]];
    index_of[node] = result.AddNode(graph.positions[node], up);
  }
  result.root = 0;
  // Segments that close a cycle: a copy of the farther end hangs from the
  // nearer one.
  for (const auto& [a, b] : graph.edges) {
    if (parent[a] == b || parent[b] == a) continue;
    const bool a_farther =
        std::make_pair(distance[a], index_of[a]) > std::make_pair(distance[b], index_of[b]);
    const int far = a_farther ? a : b, near = a_farther ? b : a;
    result.AddNode(graph.positions[far], index_of[near]);
  }
  result.Check("the graph from strokes");
  return result;
}

}  // namespace sylva
