#include "simulate/skeleton_consolidation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "core/util/check.h"
#include "simulate/skeleton_editing.h"

namespace sylva {
namespace {

// Points every `spacing` (at most) along the edge from `parent` to `child`,
// the parent end excluded.
std::vector<Eigen::Vector3d> EdgeSamples(const Eigen::Vector3d& parent,
                                         const Eigen::Vector3d& child, double spacing) {
  const int steps = std::max(1, static_cast<int>(std::ceil((child - parent).norm() / spacing)));
  std::vector<Eigen::Vector3d> samples;
  for (int s = 1; s <= steps; ++s)
    samples.push_back(parent + (child - parent) * (double(s) / steps));
  return samples;
}

// Samples along every edge, each owned by the edge's child node, bucketed in
// a hash grid whose cells are `radius` wide: "is there wood within radius,
// other than these nodes'?" looks at 27 cells.
class WoodSamples {
 public:
  WoodSamples(const SkeletonGraph& skeleton, double radius, double spacing)
      : WoodSamples(skeleton, spacing, std::vector<double>(skeleton.NumNodes(), radius)) {}
  // Each edge's samples with their own radius: its child node's entry of
  // `radii` (edges with radius 0 are left out).
  WoodSamples(const SkeletonGraph& skeleton, double spacing, const std::vector<double>& radii)
      : radius_(std::max(spacing, *std::max_element(radii.begin(), radii.end()))) {
    for (int i = 0; i < skeleton.NumNodes(); ++i) {
      const int parent = skeleton.nodes[i].parent_idx;
      if (parent < 0 || !(radii[i] > 0)) continue;
      for (const Eigen::Vector3d& point :
           EdgeSamples(skeleton.nodes[parent].position, skeleton.nodes[i].position, spacing)) {
        cells_[Key(Cell(point))].push_back(static_cast<int>(points_.size()));
        points_.push_back(point);
        radii_.push_back(radii[i]);
        owners_.push_back(i);
      }
    }
  }

  // Whether a sample whose owner passes `counts(owner)` (or
  // `counts(owner, sample point)`) lies within radius.
  template <typename Counts>
  bool AnyWithin(const Eigen::Vector3d& query, const Counts& counts) const {
    const Eigen::Vector3i centre = Cell(query);
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const auto found = cells_.find(Key(centre + Eigen::Vector3i(dx, dy, dz)));
          if (found == cells_.end()) continue;
          for (int s : found->second) {
            if ((points_[s] - query).norm() > radii_[s]) continue;
            if constexpr (std::is_invocable_v<Counts, int, const Eigen::Vector3d&>) {
              if (counts(owners_[s], points_[s])) return true;
            } else {
              if (counts(owners_[s])) return true;
            }
          }
        }
      }
    }
    return false;
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const {
    return (p / radius_).array().floor().cast<int>();
  }
  static int64_t Key(const Eigen::Vector3i& c) {
    return (static_cast<int64_t>(c.x() & 0x1FFFFF) << 42) |
           (static_cast<int64_t>(c.y() & 0x1FFFFF) << 21) | static_cast<int64_t>(c.z() & 0x1FFFFF);
  }

  double radius_;  // the largest sample radius: the cells' width
  std::vector<Eigen::Vector3d> points_;
  std::vector<double> radii_;
  std::vector<int> owners_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
};

// The share of the (2r+1)^3 voxels around `point` (world), r =
// support_radius_voxels, whose opacity reaches support_opacity: how much the
// density holds there. Wood seen in the photos shows as occupied voxels
// along it; a trace across a gap, or off to the side of a branch, does not.
double Support(const DensityGrid& density, const Eigen::Vector3d& point,
               const ConsolidationOptions& options) {
  const Eigen::Vector3i centre = density.IndexFromWorld(point).array().round().cast<int>();
  const int r = options.support_radius_voxels;
  int occupied = 0;
  for (int dz = -r; dz <= r; ++dz) {
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        occupied += density.Value(centre + Eigen::Vector3i(dx, dy, dz)) >= options.support_opacity;
      }
    }
  }
  return occupied / std::pow(2.0 * r + 1, 3);
}

// Strands `moved` off a removed child of `node` go on down the heaviest
// remaining children to a tip (its particles did flow into that wood), so
// every junction still carries the sum of its children.
void CarryDown(int node, int moved, const std::vector<std::vector<int>>& children,
               const std::vector<char>& removed, std::vector<int>* strands) {
  for (;;) {
    int heaviest = -1;
    for (int child : children[node]) {
      if (!removed[child] && (heaviest < 0 || (*strands)[child] > (*strands)[heaviest])) {
        heaviest = child;
      }
    }
    if (heaviest < 0) return;
    (*strands)[heaviest] += moved;
    node = heaviest;
  }
}

// Step 1: trims every axis, the trunk included, from its tip while its edges
// lie within `radius` of wood on another axis or the density does not
// support them;
// returns the removed nodes. The trimmed particles did flow into the wood
// that stays: where a trimmed stretch left a node that keeps other children,
// its strands move onto that node's heaviest remaining child and on down
// the heaviest children to a tip (a new tip keeps its own), so every
// junction still carries the sum of its children and the root all of them.
// `strands` (in: the skeleton's) receives the moved counts.
std::vector<char> TrimTwigs(const SkeletonGraph& skeleton, const DensityGrid& density,
                            const ConsolidationOptions& options, double radius, double spacing,
                            std::vector<int>* strands) {
  std::vector<char> removed(skeleton.NumNodes(), 0);
  const std::vector<BranchAxis> axes = skeleton.BranchAxes();
  const std::vector<int> axis_of = skeleton.AxisOfNodes(axes);
  const WoodSamples wood(skeleton, std::max(radius, spacing), spacing);
  const std::vector<std::vector<int>> children = skeleton.Children();
  // Axes are listed by order: backwards, the outermost go first.
  for (int a = static_cast<int>(axes.size()) - 1; a >= 0; --a) {
    const BranchAxis& axis = axes[a];
    // Nodes up to the last one still carrying a side branch stay (0: none).
    size_t keep = 0;
    for (size_t k = 1; k < axis.size(); ++k) {
      for (int child : children[axis[k]]) {
        if (!removed[child] && (k + 1 == axis.size() || child != axis[k + 1])) keep = k;
      }
    }
    const auto other_wood = [&](int owner) { return !removed[owner] && axis_of[owner] != a; };
    size_t first_removed = axis.size();
    for (size_t k = axis.size() - 1; k > keep; --k) {
      const std::vector<Eigen::Vector3d> samples = EdgeSamples(
          skeleton.nodes[axis[k - 1]].position, skeleton.nodes[axis[k]].position, spacing);
      const bool redundant =
          radius > 0 && std::all_of(samples.begin(), samples.end(), [&](const Eigen::Vector3d& p) {
            return wood.AnyWithin(p, other_wood);
          });
      double support = 0;
      if (!redundant && options.min_support > 0) {
        for (const Eigen::Vector3d& p : samples) support += Support(density, p, options);
        support /= samples.size();
      }
      if (!redundant && support >= options.min_support) break;
      removed[axis[k]] = 1;
      first_removed = k;
    }
    // The node left where the trim stopped: a junction (the whole axis went)
    // or the last side branch's node still has children.
    if (first_removed < axis.size() && (first_removed == 1 || first_removed - 1 == keep)) {
      CarryDown(axis[first_removed - 1], (*strands)[axis[first_removed]], children, removed,
                strands);
    }
  }
  return removed;
}

// Step 2: zips stretches that run beside their parent axis. A bundle of
// particles that flowed beside its parent to join it lower down traces the
// parent's wood twice (on laser-scanned trees, limbs beside the trunk for a
// fifth of its height, a few centimetres from it; in drawn crowns, limbs
// beside a drawn trunk). Such an axis starts instead where it leaves the
// parent: its first stretch, while within `radius` of the parent axis,
// goes, and the first node beyond it joins the parent axis' nearest node at
// or above the old junction. Side branches that grew from the stretch grow
// from the parent's nearest point instead, at the height they grew at (a
// new node splits the parent's edge there). The parent's nodes between the
// old junction and each new one carry what joins there (its particles
// flowed down that wood).
// Axes are zipped trunk first, so a zipped parent is final before its
// children; the result lists parents before children.
class StretchZipper {
 public:
  StretchZipper(const SkeletonGraph& skeleton, double radius, double max_spacing)
      // Samples at most half the radius apart, so that a stretch between two
      // samples cannot stray far beyond the radius unseen.
      : spacing_(std::min(max_spacing, 0.5 * radius)),
        wood_(skeleton, radius, spacing_),
        children_(skeleton.Children()),
        axes_(skeleton.BranchAxes()),
        axis_of_(skeleton.AxisOfNodes(axes_)),
        result_(skeleton),
        removed_(skeleton.NumNodes(), 0) {}

  SkeletonGraph Zip(int* zipped_axes) {
    for (size_t a = 1; a < axes_.size(); ++a) {
      // A side branch of a zipped stretch now grows from the grandparent
      // axis (its junction is gone): it is left as it is.
      if (removed_[axes_[a][0]]) continue;
      if (ZipAxis(axes_[a])) ++*zipped_axes;
    }
    return ParentsFirst(WithoutNodes(result_, removed_));
  }

 private:
  // Zips `axis` (a copy: its parent's node list may grow) if its first edge
  // runs beside its parent axis.
  bool ZipAxis(const BranchAxis axis) {
    parent_axis_ = axis_of_[axis[0]];
    const size_t leave = FirstNodeLeaving(axis);
    if (leave == 1) return false;
    const BranchAxis& parent = axes_[parent_axis_];
    at_ = std::find(parent.begin(), parent.end(), axis[0]) - parent.begin();
    for (size_t k = 1; k < leave; ++k) {
      int started_here = result_.nodes[axis[k]].strands;  // particles seeded on the stretch
      for (int child : children_[axis[k]]) {
        started_here -= result_.nodes[child].strands;
        if (child == axis[k + 1]) continue;
        const size_t to = NearestPoint(result_.nodes[axis[k]].position);
        result_.nodes[child].parent_idx = Carry(to, result_.nodes[child].strands);
      }
      if (started_here > 0) Carry(NearestNode(result_.nodes[axis[k]].position), started_here);
      removed_[axis[k]] = 1;
    }
    const int free = axis[leave];
    result_.nodes[free].parent_idx =
        Carry(NearestNode(result_.nodes[free].position), result_.nodes[free].strands);
    return true;
  }

  // The first node of `axis` whose edge leaves the parent axis' wood.
  size_t FirstNodeLeaving(const BranchAxis& axis) const {
    const auto beside_parent = [&](int owner) {
      return !removed_[owner] && axis_of_[owner] == parent_axis_;
    };
    size_t leave = 1;
    while (leave + 1 < axis.size()) {
      const std::vector<Eigen::Vector3d> samples = EdgeSamples(
          result_.nodes[axis[leave - 1]].position, result_.nodes[axis[leave]].position, spacing_);
      const bool beside = std::all_of(samples.begin(), samples.end(), [&](const auto& p) {
        return wood_.AnyWithin(p, beside_parent);
      });
      if (!beside) break;
      ++leave;
    }
    return leave;
  }

  // Adds `strands` to the parent from the old junction up to its node k;
  // returns that node.
  int Carry(size_t k, int strands) {
    const BranchAxis& parent = axes_[parent_axis_];
    for (size_t i = at_ + 1; i <= k; ++i) result_.nodes[parent[i]].strands += strands;
    return parent[k];
  }

  // The parent's nearest node to `point` at or above the junction, short of
  // its tip (whose strands are the particles that started there, not the
  // sum of children it would gain).
  size_t NearestNode(const Eigen::Vector3d& point) const {
    const BranchAxis& parent = axes_[parent_axis_];
    size_t nearest = at_;
    for (size_t k = at_; k + 1 < parent.size(); ++k) {
      if ((result_.nodes[parent[k]].position - point).norm() <
          (result_.nodes[parent[nearest]].position - point).norm()) {
        nearest = k;
      }
    }
    return nearest;
  }

  // The parent's nearest point to `point` above the junction: a node, or a
  // new node splitting the edge it lies on (a side branch keeps the height
  // it grew at).
  size_t NearestPoint(const Eigen::Vector3d& point) {
    BranchAxis& parent = axes_[parent_axis_];
    size_t best_edge = at_ + 1;
    double best_t = 0.0, best_d = std::numeric_limits<double>::infinity();
    for (size_t k = at_ + 1; k < parent.size(); ++k) {
      const Eigen::Vector3d& from = result_.nodes[parent[k - 1]].position;
      const Eigen::Vector3d edge = result_.nodes[parent[k]].position - from;
      const double t = std::clamp((point - from).dot(edge) / std::max(edge.squaredNorm(), 1e-300),
                                  0.0, k + 1 < parent.size() ? 1.0 : 0.5);
      const double d = (from + t * edge - point).norm();
      if (d < best_d) best_edge = k, best_t = t, best_d = d;
    }
    constexpr double kAtNode = 1e-6;
    if (best_t < kAtNode) return best_edge - 1;
    if (best_t > 1 - kAtNode) return best_edge;
    const SkeletonNode& upper = result_.nodes[parent[best_edge]];
    const SkeletonNode& lower = result_.nodes[parent[best_edge - 1]];
    const int split = result_.AddNode((1 - best_t) * lower.position + best_t * upper.position,
                                      (1 - best_t) * lower.radius + best_t * upper.radius,
                                      upper.parent_idx, upper.order);
    result_.nodes[split].strands = result_.nodes[parent[best_edge]].strands;
    result_.nodes[parent[best_edge]].parent_idx = split;
    removed_.push_back(0);
    axis_of_.push_back(parent_axis_);
    parent.insert(parent.begin() + best_edge, split);
    return best_edge;
  }

  const double spacing_;
  const WoodSamples wood_;
  const std::vector<std::vector<int>> children_;
  // Each axis' nodes as they are now: side branches moved onto a parent
  // split its edges where they join.
  std::vector<BranchAxis> axes_;
  std::vector<int> axis_of_;
  SkeletonGraph result_;
  std::vector<char> removed_;
  // The axis being zipped: its parent axis, and the index of its junction
  // on that axis.
  int parent_axis_ = -1;
  size_t at_ = 0;
};

SkeletonGraph ZipParallelStretches(const SkeletonGraph& skeleton, double radius, double max_spacing,
                                   int* zipped_axes) {
  return StretchZipper(skeleton, radius, max_spacing).Zip(zipped_axes);
}

// Step 2b: joins stretches that run beside other wood of the tree. Two
// bundles of particles that took the same path at different times (the
// first still flowing when the second passed) each leave a trace: one
// branch drawn twice, side by side, by traces that part again further up
// or down (step 1 sees only tips, step 2 only a branch's own parent). A
// stretch of at least 3 radii whose edges lie within `radius` of thicker
// wood (ties: the earlier node), more than 3 radii from it along the
// skeleton, is the second trace: its upper end joins that wood at the
// nearest point, with what it carries; the old path down to where both
// meet loses those strands, the new one gains them, and wood left carrying
// nothing goes. Passes repeat until nothing joins (at most 8).
class DuplicateJoiner {
 public:
  DuplicateJoiner(double radius, double max_spacing)
      : radius_(radius), spacing_(std::min(max_spacing, 0.5 * radius)) {}

  SkeletonGraph Join(SkeletonGraph skeleton, int* joined) {
    skeleton = Subdivided(skeleton, radius_);
    for (int pass = 0; pass < kMaxPasses; ++pass) {
      const int joins = Pass(&skeleton);
      *joined += joins;
      if (joins == 0) break;
    }
    return WithoutPassThroughNodes(skeleton);
  }

 private:
  struct Target {
    int owner = -1;  // the child node of the edge joined
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
  };

  // One pass over `skeleton` (parents first); returns the joins made.
  int Pass(SkeletonGraph* skeleton) {
    const int n = skeleton->NumNodes();
    nodes_ = &skeleton->nodes;
    const SkeletonPathLengths paths(*skeleton);
    paths_ = &paths;
    const WoodSamples wood(*skeleton, radius_, spacing_);
    wood_ = &wood;
    // Per node: its edge lies beside other, thicker wood; and where.
    std::vector<char> beside(n, 0);
    std::vector<Target> targets(n);
    for (int i = 0; i < n; ++i) {
      if (Parent(i) < 0) continue;
      beside[i] = EdgeBeside(i, &targets[i]);
    }
    const std::vector<std::vector<int>> children = skeleton->Children();
    std::vector<char> touched(n, 0);
    int joins = 0;
    // Tips first: the upper end of each beside stretch joins.
    for (int u = n - 1; u > 0; --u) {
      if (!beside[u] || touched[u]) continue;
      bool top = true;
      for (int child : children[u]) top = top && !beside[child];
      if (!top || BesideLength(u, beside) < kDuplicateApart * radius_) continue;
      const int owner = targets[u].owner;
      if (touched[owner] || IsAncestor(u, owner)) continue;
      // A child moved or split this pass: u waits for the next one.
      bool child_touched = false;
      for (int child : children[u]) child_touched = child_touched || touched[child];
      if (child_touched) continue;
      const int moved = (*nodes_)[u].strands;
      // The joint: an end of the owner's edge, or a node splitting it.
      const int joint = JointOn(skeleton, owner, targets[u].point);
      nodes_ = &skeleton->nodes;
      touched.resize(skeleton->NumNodes(), 0);
      touched[owner] = touched[joint] = 1;
      // u's children hang from the joint; u's strands leave its old path and
      // follow the new one, down to where the two meet.
      for (int child : children[u]) (*nodes_)[child].parent_idx = joint, touched[child] = 1;
      for (int k = u; k >= 0; k = Parent(k)) (*nodes_)[k].strands -= moved, touched[k] = 1;
      for (int k = joint; k >= 0; k = Parent(k)) (*nodes_)[k].strands += moved;
      ++joins;
    }
    if (joins == 0) return 0;
    // Wood that carries nothing now goes (never the root), from the tips
    // down: a node goes once all its children have.
    const std::vector<std::vector<int>> now = skeleton->Children();
    std::vector<char> removed(skeleton->NumNodes(), 0);
    for (bool changed = true; changed;) {
      changed = false;
      for (int i = 0; i < skeleton->NumNodes(); ++i) {
        if (removed[i] || Parent(i) < 0 || (*nodes_)[i].strands > 0) continue;
        if (std::all_of(now[i].begin(), now[i].end(), [&](int c) { return removed[c] != 0; })) {
          removed[i] = 1;
          changed = true;
        }
      }
    }
    *skeleton = ParentsFirst(WithoutNodes(*skeleton, removed));
    return joins;
  }

  const Eigen::Vector3d& Position(int i) const { return (*nodes_)[i].position; }
  int Parent(int i) const { return (*nodes_)[i].parent_idx; }

  // Without the nodes that only continue a straight edge (one child, the
  // same strands, on the segment from their parent to it): the subdivision's
  // nodes that no join used.
  static SkeletonGraph WithoutPassThroughNodes(SkeletonGraph skeleton) {
    const std::vector<std::vector<int>> children = skeleton.Children();
    std::vector<char> removed(skeleton.NumNodes(), 0);
    for (int i = 0; i < skeleton.NumNodes(); ++i) {
      const int parent = skeleton.nodes[i].parent_idx;
      if (parent < 0 || children[i].size() != 1) continue;
      const int child = children[i][0];
      if (skeleton.nodes[child].strands != skeleton.nodes[i].strands) continue;
      const Eigen::Vector3d& from = skeleton.nodes[parent].position;
      const Eigen::Vector3d edge = skeleton.nodes[child].position - from;
      const Eigen::Vector3d offset = skeleton.nodes[i].position - from;
      const double t = offset.dot(edge) / std::max(edge.squaredNorm(), 1e-300);
      if (t <= 0 || t >= 1 || (offset - t * edge).norm() > 1e-9 * edge.norm()) continue;
      skeleton.nodes[child].parent_idx = parent;
      removed[i] = 1;
    }
    return WithoutNodes(skeleton, removed);
  }

  // Edges longer than `length` split evenly (a stretch can then start or
  // end within an edge's length of where it does); parents first.
  static SkeletonGraph Subdivided(const SkeletonGraph& skeleton, double length) {
    SkeletonGraph result = skeleton;
    for (int i = 0; i < skeleton.NumNodes(); ++i) {
      const int parent = skeleton.nodes[i].parent_idx;
      if (parent < 0) continue;
      const SkeletonNode& lower = skeleton.nodes[parent];
      const SkeletonNode& upper = skeleton.nodes[i];
      const int pieces =
          static_cast<int>(std::ceil((upper.position - lower.position).norm() / length));
      int below = parent;
      for (int k = 1; k < pieces; ++k) {
        const double t = double(k) / pieces;
        below = result.AddNode((1 - t) * lower.position + t * upper.position,
                               (1 - t) * lower.radius + t * upper.radius, below, upper.order);
        result.nodes[below].strands = upper.strands;
      }
      result.nodes[i].parent_idx = below;
    }
    return ParentsFirst(result);
  }

  // Whether `a` lies on the path from `b` to the root.
  bool IsAncestor(int a, int b) const {
    for (int k = b; k >= 0; k = Parent(k)) {
      if (k == a) return true;
    }
    return false;
  }

  // Whether every sample of edge i lies within the radius of thicker wood
  // far along the skeleton; `target` receives the nearest such wood to the
  // edge's upper end.
  bool EdgeBeside(int i, Target* target) const {
    const int strands = (*nodes_)[i].strands;
    const auto thicker_elsewhere = [&](int owner, const Eigen::Vector3d& point,
                                       const Eigen::Vector3d& query) {
      if (owner == i) return false;
      const int other = (*nodes_)[owner].strands;
      if (other < strands || (other == strands && owner > i)) return false;
      return paths_->Between(i, paths_->FromRoot(i, query), owner, paths_->FromRoot(owner, point)) >
             kDuplicateApart * radius_;
    };
    const std::vector<Eigen::Vector3d> samples =
        EdgeSamples(Position(Parent(i)), Position(i), spacing_);
    for (const Eigen::Vector3d& query : samples) {
      if (!wood_->AnyWithin(query, [&](int owner, const Eigen::Vector3d& point) {
            return thicker_elsewhere(owner, point, query);
          })) {
        return false;
      }
    }
    // The nearest accepted sample to the upper end (the last sample).
    double best = std::numeric_limits<double>::infinity();
    wood_->AnyWithin(samples.back(), [&](int owner, const Eigen::Vector3d& point) {
      if (!thicker_elsewhere(owner, point, samples.back())) return false;
      const double d = (point - samples.back()).norm();
      if (d < best) best = d, target->owner = owner, target->point = point;
      return false;  // visit them all
    });
    return target->owner >= 0;
  }

  // The length of the beside stretch from u down (u's edge and the beside
  // edges below it, along parents).
  double BesideLength(int u, const std::vector<char>& beside) const {
    double length = 0.0;
    for (int k = u; Parent(k) >= 0 && beside[k]; k = Parent(k)) {
      length += (Position(k) - Position(Parent(k))).norm();
      if (length >= kDuplicateApart * radius_) break;
    }
    return length;
  }

  // The node where a join onto edge `owner` at `point` lands: an end of the
  // edge, or a new node splitting it.
  static int JointOn(SkeletonGraph* skeleton, int owner, const Eigen::Vector3d& point) {
    const int parent = skeleton->nodes[owner].parent_idx;
    const Eigen::Vector3d from = skeleton->nodes[parent].position;
    const Eigen::Vector3d edge = skeleton->nodes[owner].position - from;
    const double t =
        std::clamp((point - from).dot(edge) / std::max(edge.squaredNorm(), 1e-300), 0.0, 1.0);
    constexpr double kAtNode = 1e-6;
    if (t < kAtNode) return parent;
    if (t > 1 - kAtNode) return owner;
    const SkeletonNode upper = skeleton->nodes[owner];
    const SkeletonNode& lower = skeleton->nodes[parent];
    const int split =
        skeleton->AddNode((1 - t) * lower.position + t * upper.position,
                          (1 - t) * lower.radius + t * upper.radius, parent, upper.order);
    skeleton->nodes[split].strands = upper.strands;
    skeleton->nodes[owner].parent_idx = split;
    return split;
  }

  // A stretch at least this many radii long joins wood at least this many
  // radii from it along the skeleton (closer wood is its own branch).
  static constexpr double kDuplicateApart = 3.0;
  // Passes at most (each joins the top of every beside stretch).
  static constexpr int kMaxPasses = 8;

  const double radius_, spacing_;
  std::vector<SkeletonNode>* nodes_ = nullptr;
  const SkeletonPathLengths* paths_ = nullptr;  // of the skeleton as the pass began
  const WoodSamples* wood_ = nullptr;
};

// Steps 3 and 4 on the trimmed and zipped skeleton (changed in place).
void RemoveUnsupportedAxes(const DensityGrid& density, const ConsolidationOptions& options,
                           double height, double spacing, const PaintedDensity* painted,
                           SkeletonGraph* skeleton, ConsolidationSummary* summary) {
  const int root = skeleton->RootIdx();
  const double max_strands = options.max_strand_fraction * skeleton->nodes[root].strands;
  const double base_top = skeleton->nodes[root].position.z() + options.base_fraction * height;
  std::vector<int> orders;
  const std::vector<BranchAxis> axes = skeleton->BranchAxes(&orders);
  std::vector<char> removed(skeleton->NumNodes(), 0);
  std::vector<int> strands_taken(skeleton->NumNodes(), 0);
  const std::vector<char> carrying =
      painted != nullptr ? painted->CarryingWood(*skeleton) : std::vector<char>(removed.size(), 0);
  for (size_t a = 1; a < axes.size(); ++a) {
    const BranchAxis& axis = axes[a];
    if (axis.size() < 2 || removed[axis[0]]) continue;
    if (skeleton->nodes[axis[1]].strands > max_strands) continue;
    if (carrying[axis[1]]) {
      ++summary->painted_axes;
      continue;
    }
    const Eigen::Vector3d& junction = skeleton->nodes[axis[0]].position;
    const bool at_base = orders[a] == 1 && junction.z() < base_top;
    double length = 0, empty = 0;
    for (size_t k = 1; k < axis.size() && !at_base; ++k) {
      const Eigen::Vector3d& from = skeleton->nodes[axis[k - 1]].position;
      const std::vector<Eigen::Vector3d> samples =
          EdgeSamples(from, skeleton->nodes[axis[k]].position, spacing);
      const double piece = (skeleton->nodes[axis[k]].position - from).norm() / samples.size();
      for (const Eigen::Vector3d& point : samples) {
        length += piece;
        if (density.MaxValueAround(point) <= 0.0f) empty += piece;
      }
    }
    const bool bare = !at_base && empty > options.max_empty_fraction * length;
    if (!at_base && !bare) continue;
    int nodes = 0;
    for (size_t k = 1; k < axis.size(); ++k) removed[axis[k]] = 1, ++nodes;
    strands_taken[axis[0]] += skeleton->nodes[axis[1]].strands;
    (at_base ? summary->base_axes : summary->bare_axes) += 1;
    (at_base ? summary->base_nodes : summary->bare_nodes) += nodes;
  }
  MarkDescendants(*skeleton, &removed);
  TakeStrands(strands_taken, removed, skeleton);
  *skeleton = WithoutNodes(*skeleton, removed);
}

constexpr int kMaxHiddenTwigPasses = 8;

// One pass of RemoveHiddenTwigs; the number of twigs removed.
int RemoveHiddenTwigsOnce(double spacing, SkeletonGraph* skeleton) {
  const int n = skeleton->NumNodes();
  std::vector<double> radii(n);
  for (int i = 0; i < n; ++i) radii[i] = skeleton->nodes[i].radius;
  const WoodSamples wood(*skeleton, spacing, radii);
  const std::vector<std::vector<int>> children = skeleton->Children();
  // Terminal twigs: from each tip down to the node below which the tree
  // branches (a junction; twigs that reach the root are the whole tree).
  struct Twig {
    std::vector<int> nodes;  // tip first
    int junction;
  };
  std::vector<Twig> twigs;
  for (int tip = 0; tip < n; ++tip) {
    if (!children[tip].empty() || skeleton->nodes[tip].parent_idx < 0) continue;
    Twig twig{{tip}, skeleton->nodes[tip].parent_idx};
    while (twig.junction >= 0 && children[twig.junction].size() == 1) {
      twig.nodes.push_back(twig.junction);
      twig.junction = skeleton->nodes[twig.junction].parent_idx;
    }
    if (twig.junction >= 0) twigs.push_back(std::move(twig));
  }
  // Thicker twigs first: a thinner one is only hidden by wood that stays.
  std::stable_sort(twigs.begin(), twigs.end(), [&](const Twig& a, const Twig& b) {
    return radii[a.nodes.back()] > radii[b.nodes.back()];
  });
  std::vector<char> removed(n, 0), in_twig(n, 0);
  std::vector<int> strands(n);
  for (int i = 0; i < n; ++i) strands[i] = skeleton->nodes[i].strands;
  int count = 0;
  for (const Twig& twig : twigs) {
    for (int node : twig.nodes) in_twig[node] = 1;
    const bool hidden = std::all_of(twig.nodes.begin(), twig.nodes.end(), [&](int node) {
      const int parent = skeleton->nodes[node].parent_idx;
      const std::vector<Eigen::Vector3d> samples =
          EdgeSamples(skeleton->nodes[parent].position, skeleton->nodes[node].position, spacing);
      return std::all_of(samples.begin(), samples.end(), [&](const Eigen::Vector3d& p) {
        return wood.AnyWithin(p, [&](int owner) {
          return !removed[owner] && !in_twig[owner] && radii[owner] > radii[node];
        });
      });
    });
    for (int node : twig.nodes) in_twig[node] = 0;
    if (!hidden) continue;
    for (int node : twig.nodes) removed[node] = 1;
    CarryDown(twig.junction, strands[twig.nodes.back()], children, removed, &strands);
    ++count;
  }
  if (count == 0) return 0;
  for (int i = 0; i < n; ++i) skeleton->nodes[i].strands = strands[i];
  *skeleton = WithoutNodes(*skeleton, removed);
  return count;
}

}  // namespace

int RemoveHiddenTwigs(double sample_spacing, SkeletonGraph* skeleton) {
  SYLVA_CHECK(sample_spacing > 0);
  int total = 0;
  // A junction left with no children is a new tip, whose twig may be
  // hidden in turn; a few passes settle it.
  for (int pass = 0; pass < kMaxHiddenTwigPasses; ++pass) {
    const int removed = RemoveHiddenTwigsOnce(sample_spacing, skeleton);
    total += removed;
    if (removed == 0) break;
  }
  return total;
}

ConsolidationOptions ConsolidationOptions::Off() {
  ConsolidationOptions off;
  off.redundancy_fraction = 0;
  off.zip_radius_voxels = 0;
  off.duplicate_radius_voxels = 0;
  off.min_support = 0;
  off.max_empty_fraction = 1;
  off.base_fraction = 0;
  off.remove_hidden_twigs = false;
  return off;
}

std::string ConsolidationSummary::BriefReport() const {
  std::ostringstream out;
  out << "Consolidation: length " << length_before << " -> " << length_after << " ("
      << trimmed_nodes << " twig nodes trimmed (redundant or unsupported), " << zipped_axes
      << " branches beside their parent zipped onto it, " << joined_duplicates
      << " stretches beside other wood joined to it, " << bare_axes
      << " bare sticks through empty density removed (" << bare_nodes << " nodes), " << base_axes
      << " thin branches at the trunk's foot removed (" << base_nodes << " nodes), " << hidden_twigs
      << " twigs hidden inside thicker wood removed";
  if (painted_axes > 0) out << ", " << painted_axes << " kept: they carry painted density";
  out << ").";
  return out.str();
}

SkeletonGraph ConsolidateSkeleton(const SkeletonGraph& skeleton, const DensityGrid& density,
                                  const ConsolidationOptions& options,
                                  ConsolidationSummary* summary, const PaintedDensity* painted) {
  options.Check();
  skeleton.Check();
  ConsolidationSummary local;
  if (summary == nullptr) summary = &local;
  *summary = ConsolidationSummary();
  summary->length_before = summary->length_after = skeleton.TotalLength();
  const double height = skeleton.Height();
  if (skeleton.RootIdx() < 0 || height <= 0) return skeleton;
  const double spacing = options.sample_spacing_fraction * height;
  SkeletonGraph result = skeleton;
  if (options.redundancy_fraction > 0 || options.min_support > 0) {
    std::vector<int> strands(skeleton.NumNodes());
    for (int i = 0; i < skeleton.NumNodes(); ++i) strands[i] = skeleton.nodes[i].strands;
    const std::vector<char> trimmed = TrimTwigs(
        skeleton, density, options, options.redundancy_fraction * height, spacing, &strands);
    summary->trimmed_nodes = static_cast<int>(std::count(trimmed.begin(), trimmed.end(), 1));
    for (int i = 0; i < skeleton.NumNodes(); ++i) result.nodes[i].strands = strands[i];
    result = WithoutNodes(result, trimmed);
  }
  if (options.zip_radius_voxels > 0) {
    result = ZipParallelStretches(result, options.zip_radius_voxels * density.voxel_size(), spacing,
                                  &summary->zipped_axes);
  }
  // Step 2b moves strands: only where the skeleton counts them.
  if (options.duplicate_radius_voxels > 0 && result.nodes[result.RootIdx()].strands > 0) {
    result = DuplicateJoiner(options.duplicate_radius_voxels * density.voxel_size(), spacing)
                 .Join(std::move(result), &summary->joined_duplicates);
  }
  RemoveUnsupportedAxes(density, options, height, spacing, painted, &result, summary);
  summary->length_after = result.TotalLength();
  return result;
}

}  // namespace sylva
