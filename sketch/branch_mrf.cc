#include "sketch/branch_mrf.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/geometry/polyline.h"
#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Spreads below these are no information: a relation seen a few times must
// not become a spike.
constexpr double kMinScaleSd = 0.05;
constexpr double kMinAngleSd = 0.05;  // radians, about 3 degrees
// The spread of log(length ratio) is at least this (a factor of about 2).
constexpr double kMinLogScaleSd = 0.7;
// The trunk leaves the ground about upright: its angle to the vertical is a
// normal of this spread about 0 (radians).
constexpr double kTrunkAngleSd = 0.3;
// Segments closer than this fraction of the tree's size interpenetrate.
constexpr double kInterpenetration = 0.01;
// Propagated segments shorter than this fraction of the tree's size end
// their axis.
constexpr double kMinPropagatedLength = 0.004;
// Drawn segments longer than this fraction of the tree's size get lateral
// branches along them, this far apart.
constexpr double kLongSegment = 0.08;
// With a crown, propagation also stops after this many generations.
constexpr int kMaxCrownGenerations = 12;
// Exemplars are seen from this many azimuths.
constexpr int kFootprintAzimuths = 8;

double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

struct Accumulator {
  double sum = 0, sum2 = 0;
  int n = 0;
  void Add(double x) { sum += x, sum2 += x * x, ++n; }
  double Mean() const { return sum / n; }
  double Sd() const { return std::sqrt(std::max(0.0, sum2 / n - Mean() * Mean())); }
};

struct RelationAccumulator {
  Accumulator scale, angle;
  RelationStatistics Statistics(const RelationStatistics& fallback) const {
    if (scale.n < 2) return fallback;
    RelationStatistics s;
    s.scale_mean = scale.Mean();
    s.scale_sd = std::max(kMinScaleSd, scale.Sd());
    s.angle_mean = angle.Mean();
    s.angle_sd = std::max(kMinAngleSd, angle.Sd());
    s.count = scale.n;
    return s;
  }
};

// Omega of the relations of `tree` (apical by `apical`).
TreeParameters Learn(const SegmentTree& tree, const std::vector<int>& apical) {
  RelationAccumulator acc[2];  // 0 apical, 1 lateral
  for (int i = 0; i < tree.Size(); ++i) {
    const int p = tree.parent[i];
    if (p < 0 || tree.parent[p] < 0) continue;
    const Eigen::Vector3d vc = tree.points[i] - tree.points[p];
    const Eigen::Vector3d vp = tree.points[p] - tree.points[tree.parent[p]];
    if (vc.norm() <= 0 || vp.norm() <= 0) continue;
    RelationAccumulator& a = acc[apical[p] == i ? 0 : 1];
    a.scale.Add(vc.norm() / vp.norm());
    a.angle.Add(Angle(vp, vc));
  }
  const TreeParameters defaults;
  return {acc[0].Statistics(defaults.apical), acc[1].Statistics(defaults.lateral)};
}

// An orthonormal frame whose first axis is `v`'s direction, turned by
// `twist` about it.
Eigen::Matrix3d FrameAlong(const Eigen::Vector3d& v, double twist) {
  const Eigen::Vector3d e1 = v.normalized();
  Eigen::Vector3d helper =
      std::abs(e1.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d e2 = e1.cross(helper).normalized();
  const Eigen::Vector3d e3 = e1.cross(e2);
  Eigen::Matrix3d frame;
  frame.col(0) = e1;
  frame.col(1) = std::cos(twist) * e2 + std::sin(twist) * e3;
  frame.col(2) = -std::sin(twist) * e2 + std::cos(twist) * e3;
  return frame;
}

// The branch density grid of section 5.2.1 over a box.
class DensityGrid3 {
 public:
  DensityGrid3(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int cells, int reach)
      : lo_(lo), reach_(reach > 0 ? reach : cells) {
    voxel_ = std::max((hi - lo).maxCoeff() / cells, 1e-9);
    for (int a = 0; a < 3; ++a)
      dims_[a] = std::max(1, static_cast<int>(std::ceil((hi[a] - lo[a]) / voxel_)));
    values_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2], 0.0f);
  }
  void Add(const Eigen::Vector3d& p, float weight) {
    Eigen::Vector3i c;
    for (int a = 0; a < 3; ++a) {
      c[a] = std::clamp(static_cast<int>(std::floor((p[a] - lo_[a]) / voxel_)), 0, dims_[a] - 1);
    }
    values_[Index(c)] += weight;
  }
  // sum_v d_v / (1 + |p - p_v|^2 / voxel^2) over the voxels within reach
  // of p's.
  double Crowding(const Eigen::Vector3d& p) const {
    const int reach = reach_;
    Eigen::Vector3i c;
    for (int a = 0; a < 3; ++a) c[a] = static_cast<int>(std::floor((p[a] - lo_[a]) / voxel_));
    double sum = 0.0;
    for (int k = std::max(0, c.z() - reach); k <= std::min(dims_[2] - 1, c.z() + reach); ++k) {
      for (int j = std::max(0, c.y() - reach); j <= std::min(dims_[1] - 1, c.y() + reach); ++j) {
        for (int i = std::max(0, c.x() - reach); i <= std::min(dims_[0] - 1, c.x() + reach); ++i) {
          const float d = values_[Index({i, j, k})];
          if (d == 0.0f) continue;
          const Eigen::Vector3d center =
              lo_ + voxel_ * (Eigen::Vector3d(i, j, k).array() + 0.5).matrix();
          sum += d / (1.0 + (p - center).squaredNorm() / (voxel_ * voxel_));
        }
      }
    }
    return sum;
  }

 private:
  size_t Index(const Eigen::Vector3i& c) const {
    return (static_cast<size_t>(c.z()) * dims_[1] + c.y()) * dims_[0] + c.x();
  }
  Eigen::Vector3d lo_;
  int reach_ = 2;
  double voxel_ = 1.0;
  int dims_[3] = {1, 1, 1};
  std::vector<float> values_;
};

// The state of the inference: the drawn tree with depths.
class DepthField {
 public:
  DepthField(const SegmentTree& drawn, const Eigen::Vector3d& view_direction,
             const MrfOptions& options)
      : drawn_(drawn),
        view_(view_direction.normalized()),
        options_(options),
        children_(drawn.Children()),
        apical_(drawn.ApicalChildren()),
        depth_(drawn.Size(), 0.0),
        grid_(GridBox(drawn, view_, true), GridBox(drawn, view_, false), options.density_grid,
              options.crowding_reach) {
    Eigen::Vector3d lo = drawn.points[0], hi = lo;
    for (const Eigen::Vector3d& p : drawn.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    size_ = std::max((hi - lo).norm(), 1e-9);
  }

  const std::vector<std::vector<int>>& children() const { return children_; }
  double size() const { return size_; }
  double depth(int i) const { return depth_[i]; }
  Eigen::Vector3d Point(int i) const { return drawn_.points[i] + depth_[i] * view_; }
  Eigen::Vector3d Mid(int i) const { return 0.5 * (Point(i) + Point(drawn_.parent[i])); }
  int parent(int i) const { return drawn_.parent[i]; }
  int Size() const { return drawn_.Size(); }
  const TreeParameters& parameters() const { return parameters_; }
  void SetParameters(const TreeParameters& parameters) { parameters_ = parameters; }
  // The drawn (2D) length of segment i.
  double DrawnLength(int i) const { return (drawn_.points[i] - drawn_.points[parent(i)]).norm(); }

  // log P_sa of segment i given its parent segment (or the vertical).
  double LogRelation(int i) const {
    const int p = parent(i);
    const Eigen::Vector3d vc = Point(i) - Point(p);
    if (vc.norm() <= 0) return 0.0;
    if (parent(p) < 0) {
      const double a = Angle(Eigen::Vector3d::UnitZ(), vc);
      return -0.5 * a * a / (kTrunkAngleSd * kTrunkAngleSd);
    }
    const Eigen::Vector3d vp = Point(p) - Point(parent(p));
    if (vp.norm() <= 0) return 0.0;
    const bool apical = apical_[p] == i;
    const RelationStatistics& s = apical ? parameters_.apical : parameters_.lateral;
    // The length ratio in log space, never sharper than kMinLogScaleSd:
    // where branches leave an axis close together, the axis' internodes are
    // short, and a sharp ratio would stretch them in depth to fit it. An
    // axis' own internodes are as long as its branchings make them: no
    // ratio for apical relations.
    const double log_sd = std::max(kMinLogScaleSd, s.scale_sd / std::max(s.scale_mean, 1e-6));
    const double ds =
        apical ? 0.0 : std::log(vc.norm() / vp.norm() / std::max(s.scale_mean, 1e-6)) / log_sd;
    // An axis continues straight as often as it bends: the apical angle is
    // half-normal about 0 with the learnt root mean square, not a normal
    // about its mean (which would make a straight continuation improbable
    // and bend every drawn axis in depth).
    const double da = apical ? Angle(vp, vc) / std::hypot(s.angle_mean, s.angle_sd)
                             : (Angle(vp, vc) - s.angle_mean) / s.angle_sd;
    return -0.5 * (ds * ds + da * da);
  }
  // log P_d at segment i's end and middle.
  double LogCrowding(int i) const {
    return -options_.interaction * (grid_.Crowding(Point(i)) + grid_.Crowding(Mid(i)));
  }
  // Segment i's share of the branch density (the density sums to 1 over
  // the tree's segment ends and middles, so the interaction's weight does not
  // grow with the number of segments drawn).
  void Splat(int i, float sign) {
    const float weight = sign * 0.5f / std::max(1, Size() - 1);
    grid_.Add(Point(i), weight);
    grid_.Add(Mid(i), weight);
  }
  // Node i's factors: its own, its children's and grandchildren's relations
  // (their vectors move with it) and the crowding of the segments it ends
  // or starts.
  double LocalLogProbability(int i) const {
    double sum = LogRelation(i) + LogCrowding(i);
    for (int c : children_[i]) {
      sum += LogRelation(c) + LogCrowding(c);
      for (int g : children_[c]) sum += LogRelation(g);
    }
    return sum;
  }
  void RemoveSplats(int i) {
    Splat(i, -1.0f);
    for (int c : children_[i]) Splat(c, -1.0f);
  }
  void AddSplats(int i) {
    Splat(i, 1.0f);
    for (int c : children_[i]) Splat(c, 1.0f);
  }
  void SetDepth(int i, double depth) { depth_[i] = depth; }
  const std::vector<int>& apical() const { return apical_; }

 private:
  // The density grid's box: the drawing, and as deep as it is wide.
  static Eigen::Vector3d GridBox(const SegmentTree& drawn, const Eigen::Vector3d& view, bool lo) {
    Eigen::Vector3d a = drawn.points[0], b = a;
    for (const Eigen::Vector3d& p : drawn.points) a = a.cwiseMin(p), b = b.cwiseMax(p);
    const double reach = (b - a).norm();
    const Eigen::Vector3d slack = reach * view.cwiseAbs() + 1e-6 * Eigen::Vector3d::Ones();
    return lo ? Eigen::Vector3d(a - slack) : Eigen::Vector3d(b + slack);
  }

  const SegmentTree& drawn_;
  Eigen::Vector3d view_;
  MrfOptions options_;
  std::vector<std::vector<int>> children_;
  std::vector<int> apical_;
  std::vector<double> depth_;
  DensityGrid3 grid_;
  TreeParameters parameters_;
  double size_ = 1.0;
};

// Nodes parents first (the drawn tree's order already is).
std::vector<int> NonRootNodes(const DepthField& field) {
  std::vector<int> nodes;
  for (int i = 0; i < field.Size(); ++i) {
    if (field.parent(i) >= 0) nodes.push_back(i);
  }
  return nodes;
}

// Step 2: each segment's best depth given its parent and what is placed,
// candidates tried in a seeded order so that ties fall either way.
void BottomUp(const MrfOptions& options, RandomEngine* rng, DepthField* field) {
  const int k = options.depth_candidates;
  std::vector<int> order(k);
  for (int i : NonRootNodes(*field)) {
    const int p = field->parent(i);
    const int g = field->parent(p);
    const double parent_length = g >= 0 ? (field->Point(p) - field->Point(g)).norm() : 0.0;
    const double reach = 2.0 * std::max(field->DrawnLength(i), 0.5 * parent_length);
    std::iota(order.begin(), order.end(), 0);
    for (int a = k - 1; a > 0; --a) std::swap(order[a], order[rng->UniformInt(a + 1)]);
    double best = -1e300, best_depth = field->depth(p);
    for (int c : order) {
      const double depth = field->depth(p) + reach * (2.0 * c / (k - 1) - 1.0);
      field->SetDepth(i, depth);
      const double score = field->LogRelation(i) + field->LogCrowding(i);
      if (score > best) best = score, best_depth = depth;
    }
    field->SetDepth(i, best_depth);
    field->Splat(i, 1.0f);
  }
}

// The shortest distance between segments [a0, a1] and [b0, b1] (sampled).
double SegmentDistance(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                       const Eigen::Vector3d& b0, const Eigen::Vector3d& b1) {
  const Eigen::Vector3d u = a1 - a0, v = b1 - b0, w = a0 - b0;
  const double a = u.dot(u), b = u.dot(v), c = v.dot(v), d = u.dot(w), e = v.dot(w);
  const double den = a * c - b * b;
  double s = den > 1e-12 ? std::clamp((b * e - c * d) / den, 0.0, 1.0) : 0.0;
  double t = c > 1e-12 ? std::clamp((b * s + e) / c, 0.0, 1.0) : 0.0;
  s = a > 1e-12 ? std::clamp((b * t - d) / a, 0.0, 1.0) : 0.0;
  return (w + s * u - t * v).norm();
}

// Step 3: segments closer than kInterpenetration x size that do not share
// an end: the later one's end moves away along the line of sight.
int SeparateInterpenetrating(DepthField* field) {
  const int n = field->Size();
  constexpr int kMaxPairsNodes = 2000;  // O(n^2): the drawn tree only
  if (n > kMaxPairsNodes) return 0;
  const double gap = kInterpenetration * field->size();
  int moved = 0;
  for (int j = 0; j < n; ++j) {
    const int pj = field->parent(j);
    if (pj < 0) continue;
    for (int i = 0; i < j; ++i) {
      const int pi = field->parent(i);
      if (pi < 0 || pi == pj || pi == j || pj == i) continue;
      const double d =
          SegmentDistance(field->Point(pi), field->Point(i), field->Point(pj), field->Point(j));
      if (d >= gap) continue;
      const double side = field->depth(j) >= field->depth(i) ? 1.0 : -1.0;
      field->Splat(j, -1.0f);
      field->SetDepth(j, field->depth(j) + side * (gap - d + 1e-9));
      field->Splat(j, 1.0f);
      ++moved;
    }
  }
  return moved;
}

// Step 4: ICM. Returns the sweeps made.
int Icm(const MrfOptions& options, DepthField* field) {
  const std::vector<int> nodes = NonRootNodes(*field);
  std::vector<double> step(field->Size(), 0.0);
  for (int i : nodes) step[i] = std::max(field->DrawnLength(i), 1e-3 * field->size());
  const int k = options.depth_candidates;
  int sweep = 0;
  while (sweep < options.max_icm_sweeps) {
    ++sweep;
    double moved = 0.0;
    for (int i : nodes) {
      field->RemoveSplats(i);
      const double current = field->depth(i);
      double best = field->LocalLogProbability(i), best_depth = current;
      for (int c = 0; c < k; ++c) {
        const double depth = current + step[i] * (2.0 * c / (k - 1) - 1.0);
        field->SetDepth(i, depth);
        const double score = field->LocalLogProbability(i);
        if (score > best + 1e-12) best = score, best_depth = depth;
      }
      field->SetDepth(i, best_depth);
      field->AddSplats(i);
      if (best_depth == current) step[i] *= 0.5;
      moved += std::abs(best_depth - current);
    }
    if (moved < options.icm_epsilon * field->size()) break;
  }
  return sweep;
}

// Step 5's M-step: Omega of the current tree blended with the template's.
TreeParameters BlendedParameters(const DepthField& field, const TreeParameters& prior,
                                 double prior_weight) {
  SegmentTree tree;
  for (int i = 0; i < field.Size(); ++i) tree.AddPoint(field.Point(i), field.parent(i));
  const TreeParameters data = Learn(tree, field.apical());
  auto blend = [&](const RelationStatistics& t, const RelationStatistics& d) {
    if (d.count == 0) return t;
    const double w = prior_weight, n = d.count;
    RelationStatistics s;
    s.scale_mean = (w * t.scale_mean + n * d.scale_mean) / (w + n);
    s.angle_mean = (w * t.angle_mean + n * d.angle_mean) / (w + n);
    s.scale_sd = std::sqrt((w * t.scale_sd * t.scale_sd + n * d.scale_sd * d.scale_sd) / (w + n));
    s.angle_sd = std::sqrt((w * t.angle_sd * t.angle_sd + n * d.angle_sd * d.angle_sd) / (w + n));
    s.count = d.count;
    return s;
  };
  return {blend(prior.apical, data.apical), blend(prior.lateral, data.lateral)};
}

double ParameterChange(const TreeParameters& a, const TreeParameters& b) {
  auto diff = [](const RelationStatistics& x, const RelationStatistics& y) {
    return std::abs(x.scale_mean - y.scale_mean) + std::abs(x.angle_mean - y.angle_mean) +
           std::abs(x.scale_sd - y.scale_sd) + std::abs(x.angle_sd - y.angle_sd);
  };
  return diff(a.apical, b.apical) + diff(a.lateral, b.lateral);
}

// A replication block: a segment and its child segments, the children in
// the segment's frame (FrameAlong, twist 0) divided by its length.
struct Block {
  std::vector<Eigen::Vector3d> children;
};

std::vector<Block> BlocksOf(const SegmentTree& tree) {
  std::vector<Block> blocks;
  const std::vector<std::vector<int>> children = tree.Children();
  for (int p = 0; p < tree.Size(); ++p) {
    const int g = tree.parent[p];
    if (g < 0 || children[p].size() < 2) continue;
    const Eigen::Vector3d v = tree.points[p] - tree.points[g];
    if (v.norm() <= 0) continue;
    const Eigen::Matrix3d frame = FrameAlong(v, 0.0);
    Block block;
    for (int c : children[p]) {
      block.children.push_back(frame.transpose() * (tree.points[c] - tree.points[p]) / v.norm());
    }
    blocks.push_back(std::move(block));
  }
  return blocks;
}

// Where along [a, b] (a inside) the crown ends (bisection).
Eigen::Vector3d ClipToCrown(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const CrownTest& crown) {
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < 20; ++k) {
    const double mid = 0.5 * (lo + hi);
    (crown(a + mid * (b - a)) ? lo : hi) = mid;
  }
  return a + lo * (b - a);
}

}  // namespace

int SegmentTree::AddPoint(const Eigen::Vector3d& point, int parent_idx) {
  SYLVA_CHECK(parent_idx >= -1 && parent_idx < Size()) << "bad parent " << parent_idx;
  points.push_back(point);
  parent.push_back(parent_idx);
  return Size() - 1;
}

std::vector<std::vector<int>> SegmentTree::Children() const {
  std::vector<std::vector<int>> children(points.size());
  for (int i = 0; i < Size(); ++i) {
    if (parent[i] >= 0) children[parent[i]].push_back(i);
  }
  return children;
}

std::vector<int> SegmentTree::ApicalChildren(int drop_axis) const {
  auto flat = [drop_axis](Eigen::Vector3d v) {
    if (drop_axis >= 0 && drop_axis < 3) v[drop_axis] = 0.0;
    return v;
  };
  const std::vector<std::vector<int>> children = Children();
  std::vector<int> apical(points.size(), -1);
  for (int p = 0; p < Size(); ++p) {
    const Eigen::Vector3d own = parent[p] >= 0 ? flat(points[p] - points[parent[p]])
                                               : Eigen::Vector3d(Eigen::Vector3d::UnitZ());
    double best = 1e300;
    for (int c : children[p]) {
      const double a = Angle(own, flat(points[c] - points[p]));
      if (a < best) best = a, apical[p] = c;
    }
  }
  return apical;
}

SegmentTree SegmentTreeOfSkeleton(const SkeletonGraph& skeleton, double tolerance) {
  SegmentTree tree;
  const int root = skeleton.RootIdx();
  if (root < 0) return tree;
  const std::vector<std::vector<int>> children = skeleton.Children();
  tree.AddPoint(skeleton.nodes[root].position, -1);
  // (skeleton node, its index in `tree`) of kept nodes still to expand.
  std::vector<std::pair<int, int>> stack = {{root, 0}};
  while (!stack.empty()) {
    const auto [node, kept] = stack.back();
    stack.pop_back();
    for (int child : children[node]) {
      std::vector<int> chain = {node, child};
      while (children[chain.back()].size() == 1) chain.push_back(children[chain.back()][0]);
      std::vector<Eigen::Vector3d> points;
      for (int c : chain) points.push_back(skeleton.nodes[c].position);
      std::vector<char> keep(points.size(), 0);
      DouglasPeucker(
          static_cast<int>(points.size()), [&](int k) { return points[k]; }, tolerance, &keep);
      int last = kept;
      for (size_t k = 1; k < points.size(); ++k) {
        if (keep[k]) last = tree.AddPoint(points[k], last);
      }
      stack.push_back({chain.back(), last});
    }
  }
  return tree;
}

TreeParameters LearnTreeParameters(const SegmentTree& tree) {
  return Learn(tree, tree.ApicalChildren());
}

double Footprint::Distance(const Footprint& other) const {
  return std::abs(aspect - other.aspect) / 0.5 + std::abs(scale_2d - other.scale_2d) / 0.3 +
         std::abs(apical_2d - other.apical_2d) / 0.3 +
         std::abs(lateral_2d - other.lateral_2d) / 0.3;
}

Footprint FootprintOf(const std::vector<Eigen::Vector2d>& points, const std::vector<int>& parent) {
  SegmentTree tree;
  for (size_t i = 0; i < points.size(); ++i) {
    tree.points.emplace_back(points[i].x(), 0.0, points[i].y());
    tree.parent.push_back(parent[i]);
  }
  Footprint footprint;
  if (points.empty()) return footprint;
  Eigen::Vector2d lo = points[0], hi = points[0];
  for (const Eigen::Vector2d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  footprint.aspect = (hi.x() - lo.x()) / std::max(hi.y() - lo.y(), 1e-9);
  const TreeParameters params = LearnTreeParameters(tree);
  if (params.apical.count > 0) {
    footprint.scale_2d = params.apical.scale_mean;
    footprint.apical_2d = params.apical.angle_mean;
  }
  if (params.lateral.count > 0) footprint.lateral_2d = params.lateral.angle_mean;
  return footprint;
}

TreeExemplar MakeExemplar(const std::string& name, const SkeletonGraph& skeleton) {
  TreeExemplar exemplar;
  exemplar.name = name;
  exemplar.tree = SegmentTreeOfSkeleton(skeleton, std::numeric_limits<double>::infinity());
  exemplar.parameters = LearnTreeParameters(exemplar.tree);
  for (int a = 0; a < kFootprintAzimuths; ++a) {
    const double angle = 2.0 * kPi * a / kFootprintAzimuths;
    const Eigen::Vector2d across(std::cos(angle), std::sin(angle));
    std::vector<Eigen::Vector2d> points;
    for (const Eigen::Vector3d& p : exemplar.tree.points) {
      points.emplace_back(across.dot(p.head<2>()), p.z());
    }
    exemplar.footprints.push_back(FootprintOf(points, exemplar.tree.parent));
  }
  return exemplar;
}

int SelectTemplate(const std::vector<TreeExemplar>& exemplars, const Footprint& footprint) {
  int best = -1;
  double best_distance = 1e300;
  for (size_t e = 0; e < exemplars.size(); ++e) {
    for (const Footprint& f : exemplars[e].footprints) {
      const double d = f.Distance(footprint);
      if (d < best_distance) best_distance = d, best = static_cast<int>(e);
    }
  }
  return best;
}

namespace {

// Where `p` lies against a crown's slice: (across offset from the span's
// middle, depth, the span's half width); false outside the drawn heights.
bool SliceOf(const CrownOfRevolution& crown, const Eigen::Vector3d& p, double* x, double* z,
             double* radius) {
  const Eigen::Vector3d d = p - crown.origin;
  const int k = static_cast<int>(std::floor((d.dot(crown.up) - crown.bottom) / crown.step));
  if (k < 0 || k >= static_cast<int>(crown.spans.size())) return false;
  const auto [lo, hi] = crown.spans[k];
  if (lo > hi) return false;
  *x = d.dot(crown.across) - 0.5 * (lo + hi);
  *z = d.dot(crown.up.cross(crown.across));
  *radius = 0.5 * (hi - lo);
  return true;
}

}  // namespace

bool CrownOfRevolution::Contains(const Eigen::Vector3d& p) const {
  double x, z, radius;
  if (!SliceOf(*this, p, &x, &z, &radius)) return false;
  z /= depth_scale;
  return x * x + z * z <= radius * radius;
}

void CrownOfRevolution::DeepenToHold(const std::vector<Eigen::Vector3d>& points, double max_scale) {
  for (const Eigen::Vector3d& p : points) {
    double x, z, radius;
    if (!SliceOf(*this, p, &x, &z, &radius) || std::abs(x) >= radius) continue;
    const double needed = std::abs(z) / std::sqrt(radius * radius - x * x);
    depth_scale = std::clamp(needed * 1.01, depth_scale, max_scale);
  }
}

MrfResult InferBranchDepths(const SegmentTree& drawn, const Eigen::Vector3d& view_direction,
                            const TreeParameters& template_parameters, const MrfOptions& options) {
  options.Check();
  SYLVA_CHECK(drawn.Size() >= 1 && drawn.parent[0] == -1) << "the drawn tree needs its root first";
  for (int i = 1; i < drawn.Size(); ++i) {
    SYLVA_CHECK(drawn.parent[i] >= 0 && drawn.parent[i] < i) << "parents must come first";
  }
  RandomEngine rng(DeriveSeed(options.seed, 0x6d7266));
  DepthField field(drawn, view_direction, options);
  field.SetParameters(template_parameters);
  MrfResult result;
  BottomUp(options, &rng, &field);
  result.interpenetrations = SeparateInterpenetrating(&field);
  result.icm_sweeps = Icm(options, &field);
  for (int round = 0; round < options.em_iterations; ++round) {
    const TreeParameters next = BlendedParameters(field, template_parameters, options.prior_weight);
    const double change = ParameterChange(next, field.parameters());
    field.SetParameters(next);
    ++result.em_iterations;
    result.icm_sweeps += Icm(options, &field);
    if (change < 1e-3) break;
  }
  result.parameters = field.parameters();
  for (int i = 0; i < field.Size(); ++i) result.tree.AddPoint(field.Point(i), field.parent(i));
  result.drawn = field.Size();
  return result;
}

void PropagateBranches(const SegmentTree& fallback, const CrownTest& crown,
                       const MrfOptions& options, MrfResult* result) {
  options.Check();
  SegmentTree& tree = result->tree;
  std::vector<Block> blocks = BlocksOf(tree);
  if (blocks.empty()) blocks = BlocksOf(fallback);
  if (blocks.empty() || tree.Size() < 2) return;
  Eigen::Vector3d lo = tree.points[0], hi = lo;
  for (const Eigen::Vector3d& p : tree.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double min_length = kMinPropagatedLength * std::max((hi - lo).norm(), 1e-9);
  RandomEngine rng(DeriveSeed(options.seed, 0x70726f70));
  std::vector<int> open;
  const std::vector<std::vector<int>> children = tree.Children();
  for (int i = 0; i < tree.Size(); ++i) {
    if (tree.parent[i] >= 0 && children[i].empty()) open.push_back(i);
  }
  // New lateral branches along disproportionately long segments (section
  // 6): each drawn segment longer than kLongSegment x the tree's size gets
  // laterals at even steps, from a block's children turned onto the piece
  // below.
  const double size = (hi - lo).norm();
  const int drawn = tree.Size();
  for (int i = 0; i < drawn; ++i) {
    const int p = tree.parent[i];
    if (p < 0) continue;
    const Eigen::Vector3d a = tree.points[p], b = tree.points[i];
    const int pieces = static_cast<int>((b - a).norm() / (kLongSegment * size));
    // The trunk's first segment is bare in its lowest third (a crown, when
    // drawn, decides instead).
    const int first = tree.parent[p] < 0 && !crown ? std::max(1, pieces / 3) : 1;
    for (int k = first; k < pieces; ++k) {
      if (tree.Size() >= options.max_segments) return;
      const Eigen::Vector3d base = a + (b - a) * (static_cast<double>(k) / pieces);
      const Eigen::Vector3d v = (b - a) / pieces;
      const Block& block = blocks[rng.UniformInt(static_cast<uint32_t>(blocks.size()))];
      const Eigen::Matrix3d frame = FrameAlong(v, rng.Uniform(0.0, 2.0 * kPi));
      // The block's most lateral child (the largest angle to its axis).
      const Eigen::Vector3d* lateral = &block.children[0];
      for (const Eigen::Vector3d& c : block.children) {
        if (c.normalized().x() < lateral->normalized().x()) lateral = &c;
      }
      Eigen::Vector3d end = base + v.norm() * (frame * *lateral);
      bool clipped = false;
      if (crown && !crown(base)) continue;
      if (crown && !crown(end)) end = ClipToCrown(base, end, crown), clipped = true;
      if ((end - base).norm() < min_length) continue;
      // The lateral hangs from a point of its own on the segment.
      const int joint = tree.AddPoint(base, p);
      const int added = tree.AddPoint(end, joint);
      if (!clipped) open.push_back(added);
    }
  }
  const int generations = crown ? kMaxCrownGenerations : options.generations;
  for (int g = 0; g < generations && !open.empty(); ++g) {
    std::vector<int> next;
    for (int tip : open) {
      if (tree.Size() >= options.max_segments) return;
      const Eigen::Vector3d base = tree.points[tip];
      if (crown && !crown(base)) continue;
      const Eigen::Vector3d v = base - tree.points[tree.parent[tip]];
      if (v.norm() < min_length) continue;
      const Block& block = blocks[rng.UniformInt(static_cast<uint32_t>(blocks.size()))];
      const Eigen::Matrix3d frame = FrameAlong(v, rng.Uniform(0.0, 2.0 * kPi));
      for (const Eigen::Vector3d& child : block.children) {
        if (tree.Size() >= options.max_segments) return;
        Eigen::Vector3d end = base + v.norm() * (frame * child);
        bool clipped = false;
        if (crown && !crown(end)) end = ClipToCrown(base, end, crown), clipped = true;
        if ((end - base).norm() < min_length) continue;
        const int added = tree.AddPoint(end, tip);
        if (!clipped) next.push_back(added);
      }
    }
    open = std::move(next);
  }
}

SkeletonGraph SkeletonOfSegments(const SegmentTree& tree, double max_edge) {
  SYLVA_CHECK(max_edge > 0) << "max_edge must be > 0";
  SkeletonGraph skeleton;
  std::vector<int> node_of(tree.points.size(), -1);
  for (int i = 0; i < tree.Size(); ++i) {
    const int p = tree.parent[i];
    if (p < 0) {
      node_of[i] = skeleton.AddNode(tree.points[i], 0.0, -1, 0);
      continue;
    }
    const Eigen::Vector3d a = tree.points[p], b = tree.points[i];
    const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / max_edge)));
    int last = node_of[p];
    for (int k = 1; k <= pieces; ++k) {
      last = skeleton.AddNode(a + (b - a) * (static_cast<double>(k) / pieces), 0.0, last, 0);
    }
    node_of[i] = last;
  }
  skeleton.AssignOrders();
  return skeleton;
}

}  // namespace sylva
