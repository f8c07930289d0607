#include "sketch/silhouette_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/geometry/polyline.h"
#include "core/util/check.h"

namespace sylva {
namespace {

constexpr double kDegrees = M_PI / 180.0;
// Samples of the parent tried as a branch's base (section 3.2).
constexpr int kBaseSamples = 40;
// Points of a Hermite branch, and of each curve closing a sub-silhouette.
constexpr int kCurvePoints = 32;
// Cells along the longer side of a crown's box when areas are compared.
constexpr int kRasterCells = 96;
// Coverage: positions tried along each side of a parent.
constexpr int kCoverageSteps = 16;
// Coverage: scales tried to fit a copied branch inside the parent's crown,
// and the share of its crown that must be inside.
constexpr double kScales[] = {1.0, 0.85, 0.7, 0.55, 0.4};
constexpr double kMinInside = 0.8;
// A sub-silhouette's shared edge starts this share of |E - B| from B.
constexpr double kConeNearShare = 0.3;
// The ratio r / d at which the cone is widest.
constexpr double kRoundBump = 0.5;
// Phyllotaxis cost weights (the paper's w1, w2).
constexpr double kCloseness = 2.0, kPattern = 1.0;
// A branch's initial direction: over this share of its length.
constexpr double kInitialShare = 0.1;
// A parent whose tangent's upward component is at least this is upright:
// extra branches go all around it; around a leaning one, within this many
// degrees of its upper side.
constexpr double kUprightParent = 0.9;
constexpr double kUpperHalfDeg = 90.0;
// Outlines go to OpenCV's convexity defects in integer coordinates, this
// many units across the outline's box.
constexpr double kDefectScale = 4096.0;
// A bump's apex lies past where the parent enters the crown by at least
// this fraction of the parent.
constexpr double kEntryMargin = 1e-3;
// E is searched for on this many points over this share of the way from
// the apex to the parent.
constexpr int kInwardSteps = 48;
constexpr double kInwardShare = 0.5;
// Bases are tried on the parent past its entry into the crown, leaving
// this share of that part at either end.
constexpr double kBaseMargin = 0.05;
// A branch with no outline in its cone gets a disc of at least this share
// of its span around its end, as a polygon of kDiscPoints.
constexpr double kDiscShare = 0.2;
constexpr int kDiscPoints = 24;
// A drawn branch whose nearer end is within this share of the tree's height
// of the trunk grows from it.
constexpr double kDrawnReach = 0.05;

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Eigen::Vector2d Rotated(const Eigen::Vector2d& v, double radians) {
  const double c = std::cos(radians), s = std::sin(radians);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

double Length(const Outline2& line) {
  double length = 0.0;
  for (size_t i = 1; i < line.size(); ++i) length += (line[i] - line[i - 1]).norm();
  return length;
}

// The point at arc-length fraction t of `line`, and the tangent there.
Eigen::Vector2d At(const Outline2& line, double t, Eigen::Vector2d* tangent = nullptr) {
  const double target = std::clamp(t, 0.0, 1.0) * Length(line);
  double walked = 0.0;
  for (size_t i = 1; i < line.size(); ++i) {
    const double piece = (line[i] - line[i - 1]).norm();
    if (piece <= 0) continue;
    if (walked + piece >= target || i + 1 == line.size()) {
      if (tangent) *tangent = (line[i] - line[i - 1]) / piece;
      return line[i - 1] + std::min(1.0, (target - walked) / piece) * (line[i] - line[i - 1]);
    }
    walked += piece;
  }
  if (tangent) *tangent = Eigen::Vector2d::UnitY();
  return line.front();
}

// The arc-length fraction of the point of `line` nearest `p`, and its distance.
double NearestFraction(const Outline2& line, const Eigen::Vector2d& p, double* distance) {
  const double total = std::max(Length(line), 1e-300);
  double best = std::numeric_limits<double>::infinity(), best_t = 0.0, walked = 0.0;
  for (size_t i = 1; i < line.size(); ++i) {
    double s = 0.0;
    const double d = SegmentDistance2(p, line[i - 1], line[i], &s);
    const double piece = (line[i] - line[i - 1]).norm();
    if (d < best) best = d, best_t = (walked + s * piece) / total;
    walked += piece;
  }
  if (distance) *distance = std::sqrt(best);
  return best_t;
}

// Distance from `p` to the closed outline.
double DistanceToOutline(const Outline2& outline, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0, j = outline.size() - 1; i < outline.size(); j = i++) {
    best = std::min(best, SegmentDistance2(p, outline[j], outline[i]));
  }
  return std::sqrt(best);
}

// A cubic Hermite curve from p0 (tangent m0) to p1 (tangent m1).
Outline2 Hermite(const Eigen::Vector2d& p0, const Eigen::Vector2d& m0, const Eigen::Vector2d& p1,
                 const Eigen::Vector2d& m1) {
  return HermiteCurve(p0, m0, p1, m1, kCurvePoints);
}

// Which cells of a grid over a crown's box are inside outlines (OpenCV's
// polygon filling: a cell is inside if the outline covers its pixel).
class Raster {
 public:
  explicit Raster(const Outline2& frame) {
    Eigen::Vector2d low = frame[0], high = frame[0];
    for (const Eigen::Vector2d& p : frame) low = low.cwiseMin(p), high = high.cwiseMax(p);
    cell_ = std::max((high - low).maxCoeff(), 1e-12) / kRasterCells;
    origin_ = low;
    nx_ = static_cast<int>((high.x() - low.x()) / cell_) + 1;
    ny_ = static_cast<int>((high.y() - low.y()) / cell_) + 1;
  }
  std::vector<char> Cells(const Outline2& polygon) const {
    cv::Mat cells = cv::Mat::zeros(ny_, nx_, CV_8U);
    if (polygon.size() >= 3) {
      constexpr int kShift = 8;  // fractional bits of the vertices
      std::vector<cv::Point> points;
      for (const Eigen::Vector2d& p : polygon) {
        const Eigen::Vector2d c = (p - origin_) / cell_ - Eigen::Vector2d(0.5, 0.5);
        points.emplace_back(static_cast<int>(std::lround(c.x() * (1 << kShift))),
                            static_cast<int>(std::lround(c.y() * (1 << kShift))));
      }
      cv::fillPoly(cells, std::vector<std::vector<cv::Point>>{points}, cv::Scalar(1), cv::LINE_8,
                   kShift);
    }
    return std::vector<char>(cells.datastart, cells.dataend);
  }

 private:
  Eigen::Vector2d origin_;
  double cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
};

int Count(const std::vector<char>& cells) { return std::count(cells.begin(), cells.end(), 1); }

// The branching angle function of one parent: the two ends, and samples
// added by drawn branches, linear in between.
class Baf {
 public:
  Baf(double base_deg, double tip_deg) : samples_{{0.0, base_deg}, {1.0, tip_deg}} {}
  void Add(double t, double degrees) {
    samples_.emplace_back(t, degrees);
    std::sort(samples_.begin(), samples_.end());
  }
  double Degrees(double t) const {
    for (size_t k = 1; k < samples_.size(); ++k) {
      if (t <= samples_[k].first || k + 1 == samples_.size()) {
        const auto& [t0, a0] = samples_[k - 1];
        const auto& [t1, a1] = samples_[k];
        const double w = t1 > t0 ? std::clamp((t - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
        return (1 - w) * a0 + w * a1;
      }
    }
    return samples_.back().second;
  }

 private:
  std::vector<std::pair<double, double>> samples_;
};

// The unit direction `line` leaves its first point in.
Eigen::Vector2d InitialDirection(const Outline2& line) {
  const Eigen::Vector2d to = At(line, kInitialShare);
  const Eigen::Vector2d d = to - line.front();
  return d.norm() > 0 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d::UnitY();
}

// +1 if `direction` leaves the parent (tangent) to its left, -1 to its right.
int SideOf(const Eigen::Vector2d& tangent, const Eigen::Vector2d& direction) {
  return Cross(tangent, direction) >= 0 ? 1 : -1;
}

// The end of a branch into a bump: E and the tangent there (section 3.1).
struct BumpEnd {
  Eigen::Vector2d end, tangent;
  double radius = 0.0;  // E's distance to the outline
};

// The bumps of `crown` beside `parent` (past where the parent enters it).
std::vector<BumpEnd> BumpEnds(const Outline2& crown, const Outline2& parent, double entry,
                              double valley_depth, double min_length) {
  Eigen::Vector2d low = crown[0], high = crown[0];
  for (const Eigen::Vector2d& p : crown) low = low.cwiseMin(p), high = high.cwiseMax(p);
  const double size = (high - low).maxCoeff();
  if (size <= 0) return {};
  const double scale = kDefectScale / size;
  std::vector<cv::Point> points;
  for (const Eigen::Vector2d& p : crown) {
    points.emplace_back(static_cast<int>(std::lround((p.x() - low.x()) * scale)),
                        static_cast<int>(std::lround((p.y() - low.y()) * scale)));
  }
  std::vector<int> valleys;
  std::vector<int> hull;
  cv::convexHull(points, hull, false, false);
  if (hull.size() >= 3) {
    std::sort(hull.begin(), hull.end());
    std::vector<cv::Vec4i> defects;
    try {
      cv::convexityDefects(points, hull, defects);
    } catch (const cv::Exception&) {
      defects.clear();  // a self-crossing outline: one bump
    }
    for (const cv::Vec4i& defect : defects) {
      // OpenCV's depths are fixed-point with 8 fractional bits.
      if (defect[3] / 256.0 > valley_depth * kDefectScale) valleys.push_back(defect[2]);
    }
  }
  std::sort(valleys.begin(), valleys.end());
  const int n = static_cast<int>(crown.size());
  if (valleys.empty()) valleys.push_back(0);
  std::vector<BumpEnd> ends;
  for (size_t k = 0; k < valleys.size(); ++k) {
    const int begin = valleys[k];
    const int end = k + 1 < valleys.size() ? valleys[k + 1] : valleys[0] + n;
    // The apex: the bump's point farthest from the parent, beside the part
    // of the parent inside the crown.
    double farthest = 0.0;
    Eigen::Vector2d apex = Eigen::Vector2d::Zero(), foot = Eigen::Vector2d::Zero();
    for (int i = begin; i < end; ++i) {
      const Eigen::Vector2d& q = crown[i % n];
      double d = 0.0;
      const double t = NearestFraction(parent, q, &d);
      if (t <= entry + kEntryMargin || d <= farthest) continue;
      farthest = d, apex = q, foot = At(parent, t);
    }
    if (farthest < min_length) continue;
    // E: where the distance to the outline peaks on the way in.
    const Eigen::Vector2d inward = (foot - apex).normalized();
    BumpEnd best{apex, -inward, 0.0};
    for (int s = 1; s <= kInwardSteps; ++s) {
      const Eigen::Vector2d p = apex + (kInwardShare * farthest * s / kInwardSteps) * inward;
      if (!InsideOutline(crown, p)) continue;
      const double r = DistanceToOutline(crown, p);
      if (r > best.radius) best = {p, -inward, r};
    }
    ends.push_back(best);
  }
  return ends;
}

// The shortest Hermite branch from the parent to `end` (section 3.2), from
// the parent's part past `entry`.
SilhouetteBranch ShortestBranch(const Outline2& parent, double entry, const Baf& baf,
                                const BumpEnd& end) {
  SilhouetteBranch best;
  double shortest = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kBaseSamples; ++i) {
    const double t =
        entry + (1.0 - entry) * (kBaseMargin + (1 - 2 * kBaseMargin) * i / kBaseSamples);
    Eigen::Vector2d tangent;
    const Eigen::Vector2d base = At(parent, t, &tangent);
    const Eigen::Vector2d span = end.end - base;
    const double d = span.norm();
    if (d <= 0) continue;
    const int side = SideOf(tangent, span);
    const Eigen::Vector2d leave = Rotated(tangent, side * baf.Degrees(t) * kDegrees);
    Outline2 curve = Hermite(base, 0.5 * d * leave, end.end, 0.5 * d * end.tangent);
    const double length = Length(curve);
    if (length < shortest) {
      shortest = length;
      best.points = std::move(curve);
      best.u = t;
    }
  }
  return best;
}

// `source` moved into the span frame of a branch from `base` to `end`: the
// span frame of `from` (its first and last points) is mapped onto the new
// one, scaled by the spans' ratio, mirrored if `mirror`.
Outline2 InSpanFrame(const Outline2& line, const Outline2& from, const Eigen::Vector2d& base,
                     const Eigen::Vector2d& end, bool mirror) {
  const Eigen::Vector2d s0 = from.back() - from.front(), s1 = end - base;
  const double l0 = std::max(s0.norm(), 1e-300), l1 = s1.norm();
  const Eigen::Vector2d a0 = s0 / l0, b0(-a0.y(), a0.x());
  const Eigen::Vector2d a1 = l1 > 0 ? Eigen::Vector2d(s1 / l1) : a0, b1(-a1.y(), a1.x());
  Outline2 out;
  for (const Eigen::Vector2d& p : line) {
    const Eigen::Vector2d q = (p - from.front()) / l0;
    const double along = q.dot(a0), across = q.dot(b0) * (mirror ? -1 : 1);
    out.push_back(base + l1 * (along * a1 + across * b1));
  }
  return out;
}

// Turns `line` (and the rest) about `pivot` by `radians`, then scales by `k`.
Outline2 Turned(const Outline2& line, const Eigen::Vector2d& pivot, double radians, double k,
                bool mirror, const Eigen::Vector2d& mirror_axis) {
  Outline2 out;
  for (const Eigen::Vector2d& p : line) {
    Eigen::Vector2d q = p - pivot;
    if (mirror) q = 2 * q.dot(mirror_axis) * mirror_axis - q;
    out.push_back(pivot + k * Rotated(q, radians));
  }
  return out;
}

// The sub-silhouette of a branch inside its parent's crown (section 4.1).
Outline2 SubSilhouette(const Outline2& crown, const Outline2& branch, double radius,
                       const SilhouetteTreeOptions& options) {
  const Eigen::Vector2d base = branch.front(), end = branch.back();
  const double d = (end - base).norm();
  if (d <= 0 || crown.size() < 3) return {};
  const Eigen::Vector2d axis = (end - base) / d;
  const double w = std::clamp(radius / d / kRoundBump, 0.0, 1.0);
  const double half = 0.5 * ((1 - w) * options.cone_min_deg + w * options.cone_max_deg) * kDegrees;
  const int n = static_cast<int>(crown.size());
  auto in_cone = [&](int i) {
    const Eigen::Vector2d v = crown[((i % n) + n) % n] - base;
    const double r = v.norm();
    return r >= kConeNearShare * d && std::acos(std::clamp(v.dot(axis) / r, -1.0, 1.0)) <= half;
  };
  // The shared edge: the run of outline points in the cone around the one
  // nearest the branch's axis beyond E.
  int centre = -1;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    if (!in_cone(i)) continue;
    const Eigen::Vector2d v = crown[i] - base;
    const double off_axis = std::abs(Cross(axis, v)) - 1e-3 * v.dot(axis);
    if (off_axis < best) best = off_axis, centre = i;
  }
  Outline2 outline;
  if (centre < 0) {
    // No outline in the cone (a branch inside the crown): a disc around E.
    const double r = std::max(radius, kDiscShare * d);
    for (int k = 0; k < kDiscPoints; ++k) {
      const double a = 2 * M_PI * k / kDiscPoints;
      outline.push_back(end + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    return outline;
  }
  int first = centre, last = centre;
  while (last - first + 1 < n && in_cone(first - 1)) --first;
  while (last - first + 1 < n && in_cone(last + 1)) ++last;
  for (int i = first; i <= last; ++i) outline.push_back(crown[((i % n) + n) % n]);
  if (outline.size() < 2) return {};
  auto direction = [&](int i) {
    const Eigen::Vector2d v = crown[((i + 1) % n + n) % n] - crown[((i - 1) % n + n) % n];
    return v.norm() > 0 ? Eigen::Vector2d(v.normalized()) : Eigen::Vector2d(axis);
  };
  const Eigen::Vector2d p_first = outline.front(), p_last = outline.back();
  Eigen::Vector2d across = p_first - p_last;
  across -= across.dot(axis) * axis;
  across = across.norm() > 0 ? Eigen::Vector2d(across.normalized())
                             : Eigen::Vector2d(-axis.y(), axis.x());
  const double l1 = (p_last - base).norm(), l2 = (p_first - base).norm();
  const Outline2 down = Hermite(p_last, 0.5 * l1 * direction(last), base, 0.25 * l1 * across);
  const Outline2 up = Hermite(base, 0.25 * l2 * across, p_first, 0.5 * l2 * direction(first));
  outline.insert(outline.end(), down.begin() + 1, down.end());
  outline.insert(outline.end(), up.begin() + 1, up.end() - 1);
  return outline;
}

// Where `parent` enters `crown`: the arc-length fraction of its first point
// inside (0 if it starts inside).
double EntryInto(const Outline2& parent, const Outline2& crown) {
  constexpr int kSamples = 100;
  for (int k = 0; k <= kSamples; ++k) {
    if (InsideOutline(crown, At(parent, static_cast<double>(k) / kSamples))) {
      return static_cast<double>(k) / kSamples;
    }
  }
  return 1.0;
}

// A parent's children while they are inferred: each with its end and
// whether it was drawn.
struct Children {
  std::vector<SilhouetteBranch> branches;
  std::vector<BumpEnd> ends;
  std::vector<char> drawn;
  void Add(SilhouetteBranch branch, const BumpEnd& end, bool is_drawn) {
    branches.push_back(std::move(branch));
    ends.push_back(end);
    drawn.push_back(is_drawn);
  }
};

// A drawn branch (section 3.3) replaces the inferred child whose ends are
// nearest its own (or joins the children) and adds its angle to the BAF.
void AddDrawn(const Outline2& parent, const Outline2& crown, const Outline2& line, Baf* baf,
              Children* children) {
  double distance = 0.0;
  const double t = NearestFraction(parent, line.front(), &distance);
  SilhouetteBranch child;
  child.points = line;
  if (distance > 0) child.points.insert(child.points.begin(), At(parent, t));
  child.u = t;
  child.drawn_shape = true;
  const Outline2& placed = child.points;
  Eigen::Vector2d tangent;
  At(parent, t, &tangent);
  baf->Add(t, std::acos(std::clamp(tangent.dot(InitialDirection(placed)), -1.0, 1.0)) / kDegrees);
  const BumpEnd end{placed.back(), (placed.back() - placed[placed.size() - 2]).normalized(),
                    DistanceToOutline(crown, placed.back())};
  int match = -1;
  double cost = std::numeric_limits<double>::infinity();
  for (size_t c = 0; c < children->branches.size(); ++c) {
    if (children->drawn[c]) continue;
    const double k = (children->branches[c].points.front() - placed.front()).norm() +
                     (children->branches[c].points.back() - placed.back()).norm();
    if (k < cost) cost = k, match = static_cast<int>(c);
  }
  if (match < 0) {
    children->Add(std::move(child), end, true);
    return;
  }
  children->branches[match] = std::move(child);
  children->ends[match] = end;
  children->drawn[match] = true;
}

// The inferred children follow the BAF with the drawn angles, and take the
// shape of the drawn child nearest them along the parent.
void Restyle(const Outline2& parent, double entry, const Baf& baf, Children* children) {
  std::vector<SilhouetteBranch>& branches = children->branches;
  for (size_t c = 0; c < branches.size(); ++c) {
    if (children->drawn[c]) continue;
    SilhouetteBranch redone = ShortestBranch(parent, entry, baf, children->ends[c]);
    if (redone.points.empty()) continue;
    int nearest = -1;
    double gap = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < branches.size(); ++k) {
      if (children->drawn[k] && std::abs(branches[k].u - redone.u) < gap) {
        gap = std::abs(branches[k].u - redone.u), nearest = static_cast<int>(k);
      }
    }
    const Outline2& shape = branches[nearest].points;
    Eigen::Vector2d t_src, t_dst;
    At(parent, branches[nearest].u, &t_src);
    At(parent, redone.u, &t_dst);
    const bool mirror = SideOf(t_src, shape.back() - shape.front()) !=
                        SideOf(t_dst, redone.points.back() - redone.points.front());
    redone.points = InSpanFrame(shape, shape, redone.points.front(), redone.points.back(), mirror);
    branches[c] = std::move(redone);
  }
}

class StructureBuilder {
 public:
  StructureBuilder(const SilhouetteTreeOptions& options, double height)
      : options_(options), min_length_(options.min_branch_share * height) {}

  SilhouetteStructure structure;

  // Whether the structure holds its share of options.max_branches.
  bool Full() const {
    return static_cast<int>(structure.branches.size()) >= options_.max_branches / 2;
  }

  // The children of branch `p` inferred in its crown: bumps, drawn
  // branches, coverage, sub-silhouettes.
  void InferChildren(int p, const std::vector<Outline2>& drawn) {
    if (Full()) return;
    const Outline2 parent = structure.branches[p].points;
    const Outline2 crown = structure.branches[p].crown;
    if (crown.size() < 3 || Length(parent) <= 0) return;
    const double entry = EntryInto(parent, crown);
    Baf baf(options_.baf_base_deg, options_.baf_tip_deg);
    Children children;
    for (const BumpEnd& end : BumpEnds(crown, parent, entry, options_.valley_depth, min_length_)) {
      SilhouetteBranch child = ShortestBranch(parent, entry, baf, end);
      if (child.points.empty() || Length(child.points) < min_length_) continue;
      children.Add(std::move(child), end, false);
    }
    if (!drawn.empty()) {
      for (const Outline2& line : drawn) AddDrawn(parent, crown, line, &baf, &children);
      Restyle(parent, entry, baf, &children);
      structure.drawn_branches += static_cast<int>(drawn.size());
    }
    const int first_child = static_cast<int>(structure.branches.size());
    for (SilhouetteBranch& child : children.branches) {
      child.parent = p;
      child.level = structure.branches[p].level + 1;
      child.crown = SubSilhouette(crown, child.points,
                                  DistanceToOutline(crown, child.points.back()), options_);
      structure.branches.push_back(std::move(child));
    }
    Cover(p, entry, baf, first_child);
  }

  // Adds copies of the nearest sibling where the children's crowns leave
  // the parent's uncovered (section 4.1).
  void Cover(int p, double entry, const Baf& baf, int first_child) {
    const Outline2 parent = structure.branches[p].points;
    const Outline2 crown = structure.branches[p].crown;
    if (static_cast<int>(structure.branches.size()) == first_child) return;
    const Raster raster(crown);
    const std::vector<char> inside_parent = raster.Cells(crown);
    std::vector<char> covered(inside_parent.size(), 0);
    auto add_cells = [&](const std::vector<char>& cells) {
      for (size_t i = 0; i < cells.size(); ++i) covered[i] |= cells[i];
    };
    for (size_t c = first_child; c < structure.branches.size(); ++c) {
      add_cells(raster.Cells(structure.branches[c].crown));
    }
    for (int step = 0; step < kCoverageSteps && !Full(); ++step) {
      const double t = entry + (1.0 - entry) * (step + 0.5) / kCoverageSteps;
      for (int side : {-1, 1}) {
        Eigen::Vector2d tangent;
        const Eigen::Vector2d base = At(parent, t, &tangent);
        // The sibling nearest in u.
        int source = -1;
        double gap = std::numeric_limits<double>::infinity();
        for (size_t c = first_child; c < structure.branches.size(); ++c) {
          if (std::abs(structure.branches[c].u - t) < gap) {
            gap = std::abs(structure.branches[c].u - t), source = static_cast<int>(c);
          }
        }
        const SilhouetteBranch from = structure.branches[source];
        Eigen::Vector2d from_tangent;
        At(parent, from.u, &from_tangent);
        const Eigen::Vector2d from_leave = InitialDirection(from.points);
        const bool mirror = SideOf(from_tangent, from_leave) != side;
        const Eigen::Vector2d leave = Rotated(tangent, side * baf.Degrees(t) * kDegrees);
        // Mirrored about the source's initial direction, then turned so that
        // it leaves at the BAF's angle, from `base`.
        auto place = [&](const Outline2& line, double k) {
          Outline2 moved = line;
          for (Eigen::Vector2d& q : moved) q += base - from.points.front();
          const Eigen::Vector2d mirrored_leave =
              mirror ? Eigen::Vector2d(2 * from_leave.dot(from_tangent) * from_tangent - from_leave)
                     : from_leave;
          const double turn = std::atan2(Cross(mirrored_leave, leave), mirrored_leave.dot(leave));
          return Turned(moved, base, turn, k, mirror, from_tangent);
        };
        for (double k : kScales) {
          SilhouetteBranch copy;
          copy.points = place(from.points, k);
          copy.crown = place(from.crown, k);
          if (Length(copy.points) < min_length_ || !InsideOutline(crown, copy.points.back()))
            continue;
          const std::vector<char> cells = raster.Cells(copy.crown);
          const int area = Count(cells);
          if (area == 0) continue;
          int in_parent = 0, overlap = 0;
          for (size_t i = 0; i < cells.size(); ++i) {
            in_parent += cells[i] && inside_parent[i];
            overlap += cells[i] && covered[i];
          }
          if (in_parent < kMinInside * area) continue;
          if (overlap > options_.max_overlap * area) break;  // smaller copies overlap too
          copy.parent = p;
          copy.u = t;
          copy.level = from.level;
          copy.coverage = true;
          add_cells(cells);
          structure.branches.push_back(std::move(copy));
          ++structure.coverage_branches;
          break;
        }
      }
    }
  }

  // The children of `source` copied onto `target` (section 4.2), in their
  // span frames.
  void CopyChildren(int source, int target) {
    const SilhouetteBranch from = structure.branches[source];
    const SilhouetteBranch to = structure.branches[target];
    const int parent = from.parent;
    Eigen::Vector2d t_from, t_to;
    At(structure.branches[parent].points, from.u, &t_from);
    At(structure.branches[to.parent].points, to.u, &t_to);
    const bool mirror = SideOf(t_from, from.points.back() - from.points.front()) !=
                        SideOf(t_to, to.points.back() - to.points.front());
    const size_t count = structure.branches.size();
    for (size_t c = 0; c < count && !Full(); ++c) {
      if (structure.branches[c].parent != source) continue;
      SilhouetteBranch copy = structure.branches[c];
      copy.points =
          InSpanFrame(copy.points, from.points, to.points.front(), to.points.back(), mirror);
      copy.crown =
          InSpanFrame(copy.crown, from.points, to.points.front(), to.points.back(), mirror);
      // The copy grows from the target at the same u.
      const Eigen::Vector2d shift = At(to.points, copy.u) - copy.points.front();
      for (Eigen::Vector2d& q : copy.points) q += shift;
      for (Eigen::Vector2d& q : copy.crown) q += shift;
      // Scaled about its base until it ends inside the target's crown, or
      // not copied.
      bool inside = false;
      for (double k : kScales) {
        const Outline2 points =
            Turned(copy.points, copy.points.front(), 0.0, k, false, Eigen::Vector2d::UnitY());
        if (!to.crown.empty() && InsideOutline(to.crown, points.back())) {
          copy.crown =
              Turned(copy.crown, copy.points.front(), 0.0, k, false, Eigen::Vector2d::UnitY());
          copy.points = points;
          inside = true;
          break;
        }
      }
      if (!inside) continue;
      copy.parent = target;
      copy.drawn_shape = copy.drawn_crown = false;
      structure.branches.push_back(std::move(copy));
    }
    ++structure.copied_styles;
  }

 private:
  const SilhouetteTreeOptions& options_;
  double min_length_;
};

}  // namespace

bool InsideOutline(const Outline2& outline, const Eigen::Vector2d& p) {
  bool inside = false;
  for (size_t i = 0, j = outline.size() - 1; i < outline.size(); j = i++) {
    const Eigen::Vector2d& a = outline[i];
    const Eigen::Vector2d& b = outline[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

double OutlineArea(const Outline2& outline) {
  double twice = 0.0;
  for (size_t i = 0, j = outline.size() - 1; i < outline.size(); j = i++) {
    twice += outline[j].x() * outline[i].y() - outline[i].x() * outline[j].y();
  }
  return 0.5 * std::abs(twice);
}

SilhouetteStructure InferSilhouetteStructure(const Outline2& trunk, const Outline2& crown,
                                             const std::vector<Outline2>& sub_silhouettes,
                                             const std::vector<Outline2>& drawn_branches,
                                             const SilhouetteTreeOptions& options) {
  options.Check();
  SYLVA_CHECK_INPUT(trunk.size() >= 2 && Length(trunk) > 0, "the drawing's trunk")
      << "has no length";
  SYLVA_CHECK_INPUT(crown.size() >= 3, "the drawing's crown") << "encloses nothing";
  double top = trunk.front().y();
  for (const Eigen::Vector2d& p : crown) top = std::max(top, p.y());
  StructureBuilder builder(options, top - trunk.front().y());
  SilhouetteStructure& s = builder.structure;
  SilhouetteBranch root;
  root.points = trunk;
  root.crown = crown;
  s.branches.push_back(root);
  // Drawn branches starting within reach of the trunk, leaving it, are its
  // children
  std::vector<Outline2> drawn;
  const double reach = kDrawnReach * (top - trunk.front().y());
  for (Outline2 line : drawn_branches) {
    if (line.size() < 2) continue;
    double d_front = 0.0, d_back = 0.0;
    NearestFraction(trunk, line.front(), &d_front);
    NearestFraction(trunk, line.back(), &d_back);
    if (d_back < d_front) std::reverse(line.begin(), line.end()), std::swap(d_front, d_back);
    // and ending in the crown (a line beside the trunk, like a trunk's
    // outline, or a ground line, is not a branch)
    if (d_front <= reach && d_back > d_front + reach && InsideOutline(crown, line.back())) {
      drawn.push_back(std::move(line));
    }
  }
  builder.InferChildren(0, drawn);
  // Drawn sub-silhouettes: each the crown of the first-level branch whose
  // length it covers most.
  for (const Outline2& outline : sub_silhouettes) {
    if (outline.size() < 3) continue;
    int best = -1;
    double covered_most = 0.0;
    for (size_t b = 1; b < s.branches.size(); ++b) {
      const Outline2& line = s.branches[b].points;
      double covered = 0.0;
      for (size_t i = 1; i < line.size(); ++i) {
        if (InsideOutline(outline, 0.5 * (line[i] + line[i - 1])))
          covered += (line[i] - line[i - 1]).norm();
      }
      if (covered > covered_most) covered_most = covered, best = static_cast<int>(b);
    }
    if (best < 0) continue;
    s.branches[best].crown = outline;
    s.branches[best].drawn_crown = true;
    ++s.drawn_crowns;
  }
  // Level by level: branches with a drawn crown first; their siblings
  // without one copy the nearest drawn sibling's children.
  for (int level = 1; level < options.levels; ++level) {
    const size_t count = s.branches.size();
    std::vector<int> drawn_at, others;
    for (size_t b = 0; b < count; ++b) {
      if (s.branches[b].level != level) continue;
      (s.branches[b].drawn_crown ? drawn_at : others).push_back(static_cast<int>(b));
    }
    for (int b : drawn_at) builder.InferChildren(b, {});
    for (int b : others) {
      int source = -1;
      double gap = std::numeric_limits<double>::infinity();
      for (int d : drawn_at) {
        if (s.branches[d].parent != s.branches[b].parent) continue;
        if (std::abs(s.branches[d].u - s.branches[b].u) < gap) {
          gap = std::abs(s.branches[d].u - s.branches[b].u), source = d;
        }
      }
      if (source >= 0) {
        builder.CopyChildren(source, b);
      } else {
        builder.InferChildren(b, {});
      }
    }
  }
  return s;
}

namespace {

// The cost of two insertion points among `count` on a parent: the
// closeness penalty f (counted for both orders), plus with a phyllotaxis
// the distance to the pattern's nearest privileged position (section 5.4:
// phi between successive nodes, gamma = 360 / n within a node of n
// branches, an average node length of n / count in u; the number of nodes
// between the two is rounded where the paper floors it).
double PairCost(const InsertionPoint& a, const InsertionPoint& b, size_t count,
                const SilhouetteTreeOptions& options) {
  const double du = a.u - b.u;
  double dtheta = std::fmod(std::abs(a.theta - b.theta), 360.0);
  dtheta = std::min(dtheta, 360.0 - dtheta) / 360.0;
  const double f = 1.0 / (1.0 + options.gibbs_alpha * (du * du + dtheta * dtheta));
  if (options.phyllotaxis == "none") return 2 * f;
  double phi = 144.0, n = 1.0;
  if (options.phyllotaxis == "decussate") phi = 90.0, n = 2.0;
  if (options.phyllotaxis == "whorl3") phi = 60.0, n = 3.0;
  const double gamma = 360.0 / n;
  const double node = n / std::max<double>(count, 1.0);
  const InsertionPoint& lower = a.u <= b.u ? a : b;
  const InsertionPoint& upper = a.u <= b.u ? b : a;
  const double nodes = std::round((upper.u - lower.u) / node);
  double angle = std::fmod(upper.theta - lower.theta - nodes * phi, gamma);
  if (angle < 0) angle += gamma;
  const double pattern = std::min(angle, gamma - angle) / gamma;
  return 2 * (kCloseness * f + kPattern * pattern);
}

// The cost of point i with all the others.
double CostOf(const std::vector<InsertionPoint>& points, size_t i,
              const SilhouetteTreeOptions& options) {
  double cost = 0.0;
  for (size_t j = 0; j < points.size(); ++j) {
    if (j != i) cost += PairCost(points[i], points[j], points.size(), options);
  }
  return cost;
}

}  // namespace

double GibbsCost(const std::vector<InsertionPoint>& points, const SilhouetteTreeOptions& options) {
  double cost = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      cost += PairCost(points[i], points[j], points.size(), options);
    }
  }
  return cost;
}

double PlaceByGibbs(const SilhouetteTreeOptions& options, uint64_t seed,
                    std::vector<InsertionPoint>* points) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  if (points->size() < 2) return GibbsCost(*points, options);
  double u_low = 1.0, u_high = 0.0;
  for (const InsertionPoint& p : *points) {
    u_low = std::min(u_low, p.u), u_high = std::max(u_high, p.u);
  }
  for (int k = 0; k < options.gibbs_iterations; ++k) {
    const size_t i =
        std::min(points->size() - 1, static_cast<size_t>(unit(random) * points->size()));
    InsertionPoint& p = (*points)[i];
    const InsertionPoint old = p;
    const double before = CostOf(*points, i, options);
    p.theta = std::fmod(p.theta_min + unit(random) * (p.theta_max - p.theta_min) + 360.0, 360.0);
    if (!p.fixed_u) p.u = u_low + unit(random) * (u_high - u_low);
    if (CostOf(*points, i, options) >= before) p = old;
  }
  return GibbsCost(*points, options);
}

namespace {

// One branch of the 3D tree: a 2D branch (or a copy of one) and the map
// from the drawing's plane to the world.
struct Placed {
  int branch;  // in the structure
  int parent;  // placed parent, -1 for the trunk
  double u;    // on the placed parent
  Eigen::Isometry3d map;
};

Eigen::Vector3d Embed(const Eigen::Vector2d& p) { return {p.x(), 0.0, p.y()}; }

// The insertion points of the children `kids` of a parent (section 5.3):
// theirs within `spread_deg` of the drawing's plane on their side (`source` their branch,
// `theta_2d` their side), and `extra` more anywhere between the lowest and
// highest child (source -1).
std::vector<InsertionPoint> InsertionPoints(const std::vector<SilhouetteBranch>& branches,
                                            const Outline2& parent, const std::vector<int>& kids,
                                            int extra, double spread_deg, std::mt19937_64* random,
                                            std::vector<int>* source,
                                            std::vector<double>* theta_2d) {
  std::vector<InsertionPoint> points;
  for (int c : kids) {
    Eigen::Vector2d tangent;
    At(parent, branches[c].u, &tangent);
    const double theta = SideOf(tangent, InitialDirection(branches[c].points)) < 0 ? 0.0 : 180.0;
    points.push_back({branches[c].u, theta, true, theta - spread_deg, theta + spread_deg});
    source->push_back(c);
    theta_2d->push_back(theta);
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double u_low = 1.0, u_high = 0.0;
  for (int c : kids) {
    u_low = std::min(u_low, branches[c].u), u_high = std::max(u_high, branches[c].u);
  }
  for (int e = 0; e < extra; ++e) {
    const double u = u_low + unit(*random) * (u_high - u_low);
    // Around a leaning parent, on its upper half (a departure from the
    // paper, whose extra branches go anywhere: on a limb they would hang).
    Eigen::Vector2d tangent;
    At(parent, u, &tangent);
    double low = 0.0, high = 360.0;
    if (std::abs(tangent.y()) < kUprightParent) {
      const Eigen::Vector2d up = tangent.x() >= 0 ? Eigen::Vector2d(-tangent.y(), tangent.x())
                                                  : Eigen::Vector2d(tangent.y(), -tangent.x());
      const double theta_up = SideOf(tangent, up) < 0 ? 0.0 : 180.0;
      low = theta_up - kUpperHalfDeg, high = theta_up + kUpperHalfDeg;
    }
    points.push_back({u, low + unit(*random) * (high - low), false, low, high});
    source->push_back(-1);
    theta_2d->push_back(0.0);
  }
  return points;
}

// The skeleton of the placed branches: each one's polyline, split where its
// children join and into edges of at most max_edge.
SkeletonGraph SkeletonOfPlaced(const std::vector<SilhouetteBranch>& branches,
                               const std::vector<Placed>& placed, double max_edge) {
  std::vector<std::vector<int>> placed_children(placed.size());
  for (size_t q = 1; q < placed.size(); ++q) placed_children[placed[q].parent].push_back(q);
  std::vector<int> junction_node(placed.size(), -1);
  SkeletonGraph skeleton;
  for (size_t q = 0; q < placed.size(); ++q) {
    const SilhouetteBranch& branch = branches[placed[q].branch];
    const Outline2& line = branch.points;
    std::vector<std::pair<double, int>> stops;  // (fraction, placed child or -1)
    const int pieces = std::max(1, static_cast<int>(std::ceil(Length(line) / max_edge)));
    for (int k = 1; k <= pieces; ++k) stops.emplace_back(static_cast<double>(k) / pieces, -1);
    for (int child : placed_children[q]) stops.emplace_back(placed[child].u, child);
    std::sort(stops.begin(), stops.end());
    int node = junction_node[q];
    if (node < 0) node = skeleton.AddNode(placed[q].map * Embed(line.front()), 0.0, -1, 0);
    double last = 0.0;
    for (const auto& [t, child] : stops) {
      if (t > last + 1e-9) {
        node = skeleton.AddNode(placed[q].map * Embed(At(line, t)), 0.0, node, branch.level);
        last = t;
      }
      if (child >= 0) junction_node[child] = node;
    }
  }
  return skeleton;
}

}  // namespace

SilhouetteTree PlaceSilhouetteTree(const SilhouetteStructure& structure, double max_edge,
                                   const SilhouetteTreeOptions& options) {
  options.Check();
  SYLVA_CHECK(!structure.branches.empty() && max_edge > 0);
  const std::vector<SilhouetteBranch>& branches = structure.branches;
  std::vector<std::vector<int>> children(branches.size());
  for (size_t b = 1; b < branches.size(); ++b) children[branches[b].parent].push_back(b);
  SilhouetteTree tree;
  tree.structure = structure;
  std::vector<Placed> placed = {{0, -1, 0.0, Eigen::Isometry3d::Identity()}};
  for (size_t q = 0; q < placed.size(); ++q) {
    const Placed here = placed[q];
    const std::vector<int>& kids = children[here.branch];
    if (kids.empty()) continue;
    const Outline2& parent = branches[here.branch].points;
    std::mt19937_64 random(options.seed * 0x9E3779B97F4A7C15ull + q);
    const int extra = static_cast<int>(placed.size()) < options.max_branches / 2
                          ? static_cast<int>(std::lround(options.extra_branches * kids.size()))
                          : 0;
    std::vector<int> source;
    std::vector<double> theta_2d;
    std::vector<InsertionPoint> points = InsertionPoints(
        branches, parent, kids, extra, options.drawn_spread_deg, &random, &source, &theta_2d);
    PlaceByGibbs(options, options.seed + q, &points);
    for (size_t k = 0; k < points.size(); ++k) {
      if (static_cast<int>(placed.size()) >= options.max_branches) break;
      int c = source[k];
      double side = theta_2d[k];
      Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
      if (c < 0) {
        // An extra branch copies the drawn sibling nearest its u, moved
        // along the parent to its u, keeping its angle to it.
        double gap = std::numeric_limits<double>::infinity();
        for (size_t d = 0; d < kids.size(); ++d) {
          if (std::abs(branches[kids[d]].u - points[k].u) < gap) {
            gap = std::abs(branches[kids[d]].u - points[k].u), c = kids[d], side = theta_2d[d];
          }
        }
        Eigen::Vector2d t_old, t_new;
        const Eigen::Vector2d from = At(parent, branches[c].u, &t_old);
        const Eigen::Vector2d to = At(parent, points[k].u, &t_new);
        const double turn = std::atan2(Cross(t_old, t_new), t_old.dot(t_new));
        local = Eigen::Translation3d(Embed(to)) *
                Eigen::AngleAxisd(-turn, Eigen::Vector3d::UnitY()) *
                Eigen::Translation3d(-Embed(from));
        ++tree.extra_branches;
      }
      // Turned about the parent's tangent at the junction from its side of
      // the drawing's plane to its theta.
      Eigen::Vector2d tangent;
      const Eigen::Vector2d junction = At(parent, points[k].u, &tangent);
      const Eigen::Isometry3d turn =
          Eigen::Translation3d(Embed(junction)) *
          Eigen::AngleAxisd((points[k].theta - side) * kDegrees, Embed(tangent).normalized()) *
          Eigen::Translation3d(-Embed(junction));
      placed.push_back({c, static_cast<int>(q), points[k].u, here.map * turn * local});
    }
  }
  tree.skeleton = SkeletonOfPlaced(branches, placed, max_edge);
  return tree;
}

}  // namespace sylva
