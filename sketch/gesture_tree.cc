#include "sketch/gesture_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "core/geometry/polyline.h"
#include "core/util/check.h"
#include "core/util/random.h"
#include "sketch/gesture_geometry.h"
#include "sketch/gesture_trunks.h"

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

using gesture_internal::AxisTrunk;
using gesture_internal::Capsule;
using gesture_internal::CapsuleGrid;
using gesture_internal::Frame;
using gesture_internal::kAdjacentReach;
using gesture_internal::kBypassThreshold;
using gesture_internal::kDegree;
using gesture_internal::Pitch;
using gesture_internal::PlanTrunks;
using gesture_internal::Roll;
using gesture_internal::TreePaths;
using gesture_internal::TrunkPath;
using gesture_internal::TrunkPlan;
using gesture_internal::TurnTo;
using gesture_internal::Yaw;

// Bisection steps clipping a segment to the region's boundary, and the
// points checked along a clipped segment.
constexpr int kClipSteps = 24;
constexpr int kClipChecks = 8;
// The longest L-string grown (memory: about 40 bytes a module).
constexpr int kMaxModules = 5000000;
// The thinnest segment, as a fraction of the tree's size.
constexpr double kMinRadius = 1e-5;
// Cells of the capsule grid across the tree's size.
constexpr double kGridCells = 25.0;

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

}  // namespace

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

}  // namespace sylva
