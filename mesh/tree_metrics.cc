#include "mesh/tree_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_set>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/statistics.h"
#include "mesh/crown_volume.h"

namespace sylva {

// ---------------------------------------------------------------------------
// Convex hull volume: incremental hull over triangles with outward normals.

namespace {

// Points closer than this (relative to the points' extent) to a plane are on it.
constexpr double kHullPlaneTolerance = 1e-12;

struct HullFace {
  int a, b, c;
  Eigen::Vector3d normal;  // outward, unnormalised
  bool alive = true;
};

class IncrementalHull {
 public:
  IncrementalHull(const std::vector<Eigen::Vector3d>& points, double tolerance)
      : points_(points), tolerance_(tolerance) {}

  // Builds the hull from the tetrahedron (i0..i3), then adds every point.
  void Build(int i0, int i1, int i2, int i3) {
    interior_ = (points_[i0] + points_[i1] + points_[i2] + points_[i3]) / 4.0;
    AddFace(i0, i1, i2);
    AddFace(i0, i1, i3);
    AddFace(i0, i2, i3);
    AddFace(i1, i2, i3);
    for (int i = 0; i < static_cast<int>(points_.size()); ++i) AddPoint(i);
  }

  double Volume() const {
    double volume = 0.0;
    for (const HullFace& f : faces_) {
      if (!f.alive) continue;
      volume += (points_[f.a] - interior_)
                    .dot((points_[f.b] - interior_).cross(points_[f.c] - interior_));
    }
    return volume / 6.0;
  }

 private:
  // Adds triangle (a, b, c), flipped if needed so that its normal points away
  // from the interior point.
  void AddFace(int a, int b, int c) {
    Eigen::Vector3d normal = (points_[b] - points_[a]).cross(points_[c] - points_[a]);
    if (normal.dot(interior_ - points_[a]) > 0) {
      std::swap(b, c);
      normal = -normal;
    }
    faces_.push_back({a, b, c, normal});
  }

  bool Sees(const HullFace& f, int i) const {
    return f.normal.dot(points_[i] - points_[f.a]) > tolerance_ * f.normal.norm();
  }

  // Removes the faces point i sees and closes the hole with a fan from i.
  void AddPoint(int i) {
    std::vector<std::pair<int, int>> edges;  // directed edges of the visible faces
    std::unordered_set<int64_t> edge_set;
    const auto key = [](int u, int v) { return (static_cast<int64_t>(u) << 32) | v; };
    const size_t num_faces = faces_.size();
    for (size_t f = 0; f < num_faces; ++f) {
      HullFace& face = faces_[f];
      if (!face.alive || !Sees(face, i)) continue;
      face.alive = false;
      for (const auto& [u, v] : {std::pair{face.a, face.b}, {face.b, face.c}, {face.c, face.a}}) {
        edges.emplace_back(u, v);
        edge_set.insert(key(u, v));
      }
    }
    // Horizon: visible edges whose twin belongs to a face i does not see.
    for (const auto& [u, v] : edges) {
      if (edge_set.count(key(v, u)) == 0) AddFace(u, v, i);
    }
  }

  const std::vector<Eigen::Vector3d>& points_;
  double tolerance_;
  Eigen::Vector3d interior_ = Eigen::Vector3d::Zero();
  std::vector<HullFace> faces_;
};

// Index of the point farthest by `distance`.
template <typename Distance>
int Farthest(const std::vector<Eigen::Vector3d>& points, Distance distance) {
  int best = 0;
  for (int i = 1; i < static_cast<int>(points.size()); ++i) {
    if (distance(points[i]) > distance(points[best])) best = i;
  }
  return best;
}

}  // namespace

double ConvexHullVolume(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 4) return 0.0;
  Eigen::Vector3d low = points[0], high = points[0];
  for (const Eigen::Vector3d& p : points) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const double tolerance = kHullPlaneTolerance * (high - low).norm();
  // A large initial tetrahedron: extreme x, farthest from it, from their line,
  // from their plane.
  const int i0 = Farthest(points, [&](const Eigen::Vector3d& p) { return -p.x(); });
  const int i1 =
      Farthest(points, [&](const Eigen::Vector3d& p) { return (p - points[i0]).norm(); });
  const Eigen::Vector3d line = (points[i1] - points[i0]).normalized();
  const int i2 =
      Farthest(points, [&](const Eigen::Vector3d& p) { return line.cross(p - points[i0]).norm(); });
  const Eigen::Vector3d normal = line.cross(points[i2] - points[i0]).normalized();
  const int i3 = Farthest(
      points, [&](const Eigen::Vector3d& p) { return std::abs(normal.dot(p - points[i0])); });
  if (!normal.allFinite() || std::abs(normal.dot(points[i3] - points[i0])) <= tolerance) return 0.0;
  IncrementalHull hull(points, tolerance);
  hull.Build(i0, i1, i2, i3);
  return hull.Volume();
}

// ---------------------------------------------------------------------------
// Tree metrics

namespace {

constexpr double kRadiansToDegrees = 180.0 / M_PI;

// World units per metre, or 0 if the units are not metric.
double UnitsPerMetre(const std::string& units) {
  if (units == "m") return 1.0;
  if (units == "cm") return 100.0;
  if (units == "mm") return 1000.0;
  return 0.0;
}

// Per node: the branch length its subtree holds (the edges below it) and
// the lowest z in its subtree (itself included).
struct Subtrees {
  std::vector<double> length;
  std::vector<double> lowest_z;
};

Subtrees MeasureSubtrees(const SkeletonGraph& skeleton,
                         const std::vector<std::vector<int>>& children) {
  // Parents before children (depth first from the root), then backwards.
  std::vector<int> order = {skeleton.RootIdx()};
  for (size_t k = 0; k < order.size(); ++k) {
    for (int child : children[order[k]]) order.push_back(child);
  }
  Subtrees subtrees{std::vector<double>(skeleton.nodes.size(), 0.0), {}};
  for (const SkeletonNode& node : skeleton.nodes) subtrees.lowest_z.push_back(node.position.z());
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const SkeletonNode& node = skeleton.nodes[*it];
    if (node.parent_idx < 0) continue;
    const double edge = (node.position - skeleton.nodes[node.parent_idx].position).norm();
    subtrees.length[node.parent_idx] += edge + subtrees.length[*it];
    subtrees.lowest_z[node.parent_idx] =
        std::min(subtrees.lowest_z[node.parent_idx], subtrees.lowest_z[*it]);
  }
  return subtrees;
}

// The z of the lowest point of the major first-order branches (see the
// header); nullopt if there is no first-order branch.
std::optional<double> CrownBaseZ(const SkeletonGraph& skeleton, const std::vector<BranchAxis>& axes,
                                 const std::vector<int>& orders, double major_branch_fraction) {
  const Subtrees subtrees = MeasureSubtrees(skeleton, skeleton.Children());
  std::vector<std::pair<double, double>> branches;  // (carried length, lowest z)
  double largest = 0.0;
  for (size_t a = 1; a < axes.size(); ++a) {
    if (orders[a] != 1) continue;
    const SkeletonNode& junction = skeleton.nodes[axes[a][0]];
    const SkeletonNode& first = skeleton.nodes[axes[a][1]];
    const double carried =
        (first.position - junction.position).norm() + subtrees.length[axes[a][1]];
    branches.emplace_back(carried, std::min(junction.position.z(), subtrees.lowest_z[axes[a][1]]));
    largest = std::max(largest, carried);
  }
  if (branches.empty()) return std::nullopt;
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& [carried, lowest_z] : branches) {
    if (carried >= major_branch_fraction * largest) lowest = std::min(lowest, lowest_z);
  }
  return lowest;
}

// The child the axis through `node` continues into: among the children of
// no higher order than the node, the lowest order, then most strands, then
// thickest, then lowest index; -1 if none.
int ContinuationByOrder(const SkeletonGraph& skeleton, int node, const std::vector<int>& children) {
  int best = -1;
  for (int child : children) {
    if (skeleton.nodes[child].order > skeleton.nodes[node].order) continue;
    if (best < 0) {
      best = child;
      continue;
    }
    const SkeletonNode& c = skeleton.nodes[child];
    const SkeletonNode& b = skeleton.nodes[best];
    if (std::tie(c.order, b.strands, b.radius) < std::tie(b.order, c.strands, c.radius))
      best = child;
  }
  return best;
}

// Largest horizontal distance between two of `points`, by brute force
// (O(n^2): 0.1 s for 10^4 crown nodes).
// The points' 2D convex hull in the horizontal plane (Andrew's monotone
// chain), collinear boundary points kept: the farthest pair is among them.
std::vector<Eigen::Vector2d> HorizontalHull(const std::vector<Eigen::Vector3d>& points) {
  std::vector<Eigen::Vector2d> sorted;
  sorted.reserve(points.size());
  for (const Eigen::Vector3d& p : points) sorted.push_back(p.head<2>());
  std::sort(sorted.begin(), sorted.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  if (sorted.size() < 3) return sorted;
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> hull;
  for (int pass = 0; pass < 2; ++pass) {  // lower chain, then upper
    const size_t start = hull.size();
    for (size_t k = 0; k < sorted.size(); ++k) {
      const Eigen::Vector2d& p = pass == 0 ? sorted[k] : sorted[sorted.size() - 1 - k];
      while (hull.size() >= start + 2 && cross(hull[hull.size() - 2], hull.back(), p) < 0) {
        hull.pop_back();
      }
      hull.push_back(p);
    }
  }
  return hull;
}

// The largest horizontal distance between two points: between two points of
// their horizontal hull (O(n log n + h^2) instead of O(n^2): a skeleton of
// 10^5 particles has 10^5 crown nodes).
double HorizontalDiameter(const std::vector<Eigen::Vector3d>& points) {
  const std::vector<Eigen::Vector2d> hull = HorizontalHull(points);
  double best = 0.0;
  for (size_t i = 0; i < hull.size(); ++i) {
    for (size_t j = i + 1; j < hull.size(); ++j) {
      best = std::max(best, (hull[i] - hull[j]).squaredNorm());
    }
  }
  return std::sqrt(best);
}

// Length of a branch axis (junction to tip).
double AxisLength(const SkeletonGraph& skeleton, const BranchAxis& axis) {
  double length = 0.0;
  for (size_t k = 1; k < axis.size(); ++k) {
    length += (skeleton.nodes[axis[k]].position - skeleton.nodes[axis[k - 1]].position).norm();
  }
  return length;
}

// Walks `path` (node indices starting at the junction) until `distance` from
// the start is reached; returns the unit direction to that node (zero if the
// path is degenerate).
Eigen::Vector3d DirectionAlong(const SkeletonGraph& skeleton, const std::vector<int>& path,
                               double distance) {
  const Eigen::Vector3d& from = skeleton.nodes[path[0]].position;
  Eigen::Vector3d to = from;
  double walked = 0.0;
  for (size_t k = 1; k < path.size() && (walked < distance || to == from); ++k) {
    walked += (skeleton.nodes[path[k]].position - skeleton.nodes[path[k - 1]].position).norm();
    to = skeleton.nodes[path[k]].position;
  }
  const Eigen::Vector3d direction = to - from;
  return direction.norm() > 0 ? Eigen::Vector3d(direction.normalized()) : Eigen::Vector3d::Zero();
}

// Branching angle of axis `a` in degrees: between its initial direction and
// its parent axis' direction at the junction (arriving there; leaving it when
// the junction is where the parent axis starts). Negative if not measurable.
double BranchingAngle(const SkeletonGraph& skeleton, const std::vector<BranchAxis>& axes,
                      const std::vector<int>& axis_of_node, int a, double direction_fraction) {
  const BranchAxis& axis = axes[a];  // axis[0] is the junction
  const double distance = direction_fraction * AxisLength(skeleton, axis);
  // From the branch's first node, so that a connector from the junction (a
  // QSM child cylinder starting off its parent's axis) does not count; from
  // the junction for a single-edge branch.
  const std::vector<int> from_first(axis.begin() + (axis.size() > 2 ? 1 : 0), axis.end());
  const Eigen::Vector3d branch = DirectionAlong(skeleton, from_first, distance);
  const BranchAxis& parent = axes[axis_of_node[axis[0]]];
  const int at =
      static_cast<int>(std::find(parent.begin(), parent.end(), axis[0]) - parent.begin());
  Eigen::Vector3d along_parent;
  if (at > 0) {
    const std::vector<int> back(parent.rend() - at - 1, parent.rend());  // junction, then backwards
    along_parent = -DirectionAlong(skeleton, back, distance);
  } else {
    along_parent = DirectionAlong(skeleton, parent, distance);
  }
  if (branch.isZero() || along_parent.isZero()) return -1.0;
  return std::acos(std::clamp(branch.dot(along_parent), -1.0, 1.0)) * kRadiansToDegrees;
}

// Per-order branch counts, lengths and angles.
std::vector<OrderMetrics> BranchMetrics(const SkeletonGraph& skeleton,
                                        const std::vector<BranchAxis>& axes,
                                        const std::vector<int>& orders, double direction_fraction) {
  const std::vector<int> axis_of_node = skeleton.AxisOfNodes(axes);
  const int max_order = *std::max_element(orders.begin(), orders.end());
  std::vector<OrderMetrics> metrics(max_order + 1);
  std::vector<std::vector<double>> angles(max_order + 1);
  for (size_t a = 0; a < axes.size(); ++a) {
    OrderMetrics& m = metrics[orders[a]];
    ++m.num_branches;
    m.total_length += AxisLength(skeleton, axes[a]);
    if (a == 0) continue;
    const double angle = BranchingAngle(skeleton, axes, axis_of_node, a, direction_fraction);
    if (angle >= 0) angles[orders[a]].push_back(angle);
  }
  for (int o = 0; o <= max_order; ++o) {
    OrderMetrics& m = metrics[o];
    m.order = o;
    m.num_angles = static_cast<int>(angles[o].size());
    if (angles[o].empty()) continue;
    double sum = 0.0;
    for (double angle : angles[o]) sum += angle;
    m.mean_angle_deg = sum / m.num_angles;
    m.median_angle_deg = Median(angles[o]);
  }
  return metrics;
}

// DBH from the trunk edge crossing `height` above the base.
void MeasureDbh(const SkeletonGraph& skeleton, const BranchAxis& trunk, const std::string& units,
                double dbh_height_m, TreeMetricsReport* report) {
  const double per_metre = UnitsPerMetre(units);
  if (per_metre == 0) {
    report->dbh_note = "units '" + units + "' are not metric (m, cm, mm): no breast height";
    return;
  }
  const double z = skeleton.nodes[trunk[0]].position.z() + dbh_height_m * per_metre;
  for (size_t k = 1; k < trunk.size(); ++k) {
    const double z0 = skeleton.nodes[trunk[k - 1]].position.z();
    const double z1 = skeleton.nodes[trunk[k]].position.z();
    if ((z0 <= z && z < z1) || (z1 <= z && z < z0)) {
      report->dbh = 2.0 * skeleton.nodes[trunk[k]].radius;
      report->dbh_note =
          "2 x the radius of the trunk edge at breast height; radii: " + skeleton.radius_source;
      return;
    }
  }
  report->dbh_note = "the trunk does not reach breast height";
}

// The crown volume's options for a tree `height` tall.
CrownVolumeOptions CrownVolumeOf(const TreeMetricsOptions& options, double height) {
  CrownVolumeOptions crown;
  crown.scale = options.crown_scale_fraction * height;
  crown.support_fraction = options.density_support_fraction;
  return crown;
}

// The labels of the figures (see the header).
std::vector<std::pair<std::string, std::string>> FigureSources(const std::string& radius_source,
                                                               const SkeletonSources& skeleton) {
  std::vector<std::pair<std::string, std::string>> sources;
  for (const char* figure :
       {"height", "crown_base_height", "crown_depth", "crown_width", "crown_volume_hull"}) {
    sources.emplace_back(figure, skeleton.positions);
  }
  sources.emplace_back("crown_volume_density", kMeasured);
  sources.emplace_back("dbh", radius_source);
  for (const char* figure : {"num_tips", "total_length", "orders"}) {
    sources.emplace_back(figure, skeleton.branching);
  }
  return sources;
}

}  // namespace

std::string TreeMetricsReport::SourceOf(const std::string& figure) const {
  for (const auto& [name, label] : sources) {
    if (name == figure) return label;
  }
  return "unknown";
}

TreeMetricsReport ComputeTreeMetrics(const SkeletonGraph& skeleton, const DensityGrid* density,
                                     const std::string& units, const TreeMetricsOptions& options,
                                     const SkeletonSources& sources) {
  options.Check();
  skeleton.Check();
  SYLVA_CHECK(skeleton.NumNodes() > 0) << "tree metrics of an empty skeleton";
  TreeMetricsReport report;
  report.units = units;
  report.radius_source = skeleton.radius_source;
  report.skeleton_sources = sources;
  report.sources = FigureSources(skeleton.radius_source, sources);
  report.num_nodes = skeleton.NumNodes();
  report.num_tips = static_cast<int>(skeleton.Tips().size());
  report.total_length = skeleton.TotalLength();
  report.height = skeleton.Height();
  const double base_z = skeleton.nodes[skeleton.RootIdx()].position.z();
  std::vector<int> orders;
  // Axes continue into the child of lowest node order first (see the header).
  const std::vector<BranchAxis> axes = skeleton.BranchAxes(
      [&skeleton](int node, const std::vector<int>& children) {
        return ContinuationByOrder(skeleton, node, children);
      },
      &orders);
  const std::optional<double> crown_base_z =
      CrownBaseZ(skeleton, axes, orders, options.major_branch_fraction);
  if (density != nullptr) {
    DensityCrown crown;
    if (crown_base_z) {
      crown = MeasureDensityCrown(*density, *crown_base_z, CrownVolumeOf(options, report.height));
    }
    report.crown_volume_density = crown.volume;
    // The leaves above the last branch tip.
    if (crown.top_z) report.height = std::max(report.height, *crown.top_z - base_z);
  }
  // A crown drooping below the base starts at the base.
  report.crown_base_height = crown_base_z ? std::max(0.0, *crown_base_z - base_z) : report.height;
  report.crown_depth = report.height - report.crown_base_height;
  if (crown_base_z) {
    std::vector<Eigen::Vector3d> crown;
    for (const SkeletonNode& node : skeleton.nodes) {
      if (node.position.z() - base_z >= report.crown_base_height) crown.push_back(node.position);
    }
    report.crown_width = HorizontalDiameter(crown);
    report.crown_volume_hull = ConvexHullVolume(crown);
  }
  MeasureDbh(skeleton, axes[0], units, options.dbh_height_m, &report);
  report.orders = BranchMetrics(skeleton, axes, orders, options.direction_fraction);
  return report;
}

namespace {

constexpr const char* kFormat = "sylva-tree-metrics";
constexpr int kVersion = 2;

Json AngleOrNull(const OrderMetrics& m, double angle) {
  return m.num_angles > 0 ? Json(angle) : Json(nullptr);
}

// What each source label sylva writes means.
Json SourceMeanings() {
  return {{kMeasured,
           "from the photos' evidence: the density reconstructed from the mattes, or the "
           "positions of a skeleton that follows it"},
          {kPrior,
           "follows from the model, not measured: the particle count and merging decide how "
           "many branches there are, how long and at what angles"},
          {"allometric prior",
           "radii from the pipe model, scaled to the trunk width: an estimate, not a measurement"},
          {"measured in the mattes",
           "radii from the pipe model's taper, each branch axis scaled to the width the mattes "
           "show (a low quantile over the views seeing it side-on); axes the mattes do not "
           "resolve are scaled like their parent"},
          {"ground truth", "exact (a synthetic tree)"},
          {"unknown", "not recorded by the source (e.g. a QSM table without source columns)"}};
}

}  // namespace

std::string TreeMetricsReport::ToJson() const {
  Json json;
  json["format"] = kFormat;
  json["version"] = kVersion;
  json["units"] = units;
  json["height"] = height;
  json["crown_base_height"] = crown_base_height;
  json["crown_depth"] = crown_depth;
  json["crown_width"] = crown_width;
  json["crown_volume_hull"] = crown_volume_hull;
  json["crown_volume_density"] = crown_volume_density ? Json(*crown_volume_density) : Json(nullptr);
  json["volume_units"] = units + "^3";
  json["dbh"] = dbh ? Json(*dbh) : Json(nullptr);
  json["dbh_note"] = dbh_note;
  json["num_nodes"] = num_nodes;
  json["num_tips"] = num_tips;
  json["total_length"] = total_length;
  json["angle_units"] = "degrees";
  json["orders"] = Json::array();
  for (const OrderMetrics& m : orders) {
    json["orders"].push_back({{"order", m.order},
                              {"num_branches", m.num_branches},
                              {"total_length", m.total_length},
                              {"num_angles", m.num_angles},
                              {"mean_angle_deg", AngleOrNull(m, m.mean_angle_deg)},
                              {"median_angle_deg", AngleOrNull(m, m.median_angle_deg)}});
  }
  json["radius_source"] = radius_source;
  json["position_source"] = skeleton_sources.positions;
  json["branching_source"] = skeleton_sources.branching;
  json["sources"] = Json::object();
  for (const auto& [figure, label] : sources) json["sources"][figure] = label;
  json["source_meanings"] = SourceMeanings();
  return json.dump(2);
}

void WriteTreeMetricsJson(const std::filesystem::path& path, const TreeMetricsReport& report) {
  AtomicWriteString(path, report.ToJson() + "\n");
}

namespace {

std::optional<double> OptionalDouble(const JsonCursor& value) {
  if (value.value().is_null()) return std::nullopt;
  return value.AsDouble();
}

OrderMetrics ReadOrderMetrics(const JsonCursor& json) {
  OrderMetrics m;
  m.order = json["order"].AsInt();
  m.num_branches = json["num_branches"].AsInt();
  m.total_length = json["total_length"].AsDouble();
  m.num_angles = json["num_angles"].AsInt();
  m.mean_angle_deg = OptionalDouble(json["mean_angle_deg"]).value_or(0.0);
  m.median_angle_deg = OptionalDouble(json["median_angle_deg"]).value_or(0.0);
  return m;
}

// The sources of a version 2 file.
void ReadSources(const JsonCursor& root, TreeMetricsReport* report) {
  report->radius_source = root["radius_source"].AsString();
  report->skeleton_sources.positions = root["position_source"].AsString();
  report->skeleton_sources.branching = root["branching_source"].AsString();
  const JsonCursor sources = root["sources"];
  if (!sources.IsObject()) sources.Fail("expected an object");
  for (const auto& [figure, label] : sources.value().items()) {
    report->sources.emplace_back(figure, sources[figure].AsString());
  }
}

}  // namespace

TreeMetricsReport ReadTreeMetricsJson(const std::filesystem::path& path) {
  const Json json = ReadJsonFile(path);
  const JsonCursor root(json, path.string());
  if (!root.IsObject() || !root.Has("format") || root["format"].AsString() != kFormat) {
    root.Fail(std::string("not a ") + kFormat + " file");
  }
  const int version = root["version"].AsInt();
  if (version < 1 || version > kVersion) {
    root["version"].Fail("unsupported version " + std::to_string(version) + " (1 to " +
                         std::to_string(kVersion) + " are read)");
  }
  TreeMetricsReport report;
  report.units = root["units"].AsString();
  report.height = root["height"].AsDouble();
  report.crown_base_height = root["crown_base_height"].AsDouble();
  report.crown_depth = root["crown_depth"].AsDouble();
  report.crown_width = root["crown_width"].AsDouble();
  report.crown_volume_hull = root["crown_volume_hull"].AsDouble();
  report.crown_volume_density = OptionalDouble(root["crown_volume_density"]);
  report.dbh = OptionalDouble(root["dbh"]);
  report.dbh_note = root["dbh_note"].AsString();
  report.num_nodes = root["num_nodes"].AsInt();
  report.num_tips = root["num_tips"].AsInt();
  report.total_length = root["total_length"].AsDouble();
  const JsonCursor orders = root["orders"];
  for (size_t k = 0; k < orders.Size(); ++k) report.orders.push_back(ReadOrderMetrics(orders[k]));
  if (version >= 2) ReadSources(root, &report);
  return report;
}

}  // namespace sylva
