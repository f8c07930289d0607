#include "mesh/bark_mesh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <list>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "core/geometry/polyline.h"
#include "core/util/check.h"
#include "mesh/mesh_checks.h"

namespace sylva {
namespace {

// Pushing a joint's cuts out: factor per try, number of tries.
constexpr double kPushFactor = 1.25;
constexpr int kMaxPushes = 16;
// A convex joint over more nodes than this is split up (see Run()).
constexpr int kMaxJointNodes = 4;
// ... and the most nodes such a joint may swallow (else the crossing stays).
constexpr int kMaxRepairJointNodes = 8;
// Repairs take chains of at most this many nodes into a joint.
constexpr int kMaxMergedChainNodes = 4;
// Attempts a repair round may take to undo overflowing repairs one joint at a
// time before it is given up as a whole.
constexpr int kMaxOverflowsPerRound = 2;
// Meshing attempts in all (each repair and each failed attachment retries).
constexpr int kMaxAttempts = 24;
// A crossing within this many radii of a junction node is that junction's.
constexpr double kNearJunction = 4.0;
// A ring must lie behind every other ring's plane by this fraction of the
// joint's largest ring radius.
constexpr double kFaceClearance = 1e-3;
// Sides a parent tube gets per lateral attached at one of its nodes, where
// two or more are (a quad and its two neighbours each).
constexpr int kSidesPerPiledLateral = 3;
// Rings of a tube a fold may span (WithoutCrossingRings).
constexpr int kFoldWindow = 48;
// Tie-breaking jitter of the hull's points, as a fraction of the joint's size.
constexpr double kJitter = 1e-7;
// An attached lateral's first cut (FindAttachment) lies this many of its
// ring radii beyond the centre of the parent quad it leaves through (about
// where the parent's surface is), and each next try 12 % further out: the
// cut is wanted as close to the parent as the quad test allows, so the
// steps are fine there and coarser further out.
constexpr double kFirstCutRadii = 0.5;
constexpr double kCutGrowth = 1.12;
// The parent's axis that an attached lateral's rings must stay clear of
// (LateralOutsideParent) is looked up within the cut's limit plus this many
// of the parent tube's widest ring radii and of the lateral's ring radius
// of the junction: a margin for the parent's width and for the lateral's
// rings, which reach one radius beyond their centres.
constexpr double kReachParentWidths = 2.0;
constexpr double kReachLateralRadii = 4.0;
// Rings of an attached lateral first sampled to see whether it clears its
// parent (CutFits): most clear it within them.
constexpr int kFirstRingsSampled = 6;
// Relative slack of the bounds by which NearestFreeQuad skips ring gaps and
// CrossingJunctions skips junctions, for rounding (a bound must never
// exceed the true distance).
constexpr double kBoundSlack = 1e-9;

// One way out of a joint: the chain of nodes from a joint node through
// pass-through nodes (one child, not in a joint, not the root) to the next
// joint node, tip or root, cut at arc length `t` from the joint node.
struct Exit {
  std::vector<int> path;    // joint node, its neighbour, ..., the chain's end
  std::vector<double> arc;  // arc length from path[0] at each path node
  double t = 0.0;
  // Set by Place(): the cut ring's centre, unit normal (pointing away from
  // the joint), radius, and the path segment [segment, segment + 1] it is on.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  double radius = 0.0;
  int segment = 0;

  double Length() const { return arc.back(); }
};

// Eq. 5.25: the radius of the smallest sphere around the junction on which
// circles of radii r1, r2 perpendicular to two exits at angle gamma meet.
double EnclosingSphereRadius(double r1, double r2, double gamma) {
  if (gamma <= 1e-9) return std::numeric_limits<double>::infinity();
  const double alpha = std::atan2(std::sin(gamma), r2 / r1 + std::cos(gamma));
  // alpha >= 90 degrees: the circles cannot meet on a sphere that holds both
  // (wide angles); the smallest such sphere is the thicker exit's radius.
  if (alpha >= M_PI / 2) return std::max(r1, r2);
  return std::max(r1 / std::sin(alpha), std::max(r1, r2));
}

// A joint's cuts pushed out until its rings are hull faces (or kMaxPushes):
// a function of its members and of the chains leaving it (`exits` before the
// pushes, paths only, is the rest of the key).
struct GroupFit {
  std::vector<int> members;
  std::vector<std::vector<int>> paths;
  std::vector<Exit> exits;
  std::vector<char> bad;
  bool faces = true;
  int pushes = 0;
  int misfit = -1;  // the exit whose chain the joint must take in, -1: it fits
};

// A segment of a tube's axis with the radii at its ends.
struct AxisSegment {
  Eigen::Vector3d a, b;
  double radius_a = 0.0, radius_b = 0.0;

  bool operator==(const AxisSegment& o) const {
    return a == o.a && b == o.b && radius_a == o.radius_a && radius_b == o.radius_b;
  }
};

// A search for an attached lateral's first cut (BarkAttempt::FindAttachment)
// and all it depends on: the lateral's chain and the laterals attached
// along it (they widen its tube), its end cut, the parent quad it must see
// and the parent's axis it must clear. Its result: the cut found.
struct CutSearch {
  std::vector<int> chain;
  std::vector<size_t> piled;
  double end_t = 0.0;  // < 0: no end cut
  double along = 0.0;
  std::vector<Eigen::Vector3d> face;
  std::vector<AxisSegment> parent_axis;
  double t = -1.0;  // the cut (found), < 0: none fits

  bool SameSearch(const CutSearch& o) const {
    return chain == o.chain && piled == o.piled && end_t == o.end_t && along == o.along &&
           face == o.face && parent_axis == o.parent_axis;
  }
};

// What every meshing attempt shares: the skeleton, the options and what
// follows from them alone.
struct BarkTree {
  BarkTree(const SkeletonGraph& skeleton, const BarkMeshOptions& options)
      : skeleton(skeleton), options(options) {
    children = skeleton.Children();
    root = skeleton.RootIdx();
    for (const SkeletonNode& node : skeleton.nodes) max_radius = std::max(max_radius, node.radius);
    axis_child.assign(skeleton.NumNodes(), -1);
    const std::vector<BranchAxis> axes = skeleton.BranchAxes();
    for (size_t a = 0; a < axes.size(); ++a) {
      for (size_t k = a == 0 ? 0 : 1; k + 1 < axes[a].size(); ++k) {
        axis_child[axes[a][k]] = axes[a][k + 1];
      }
    }
  }

  const SkeletonGraph& skeleton;
  const BarkMeshOptions& options;
  std::vector<std::vector<int>> children;
  int root = -1;
  double max_radius = 0.0;
  std::vector<int> axis_child;  // the child continuing each node's axis, else -1
  // Joints fitted by earlier plans and attempts, by their members: most
  // joints stay as they were from one attempt to the next.
  mutable std::map<std::vector<int>, std::list<GroupFit>> fits;
  // Cut searches of earlier attempts, by the lateral's first two nodes.
  mutable std::map<std::pair<int, int>, std::vector<CutSearch>> cut_searches;
};

// The settings of one meshing attempt: what the retry loop (MeshWithRetries)
// has decided about the junctions so far.
struct AttemptSettings {
  std::set<int> forced;       // junctions made convex joints because a lateral found no quad
  std::set<int> repairs;      // ... and to take their triangles off others
  std::set<int> spread;       // junctions of 3+ children attaching their laterals one by one
  std::set<int> overlapping;  // junctions whose unattached laterals stay capped, overlapping
  std::set<std::pair<int, int>> merges;  // chains (first two nodes) taken into their joint
  // Look up the junctions next to crossing triangles when the attempt
  // meshed everything it was asked to (no overflow, every lateral attached).
  bool find_crossings = false;
};

// What one attempt gave.
struct AttemptResult {
  TriangleMesh mesh;                        // empty if `overflow` is not
  std::vector<BarkTriangleOrigin> origins;  // one per triangle of `mesh`
  BarkMeshSummary summary;                  // of this attempt (without `repaired`)
  // Repairs and forced junctions in a joint that grew over
  // kMaxRepairJointNodes nodes: the attempt stopped there.
  std::vector<int> overflow;
  std::vector<int> failed_attach;  // attach junctions with a lateral left unattached
  std::set<int> spread;            // settings.spread and the junctions this attempt spread
  // With settings.find_crossings: BarkAttempt::CrossingJunctions.
  std::set<int> crossing_junctions;
  std::set<std::pair<int, int>> crossing_merges;
};

// One meshing attempt with fixed settings: plans the joints, meshes the
// pieces and joints, and (asked) finds where the result crosses itself.
// Holds all of the attempt's state; used once.
class BarkAttempt {
 public:
  BarkAttempt(const BarkTree& tree, const AttemptSettings& settings)
      : skeleton_(tree.skeleton),
        options_(tree.options),
        children_(tree.children),
        max_radius_(tree.max_radius),
        root_(tree.root),
        axis_child_(tree.axis_child),
        fits_(tree.fits),
        cut_searches_(tree.cut_searches),
        forced_(settings.forced),
        repairs_(settings.repairs),
        overlapping_(settings.overlapping),
        merges_(settings.merges),
        spread_(settings.spread) {}

  // `crossings` keeps the crossings of earlier attempts, so only what this
  // one changed is tested again.
  AttemptResult Run(bool find_crossings, CrossingTracker* crossings) {
    AttemptResult result;
    result.mesh = Attempt();
    result.overflow = overflow_;
    result.failed_attach = failed_attach_;
    result.spread = spread_;
    if (find_crossings && overflow_.empty() && failed_attach_.empty()) {
      result.crossing_junctions =
          CrossingJunctions(result.mesh, crossings, &result.crossing_merges);
    }
    result.origins = std::move(origins_);
    result.summary = summary_;
    return result;
  }

  // Junctions next to crossing triangles: those of attached laterals, and
  // the junction nearest a crossing within kNearJunction of its radius
  // (tubes of branches crossing far from any junction are left alone).
  // `merges` receives chains (first two nodes) to take into the joint they
  // leave: short chains whose tube crosses a joint at one of its ends, and
  // the chain between two joints whose hulls cross.
  std::set<int> CrossingJunctions(const TriangleMesh& mesh, CrossingTracker* crossings,
                                  std::set<std::pair<int, int>>* merges) const {
    // Junctions by x, each with the distance within which it is near (its
    // largest radius's ring times kNearJunction): a crossing looks only at
    // those whose x lies within the largest such distance of its own.
    struct Junction {
      double x;
      int node;
      double ring;
    };
    std::vector<Junction> junctions;
    double reach = 0.0;
    for (int i = 0; i < skeleton_.NumNodes(); ++i) {
      if (children_[i].size() < 2) continue;
      double r = skeleton_.nodes[i].radius;
      for (int v : children_[i]) r = std::max(r, skeleton_.nodes[v].radius);
      junctions.push_back({Position(i).x(), i, RingRadius(r)});
      reach = std::max(reach, kNearJunction * junctions.back().ring);
    }
    std::sort(junctions.begin(), junctions.end(), [](const Junction& a, const Junction& b) {
      return a.x < b.x || (a.x == b.x && a.node < b.node);
    });
    std::set<int> culprits;
    for (const auto& [a, b] : crossings->Find(mesh)) {
      for (const BarkTriangleOrigin* o : {&origins_[a], &origins_[b]}) {
        if (o->kind == BarkTriangleOrigin::kAttachment) culprits.insert(o->node);
      }
      for (int k = 0; k < 2; ++k) {
        const BarkTriangleOrigin& o = origins_[k == 0 ? a : b];
        const BarkTriangleOrigin& joint = origins_[k == 0 ? b : a];
        if (joint.kind != BarkTriangleOrigin::kJoint) continue;
        if (o.kind == BarkTriangleOrigin::kTube && group_[o.node] >= 0) {
          const Exit chain = Chain(o.node, o.next);
          const int end = chain.path.back();
          if (static_cast<int>(chain.path.size()) <= kMaxMergedChainNodes &&
              (Group(o.node) == joint.node || (group_[end] >= 0 && Group(end) == joint.node))) {
            merges->insert({o.node, o.next});
          }
        } else if (o.kind == BarkTriangleOrigin::kJoint && k == 0 && o.node != joint.node) {
          for (const auto& [key, e] : exits_) {
            const int end = e->path.back();
            if (Group(key.first) == o.node && group_[end] >= 0 && Group(end) == joint.node &&
                static_cast<int>(e->path.size()) <= kMaxMergedChainNodes) {
              merges->insert(key);
            }
          }
        }
      }
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int t : {a, b}) {
        for (int k = 0; k < 3; ++k) c += mesh.vertices[mesh.triangles[t][k]].cast<double>() / 6;
      }
      // The nearest in units of its ring (ties: the lowest node).
      int best = -1;
      double best_ratio = kNearJunction;
      const auto first =
          std::lower_bound(junctions.begin(), junctions.end(), c.x() - reach,
                           [](const Junction& junction, double x) { return junction.x < x; });
      for (auto it = first; it != junctions.end() && it->x <= c.x() + reach; ++it) {
        // Too far along an axis to be nearer (with a margin for rounding).
        const Eigen::Vector3d d = c - Position(it->node);
        const double bound = best_ratio * it->ring * (1 + kBoundSlack);
        if (std::abs(d.y()) > bound || std::abs(d.z()) > bound) continue;
        const double ratio = d.norm() / it->ring;
        if (ratio < best_ratio || (ratio == best_ratio && best >= 0 && it->node < best)) {
          best_ratio = ratio;
          best = it->node;
        }
      }
      if (best >= 0 && group_[best] < 0) culprits.insert(best);
    }
    return culprits;
  }

  // Plans the joints and meshes them and the pieces between. Junctions
  // whose joints grow too large attach their laterals one by one instead,
  // and the plan is made again (spread_ only grows, so this ends).
  TriangleMesh Attempt() {
    do {
      StartPlan();
      FormJoints();
      if (!overflow_.empty()) return TriangleMesh();
      if (!respread_) SpreadLargeJoints();
    } while (respread_);
    TriangleMesh mesh;
    material_ = mesh.AddMaterial(options_.tube.bark);
    MeshPieces(&mesh);
    for (auto& [root, rings] : joint_rings_) {
      ++summary_.joints;
      BarkTriangleOrigin origin;
      origin.kind = BarkTriangleOrigin::kJoint;
      origin.node = root;
      if (rings.size() >= 2 && !BuildHull(rings, origin, &mesh)) ++summary_.failed_joints;
    }
    return mesh;
  }

 private:
  // A fresh plan: every junction either a convex joint of its own or, if
  // its laterals are thin against the parent, an attach junction.
  void StartPlan() {
    summary_ = BarkMeshSummary();
    plan_fits_.clear();
    through_.assign(skeleton_.NumNodes(), {});
    respread_ = false;
    overflow_.clear();
    group_.assign(skeleton_.NumNodes(), -1);
    members_.clear();
    continuation_.assign(skeleton_.NumNodes(), -1);
    laterals_.assign(skeleton_.NumNodes(), {});
    for (int i = 0; i < skeleton_.NumNodes(); ++i) {
      if (children_[i].size() < 2) continue;
      ++summary_.junctions;
      if (AttachesLaterals(i)) {
        continuation_[i] = axis_child_[i];
        for (int c : children_[i]) {
          if (c != axis_child_[i]) laterals_[i].push_back(c);
        }
      } else {
        group_[i] = i;
        members_[i] = {i};
      }
    }
  }

  // Whether junction i attaches its laterals to its parent's tube: they are
  // thin against the parent, and i is no root, forced or repaired joint
  // (the root and 3+ children only once spread).
  bool AttachesLaterals(int i) const {
    bool thin = (i != root_ || spread_.count(i)) && axis_child_[i] >= 0 && !forced_.count(i) &&
                !repairs_.count(i) && (children_[i].size() == 2 || spread_.count(i));
    for (int c : children_[i]) {
      if (c == axis_child_[i]) continue;
      thin = thin && skeleton_.nodes[c].radius <= options_.attach_ratio * skeleton_.nodes[i].radius;
    }
    return thin;
  }

  // Junctions of several laterals whose convex joint grew over more than
  // kMaxJointNodes nodes are spread (respread_ set).
  void SpreadLargeJoints() {
    std::map<int, int> sizes;
    for (int i = 0; i < skeleton_.NumNodes(); ++i) {
      if (group_[i] >= 0) ++sizes[Group(i)];
    }
    for (int i = 0; i < skeleton_.NumNodes(); ++i) {
      if (group_[i] >= 0 && sizes[Group(i)] > kMaxJointNodes && children_[i].size() > 2 &&
          !spread_.count(i)) {
        spread_.insert(i);
        respread_ = true;
      }
    }
  }

  double RingRadius(double r) const {
    return std::max(r, options_.min_radius_fraction * max_radius_);
  }
  // How far the vertices of a ring of radius r may reach from its centre:
  // with circle_area, SampleTubeRings gives polygons the circle's area, and a tube through
  // this ring has at least the sides of one of radius r (at most this scale).
  double PolygonRadius(double r) const {
    if (!options_.tube.circle_area) return r;
    return r * PolygonAreaRadiusScale(TubeSides(r, max_radius_, options_.tube));
  }
  // The radius of the edge between adjacent nodes a and b.
  double EdgeRadius(int a, int b) const {
    return skeleton_.nodes[skeleton_.nodes[a].parent_idx == b ? a : b].radius;
  }
  const Eigen::Vector3d& Position(int node) const { return skeleton_.nodes[node].position; }

  int Group(int node) const {
    if (group_[node] < 0) return -1;
    int g = node;
    while (group_[g] != g) g = group_[g];
    return g;
  }
  void Join(int a, int b) {  // b (a node, maybe in a group) joins a's group
    const int ga = Group(a);
    const int gb = Group(b);
    plan_fits_.erase(ga);  // its members change
    if (gb >= 0) plan_fits_.erase(gb);
    std::vector<int>& members = members_.at(ga);
    if (gb < 0) {
      group_[b] = ga;
      members.insert(std::lower_bound(members.begin(), members.end(), b), b);
    } else if (gb != ga) {
      group_[gb] = ga;
      const std::vector<int> joining = std::move(members_.at(gb));
      members_.erase(gb);
      std::vector<int> both;
      std::merge(members.begin(), members.end(), joining.begin(), joining.end(),
                 std::back_inserter(both));
      members = std::move(both);
    }
  }
  // The node after `here` on a chain that arrived from `before`, or -1 if
  // `here` ends chains (a joint node, the root, a tip, a junction reached
  // from one of its attached laterals).
  int ChainNext(int here, int before) const {
    if (group_[here] >= 0 || here == root_ || children_[here].empty()) return -1;
    const int parent = skeleton_.nodes[here].parent_idx;
    const int down = continuation_[here];
    if (children_[here].size() > 1 && down < 0) return -1;
    if (before == parent) return down >= 0 ? down : children_[here][0];
    if (children_[here].size() > 1 && before != down) return -1;
    return parent;
  }

  // The chain from joint node u through its neighbour v.
  Exit Chain(int u, int v) const {
    Exit e;
    e.path = {u, v};
    e.arc = {0.0, (Position(v) - Position(u)).norm()};
    while (true) {
      const int here = e.path.back(), before = e.path[e.path.size() - 2];
      const int next = ChainNext(here, before);
      if (next < 0) break;
      e.arc.push_back(e.arc.back() + (Position(next) - Position(here)).norm());
      e.path.push_back(next);
    }
    return e;
  }

  // Sets the cut ring of e from e.t (clamped to the chain).
  void Place(Exit* e) const {
    const double t = std::clamp(e->t, 0.0, e->Length());
    int m = 0;
    while (m + 2 < static_cast<int>(e->path.size()) &&
           (e->arc[m + 1] < t || e->arc[m + 1] <= e->arc[m])) {
      ++m;
    }
    const Eigen::Vector3d d = Position(e->path[m + 1]) - Position(e->path[m]);
    const double length = d.norm();
    e->segment = m;
    e->direction = length > 0 ? Eigen::Vector3d(d / length) : Eigen::Vector3d::Zero();
    e->center = Position(e->path[m]) + (t - e->arc[m]) * e->direction;
    e->radius = RingRadius(EdgeRadius(e->path[m], e->path[m + 1]));
  }

  // The chains leaving group g, cut on the eq. 5.25 sphere of their node.
  std::vector<Exit> ExitsOf(int g, const std::vector<int>& members) const {
    std::vector<Exit> exits;
    for (int u : members) {
      std::vector<int> neighbours = children_[u];
      const int parent = skeleton_.nodes[u].parent_idx;
      if (parent >= 0) neighbours.insert(neighbours.begin(), parent);
      const size_t first = exits.size();
      for (int v : neighbours) {
        if (Group(v) == g) continue;
        exits.push_back(Chain(u, v));
        exits.back().t = 0.0;
        Place(&exits.back());
      }
      double rho = 0.0;
      for (size_t i = first; i < exits.size(); ++i) {
        rho = std::max(rho, exits[i].radius);
        for (size_t j = i + 1; j < exits.size(); ++j) {
          const double gamma =
              std::acos(std::clamp(exits[i].direction.dot(exits[j].direction), -1.0, 1.0));
          rho = std::max(rho, EnclosingSphereRadius(exits[i].radius, exits[j].radius, gamma));
        }
      }
      rho *= 1 + options_.sphere_margin;
      for (size_t i = first; i < exits.size(); ++i) {
        const double r = exits[i].radius;
        exits[i].t = std::min(std::sqrt(std::max(0.0, rho * rho - r * r)), 1e300);
        Place(&exits[i]);
      }
    }
    return exits;
  }

  // Marks the exits whose ring is not strictly behind another ring's plane
  // (or has another ring reaching past its own). True if none.
  bool RingsAreHullFaces(const std::vector<Exit>& exits, std::vector<char>* bad) const {
    double largest = 0.0;
    for (const Exit& e : exits) largest = std::max(largest, e.radius);
    bad->assign(exits.size(), 0);
    bool ok = true;
    for (size_t i = 0; i < exits.size(); ++i) {
      for (size_t j = 0; j < exits.size(); ++j) {
        if (i == j) continue;
        const double c = exits[i].direction.dot(exits[j].direction);
        const double reach = (exits[j].center - exits[i].center).dot(exits[i].direction) +
                             PolygonRadius(exits[j].radius) * std::sqrt(std::max(0.0, 1 - c * c));
        if (!(reach <= -kFaceClearance * largest)) {
          (*bad)[i] = (*bad)[j] = 1;
          ok = false;
        }
      }
    }
    return ok;
  }

  // True (and overflow_ set to its repairs and forced junctions) if the joint
  // of `node` holds one of those and more than kMaxRepairJointNodes nodes:
  // the attempt stops.
  // Also true (respread_ set) if the joint grew over more than
  // kMaxJointNodes nodes and holds junctions of 3+ children (or the root)
  // that may attach their laterals one by one instead: growing it further
  // would only swallow more of the tree.
  bool JointOverflows(int node) {
    const int g = Group(node);
    int size = 0;
    std::vector<int> repairs, spreadable;
    for (int i = 0; i < skeleton_.NumNodes(); ++i) {
      if (group_[i] < 0 || Group(i) != g) continue;
      ++size;
      if (repairs_.count(i) || forced_.count(i)) repairs.push_back(i);
      if ((children_[i].size() > 2 || (i == root_ && children_[i].size() > 1)) &&
          !spread_.count(i) && !repairs_.count(i) && !forced_.count(i)) {
        spreadable.push_back(i);
      }
    }
    if (size > kMaxJointNodes && !spreadable.empty()) {
      spread_.insert(spreadable.begin(), spreadable.end());
      respread_ = true;
      return true;
    }
    if (repairs.empty() || size <= kMaxRepairJointNodes) return false;
    overflow_ = repairs;
    return true;
  }

  // Groups junctions into joints whose cuts fit; fills exits_. Each misfit
  // merges a chain into a joint and the joints are fitted again, unless a
  // joint overflows (JointOverflows: the plan stops).
  void FormJoints() {
    for (const auto& [u, v] : merges_) {
      if (group_[u] < 0) continue;
      for (int node : Chain(u, v).path) Join(u, node);
    }
    Fit fit = Fit::kMerged;
    while (fit == Fit::kMerged) {
      exits_.clear();
      exit_count_.clear();
      push_count_.clear();
      fit = FitJoints();
      if (fit == Fit::kFits) fit = FitSharedChains();
      if (fit == Fit::kStop) return;
    }
    CountJoints();
  }

  // What fitting the joints' cuts came to.
  enum class Fit {
    kFits,    // every cut fits
    kMerged,  // a chain was merged into a joint: fit again
    kStop,    // ... and the joint overflowed
  };

  // The fit of joint g (members ascending): the plan's (plan_fits_) while
  // neither its members nor its chains changed, else the tree's if it fitted
  // the same joint with the same chains before, else a new one.
  const GroupFit& FitGroup(int g, const std::vector<int>& members) {
    const auto planned = plan_fits_.find(g);
    if (planned != plan_fits_.end()) return *planned->second;
    std::vector<Exit> exits = ExitsOf(g, members);
    std::vector<std::vector<int>> paths;
    for (const Exit& e : exits) paths.push_back(e.path);
    std::list<GroupFit>& known = fits_[members];
    const GroupFit* found = nullptr;
    for (const GroupFit& fit : known) {
      if (fit.paths == paths) found = &fit;
    }
    if (found == nullptr) {
      GroupFit fit;
      fit.members = members;
      fit.paths = std::move(paths);
      while (exits.size() >= 2 && !RingsAreHullFaces(exits, &fit.bad) && fit.pushes < kMaxPushes) {
        for (size_t k = 0; k < exits.size(); ++k) {
          if (!fit.bad[k]) continue;
          exits[k].t *= kPushFactor;
          Place(&exits[k]);
        }
        ++fit.pushes;
      }
      fit.faces = exits.size() < 2 || RingsAreHullFaces(exits, &fit.bad);
      const auto [worst, worst_ratio] = WorstExit(exits, fit.faces, fit.bad);
      if (worst >= 0 && (worst_ratio > options_.max_cut_fraction || !fit.faces)) fit.misfit = worst;
      fit.exits = std::move(exits);
      known.push_back(std::move(fit));
      found = &known.back();
    }
    plan_fits_[g] = found;
    for (const std::vector<int>& chain : found->paths) {
      for (size_t k = 1; k < chain.size(); ++k) through_[chain[k]].push_back(g);
    }
    return *found;
  }

  // Fits the cuts of every joint and records them in exits_, or merges the
  // worst-fitting chain of the first joint whose cuts do not fit.
  Fit FitJoints() {
    std::vector<std::pair<int, const GroupFit*>> fits;
    for (const auto& [g, members] : members_) {
      const GroupFit& fit = FitGroup(g, members);
      if (fit.misfit >= 0) return MergeIntoJoint(g, fit.exits[fit.misfit].path);
      fits.emplace_back(g, &fit);
    }
    for (const auto& [g, fit] : fits) {
      if (fit->pushes > 0) push_count_[g] = fit->pushes;
      exit_count_[g] = static_cast<int>(fit->exits.size());
      for (const Exit& e : fit->exits) exits_[{e.path[0], e.path[1]}] = &e;
    }
    return Fit::kFits;
  }

  // The exit that fits worst on its chain (its cut's fraction of the chain),
  // or, if the rings are not all hull faces, a bad one if they all fit.
  // (-1, -1) if there are no exits.
  static std::pair<int, double> WorstExit(const std::vector<Exit>& exits, bool faces,
                                          const std::vector<char>& bad) {
    int worst = -1;
    double worst_ratio = -1.0;
    for (size_t k = 0; k < exits.size(); ++k) {
      const double length = exits[k].Length();
      double ratio = length > 0 ? exits[k].t / length : 1e300;
      if (!faces && !bad[k]) ratio = -0.5;
      if (ratio > worst_ratio) {
        worst_ratio = ratio;
        worst = static_cast<int>(k);
      }
    }
    return {worst, worst_ratio};
  }

  // Chains cut by two joints: both cuts must fit together, else the first
  // such chain is merged into its joint.
  Fit FitSharedChains() {
    for (const auto& [key, e] : exits_) {
      const int n = static_cast<int>(e->path.size());
      const auto other = exits_.find({e->path[n - 1], e->path[n - 2]});
      if (other == exits_.end()) continue;
      if (e->t + other->second->t > options_.max_cut_fraction * e->Length()) {
        return MergeIntoJoint(key.first, e->path);
      }
    }
    return Fit::kFits;
  }

  // A fallback merge (counted): the chain's nodes join the joint of `node`.
  // The plan forgets the fits of joints with a chain through them.
  Fit MergeIntoJoint(int node, const std::vector<int>& path) {
    for (int member : path) {
      for (int g : through_[member]) plan_fits_.erase(g);
      through_[member].clear();
    }
    for (int member : path) Join(node, member);
    ++summary_.fallbacks;
    return JointOverflows(node) ? Fit::kStop : Fit::kMerged;
  }

  // The summary's figures of the joints formed.
  void CountJoints() {
    std::map<int, int> sizes;
    for (int i = 0; i < skeleton_.NumNodes(); ++i) {
      if (group_[i] < 0) continue;
      ++sizes[Group(i)];
      if (children_[i].empty()) ++summary_.swallowed_tips;
    }
    for (const auto& [g, size] : sizes) summary_.bridged += size == 1 ? 1 : 0;
    summary_.pushed_out = static_cast<int>(push_count_.size());
  }

  // Every chain between joints, tips and the root becomes one open or capped
  // tube; parents before their attached laterals (breadth-first order).
  void MeshPieces(TriangleMesh* mesh) {
    std::vector<int> order = {root_};
    for (size_t k = 0; k < order.size(); ++k) {
      for (int c : children_[order[k]]) order.push_back(c);
    }
    for (int u : order) {
      const bool attach_junction = group_[u] < 0 && !laterals_[u].empty();
      if (group_[u] < 0 && u != root_ && !attach_junction) continue;
      std::vector<int> starts = attach_junction ? laterals_[u] : children_[u];
      if (attach_junction && u == root_) starts.insert(starts.begin(), continuation_[u]);
      for (int v : starts) {
        if (group_[u] >= 0 && Group(v) == Group(u)) continue;  // inside a joint
        std::vector<int> chain = {u, v};
        for (int next; (next = ChainNext(chain.back(), chain[chain.size() - 2])) >= 0;) {
          chain.push_back(next);
        }
        MeshPiece(chain, attach_junction && !(u == root_ && v == continuation_[u]), mesh);
      }
    }
    // Drop the parent quads that attached laterals replaced.
    size_t kept = 0;
    for (size_t t = 0; t < mesh->triangles.size(); ++t) {
      if (t < removed_.size() && removed_[t]) continue;
      mesh->triangles[kept] = mesh->triangles[t];
      mesh->triangle_materials[kept] = mesh->triangle_materials[t];
      origins_[kept] = origins_[t];
      ++kept;
    }
    mesh->triangles.resize(kept);
    mesh->triangle_materials.resize(kept);
    origins_.resize(kept);
  }

  // The tube of `chain` between its start and end cuts (null: the node itself).
  BranchTube MakeTube(const std::vector<int>& chain, const Exit* start, const Exit* end) const {
    const int u = chain.front(), w = chain.back();
    const int last_index = static_cast<int>(chain.size()) - 1;
    BranchTube tube;
    auto add = [&](const Eigen::Vector3d& p, double r) {
      if (!tube.control_points.empty() &&
          (p - tube.control_points.back()).norm() <= 1e-9 * (1 + p.norm())) {
        tube.radii.back() = RingRadius(r);
        return;
      }
      tube.control_points.push_back(p);
      tube.radii.push_back(RingRadius(r));
    };
    // Chain nodes strictly between the cuts.
    const int first_inner = start != nullptr ? start->segment + 1 : 1;
    const int last_inner = end != nullptr ? last_index - end->segment - 1 : last_index - 1;
    add(start != nullptr ? start->center : Position(u),
        start != nullptr ? start->radius : skeleton_.nodes[u].radius);
    for (int k = first_inner; k <= last_inner; ++k) {
      add(Position(chain[k]), skeleton_.nodes[chain[k]].radius);
    }
    const Eigen::Vector3d last = end != nullptr ? end->center : Position(w);
    if (tube.control_points.size() > 1 &&
        (last - tube.control_points.back()).norm() <= 1e-9 * (1 + last.norm())) {
      tube.control_points.pop_back();
      tube.radii.pop_back();
    }
    tube.control_points.push_back(last);
    tube.radii.push_back(end != nullptr ? end->radius : RingRadius(skeleton_.nodes[w].radius));
    if (start != nullptr) tube.radii.front() = start->radius;
    if (tube.control_points.size() < 2) return BranchTube();
    for (size_t k = 0; k + 1 < tube.control_points.size(); ++k) {
      tube.rings_per_segment.push_back(TubeRingsPerSegment(
          (tube.control_points[k + 1] - tube.control_points[k]).norm(), options_.tube));
    }
    tube.circle_area = options_.tube.circle_area;
    tube.sides = TubeSides(*std::max_element(tube.radii.begin(), tube.radii.end()), max_radius_,
                           options_.tube);
    // Each lateral attached at a node takes a quad and reserves the quads
    // beside it: a parent of few sides has no room around one ring for a
    // second or third lateral from the same node (common in QSM tables),
    // which then end up capped and overlapping. Such parents get more sides.
    size_t piled = 0;
    for (int k = first_inner; k <= last_inner; ++k)
      piled = std::max(piled, laterals_[chain[k]].size());
    if (piled >= 2) {
      tube.sides = std::max(tube.sides, std::min(options_.tube.max_sides,
                                                 kSidesPerPiledLateral * static_cast<int>(piled)));
    }
    return tube;
  }

  // A tube already in the mesh: where its vertices and side triangles are.
  struct PieceInfo {
    int first_vertex = 0, first_triangle = 0, sides = 0, rings = 0;
  };
  struct Quad {
    std::array<int, 4> v = {0, 0, 0, 0};  // in the tube's orientation
    int triangle = -1;                    // its first of two side triangles
  };
  Quad QuadAt(const PieceInfo& p, int i, int j) const {
    Quad q;
    j = ((j % p.sides) + p.sides) % p.sides;
    const int ring = p.first_vertex + i * p.sides, next = ring + p.sides, j1 = (j + 1) % p.sides;
    q.v = {ring + j, ring + j1, next + j1, next + j};
    q.triangle = p.first_triangle + 2 * (i * p.sides + j);
    return q;
  }
  // A strip of `width` quads of ring gap i from side j on: its quads and its
  // boundary loop (ring i forwards, ring i + 1 backwards).
  struct Patch {
    std::vector<Quad> quads;
    std::vector<int> loop;
    int i = 0, j = 0;
  };
  Patch PatchAt(const PieceInfo& p, int i, int j, int width) const {
    Patch patch;
    patch.i = i;
    patch.j = j;
    for (int m = 0; m < width; ++m) patch.quads.push_back(QuadAt(p, i, j + m));
    for (int m = 0; m < width; ++m) patch.loop.push_back(patch.quads[m].v[0]);
    patch.loop.push_back(patch.quads.back().v[1]);
    patch.loop.push_back(patch.quads.back().v[2]);
    for (int m = width - 1; m >= 0; --m) patch.loop.push_back(patch.quads[m].v[3]);
    return patch;
  }

  // Where a thin lateral from junction u along `chain` leaves the parent
  // tube: the parent quad its first edge crosses, and a cut `start` whose
  // ring sees that quad as the hull face opposite to it. False if none fits.
  bool FindAttachment(const std::vector<int>& chain, const TriangleMesh& mesh, const Exit* end,
                      Patch* patch, Exit* start) const {
    const int u = chain[0];
    const auto it = attach_piece_.find(u);
    if (it == attach_piece_.end()) return false;
    const PieceInfo& p = pieces_[it->second];
    const Eigen::Vector3d origin = Position(u);
    const Eigen::Vector3d d = (Position(chain[1]) - origin).normalized();
    double along = 0.0;                // from the junction to the quad's centre, along d
    std::array<int, 2> quad = {0, 0};  // ring gap, side
    if (!NearestFreeQuad(it->second, origin, d, mesh, &quad, &along)) return false;
    // One quad: wider strips (as wide as the lateral) leave the strip's
    // boundary edges off the hull too often (tried: 3-5 % of joints failed).
    *patch = PatchAt(p, quad[0], quad[1], 1);
    const PatchFace face = FaceOf(*patch, mesh);
    *start = Chain(u, chain[1]);
    const double limit = options_.max_cut_fraction * start->Length() - (end ? end->t : 0.0);
    const double lateral_radius = RingRadius(skeleton_.nodes[chain[1]].radius);
    const double reach = limit + kReachParentWidths * WidestRing(it->second, mesh) +
                         kReachLateralRadii * lateral_radius;
    CutSearch search;
    search.chain = chain;
    for (int node : chain) search.piled.push_back(laterals_[node].size());
    search.end_t = end ? end->t : -1.0;
    search.along = along;
    search.face = face.loop;
    search.parent_axis = ParentAxisNear(it->second, u, reach, mesh);
    std::vector<CutSearch>& known = cut_searches_[{u, chain[1]}];
    const auto same = std::find_if(known.begin(), known.end(),
                                   [&](const CutSearch& k) { return k.SameSearch(search); });
    if (same != known.end()) {
      search.t = same->t;
    } else {
      // The cut moves out along the lateral from just beyond the quad until
      // its ring sees the quad, and the lateral clears the parent.
      for (double t = along + kFirstCutRadii * lateral_radius; t <= limit; t *= kCutGrowth) {
        start->t = t;
        Place(start);
        const BranchTube tube = MakeTube(chain, start, end);
        if (tube.sides == 0) break;
        if (CutFits(tube, *start, face, search.parent_axis)) {
          search.t = t;
          break;
        }
      }
      known.push_back(search);
    }
    if (search.t < 0) return false;
    start->t = search.t;
    Place(start);
    return true;
  }

  bool Taken(int quad_triangle) const {
    return static_cast<size_t>(quad_triangle) < taken_.size() && taken_[quad_triangle];
  }

  // The free parent quad (ring gap i, side j) of piece `piece` whose centre
  // is nearest the ray from `origin` along unit `d`, ahead of it (ties: the
  // lowest i, then j); `along`: the distance to that centre along d. False
  // if every quad is taken or behind. Ring gaps are visited nearest first
  // by a bound on their quads' distance (their rings lie in a ball), and
  // the search stops at the first gap that cannot hold a nearer quad.
  bool NearestFreeQuad(int piece, const Eigen::Vector3d& origin, const Eigen::Vector3d& d,
                       const TriangleMesh& mesh, std::array<int, 2>* quad, double* along) const {
    const PieceInfo& p = pieces_[piece];
    const std::vector<std::pair<Eigen::Vector3d, double>>& axis = RingAxisOf(piece, mesh);
    std::vector<std::pair<double, int>> gaps;  // (bound on the distance, ring gap)
    for (int i = 0; i + 1 < p.rings; ++i) {
      const Eigen::Vector3d middle = (axis[i].first + axis[i + 1].first) / 2;
      const double ball = (axis[i].first - axis[i + 1].first).norm() / 2 +
                          std::max(axis[i].second, axis[i + 1].second);
      const Eigen::Vector3d m = middle - origin;
      const double bound =
          (m - m.dot(d) * d).norm() - ball * (1 + kBoundSlack) - kBoundSlack * (1 + origin.norm());
      gaps.emplace_back(bound, i);
    }
    std::sort(gaps.begin(), gaps.end());
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [bound, i] : gaps) {
      if (bound > best) break;
      for (int j = 0; j < p.sides; ++j) {
        const Quad q = QuadAt(p, i, j);
        if (Taken(q.triangle)) continue;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int v : q.v) c += mesh.vertices[v].cast<double>() / 4;
        const double s = (c - origin).dot(d);
        if (s <= 0) continue;
        const double off = ((c - origin) - s * d).norm();
        if (off < best ||
            (off == best && std::make_pair(i, j) < std::make_pair((*quad)[0], (*quad)[1]))) {
          best = off;
          *along = s;
          *quad = {i, j};
        }
      }
    }
    return std::isfinite(best);
  }

  // The patch as the face a cut ring must see: its loop's positions, the
  // clearance (kFaceClearance of its size) and the outward planes of both
  // diagonals' triangles of every quad (point, unit normal).
  struct PatchFace {
    std::vector<Eigen::Vector3d> loop;
    double clearance = 0.0;
    std::vector<std::array<Eigen::Vector3d, 2>> planes;
  };
  PatchFace FaceOf(const Patch& patch, const TriangleMesh& mesh) const {
    PatchFace face;
    for (int v : patch.loop) face.loop.push_back(mesh.vertices[v].cast<double>());
    double size = 0.0;
    for (const Eigen::Vector3d& v : face.loop) size = std::max(size, (v - face.loop[0]).norm());
    face.clearance = kFaceClearance * size;
    for (const Quad& q : patch.quads) {
      std::array<Eigen::Vector3d, 4> c;
      for (int k = 0; k < 4; ++k) c[k] = mesh.vertices[q.v[k]].cast<double>();
      for (const auto& t :
           std::array<std::array<int, 3>, 4>{{{0, 1, 2}, {0, 2, 3}, {0, 1, 3}, {1, 2, 3}}}) {
        face.planes.push_back({c[t[0]], (c[t[1]] - c[t[0]]).cross(c[t[2]] - c[t[0]]).normalized()});
      }
    }
    return face;
  }

  // Whether the lateral's tube, cut at `start`, can be glued to the face:
  // the lateral stays outside the parent, every face vertex lies behind the
  // cut ring's plane and every ring vertex in front of the face's planes.
  bool CutFits(const BranchTube& tube, const Exit& start, const PatchFace& face,
               const std::vector<AxisSegment>& parent_axis) const {
    std::vector<TubeRing> rings = SampleTubeRings(tube, 1);
    const TubeRing ring = rings.front();
    bool ok = true;
    for (const Eigen::Vector3d& v : face.loop) {
      ok = ok && (v - ring.center).dot(start.direction) < -face.clearance;
    }
    for (int j = 0; j < tube.sides && ok; ++j) {
      const double a = 2 * M_PI * j / tube.sides;
      const Eigen::Vector3d v = ring.center + ring.radius * (std::cos(a) * ring.frame.normal +
                                                             std::sin(a) * ring.frame.binormal);
      for (const auto& pl : face.planes) ok = ok && pl[1].dot(v - pl[0]) > face.clearance;
    }
    // The lateral's rings from its start until one clears the parent: few
    // are sampled first, all if they do not tell.
    const int all = tube.NumRings();
    for (int count = kFirstRingsSampled; ok; count = all) {
      rings = SampleTubeRings(tube, count);
      const Clearance clearance = LateralOutsideParent(rings, tube.sides, parent_axis);
      if (clearance != Clearance::kUntold || count >= all) return clearance != Clearance::kInside;
    }
    return false;
  }

  // The ring centres and radii of piece `piece` (cached).
  const std::vector<std::pair<Eigen::Vector3d, double>>& RingAxisOf(
      int piece, const TriangleMesh& mesh) const {
    auto cached = ring_axes_.find(piece);
    if (cached == ring_axes_.end()) {
      cached = ring_axes_.emplace(piece, RingAxis(pieces_[piece], mesh)).first;
    }
    return cached->second;
  }
  double WidestRing(int piece, const TriangleMesh& mesh) const {
    double widest = 0.0;
    for (const auto& ring : RingAxisOf(piece, mesh)) widest = std::max(widest, ring.second);
    return widest;
  }

  // The parent's axis segments within `reach` of junction u, where a
  // lateral's cut rings may meet them: those of the parent tube `piece`,
  // and the parent's skeleton axis up and down from the junction (where
  // the parent's tube ends at a joint nearby, the joint's hull fills about
  // that volume).
  std::vector<AxisSegment> ParentAxisNear(int piece, int u, double reach,
                                          const TriangleMesh& mesh) const {
    const Eigen::Vector3d origin = Position(u);
    std::vector<AxisSegment> parent_axis;
    const std::vector<std::pair<Eigen::Vector3d, double>>& axis = RingAxisOf(piece, mesh);
    for (size_t i = 0; i + 1 < axis.size(); ++i) {
      if (SegmentDistance2(origin, axis[i].first, axis[i + 1].first) > reach * reach) continue;
      parent_axis.push_back({axis[i].first, axis[i + 1].first, axis[i].second, axis[i + 1].second});
    }
    for (int down = 0; down < 2; ++down) {
      int a = u;
      while (true) {
        const int b = down ? axis_child_[a] : skeleton_.nodes[a].parent_idx;
        if (b < 0) break;
        const double ra = RingRadius(EdgeRadius(a, b)), rb = ra;
        parent_axis.push_back({Position(a), Position(b), ra, rb});
        if ((Position(b) - origin).norm() > reach) break;
        a = b;
      }
    }
    return parent_axis;
  }

  // True if the circles of rings a and b (b further along the tube) lie
  // each on its own side of the other's plane, so the band between them
  // does not fold.
  static bool RingsApart(const TubeRing& a, const TubeRing& b) {
    const Eigen::Vector3d na = a.frame.tangent, nb = b.frame.tangent;
    const double c = std::clamp(na.dot(nb), -1.0, 1.0);
    const double tilt = std::sqrt(std::max(0.0, 1 - c * c));
    const Eigen::Vector3d d = b.center - a.center;
    return d.dot(na) > b.radius * tilt && d.dot(nb) > a.radius * tilt;
  }

  // The rings without those that fold against their neighbours where the
  // axis bends more sharply than the radius allows (QSM kinks): the longest
  // run of rings each apart from the one before (RingsApart), from the first
  // ring if `pin_first` (a joint or attachment uses it), else from any, to
  // the last if `pin_last`, else to any. A greedy pass from a pinned first
  // ring cannot drop that ring: where it faces away from the rest (a capped
  // lateral leaving at a kink), it dropped every other ring and the tube of
  // the first and last came out inside out. Folds span a few rings, so a
  // ring's predecessor is looked for among the kFoldWindow before it.
  static std::vector<TubeRing> WithoutCrossingRings(std::vector<TubeRing> rings, bool pin_first,
                                                    bool pin_last) {
    const int n = static_cast<int>(rings.size());
    if (n <= 2) return rings;
    std::vector<int> run(n, 0), previous(n, -1);  // 0: no run reaches the ring
    for (int k = 0; k < n; ++k) {
      if (k == 0 || !pin_first) run[k] = 1;
      for (int i = std::max(0, k - kFoldWindow); i < k; ++i) {
        if (run[i] > 0 && run[i] + 1 > run[k] && RingsApart(rings[i], rings[k])) {
          run[k] = run[i] + 1;
          previous[k] = i;
        }
      }
    }
    int best = -1;
    for (int k = pin_last ? n - 1 : 0; k < n; ++k) {
      if (run[k] >= 2 && (best < 0 || run[k] > run[best])) best = k;
    }
    if (best < 0) return {rings.front(), rings.back()};  // nothing unfolds
    std::vector<TubeRing> kept;
    for (int k = best; k >= 0; k = previous[k]) kept.push_back(rings[k]);
    std::reverse(kept.begin(), kept.end());
    return kept;
  }

  // A tube's ring centres and (circumscribed) radii, from its mesh vertices.
  std::vector<std::pair<Eigen::Vector3d, double>> RingAxis(const PieceInfo& p,
                                                           const TriangleMesh& mesh) const {
    std::vector<std::pair<Eigen::Vector3d, double>> axis(p.rings);
    for (int i = 0; i < p.rings; ++i) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int j = 0; j < p.sides; ++j) {
        c += mesh.vertices[p.first_vertex + i * p.sides + j].cast<double>() / p.sides;
      }
      double r = 0.0;
      for (int j = 0; j < p.sides; ++j) {
        r = std::max(r,
                     (mesh.vertices[p.first_vertex + i * p.sides + j].cast<double>() - c).norm());
      }
      axis[i] = {c, r};
    }
    return axis;
  }

  // Whether the lateral's rings (vertices) stay outside the parent tube,
  // given by its ring axis, until the first ring entirely clear of it by the
  // parent's radius: a lateral leaving at a shallow angle, or towards a
  // parent that bends its way, runs inside the parent beyond its cut.
  enum class Clearance {
    kOutside,  // a ring clears the parent, and none before entered it
    kInside,   // a ring vertex lies inside the parent
    kUntold,   // neither, by the last ring given (outside if that is the tip)
  };
  static Clearance LateralOutsideParent(const std::vector<TubeRing>& rings, int sides,
                                        const std::vector<AxisSegment>& axis) {
    for (const TubeRing& ring : rings) {
      double clearest = std::numeric_limits<double>::infinity();
      for (int j = 0; j < sides; ++j) {
        const double a = 2 * M_PI * j / sides;
        const Eigen::Vector3d v = ring.center + ring.radius * (std::cos(a) * ring.frame.normal +
                                                               std::sin(a) * ring.frame.binormal);
        double margin = std::numeric_limits<double>::infinity();  // to the parent's surface
        double radius = 0.0;
        for (const AxisSegment& segment : axis) {
          double s = 0.0;
          const double d = std::sqrt(SegmentDistance2(v, segment.a, segment.b, &s));
          const double r = (1 - s) * segment.radius_a + s * segment.radius_b;
          if (d - r < margin) {
            margin = d - r;
            radius = r;
          }
        }
        if (margin <= kFaceClearance * radius) return Clearance::kInside;
        clearest = std::min(clearest, margin / std::max(radius, 1e-300));
      }
      if (clearest > 1.0) return Clearance::kOutside;
    }
    return Clearance::kUntold;
  }

  struct JointRing {
    std::vector<int> vertices;  // mesh indices in ring order
    bool reversed = false;      // the joint uses vertices[j+1] -> vertices[j]
  };

  // The tube of `chain` (its ends cut where a joint or an attachment takes
  // it, else capped), with its rings handed to the joints at its ends, or
  // glued onto the parent's tube if it is an attached lateral (`attach`).
  void MeshPiece(const std::vector<int>& chain, bool attach, TriangleMesh* mesh) {
    const int u = chain.front(), w = chain.back();
    const int last_index = static_cast<int>(chain.size()) - 1;
    // A joint left with a single exit is no joint: that tube gets a cap.
    const bool start_cut = group_[u] >= 0 && exit_count_[Group(u)] >= 2;
    const bool end_cut = group_[w] >= 0 && exit_count_[Group(w)] >= 2;
    const Exit* end = end_cut ? exits_.at({w, chain[last_index - 1]}) : nullptr;
    Exit attach_cut;
    Patch patch;
    const bool attached = attach && FindAttachment(chain, *mesh, end, &patch, &attach_cut);
    if (attach && !attached) {
      ++summary_.unattached;
      if (!overlapping_.count(u)) failed_attach_.push_back(u);
    }
    const Exit* start = start_cut ? exits_.at({u, chain[1]}) : (attached ? &attach_cut : nullptr);
    const BranchTube tube = MakeTube(chain, start, end);
    if (tube.sides == 0) return;
    const PieceInfo info = AppendPiece(chain, tube, start != nullptr, end_cut, mesh);
    // Ring edges the joint must use: the reverse of the tube's.
    const JointRing start_ring = RingOf(info, 0, /*reversed=*/true);
    if (start_cut) joint_rings_[Group(u)].push_back(start_ring);
    if (attached) GlueToParent(chain, patch, start_ring, mesh);
    if (end_cut) joint_rings_[Group(w)].push_back(RingOf(info, info.rings - 1, false));
  }

  // Sweeps `tube` (cut at its start and/or end, else capped there) into
  // the mesh as a piece of `chain`, and makes it the piece that laterals
  // of the chain's attach junctions attach to.
  PieceInfo AppendPiece(const std::vector<int>& chain, const BranchTube& tube, bool start_cut,
                        bool end_cut, TriangleMesh* mesh) {
    const int u = chain.front();
    PieceInfo info;
    info.first_vertex = mesh->NumVertices();
    info.first_triangle = mesh->NumTriangles();
    info.sides = tube.sides;
    const std::vector<TubeRing> rings_kept =
        WithoutCrossingRings(SampleTubeRings(tube), start_cut, end_cut);
    info.rings = static_cast<int>(rings_kept.size());
    AppendTube(rings_kept, tube.sides, material_, mesh, !start_cut, !end_cut);
    BarkTriangleOrigin origin;
    origin.node = u;
    origin.next = chain[1];
    origins_.resize(mesh->NumTriangles(), origin);
    pieces_.push_back(info);
    const int piece = static_cast<int>(pieces_.size()) - 1;
    if (u == root_ && continuation_[u] == chain[1]) attach_piece_[u] = piece;
    for (size_t k = 1; k + 1 < chain.size(); ++k) {
      if (!laterals_[chain[k]].empty()) attach_piece_[chain[k]] = piece;
    }
    ++summary_.pieces;
    return info;
  }

  // Ring `ring` of a piece as a joint uses it: the tube uses j -> j+1 on
  // its first ring (the joint j+1 -> j: reversed) and j+1 -> j on its last.
  static JointRing RingOf(const PieceInfo& info, int ring, bool reversed) {
    JointRing joint_ring;
    for (int j = 0; j < info.sides; ++j) {
      joint_ring.vertices.push_back(info.first_vertex + ring * info.sides + j);
    }
    joint_ring.reversed = reversed;
    return joint_ring;
  }

  // The attached lateral of `chain` glued onto its parent's tube: the
  // patch's triangles give way to the hull of patch and `start_ring`; the
  // patch and its neighbours are taken (joints of different laterals must
  // not touch).
  void GlueToParent(const std::vector<int>& chain, const Patch& patch, const JointRing& start_ring,
                    TriangleMesh* mesh) {
    const int u = chain.front();
    const PieceInfo& parent = pieces_[attach_piece_.at(u)];
    const int width = static_cast<int>(patch.quads.size());
    for (int di = -1; di <= 1; ++di) {
      for (int dj = -1; dj <= width; ++dj) {
        if (patch.i + di < 0 || patch.i + di + 1 >= parent.rings) continue;
        const int t = QuadAt(parent, patch.i + di, patch.j + dj).triangle;
        if (taken_.size() <= static_cast<size_t>(t)) taken_.resize(mesh->NumTriangles(), 0);
        taken_[t] = 1;
      }
    }
    if (removed_.size() < static_cast<size_t>(mesh->NumTriangles())) {
      removed_.resize(mesh->NumTriangles(), 0);
    }
    for (const Quad& q : patch.quads) removed_[q.triangle] = removed_[q.triangle + 1] = 1;
    JointRing hole;
    hole.vertices = patch.loop;
    hole.reversed = false;  // the joint uses the removed triangles' edges
    BarkTriangleOrigin origin;
    origin.kind = BarkTriangleOrigin::kAttachment;
    origin.node = u;
    origin.next = chain[1];
    if (BuildHull({hole, start_ring}, origin, mesh)) {
      ++summary_.attached;
    } else {
      ++summary_.failed_joints;
    }
  }

  // The convex hull of the rings' vertices without the ring polygons, by
  // gift wrapping from the ring edges. False if it did not close cleanly.
  bool BuildHull(const std::vector<JointRing>& rings, const BarkTriangleOrigin& origin,
                 TriangleMesh* mesh) {
    std::vector<int> ids, ring_of;
    for (size_t r = 0; r < rings.size(); ++r) {
      for (int v : rings[r].vertices) {
        ids.push_back(v);
        ring_of.push_back(static_cast<int>(r));
      }
    }
    const int n = static_cast<int>(ids.size());
    // A mesh vertex's point (the last, if rings share it).
    std::vector<std::pair<int, int>> points(n);
    for (int i = 0; i < n; ++i) points[i] = {ids[i], i};
    std::sort(points.begin(), points.end());
    const auto local = [&points](int id) {
      return std::prev(std::upper_bound(points.begin(), points.end(),
                                        std::make_pair(id, std::numeric_limits<int>::max())))
          ->second;
    };
    Eigen::AlignedBox3d box;
    for (int v : ids) box.extend(mesh->vertices[v].cast<double>());
    const double size = box.sizes().maxCoeff();
    std::vector<Eigen::Vector3d> p(n);
    uint64_t state = 0x9e3779b97f4a7c15ULL;
    auto next = [&state]() {  // splitmix64 in [-1, 1)
      state += 0x9e3779b97f4a7c15ULL;
      uint64_t z = state;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      z ^= z >> 31;
      return static_cast<double>(z >> 11) / static_cast<double>(1ULL << 52) - 1.0;
    };
    for (int i = 0; i < n; ++i) {
      p[i] = mesh->vertices[ids[i]].cast<double>() +
             kJitter * size * Eigen::Vector3d(next(), next(), next());
    }
    // Directed edges (a, b) in use, at a * n + b.
    std::vector<char> used_edges(static_cast<size_t>(n) * n, 0);
    const auto used = [&](int a, int b) -> char& {
      return used_edges[static_cast<size_t>(a) * n + b];
    };
    std::vector<std::pair<int, int>> needs;
    for (const JointRing& ring : rings) {
      const int s = static_cast<int>(ring.vertices.size());
      for (int j = 0; j < s; ++j) {
        const int a = local(ring.vertices[j]), b = local(ring.vertices[(j + 1) % s]);
        if (ring.reversed) {
          used(a, b) = 1;
          needs.push_back({b, a});
        } else {
          used(b, a) = 1;
          needs.push_back({a, b});
        }
      }
    }
    std::vector<Eigen::Vector3i> triangles;
    const size_t max_triangles = 4 * static_cast<size_t>(n) + 8;
    while (!needs.empty()) {
      const auto [a, b] = needs.back();
      needs.pop_back();
      if (used(a, b)) continue;
      if (triangles.size() > max_triangles) return false;
      const bool same_ring = ring_of[a] == ring_of[b];
      int best = -1;
      for (int q = 0; q < n; ++q) {
        if (q == a || q == b || (same_ring && ring_of[q] == ring_of[a])) continue;
        if (best < 0 || (p[b] - p[a]).cross(p[best] - p[a]).dot(p[q] - p[a]) > 0) best = q;
      }
      if (best < 0) return false;
      const int c = best;
      if (used(b, c) || used(c, a)) return false;
      used(a, b) = used(b, c) = used(c, a) = 1;
      triangles.emplace_back(a, b, c);
      if (!used(c, b)) needs.push_back({c, b});
      if (!used(a, c)) needs.push_back({a, c});
    }
    for (const Eigen::Vector3i& t : triangles) {
      mesh->AddTriangle(ids[t[0]], ids[t[1]], ids[t[2]], material_);
      origins_.push_back(origin);
    }
    return true;
  }

  // The tree (shared by all attempts).
  const SkeletonGraph& skeleton_;
  const BarkMeshOptions& options_;
  const std::vector<std::vector<int>>& children_;
  const double max_radius_;
  const int root_;
  const std::vector<int>& axis_child_;                     // the child continuing each node's axis
  std::map<std::vector<int>, std::list<GroupFit>>& fits_;  // BarkTree::fits
  std::map<std::pair<int, int>, std::vector<CutSearch>>& cut_searches_;  // BarkTree's
  std::map<int, const GroupFit*> plan_fits_;
  std::vector<std::vector<int>> through_;  // joints (plan_fits_) with a chain through each node  //
                                           // of this plan's joints, by representative
  // The settings (AttemptSettings).
  const std::set<int> forced_;
  const std::set<int> repairs_;
  const std::set<int> overlapping_;
  const std::set<std::pair<int, int>> merges_;
  std::set<int> spread_;  // grows where joints grow too large
  // The plan.
  BarkMeshSummary summary_;
  std::vector<int> continuation_;            // axis child of attach junctions, else -1
  std::vector<std::vector<int>> laterals_;   // attached laterals of attach junctions
  std::vector<int> group_;                   // union-find parent of joint nodes, -1 elsewhere
  std::map<int, std::vector<int>> members_;  // of each joint (ascending), by representative
  std::map<std::pair<int, int>, const Exit*> exits_;  // in the joints' fits (BarkTree::fits)
  std::map<int, int> push_count_;
  std::map<int, int> exit_count_;
  bool respread_ = false;
  std::vector<int> overflow_;  // repairs in a joint that grew too large
  // The mesh.
  std::vector<PieceInfo> pieces_;
  // Ring centres and radii of pieces (by index) laterals attach to.
  mutable std::map<int, std::vector<std::pair<Eigen::Vector3d, double>>> ring_axes_;
  std::map<int, int> attach_piece_;  // attach junction -> the piece through it
  std::vector<char> taken_;          // by triangle: first triangles of used quads
  std::vector<char> removed_;        // triangles replaced by attachment joints
  std::vector<int> failed_attach_;   // attach junctions with a lateral left unattached
  std::map<int, std::vector<JointRing>> joint_rings_;
  int material_ = 0;
  std::vector<BarkTriangleOrigin> origins_;  // one per triangle of the mesh
};

// One attempt: a function of the tree and the settings alone (`crossings`
// only saves work).
AttemptResult MeshAttempt(const BarkTree& tree, const AttemptSettings& settings,
                          CrossingTracker* crossings) {
  return BarkAttempt(tree, settings).Run(settings.find_crossings, crossings);
}

// What the retry loop knows between attempts.
struct RetryState {
  AttemptSettings settings;       // of the next attempt
  std::set<int> given_up;         // repairs whose joint grew too large
  std::vector<int> batch;         // repairs added by the last round
  std::vector<int> forced_batch;  // junctions forced for the last attempt
  int overflows_this_round = 0;
  int rounds = 0;  // repair rounds started
};

// A repair's joint swallowed more than kMaxRepairJointNodes nodes (the
// attempt's `overflow`): it costs more than its crossing. The repairs of
// that joint from the last round's batch (else all of that joint's) are
// given up; the attempt's spread is not kept. Junctions forced for a
// lateral that found no quad leave their laterals capped and overlapping the
// parent instead.
void GiveUpOverflowing(const std::vector<int>& overflow, int attempt, RetryState* state) {
  AttemptSettings& settings = state->settings;
  std::vector<int>& batch = state->batch;
  std::vector<int> culprits;
  for (int u : overflow) {
    if (std::find(batch.begin(), batch.end(), u) != batch.end()) culprits.push_back(u);
  }
  if (culprits.empty()) culprits = overflow;
  // A round whose repairs keep overflowing is given up as a whole.
  if (++state->overflows_this_round > kMaxOverflowsPerRound) culprits = batch;
  if (attempt >= kMaxAttempts) {  // out of attempts: no repairs, no forcing
    culprits.assign(settings.repairs.begin(), settings.repairs.end());
    culprits.insert(culprits.end(), settings.forced.begin(), settings.forced.end());
  }
  // The whole forced batch goes (one by one would mean an attempt for each
  // of hundreds on dense trees).
  for (int u : culprits) {
    if (settings.overlapping.count(u)) continue;
    if (settings.forced.count(u)) {
      for (int f : state->forced_batch) {
        settings.forced.erase(f);
        settings.overlapping.insert(f);
      }
      settings.forced.erase(u);
      settings.overlapping.insert(u);
    } else {
      settings.repairs.erase(u);
      state->given_up.insert(u);
    }
  }
  state->forced_batch.clear();
  for (int u : culprits) batch.erase(std::remove(batch.begin(), batch.end(), u), batch.end());
}

// Junctions whose thin lateral found no quad on the parent tube become
// convex joints for the next attempt.
void ForceJunctions(const std::vector<int>& failed_attach, RetryState* state) {
  state->settings.forced.insert(failed_attach.begin(), failed_attach.end());
  state->forced_batch.assign(failed_attach.begin(), failed_attach.end());
}

// A repair round: the junctions next to crossings not tried before become
// the next batch, and the chains to merge are added. False if the round
// brings nothing new (the mesh stays).
bool StartRepairRound(const AttemptResult& result, RetryState* state) {
  AttemptSettings& settings = state->settings;
  state->batch.clear();
  state->overflows_this_round = 0;
  for (int u : result.crossing_junctions) {
    if (!state->given_up.count(u) && !settings.forced.count(u) && !settings.repairs.count(u) &&
        !settings.overlapping.count(u)) {
      state->batch.push_back(u);
    }
  }
  const size_t merged_before = settings.merges.size();
  settings.merges.insert(result.crossing_merges.begin(), result.crossing_merges.end());
  if (state->batch.empty() && settings.merges.size() == merged_before) return false;
  ++state->rounds;
  return true;
}

// Meshes; a junction whose thin lateral found no quad on its parent tube
// becomes a convex joint and everything is meshed again, and so do
// junctions next to crossings (repairs, options.repair_rounds rounds), at
// most kMaxAttempts + 1 attempts in all (one more to undo overflowing
// repairs after the last). The last attempt's result, `repaired` counted.
AttemptResult MeshWithRetries(const BarkTree& tree) {
  RetryState state;
  CrossingTracker crossings;
  for (int attempt = 0;; ++attempt) {
    const bool last = attempt == kMaxAttempts;
    state.settings.find_crossings = state.rounds < tree.options.repair_rounds && !last;
    AttemptResult result = MeshAttempt(tree, state.settings, &crossings);
    bool again = true;
    if (!result.overflow.empty()) {
      GiveUpOverflowing(result.overflow, attempt, &state);
    } else {
      state.settings.spread = result.spread;
      if (!result.failed_attach.empty() && !last) {
        ForceJunctions(result.failed_attach, &state);
      } else {
        again = state.settings.find_crossings && StartRepairRound(result, &state);
      }
    }
    if (!again) {
      result.summary.repaired = static_cast<int>(state.settings.repairs.size());
      return result;
    }
    state.settings.repairs.insert(state.batch.begin(), state.batch.end());
  }
}

}  // namespace

std::string BarkMeshSummary::BriefReport() const {
  std::ostringstream out;
  out << "Watertight bark: " << junctions << " junctions in " << joints << " joints (" << bridged
      << " single-junction, " << fallbacks << " fallback merges, " << pushed_out << " pushed out, "
      << swallowed_tips << " tips swallowed), " << attached
      << " laterals attached to their parent's tube";
  if (unattached > 0) out << " (" << unattached << " NOT attached: overlapping)";
  if (failed_joints > 0) out << ", " << failed_joints << " joints FAILED";
  if (repaired > 0) out << ", " << repaired << " junctions made joints to mend crossings";
  out << ", " << pieces << " tubes, " << triangles << " triangles in " << seconds
      << " s; radii: " << radius_source << ".";
  return out.str();
}

TriangleMesh MeshBarkWatertight(const SkeletonGraph& skeleton, const BarkMeshOptions& options,
                                BarkMeshSummary* summary,
                                std::vector<BarkTriangleOrigin>* origins) {
  const auto start = std::chrono::steady_clock::now();
  BarkMeshSummary local;
  if (summary == nullptr) summary = &local;
  *summary = BarkMeshSummary();
  summary->radius_source = skeleton.radius_source;
  options.Check();
  // Validates the skeleton exactly as MeshBranches does.
  PlanBranchTubes(skeleton, options.tube);
  TriangleMesh mesh;
  if (origins != nullptr) origins->clear();
  if (skeleton.NumNodes() >= 2) {
    AttemptResult result = MeshWithRetries(BarkTree(skeleton, options));
    mesh = std::move(result.mesh);
    if (origins != nullptr) *origins = std::move(result.origins);
    *summary = result.summary;
    summary->radius_source = skeleton.radius_source;
  }
  summary->triangles = mesh.NumTriangles();
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return mesh;
}

}  // namespace sylva
