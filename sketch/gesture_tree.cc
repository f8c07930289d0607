#include "sketch/gesture_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "core/geometry/polyline.h"
#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {

const char kDefaultGestureGrammar[] =
    R"(# sylva's default gesture grammar: a broadleaf crown grown from the
# growth points A(l, r, h) the gesture trunks carry (l: branch length,
# r: radius, h: height fraction along the trunk).
#define ANGLE 40      # branching angle (degrees)
#define DIV 137.5     # divergence between successive laterals (degrees)
#define LR 0.8        # length of a lateral over its parent's
#define RR 0.7        # radius of a lateral over its parent's
#define MINL 0.05     # shorter shoots stop growing (m)
#define MINR 0.003    # thinnest radius (m)
axiom: A(1, 0.02, 0)
A(l, r, h) -> &(ANGLE + uniform(-10, 10)) B(l * (1.15 - 0.7 * h), r)
B(l, r) : l >= MINL ->(3) F(l / 2, r) [ /(DIV) &(ANGLE) B(l * LR * 0.8, max(r * RR, MINR)) ] F(l / 2, max(r * 0.9, MINR)) /(DIV + uniform(-20, 20)) B(l * LR, max(r * 0.85, MINR))
B(l, r) : l >= MINL ->(1) F(l, r) [ +(ANGLE) B(l * LR, max(r * RR, MINR)) ] [ -(ANGLE) /(90) B(l * LR, max(r * RR, MINR)) ]
)";

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;
// Bisection steps clipping a segment to the region's boundary, and the
// points checked along a clipped segment.
constexpr int kClipSteps = 24;
constexpr int kClipChecks = 8;
// A trunk joins at its start when a later trunk stroke begins this close to
// the trunk (fraction of the first trunk's length); else a connecting
// segment is added.
constexpr double kJoinFraction = 1e-6;
// Below this fraction of the two radii the closest points of two axes give
// no bypass direction (4.1.5: "if the distance is equal to or smaller than
// a threshold"), and the half-space with fewer segments is taken.
constexpr double kBypassThreshold = 0.25;
// Later trunk points are pushed this much beyond touching, in at most this
// many rounds.
constexpr double kPushMargin = 1.02;
constexpr int kPushRounds = 8;
// Candidate exponents n of the supertoroid fit.
constexpr double kFitExponents[] = {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9,
                                    1.0, 1.2, 1.4, 1.6, 1.8, 2.0};
// Height slices of the ROI fit.
constexpr int kFitSlices = 8;
// Two capsules are one tube (adjacent) when the skeleton path between
// their nearest ends is at most this many times the sum of their radii:
// a branch leaving at 30 degrees or more clears its parent's tube there.
constexpr double kAdjacentReach = 2.0;
// Horizontal radii differing more than this ratio are taken as contours
// drawn on one plane.
constexpr double kRevolutionRatio = 0.5;
// The longest L-string grown (memory: about 40 bytes a module).
constexpr int kMaxModules = 5000000;
// The thinnest segment, as a fraction of the tree's size.
constexpr double kMinRadius = 1e-5;
// Cells of the capsule grid across the tree's size.
constexpr double kGridCells = 25.0;

// --- turtle frame -------------------------------------------------------

// Heading, left, up; right-handed (H x L = U).
struct Frame {
  Eigen::Vector3d h = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d l = Eigen::Vector3d::UnitX();
  Eigen::Vector3d u = Eigen::Vector3d::UnitY();
};

// Rotates a and b about axis by angle (right hand).
void Rotate(const Eigen::Vector3d& axis, double degrees, Eigen::Vector3d* a, Eigen::Vector3d* b) {
  const double c = std::cos(degrees * kDegree), s = std::sin(degrees * kDegree);
  const Eigen::Vector3d a0 = *a, b0 = *b;
  *a = a0 * c + axis.cross(a0) * s;
  *b = b0 * c + axis.cross(b0) * s;
}

void Yaw(double deg, Frame* f) { Rotate(f->u, deg, &f->h, &f->l); }    // + (turn left)
void Pitch(double deg, Frame* f) { Rotate(f->l, deg, &f->h, &f->u); }  // & (pitch down)
void Roll(double deg, Frame* f) { Rotate(f->h, deg, &f->l, &f->u); }   // / (roll)

// The turn to heading `d` as a yaw about U then a pitch about the new L
// (4.1.3: the axes in the order U, L, H; no roll needed for a direction).
std::pair<double, double> TurnTo(const Frame& frame, const Eigen::Vector3d& d) {
  const double yaw = std::atan2(d.dot(frame.l), d.dot(frame.h)) / kDegree;
  Frame turned = frame;
  Yaw(yaw, &turned);
  const double pitch = std::atan2(-d.dot(turned.u), d.dot(turned.h)) / kDegree;
  return {yaw, pitch};
}

// --- geometry -------------------------------------------------------------

// Skeleton nodes with their path length from the root, for the adjacency
// of capsules (path between their nearest ends <= sum of radii).
class TreePaths {
 public:
  void Add(int parent, double length) {
    parent_.push_back(parent);
    hops_.push_back(parent < 0 ? 0 : hops_[parent] + 1);
    dist_.push_back(parent < 0 ? 0.0 : dist_[parent] + length);
  }
  double Between(int u, int v) const {
    const double du = dist_[u], dv = dist_[v];
    while (hops_[u] > hops_[v]) u = parent_[u];
    while (hops_[v] > hops_[u]) v = parent_[v];
    while (u != v) u = parent_[u], v = parent_[v];
    return du + dv - 2 * dist_[u];
  }
  // Path between the nearest ends of edges (a0, a1) and (b0, b1).
  double BetweenEdges(int a0, int a1, int b0, int b1) const {
    return std::min(std::min(Between(a0, b0), Between(a0, b1)),
                    std::min(Between(a1, b0), Between(a1, b1)));
  }

 private:
  std::vector<int> parent_, hops_;
  std::vector<double> dist_;
};

struct Capsule {
  Eigen::Vector3d a, b;
  double radius;
  int node_a, node_b;  // skeleton nodes (parent, child)
  int module;          // the module that drew it (-1: none)
};

// Capsules in a uniform hash grid.
class CapsuleGrid {
 public:
  explicit CapsuleGrid(double cell) : cell_(cell) {}
  const std::vector<Capsule>& capsules() const { return capsules_; }
  void Add(const Capsule& c) {
    const int index = static_cast<int>(capsules_.size());
    capsules_.push_back(c);
    ForCells(c, [&](int64_t key) { cells_[key].push_back(index); });
  }
  // Calls visit(index) once per capsule whose cell range meets `c`'s.
  template <typename Visit>
  void Near(const Capsule& c, Visit visit) const {
    ++stamp_;
    seen_.resize(capsules_.size(), 0);
    ForCells(c, [&](int64_t key) {
      const auto it = cells_.find(key);
      if (it == cells_.end()) return;
      for (int index : it->second) {
        if (seen_[index] == stamp_) continue;
        seen_[index] = stamp_;
        visit(index);
      }
    });
  }

 private:
  template <typename Visit>
  void ForCells(const Capsule& c, Visit visit) const {
    const Eigen::Vector3d lo = c.a.cwiseMin(c.b).array() - c.radius;
    const Eigen::Vector3d hi = c.a.cwiseMax(c.b).array() + c.radius;
    const Eigen::Vector3i l = (lo / cell_).array().floor().cast<int>();
    const Eigen::Vector3i h = (hi / cell_).array().floor().cast<int>();
    for (int x = l.x(); x <= h.x(); ++x)
      for (int y = l.y(); y <= h.y(); ++y)
        for (int z = l.z(); z <= h.z(); ++z)
          visit((int64_t(x) * 73856093) ^ (int64_t(y) * 19349663) ^ (int64_t(z) * 83492791));
  }
  double cell_;
  std::vector<Capsule> capsules_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
  // Scratch of Near (not thread-safe).
  mutable std::vector<int> seen_;
  mutable int stamp_ = 0;
};

// --- trunk strokes (4.1.1-4.1.3) ---------------------------------------------

struct TrunkPath {
  std::vector<Eigen::Vector3d> points;  // segments + 1
  std::vector<double> radii;            // per segment
};

// Arc-length resampling into `segments` pieces, with each piece's speed.
TrunkPath ResampleStroke(const GestureStroke& stroke, int segments, std::vector<double>* speeds) {
  std::vector<double> arc = {0.0};
  for (size_t k = 1; k < stroke.samples.size(); ++k) {
    arc.push_back(arc.back() +
                  (stroke.samples[k].position - stroke.samples[k - 1].position).norm());
  }
  auto at = [&](double s, double* t) {
    size_t k = std::upper_bound(arc.begin(), arc.end(), s) - arc.begin();
    k = std::clamp<size_t>(k, 1, arc.size() - 1);
    const double w = arc[k] > arc[k - 1] ? (s - arc[k - 1]) / (arc[k] - arc[k - 1]) : 0.0;
    *t = (1 - w) * stroke.samples[k - 1].t + w * stroke.samples[k].t;
    return Eigen::Vector3d((1 - w) * stroke.samples[k - 1].position +
                           w * stroke.samples[k].position);
  };
  TrunkPath path;
  std::vector<double> times;
  for (int i = 0; i <= segments; ++i) {
    double t = 0;
    path.points.push_back(at(arc.back() * i / segments, &t));
    times.push_back(t);
  }
  speeds->clear();
  for (int i = 0; i < segments; ++i) {
    speeds->push_back(arc.back() / segments / std::max(times[i + 1] - times[i], 1e-12));
  }
  return path;
}

void SmoothPath(int passes, std::vector<Eigen::Vector3d>* points) {
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<Eigen::Vector3d> next = *points;
    for (size_t i = 1; i + 1 < points->size(); ++i) {
      next[i] = 0.5 * (*points)[i] + 0.25 * ((*points)[i - 1] + (*points)[i + 1]);
    }
    *points = std::move(next);
  }
}

// Murakami 5.2: "Trunk diameter increases in inverse proportion to the
// velocity of the stroke": radius = base x mean speed / speed, clamped.
std::vector<double> RadiiFromSpeed(const std::vector<double>& speeds, double base_radius,
                                   double max_ratio) {
  double mean = 0;
  for (double v : speeds) mean += 1.0 / v;  // time per piece (equal lengths)
  mean = speeds.size() / mean;              // length / time
  std::vector<double> radii;
  for (double v : speeds) {
    radii.push_back(base_radius * std::clamp(mean / v, 1.0 / max_ratio, max_ratio));
  }
  return radii;
}

// --- the growth ---------------------------------------------------------------

struct Symbols {
  int F, T, A, yaw_left, yaw_right, pitch_down, pitch_up, roll_left, roll_right, turn, width, push,
      pop;
  explicit Symbols(LsystemGrammar* g)
      : F(g->Symbol("F")),
        T(g->Symbol("T")),
        A(g->Symbol("A")),
        yaw_left(g->Symbol("+")),
        yaw_right(g->Symbol("-")),
        pitch_down(g->Symbol("&")),
        pitch_up(g->Symbol("^")),
        roll_left(g->Symbol("/")),
        roll_right(g->Symbol("\\")),
        turn(g->Symbol("|")),
        width(g->Symbol("!")),
        push(g->Symbol("[")),
        pop(g->Symbol("]")) {}
};

struct Turtle {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Frame frame;
  double radius = 0.01;
  int node = 0;
  int depth = 0;
};

// Interprets an L-string into a skeleton, correcting new F modules so that
// they stay in the region and clear of the capsules grown before them
// (Murakami 4.1.5, 4.2); writes the corrected string.
class Grower {
 public:
  Grower(const LsystemGrammar& grammar, const Symbols& symbols, const Supertoroid& roi,
         const GestureTreeOptions& options, double scale, const Eigen::Vector3d& base)
      : grammar_(grammar),
        symbols_(symbols),
        roi_(roi),
        options_(options),
        base_(base),
        delta_(grammar.Constant("delta", 30.0)),
        step_(grammar.Constant("step", 1.0)),
        grid_(scale / kGridCells),
        established_(scale / kGridCells),
        cell_(scale / kGridCells),
        min_radius_(kMinRadius * scale) {}

  // Lays out the established segments (fresh[i] == 0) first, then grows.
  LsystemString Grow(const LsystemString& string, const std::vector<char>& fresh,
                     GestureTree* tree);
  // Each module's position in the last grown string.
  const std::vector<Eigen::Vector3d>& positions() const { return positions_; }
  // The nodes of each trunk's T modules in the last grown string.
  const std::vector<std::vector<int>>& trunk_nodes() const { return trunk_nodes_; }

 private:
  void Reset(bool record);
  void Interpret(const LsystemString& string, const std::vector<char>& fresh, bool correct,
                 LsystemString* out, GestureTree* tree);
  // One module; false when it was a segment pruned with its branch.
  bool Step(const LsystemString& string, int i, bool is_new, bool correct, LsystemString* out,
            GestureTree* tree);
  bool Turn(int symbol, double degrees, Frame* frame) const;
  void Forward(double length, double radius, int module, bool add_capsule);
  bool Collides(const Capsule& c, Eigen::Vector3d* away) const;
  bool Clear(const Capsule& c) const;
  bool FitsRegion(Capsule* c, bool* clipped) const;
  // The corrected segment (false: pruned); writes turns into `out`.
  bool Correct(double* length, double radius, int module, LsystemString* out, GestureTree* tree);
  Eigen::Vector3d FewerSide(const Capsule& obstacle, const Capsule& c) const;

  const LsystemGrammar& grammar_;
  const Symbols& symbols_;
  const Supertoroid& roi_;
  const GestureTreeOptions& options_;
  Eigen::Vector3d base_;
  double delta_, step_;
  CapsuleGrid grid_;
  TreePaths paths_;
  // Pass 1's capsules of the established segments, its paths and the node
  // the turtle stood on at each module.
  CapsuleGrid established_;
  TreePaths established_paths_;
  std::vector<int> pass1_node_;
  SkeletonGraph skeleton_;
  Turtle turtle_;
  std::vector<Turtle> stack_;
  std::vector<Eigen::Vector3d> positions_;
  std::vector<std::vector<int>> trunk_nodes_;
  double cell_;
  double min_radius_;
  bool record_ = false;
};

void Grower::Reset(bool record) {
  skeleton_ = SkeletonGraph();
  paths_ = TreePaths();
  grid_ = CapsuleGrid(cell_);
  turtle_ = Turtle();
  turtle_.position = base_;
  turtle_.node = skeleton_.AddNode(base_, 0.0, -1, 0);
  paths_.Add(-1, 0.0);
  stack_.clear();
  trunk_nodes_.clear();
  record_ = record;
}

bool Grower::Turn(int symbol, double degrees, Frame* frame) const {
  if (symbol == symbols_.yaw_left) return Yaw(degrees, frame), true;
  if (symbol == symbols_.yaw_right) return Yaw(-degrees, frame), true;
  if (symbol == symbols_.pitch_down) return Pitch(degrees, frame), true;
  if (symbol == symbols_.pitch_up) return Pitch(-degrees, frame), true;
  if (symbol == symbols_.roll_left) return Roll(degrees, frame), true;
  if (symbol == symbols_.roll_right) return Roll(-degrees, frame), true;
  if (symbol == symbols_.turn) return Yaw(180.0, frame), true;
  return false;
}

void Grower::Forward(double length, double radius, int module, bool add_capsule) {
  const Eigen::Vector3d end = turtle_.position + length * turtle_.frame.h;
  const int node = skeleton_.AddNode(end, radius, turtle_.node, turtle_.depth);
  paths_.Add(turtle_.node, length);
  if (add_capsule) grid_.Add({turtle_.position, end, radius, turtle_.node, node, module});
  turtle_.position = end;
  turtle_.node = node;
}

// Whether `c` (from the turtle's node, drawn by module c.module) overlaps a
// non-adjacent capsule: one laid out in this pass, or an established one
// later in the string (from pass 1, with pass 1's paths); `away` (optional)
// receives the bypass direction from the obstacle.
bool Grower::Collides(const Capsule& c, Eigen::Vector3d* away) const {
  bool hit = false;
  auto check = [&](const CapsuleGrid& grid, const TreePaths& paths, int start, bool later) {
    grid.Near(c, [&](int index) {
      const Capsule& o = grid.capsules()[index];
      if (hit || (later && o.module <= c.module)) return;
      const double reach = c.radius + o.radius;
      Eigen::Vector3d cp, co;
      if (SegmentSegmentDistance2(c.a, c.b, o.a, o.b, &cp, &co) >= reach * reach) return;
      if (paths.BetweenEdges(start, start, o.node_a, o.node_b) <= kAdjacentReach * reach) return;
      hit = true;
      if (away == nullptr) return;
      *away =
          (cp - co).norm() > kBypassThreshold * reach ? Eigen::Vector3d(cp - co) : FewerSide(o, c);
    });
  };
  check(grid_, paths_, c.node_a, false);
  if (!hit && c.module >= 0 && c.module < static_cast<int>(pass1_node_.size())) {
    check(established_, established_paths_, pass1_node_[c.module], true);
  }
  return hit;
}

bool Grower::Clear(const Capsule& c) const { return !Collides(c, nullptr); }

// 4.1.5: "a plane ... contains both A and a vector generated by
// translating B until B intersects with A"; the bypass goes to the side
// holding fewer segments.
Eigen::Vector3d Grower::FewerSide(const Capsule& obstacle, const Capsule& c) const {
  Eigen::Vector3d normal = (obstacle.b - obstacle.a).cross(c.b - c.a);
  if (normal.norm() < 1e-12) normal = (obstacle.b - obstacle.a).unitOrthogonal();
  normal.normalize();
  int positive = 0, negative = 0;
  for (const Capsule& o : grid_.capsules()) {
    const double side = (0.5 * (o.a + o.b) - obstacle.a).dot(normal);
    positive += side > 0, negative += side < 0;
  }
  return positive <= negative ? normal : Eigen::Vector3d(-normal);
}

// Clips `c` to the region (its start must be inside).
bool Grower::FitsRegion(Capsule* c, bool* clipped) const {
  *clipped = false;
  if (!roi_.Contains(c->a)) return false;
  if (roi_.Contains(c->b)) return true;
  double lo = 0, hi = 1;
  for (int k = 0; k < kClipSteps; ++k) {
    const double mid = 0.5 * (lo + hi);
    (roi_.Contains(c->a + mid * (c->b - c->a)) ? lo : hi) = mid;
  }
  c->b = c->a + lo * (c->b - c->a);
  for (int k = 1; k <= kClipChecks; ++k) {
    if (!roi_.Contains(c->a + (double(k) / kClipChecks) * (c->b - c->a))) return false;
  }
  *clipped = true;
  return true;
}

bool Grower::Correct(double* length, double radius, int module, LsystemString* out,
                     GestureTree* tree) {
  const double min_length = options_.min_segment_fraction * *length;
  auto candidate = [&](const Eigen::Vector3d& h, double l, bool* clipped) {
    Capsule c{turtle_.position, turtle_.position + l * h, radius, turtle_.node, -1, module};
    if (!FitsRegion(&c, clipped) || (c.b - c.a).norm() < min_length)
      return std::optional<Capsule>();
    return std::optional<Capsule>(c);
  };
  bool clipped = false;
  std::optional<Capsule> c = candidate(turtle_.frame.h, *length, &clipped);
  Eigen::Vector3d away;
  if (c && !Collides(*c, &away)) {
    tree->segments_clipped += clipped;
    *length = (c->b - c->a).norm();
    return true;
  }
  if (c) {  // turn away from the obstacle, then shorten
    const Eigen::Vector3d h = turtle_.frame.h;
    const Eigen::Vector3d side = (away - away.dot(h) * h).normalized();
    for (int k = 1; side.allFinite() && k <= options_.avoid_turns; ++k) {
      const double angle = k * options_.avoid_turn_deg * kDegree;
      const Eigen::Vector3d turned = std::cos(angle) * h + std::sin(angle) * side;
      std::optional<Capsule> t = candidate(turned, *length, &clipped);
      if (!t || !Clear(*t)) continue;
      const auto [yaw, pitch] = TurnTo(turtle_.frame, turned);
      out->Add(symbols_.yaw_left, {yaw});
      out->Add(symbols_.pitch_down, {pitch});
      Yaw(yaw, &turtle_.frame), Pitch(pitch, &turtle_.frame);
      ++tree->segments_turned;
      *length = (t->b - t->a).norm();
      return true;
    }
    for (double l = *length / 2; l >= min_length; l /= 2) {
      std::optional<Capsule> s = candidate(turtle_.frame.h, l, &clipped);
      if (!s || !Clear(*s)) continue;
      ++tree->segments_shortened;
      *length = (s->b - s->a).norm();
      return true;
    }
  }
  ++tree->segments_pruned;
  return false;
}

void Grower::Interpret(const LsystemString& string, const std::vector<char>& fresh, bool correct,
                       LsystemString* out, GestureTree* tree) {
  int pruned_depth = -1;  // skipping the rest of a pruned branch
  for (int i = 0; i < string.Size(); ++i) {
    const int symbol = string.modules[i].symbol;
    if (pruned_depth >= 0) {
      if (symbol == symbols_.push) ++turtle_.depth;
      if (symbol != symbols_.pop || turtle_.depth-- > pruned_depth) continue;
      pruned_depth = -1;
    }
    if (!correct) pass1_node_.push_back(turtle_.node);
    const Eigen::Vector3d before = turtle_.position;
    if (!Step(string, i, fresh[i] != 0, correct, out, tree)) pruned_depth = turtle_.depth;
    while (record_ && out != nullptr && positions_.size() < out->modules.size()) {
      positions_.push_back(before);
    }
  }
}

bool Grower::Step(const LsystemString& string, int i, bool is_new, bool correct, LsystemString* out,
                  GestureTree* tree) {
  const LsystemModule& m = string.modules[i];
  const double p0 = m.count > 0 ? string.Param(i, 0) : 0.0;
  if (m.symbol == symbols_.F || m.symbol == symbols_.T) {
    double length = m.count > 0 ? p0 : step_;
    SYLVA_CHECK_INPUT(std::isfinite(length) && (m.count < 2 || std::isfinite(string.Param(i, 1))),
                      grammar_.source())
        << "the L-system made " << grammar_.SymbolName(m.symbol)
        << " with a non-finite length or radius";
    // Radii > 0 (cylinder tables need them), whatever the grammar says.
    const double radius = std::max(m.count > 1 ? string.Param(i, 1) : turtle_.radius, min_radius_);
    const bool branch = m.symbol == symbols_.F;
    if (!correct && is_new && branch) {  // layout pass: new segments are not obstacles yet
      Forward(length, radius, -1, false);
      return true;
    }
    if (correct && branch && !Correct(&length, radius, i, out, tree)) return false;
    Forward(length, radius, i, true);
    if (!branch && record_) {
      const size_t trunk = m.count > 2 ? static_cast<size_t>(string.Param(i, 2)) : 0;
      if (trunk_nodes_.size() <= trunk) trunk_nodes_.resize(trunk + 1);
      trunk_nodes_[trunk].push_back(turtle_.node);
    }
    if (out != nullptr && branch) out->Add(m.symbol, {length, radius});
    if (out != nullptr && !branch) out->Append(string, i);
    return true;
  }
  if (m.symbol == symbols_.push) stack_.push_back(turtle_), ++turtle_.depth;
  if (m.symbol == symbols_.pop && !stack_.empty()) turtle_ = stack_.back(), stack_.pop_back();
  if (m.symbol == symbols_.width && m.count > 0) turtle_.radius = p0;
  SYLVA_CHECK_INPUT(std::isfinite(p0), grammar_.source())
      << "the L-system made " << grammar_.SymbolName(m.symbol) << " with a non-finite parameter";
  Turn(m.symbol, m.count > 0 ? p0 : delta_, &turtle_.frame);
  if (out != nullptr) out->Append(string, i);
  return true;
}

LsystemString Grower::Grow(const LsystemString& string, const std::vector<char>& fresh,
                           GestureTree* tree) {
  // Pass 1: the established segments' capsules (they keep their place).
  Reset(false);
  pass1_node_.clear();
  Interpret(string, fresh, false, nullptr, tree);
  established_ = std::move(grid_);
  established_paths_ = std::move(paths_);
  // Pass 2: everything again, the new segments corrected against those and
  // against each other.
  positions_.clear();
  Reset(true);
  LsystemString out;
  Interpret(string, fresh, true, &out, tree);
  tree->skeleton = skeleton_;
  return out;
}

// --- trunk L-strings (4.1.3, 4.1.4) -------------------------------------------

struct TrunkPlan {
  std::vector<TrunkPath> paths;
  std::vector<std::vector<double>> arc;  // arc length at each point
  // joins[t][j]: trunks starting at point j of trunk t.
  std::vector<std::vector<std::vector<int>>> joins;
  double first_length = 0;
};

std::vector<double> ArcLengths(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> arc = {0.0};
  for (size_t k = 1; k < points.size(); ++k)
    arc.push_back(arc.back() + (points[k] - points[k - 1]).norm());
  return arc;
}

// The trunk string of trunk `t` from `frame`, with its growth points and
// the trunks joining it (recursively, each in brackets).
void AppendTrunk(const TrunkPlan& plan, int t, const Symbols& sym, const GestureTreeOptions& o,
                 Frame frame, int* growth_points, LsystemString* out) {
  const TrunkPath& path = plan.paths[t];
  const std::vector<double>& arc = plan.arc[t];
  const double length = arc.back();
  auto joins_at = [&](size_t j) {
    for (int u : plan.joins[t][j]) {
      out->Add(sym.push, {});
      AppendTrunk(plan, u, sym, o, frame, growth_points, out);
      out->Add(sym.pop, {});
    }
  };
  joins_at(0);
  double next_growth = o.crown_base;
  for (size_t k = 0; k + 1 < path.points.size(); ++k) {
    const Eigen::Vector3d d = (path.points[k + 1] - path.points[k]).normalized();
    const auto [yaw, pitch] = TurnTo(frame, d);
    out->Add(sym.yaw_left, {yaw});
    out->Add(sym.pitch_down, {pitch});
    Yaw(yaw, &frame), Pitch(pitch, &frame);
    out->Add(sym.T, {arc[k + 1] - arc[k], path.radii[k], static_cast<double>(t)});
    const double h = arc[k + 1] / length;
    if (h >= next_growth && k + 2 < path.points.size()) {
      // 4.1.4: a growth point A with the position, frame and (a share of
      // the) diameter of the trunk segment it grows from.
      next_growth = h + o.growth_spacing;
      out->Add(sym.push, {});
      out->Add(sym.roll_left, {std::fmod(*growth_points * o.divergence_deg, 360.0)});
      out->Add(sym.A, {o.branch_length * length, o.branch_radius_ratio * path.radii[k], h});
      out->Add(sym.pop, {});
      ++*growth_points;
    }
    joins_at(k + 1);
  }
}

// One round of 4.1.5 for a later trunk: its segments that would pierce an
// earlier trunk's are pushed off it, away from its axis (or, when they
// cross it, along the normal of the plane holding both). Returns how many
// points moved.
int PushRound(const TrunkPlan& plan, int joined, int join_point, TrunkPath* path) {
  int pushed = 0;
  for (size_t j = 1; j < path->points.size(); ++j) {
    const double along_new = ArcLengths(path->points)[j - 1];
    for (size_t t = 0; t < plan.paths.size(); ++t) {
      const TrunkPath& other = plan.paths[t];
      for (size_t k = 0; k + 1 < other.points.size(); ++k) {
        const double reach = path->radii[j - 1] + other.radii[k];
        const double along = static_cast<int>(t) != joined
                                 ? std::numeric_limits<double>::infinity()
                                 : std::min(std::abs(plan.arc[t][k] - plan.arc[t][join_point]),
                                            std::abs(plan.arc[t][k + 1] - plan.arc[t][join_point]));
        if (along_new + along <= kAdjacentReach * reach) continue;  // one tube near the join
        Eigen::Vector3d cp, co;
        const double d = std::sqrt(SegmentSegmentDistance2(
            path->points[j - 1], path->points[j], other.points[k], other.points[k + 1], &cp, &co));
        if (d >= reach) continue;
        // Away from the obstacle's axis, across it (an axial push would
        // only slide the point along the trunk).
        const Eigen::Vector3d axis = (other.points[k + 1] - other.points[k]).normalized();
        Eigen::Vector3d away = cp - co - (cp - co).dot(axis) * axis;
        const double across = away.norm();
        if (across <= kBypassThreshold * reach) {
          away = axis.cross(path->points[j] - path->points[j - 1]);
          if (away.norm() < 1e-12) away = axis.unitOrthogonal();
        }
        const Eigen::Vector3d shift = away.normalized() * (reach * kPushMargin - across);
        for (size_t m : {j - 1, j}) {
          if (m > 0) path->points[m] += shift, ++pushed;
        }
      }
    }
  }
  return pushed;
}

int PushOffEarlierTrunks(const TrunkPlan& plan, int joined, int join_point, TrunkPath* path) {
  int pushed = 0;
  for (int round = 0; round < kPushRounds; ++round) {
    const int moved = PushRound(plan, joined, join_point, path);
    if (moved == 0) break;
    pushed += moved;
  }
  return pushed;
}

// The nearest point of the earlier trunks to `p`: (trunk, point index).
std::pair<int, int> NearestTrunkPoint(const TrunkPlan& plan, const Eigen::Vector3d& p) {
  std::pair<int, int> best = {0, 0};
  double best_d = std::numeric_limits<double>::infinity();
  for (size_t t = 0; t < plan.paths.size(); ++t) {
    for (size_t j = 0; j < plan.paths[t].points.size(); ++j) {
      const double d = (plan.paths[t].points[j] - p).squaredNorm();
      if (d < best_d) best_d = d, best = {static_cast<int>(t), static_cast<int>(j)};
    }
  }
  return best;
}

// The trunk strokes resampled, smoothed, with radii from their speed
// (4.1.1, 5.2); later ones joined to the nearest trunk point.
TrunkPlan PlanTrunks(const std::vector<const GestureStroke*>& strokes, bool timed,
                     const GestureTreeOptions& o, int* pushed) {
  TrunkPlan plan;
  plan.first_length = strokes[0]->Length();
  for (size_t k = 0; k < strokes.size(); ++k) {
    std::vector<double> speeds;
    TrunkPath path = ResampleStroke(*strokes[k], o.trunk_segments, &speeds);
    SmoothPath(o.smoothing_passes, &path.points);
    std::pair<int, int> join = {-1, -1};
    double base = o.trunk_radius * plan.first_length;
    if (k > 0) {  // a main branch: thinner than the trunk it joins
      join = NearestTrunkPoint(plan, path.points.front());
      const std::vector<double>& radii = plan.paths[join.first].radii;
      base = o.branch_radius_ratio * radii[std::min<size_t>(join.second, radii.size() - 1)];
    }
    path.radii = timed ? RadiiFromSpeed(speeds, base, o.max_speed_ratio)
                       : std::vector<double>(speeds.size(), base);
    if (k > 0) {
      const Eigen::Vector3d at = plan.paths[join.first].points[join.second];
      if ((at - path.points.front()).norm() > kJoinFraction * plan.first_length) {
        path.points.insert(path.points.begin(), at);
        path.radii.insert(path.radii.begin(), path.radii.front());
      } else {
        path.points.front() = at;
      }
      *pushed += PushOffEarlierTrunks(plan, join.first, join.second, &path);
    }
    plan.paths.push_back(path);
    plan.arc.push_back(ArcLengths(path.points));
    plan.joins.emplace_back(path.points.size());
    if (k > 0) plan.joins[join.first][join.second].push_back(static_cast<int>(k));
  }
  return plan;
}

// Silhouette-based modelling (4.2) without a trunk: "the axiom at an
// arbitrary point in the region": a straight trunk up the region's axis,
// from the ground (z = 0, where sylva puts a tree's base) or the region's
// bottom if lower, to the region's centre height.
GestureStroke AxisTrunk(const Supertoroid& roi) {
  GestureStroke stroke;
  stroke.samples.push_back({0.0, roi.AxisAt(std::min(0.0, roi.center.z() - roi.az)), 1.0});
  stroke.samples.push_back({1.0, roi.AxisAt(roi.center.z()), 1.0});
  return stroke;
}

// --- the region of interest (4.2) -------------------------------------------

// Centre and axis slope from the mean position of height slices.
void FitAxis(const std::vector<Eigen::Vector3d>& points, Supertoroid* s) {
  std::vector<Eigen::Vector3d> means;
  for (int b = 0; b < kFitSlices; ++b) {
    const double lo = s->center.z() - s->az + 2 * s->az * b / kFitSlices;
    const double hi = lo + 2 * s->az / kFitSlices;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    for (const Eigen::Vector3d& p : points) {
      if (p.z() >= lo && (p.z() < hi || b == kFitSlices - 1)) sum += p, ++count;
    }
    if (count > 0) means.push_back(sum / count);
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& m : means) mean += m;
  mean /= static_cast<double>(means.size());
  double szz = 0;
  Eigen::Vector2d sxz = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& m : means) {
    szz += (m.z() - mean.z()) * (m.z() - mean.z());
    sxz += (m.head<2>() - mean.head<2>()) * (m.z() - mean.z());
  }
  s->slope = szz > 0 ? Eigen::Vector2d(sxz / szz) : Eigen::Vector2d::Zero();
  s->center.head<2>() = mean.head<2>() + s->slope * (s->center.z() - mean.z());
}

// The exponent n whose surface passes nearest the points.
double FitExponent(const std::vector<Eigen::Vector3d>& points, Supertoroid s) {
  double best = 1.0, best_error = std::numeric_limits<double>::infinity();
  for (double n : kFitExponents) {
    s.n = n;
    double error = 0;
    for (const Eigen::Vector3d& p : points) {
      error += std::pow(std::pow(s.InsideOutside(p), n / 2) - 1.0, 2);
    }
    if (error < best_error) best_error = error, best = n;
  }
  return best;
}

}  // namespace

double Supertoroid::InsideOutside(const Eigen::Vector3d& p) const {
  const double h = p.z() - center.z();
  const double dx = (p.x() - center.x() - slope.x() * h) / ax;
  const double dy = (p.y() - center.y() - slope.y() * h) / ay;
  const double rho = std::pow(std::pow(std::abs(dx), 2 / e) + std::pow(std::abs(dy), 2 / e), e / 2);
  return std::pow(std::abs(rho - alpha), 2 / n) + std::pow(std::abs(h / az), 2 / n);
}

Eigen::Vector3d Supertoroid::AxisAt(double z) const {
  const double h = z - center.z();
  return {center.x() + slope.x() * h, center.y() + slope.y() * h, z};
}

Supertoroid FitSupertoroid(const std::vector<Eigen::Vector3d>& points, bool enclose,
                           const GestureTreeOptions& options) {
  SYLVA_CHECK(!points.empty());
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const Eigen::Vector3d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double height = std::max(hi.z() - lo.z(), 1e-9);
  Supertoroid s;
  s.e = options.roi_e;
  s.alpha = options.roi_alpha;
  s.n = options.roi_n > 0 ? options.roi_n : 1.0;
  if (enclose) {  // around the gestures, a little above and beside them
    s.center = 0.5 * (lo + hi);
    s.center.z() += options.roi_lift * height;
    s.az = 0.5 * options.roi_margin * height;
    const Eigen::Vector3d half = 0.5 * options.roi_margin * (hi - lo);
    s.ax = std::max(half.x(), options.roi_min_width * height) / (1 + s.alpha);
    s.ay = std::max(half.y(), options.roi_min_width * height) / (1 + s.alpha);
    return s;
  }
  s.center.z() = 0.5 * (lo.z() + hi.z());
  s.az = 0.5 * height;
  FitAxis(points, &s);
  double rx = 0, ry = 0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d axis = s.AxisAt(p.z());
    rx = std::max(rx, std::abs(p.x() - axis.x()));
    ry = std::max(ry, std::abs(p.y() - axis.y()));
  }
  // Two contours drawn on one plane say nothing of the depth: a region of
  // revolution then (as sketch_views.h assumes of one drawing).
  if (rx < kRevolutionRatio * ry || ry < kRevolutionRatio * rx) rx = ry = std::max(rx, ry);
  s.ax = std::max(rx, 1e-9) / (1 + s.alpha);
  s.ay = std::max(ry, 1e-9) / (1 + s.alpha);
  if (options.roi_n <= 0) s.n = FitExponent(points, s);
  return s;
}

void GestureTreeOptions::Check() const {
  SYLVA_CHECK_INPUT(iterations >= 0 && iterations <= 30, "Gesture.iterations")
      << "must be in [0, 30], got " << iterations;
  SYLVA_CHECK_INPUT(trunk_segments >= 2, "Gesture.trunk_segments") << "must be >= 2";
  SYLVA_CHECK_INPUT(smoothing_passes >= 0, "Gesture.smoothing_passes") << "must be >= 0";
  SYLVA_CHECK_INPUT(trunk_radius > 0, "Gesture.trunk_radius") << "must be > 0";
  SYLVA_CHECK_INPUT(max_speed_ratio >= 1, "Gesture.max_speed_ratio") << "must be >= 1";
  SYLVA_CHECK_INPUT(crown_base >= 0 && crown_base <= 1, "Gesture.crown_base")
      << "must be in [0, 1]";
  SYLVA_CHECK_INPUT(growth_spacing > 0 && growth_spacing <= 1, "Gesture.growth_spacing")
      << "must be in (0, 1]";
  SYLVA_CHECK_INPUT(branch_length > 0, "Gesture.branch_length") << "must be > 0";
  SYLVA_CHECK_INPUT(branch_radius_ratio > 0, "Gesture.branch_radius_ratio") << "must be > 0";
  SYLVA_CHECK_INPUT(roi_e > 0 && roi_e <= 4, "Gesture.roi_e") << "must be in (0, 4]";
  SYLVA_CHECK_INPUT(roi_n <= 4, "Gesture.roi_n") << "must be <= 4 (<= 0: fitted)";
  SYLVA_CHECK_INPUT(roi_alpha >= 0, "Gesture.roi_alpha") << "must be >= 0";
  SYLVA_CHECK_INPUT(roi_min_width > 0, "Gesture.roi_min_width") << "must be > 0";
  SYLVA_CHECK_INPUT(roi_margin > 0.5, "Gesture.roi_margin") << "must be > 0.5";
  SYLVA_CHECK_INPUT(roi_lift >= 0, "Gesture.roi_lift") << "must be >= 0";
  SYLVA_CHECK_INPUT(avoid_turns >= 0 && avoid_turn_deg > 0, "Gesture.avoid_turns")
      << "needs avoid_turns >= 0 and Gesture.avoid_turn_deg > 0";
  SYLVA_CHECK_INPUT(min_segment_fraction > 0 && min_segment_fraction < 1,
                    "Gesture.min_segment_fraction")
      << "must be in (0, 1)";
}

LsystemGrammar LoadGestureGrammar(const GestureTreeOptions& options) {
  const std::map<std::string, double> overrides = ParseDefines(options.defines);
  LsystemGrammar grammar =
      options.grammar.empty()
          ? LsystemGrammar::Parse(kDefaultGestureGrammar, "the default gesture grammar", &overrides)
          : LsystemGrammar::Read(options.grammar, &overrides);
  SYLVA_CHECK_INPUT(grammar.unused_overrides().empty(), "Gesture.defines")
      << "'" << (grammar.unused_overrides().empty() ? "" : grammar.unused_overrides()[0])
      << "' is not a #define of " << grammar.source();
  return grammar;
}

std::map<std::string, double> ParseDefines(const std::string& defines) {
  std::map<std::string, double> values;
  std::stringstream items(defines);
  for (std::string item; std::getline(items, item, ',');) {
    if (item.find_first_not_of(" ") == std::string::npos) continue;
    const size_t equals = item.find('=');
    char* end = nullptr;
    std::string name = equals == std::string::npos ? "" : item.substr(0, equals);
    name.erase(0, name.find_first_not_of(' '));
    name.erase(name.find_last_not_of(' ') + 1);
    const double value =
        equals == std::string::npos ? 0.0 : std::strtod(item.c_str() + equals + 1, &end);
    SYLVA_CHECK_INPUT(!name.empty() && end != nullptr && end != item.c_str() + equals + 1 &&
                          *end == '\0' && std::isfinite(value),
                      "Gesture.defines")
        << "expected NAME=NUMBER[,NAME=NUMBER...], got '" << item << "'";
    values[name] = value;
  }
  return values;
}

namespace {

// Derivation under the region (the interactive L-system of 4.2: only
// modules inside the region are rewritten), each step grown and corrected.
void Derive(const LsystemGrammar& grammar, const GestureTreeOptions& options, Grower* grower,
            GestureTree* tree) {
  RandomEngine random(options.seed, /*stream=*/17);
  std::vector<char> fresh(tree->lstring.Size(), 0);
  tree->lstring = grower->Grow(tree->lstring, fresh, tree);
  for (int step = 0; step < options.iterations; ++step) {
    std::vector<char> inside(tree->lstring.Size());
    for (int i = 0; i < tree->lstring.Size(); ++i) {
      inside[i] = tree->roi.Contains(grower->positions()[i]);
    }
    const LsystemString next =
        DeriveStep(grammar, tree->lstring, &inside, &random, nullptr, &fresh);
    SYLVA_CHECK_INPUT(next.Size() <= kMaxModules, grammar.source())
        << "the L-string grew past " << kMaxModules << " modules in step " << step + 1
        << " (fewer Gesture.iterations?)";
    tree->lstring = grower->Grow(next, fresh, tree);
  }
}

std::string Brief(const GestureTree& tree, int trunks) {
  std::ostringstream brief;
  brief << (tree.silhouette_based ? "Silhouette-based (no trunk stroke)"
                                  : std::to_string(trunks) + " trunk stroke(s)")
        << "; region of interest "
        << (tree.roi_from_strokes ? "fitted to the ROI strokes" : "around the gestures")
        << " (supertoroid n " << tree.roi.n << ", radii " << tree.roi.ax << " x " << tree.roi.ay
        << " x " << tree.roi.az << "); " << tree.growth_points << " growth points; L-string of "
        << tree.modules << " modules; " << tree.skeleton.NumNodes()
        << " skeleton nodes. Collision avoidance: " << tree.segments_turned << " segments turned, "
        << tree.segments_shortened << " shortened, " << tree.segments_clipped
        << " clipped to the region, " << tree.segments_pruned << " pruned, "
        << tree.trunk_points_pushed
        << " trunk points pushed; smallest gap between non-adjacent capsules "
        << tree.min_capsule_distance << ".";
  return brief.str();
}

}  // namespace

GestureTree GrowGestureTree(const GestureSet& gestures, const LsystemGrammar& grammar_in,
                            const GestureTreeOptions& options) {
  options.Check();
  gestures.Check();
  LsystemGrammar grammar = grammar_in;
  const Symbols symbols(&grammar);
  GestureTree tree;
  std::vector<const GestureStroke*> trunks;
  std::vector<Eigen::Vector3d> roi_points, trunk_points;
  for (const GestureStroke& stroke : gestures.strokes) {
    if (stroke.kind == GestureKind::kTrunk) trunks.push_back(&stroke);
    for (const GestureSample& sample : stroke.samples) {
      (stroke.kind == GestureKind::kRoi ? roi_points : trunk_points).push_back(sample.position);
    }
  }
  tree.roi_from_strokes = !roi_points.empty();
  tree.roi = FitSupertoroid(tree.roi_from_strokes ? roi_points : trunk_points,
                            !tree.roi_from_strokes, options);
  GestureStroke axis_trunk;
  if (trunks.empty()) {
    tree.silhouette_based = true;
    axis_trunk = AxisTrunk(tree.roi);
    trunks.push_back(&axis_trunk);
  }
  const TrunkPlan plan = PlanTrunks(trunks, gestures.timed && !tree.silhouette_based, options,
                                    &tree.trunk_points_pushed);
  AppendTrunk(plan, 0, symbols, options, Frame(), &tree.growth_points, &tree.lstring);
  const double scale = std::max(plan.first_length, 2 * tree.roi.az);
  Grower grower(grammar, symbols, tree.roi, options, scale, plan.paths[0].points[0]);
  Derive(grammar, options, &grower, &tree);
  tree.trunk_nodes = grower.trunk_nodes();
  if (!tree.trunk_nodes.empty()) tree.trunk_nodes[0].insert(tree.trunk_nodes[0].begin(), 0);
  tree.skeleton.nodes[0].radius = plan.paths[0].radii[0];
  tree.skeleton.radius_source = "gesture speed (trunks) and L-system (branches)";
  tree.skeleton.Check();
  tree.modules = tree.lstring.Size();
  tree.lstring_text = grammar.ToText(tree.lstring);
  tree.min_capsule_distance = MinNonAdjacentCapsuleDistance(tree.skeleton);
  tree.brief = Brief(tree, tree.silhouette_based ? 0 : static_cast<int>(trunks.size()));
  return tree;
}

double MinNonAdjacentCapsuleDistance(const SkeletonGraph& skeleton) {
  // Paths from the root, nodes in breadth-first order.
  const std::vector<std::vector<int>> children = skeleton.Children();
  std::vector<int> order = {skeleton.RootIdx()}, rank(skeleton.nodes.size(), -1);
  TreePaths paths;
  double longest = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    const int node = order[k];
    const int parent = skeleton.nodes[node].parent_idx;
    const double length =
        parent < 0 ? 0.0 : (skeleton.nodes[node].position - skeleton.nodes[parent].position).norm();
    longest = std::max(longest, length);
    rank[node] = static_cast<int>(k);
    paths.Add(parent < 0 ? -1 : rank[parent], length);
    for (int child : children[node]) order.push_back(child);
  }
  CapsuleGrid grid(std::max(longest, 1e-9));
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0) continue;
    const int b = static_cast<int>(&node - skeleton.nodes.data());
    grid.Add({skeleton.nodes[node.parent_idx].position, node.position, node.radius,
              rank[node.parent_idx], rank[b], b});
  }
  double smallest = std::numeric_limits<double>::infinity();
  for (const Capsule& c : grid.capsules()) {
    Capsule reach = c;
    reach.radius += 2 * longest;  // candidates within a generous box
    grid.Near(reach, [&](int index) {
      const Capsule& o = grid.capsules()[index];
      if (o.module <= c.module) return;
      if (paths.BetweenEdges(c.node_a, c.node_b, o.node_a, o.node_b) <=
          kAdjacentReach * (c.radius + o.radius))
        return;
      Eigen::Vector3d cp, co;
      smallest =
          std::min(smallest, std::sqrt(SegmentSegmentDistance2(c.a, c.b, o.a, o.b, &cp, &co)) -
                                 c.radius - o.radius);
    });
  }
  return smallest;
}

double TrunkDeviationFraction(const GestureStroke& stroke, const SkeletonGraph& skeleton,
                              const std::vector<int>& trunk_nodes) {
  std::vector<Eigen::Vector3d> gesture, trunk;
  for (const GestureSample& s : stroke.samples) gesture.push_back(s.position);
  for (int node : trunk_nodes) trunk.push_back(skeleton.nodes[node].position);
  // Points of `from` (vertices and midpoints) against the polyline `to`.
  auto one_way = [](const std::vector<Eigen::Vector3d>& from,
                    const std::vector<Eigen::Vector3d>& to) {
    double worst = 0;
    for (size_t i = 0; i < from.size(); ++i) {
      for (const Eigen::Vector3d& p :
           {from[i], Eigen::Vector3d(0.5 * (from[i] + from[std::min(i + 1, from.size() - 1)]))}) {
        double best = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k + 1 < to.size(); ++k)
          best = std::min(best, SegmentDistance2(p, to[k], to[k + 1]));
        worst = std::max(worst, std::sqrt(best));
      }
    }
    return worst;
  };
  return std::max(one_way(gesture, trunk), one_way(trunk, gesture)) / stroke.Length();
}

}  // namespace sylva
