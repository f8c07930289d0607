#include "sketch/concept_sketch.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/util/check.h"

namespace sylva {
namespace {

using Polyline = std::vector<Eigen::Vector2d>;

// An organ end within this many organ lengths of the stem is its base.
constexpr double kBaseNearStemFraction = 0.5;
// Outlines are thinned to at most this many points for the farthest pair.
constexpr int kMaxOutlinePoints = 400;

// Lower-case alphanumeric words of `text`.
std::vector<std::string> Words(const std::string& text) {
  std::vector<std::string> words;
  std::string word;
  for (char c : text + " ") {
    if (std::isalnum(static_cast<unsigned char>(c))) {
      word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else if (!word.empty()) {
      words.push_back(word);
      word.clear();
    }
  }
  return words;
}

enum class LineKind { kUnknown, kStem, kBoundary, kInclination };

LineKind KindFromName(const std::string& name) {
  for (const std::string& word : Words(name)) {
    if (word == "stem") return LineKind::kStem;
    if (word == "boundary" || word == "boundaries" || word == "envelope") {
      return LineKind::kBoundary;
    }
    if (word == "inclination" || word == "inclinations") return LineKind::kInclination;
  }
  return LineKind::kUnknown;
}

Eigen::Vector2d Extent(const Polyline& points) {
  Eigen::Vector2d lo = points.front(), hi = points.front();
  for (const Eigen::Vector2d& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return hi - lo;
}

Eigen::Vector2d Mean(const Polyline& points) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Segments a0-a1 and b0-b1 meet at a0 + s (a1 - a0) = b0 + t (b1 - b0)
// with s, t in [0, 1]: returns true and s, t.
bool SegmentsMeet(const Eigen::Vector2d& a0, const Eigen::Vector2d& a1, const Eigen::Vector2d& b0,
                  const Eigen::Vector2d& b1, double* s, double* t) {
  const Eigen::Vector2d da = a1 - a0, db = b1 - b0;
  const double denominator = Cross(da, db);
  if (std::abs(denominator) < 1e-12) return false;
  *s = Cross(b0 - a0, db) / denominator;
  *t = Cross(b0 - a0, da) / denominator;
  return *s >= 0 && *s <= 1 && *t >= 0 && *t <= 1;
}

// The polyline with its first and last segments extended by `fraction` of
// its length.
Polyline Extended(const Polyline& points, double fraction) {
  Polyline extended = points;
  const double reach = fraction * PolylineLengthPx(points);
  const Eigen::Vector2d start_dir = (points[0] - points[1]).normalized();
  const Eigen::Vector2d end_dir = (points.back() - points[points.size() - 2]).normalized();
  extended.insert(extended.begin(), points[0] + reach * start_dir);
  extended.push_back(points.back() + reach * end_dir);
  return extended;
}

// Where `line` crosses `stem`: the stem's arc length there, or nullopt.
std::optional<double> StemCrossing(const Polyline& stem, const Polyline& line) {
  double stem_arc = 0;
  for (size_t i = 1; i < stem.size(); ++i) {
    const double segment = (stem[i] - stem[i - 1]).norm();
    for (size_t j = 1; j < line.size(); ++j) {
      double s, t;
      if (SegmentsMeet(stem[i - 1], stem[i], line[j - 1], line[j], &s, &t)) {
        return stem_arc + s * segment;
      }
    }
    stem_arc += segment;
  }
  return std::nullopt;
}

double DistanceToPolyline(const Polyline& points, const Eigen::Vector2d& q) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < points.size(); ++i) {
    const Eigen::Vector2d d = points[i] - points[i - 1];
    const double t =
        std::clamp((q - points[i - 1]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (points[i - 1] + t * d - q).norm());
  }
  return best;
}

// The canvas direction to the left of `direction` (y down: left of "up" is -x).
Eigen::Vector2d LeftOf(const Eigen::Vector2d& direction) {
  return Eigen::Vector2d(direction.y(), -direction.x());
}

// ------------------------------------------------- construction lines

struct Candidate {
  const SketchStroke* stroke;
  LineKind kind;
};

// Rule 3 of the header: the stem among unlabelled open strokes.
int PickStem(const std::vector<Candidate>& candidates) {
  std::vector<int> lengthwise, transverse;
  for (size_t k = 0; k < candidates.size(); ++k) {
    const SketchStroke& s = *candidates[k].stroke;
    if (candidates[k].kind != LineKind::kUnknown || s.closed) continue;
    const Eigen::Vector2d extent = Extent(s.points);
    (extent.y() >= extent.x() ? lengthwise : transverse).push_back(static_cast<int>(k));
  }
  if (lengthwise.empty()) return -1;
  const auto mean_x = [&](int k) { return Mean(candidates[k].stroke->points).x(); };
  std::sort(lengthwise.begin(), lengthwise.end(),
            [&](int a, int b) { return mean_x(a) < mean_x(b); });
  if (lengthwise.size() != 2 || transverse.empty()) return lengthwise[(lengthwise.size() - 1) / 2];
  double middle = 0;
  for (int k : transverse) middle += Mean(candidates[k].stroke->points).x();
  middle /= static_cast<double>(transverse.size());
  return std::abs(mean_x(lengthwise[0]) - middle) <= std::abs(mean_x(lengthwise[1]) - middle)
             ? lengthwise[0]
             : lengthwise[1];
}

// The stem from base to tip.
Polyline OrientStem(const SketchDrawing& drawing, Polyline stem) {
  bool reverse = stem.front().y() < stem.back().y();
  if (drawing.root) {
    reverse = (stem.back() - *drawing.root).norm() < (stem.front() - *drawing.root).norm();
  }
  if (reverse) std::reverse(stem.begin(), stem.end());
  return stem;
}

// Paper 6.2: the angles between the stem's downward direction at the
// crossing and the line's parts to either side.
ConceptStructure::Inclination MakeInclination(const Polyline& stem, const Polyline& line,
                                              double stem_arc) {
  ConceptStructure::Inclination inclination;
  inclination.points = line;
  inclination.stem_arc_px = stem_arc;
  Eigen::Vector2d tangent;
  const Eigen::Vector2d crossing = PointAtArc(stem, stem_arc, &tangent);
  const Eigen::Vector2d down = -tangent, left = LeftOf(tangent);
  std::optional<double> left_deg, right_deg;
  for (const Eigen::Vector2d& end : {line.front(), line.back()}) {
    const Eigen::Vector2d arm = end - crossing;
    if (arm.norm() < 1e-9) continue;
    const double deg = std::acos(std::clamp(arm.normalized().dot(down), -1.0, 1.0)) * 180.0 / M_PI;
    (arm.dot(left) > 0 ? left_deg : right_deg) = deg;
  }
  inclination.left_deg = left_deg.value_or(right_deg.value_or(90.0));
  inclination.right_deg = right_deg.value_or(inclination.left_deg);
  return inclination;
}

// Joins each boundary's ends to the nearer stem end (header).
void CloseEnvelope(const Polyline& stem, ConceptStructure* structure) {
  const size_t drawn = structure->envelope.size();
  const double near = 1e-6 * PolylineLengthPx(stem);
  for (size_t k = 0; k < drawn; ++k) {
    const Polyline boundary = structure->envelope[k];
    for (const Eigen::Vector2d& end : {boundary.front(), boundary.back()}) {
      const Eigen::Vector2d& stem_end =
          (end - stem.front()).norm() < (end - stem.back()).norm() ? stem.front() : stem.back();
      if ((end - stem_end).norm() > near) structure->envelope.push_back({end, stem_end});
    }
  }
}

void ReadConstruction(const SketchDrawing& drawing, const std::vector<Candidate>& candidates,
                      ConceptStructure* structure) {
  int stem_idx = -1;
  for (size_t k = 0; k < candidates.size(); ++k) {
    if (candidates[k].kind != LineKind::kStem) continue;
    SYLVA_CHECK_INPUT(stem_idx < 0, drawing.source)
        << "two strokes are named 'stem'; a concept drawing has one stem line";
    stem_idx = static_cast<int>(k);
  }
  if (stem_idx < 0) stem_idx = PickStem(candidates);
  SYLVA_CHECK_INPUT(stem_idx >= 0, drawing.source)
      << "no stem: a concept drawing needs a stem line (an open construction stroke taller "
         "than wide, or one named 'stem'), boundary lines beside it and optional inclination "
         "lines across it";
  const SketchStroke& stem_stroke = *candidates[stem_idx].stroke;
  structure->stem = OrientStem(drawing, stem_stroke.points);
  structure->stem_width_px = stem_stroke.width;
  const double stem_length = PolylineLengthPx(structure->stem);
  SYLVA_CHECK_INPUT(stem_length > 1e-6 * std::max(drawing.width, drawing.height), drawing.source)
      << "the stem line has zero length";
  for (size_t k = 0; k < candidates.size(); ++k) {
    if (static_cast<int>(k) == stem_idx) continue;
    const SketchStroke& s = *candidates[k].stroke;
    LineKind kind = candidates[k].kind;
    std::optional<double> crossing;
    if (kind == LineKind::kUnknown || kind == LineKind::kInclination) {
      crossing = StemCrossing(structure->stem, Extended(s.points, kInclinationReach));
    }
    if (kind == LineKind::kUnknown) {
      const Eigen::Vector2d extent = Extent(s.points);
      const bool transverse = !s.closed && extent.x() > extent.y();
      kind = transverse && crossing ? LineKind::kInclination : LineKind::kBoundary;
    }
    if (kind == LineKind::kInclination) {
      SYLVA_CHECK_INPUT(crossing.has_value(), drawing.source)
          << "an inclination line (" << s.name << ") does not cross the stem";
      structure->inclinations.push_back(MakeInclination(structure->stem, s.points, *crossing));
      continue;
    }
    Polyline boundary = s.points;
    if (s.closed) boundary.push_back(s.points.front());
    structure->envelope.push_back(boundary);
    ++structure->num_boundaries;
  }
  SYLVA_CHECK_INPUT(structure->num_boundaries > 0, drawing.source)
      << "no boundary line: a concept drawing needs boundary lines beside the stem giving the "
         "organs' extent (open strokes taller than wide, or strokes named 'boundary')";
  std::sort(structure->inclinations.begin(), structure->inclinations.end(),
            [](const auto& a, const auto& b) { return a.stem_arc_px > b.stem_arc_px; });
  CloseEnvelope(structure->stem, structure);
}

// ------------------------------------------------- organs

// The base end of an organ whose ends are `a` and `b`: true if it is `a`.
bool BaseIsFirst(const Polyline& stem, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double length = (b - a).norm();
  const double da = DistanceToPolyline(stem, a), db = DistanceToPolyline(stem, b);
  if (std::min(da, db) < kBaseNearStemFraction * length) return da <= db;
  return a.y() >= b.y();
}

ConceptOrganTemplate BladeTemplate(const Polyline& stem, const SketchStroke& stroke,
                                   const std::string& source) {
  Polyline outline;
  const size_t step = std::max<size_t>(1, stroke.points.size() / kMaxOutlinePoints);
  for (size_t i = 0; i < stroke.points.size(); i += step) outline.push_back(stroke.points[i]);
  size_t ia = 0, ib = 0;
  double best = -1;
  for (size_t i = 0; i < outline.size(); ++i) {
    for (size_t j = i + 1; j < outline.size(); ++j) {
      const double d = (outline[i] - outline[j]).squaredNorm();
      if (d > best) best = d, ia = i, ib = j;
    }
  }
  SYLVA_CHECK_INPUT(best > 0, source) << "an organ outline (" << stroke.name << ") has zero size";
  Eigen::Vector2d base = outline[ia], tip = outline[ib];
  if (!BaseIsFirst(stem, base, tip)) std::swap(base, tip);
  ConceptOrganTemplate organ;
  organ.length_px = (tip - base).norm();
  const Eigen::Vector2d along = (tip - base) / organ.length_px, left = LeftOf(along);
  organ.left.assign(kOrganStations, 0.0);
  organ.right.assign(kOrganStations, 0.0);
  // Each outline edge spanning a station's u gives a v there.
  const size_t n = stroke.points.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d p = (stroke.points[i] - base) / organ.length_px;
    const Eigen::Vector2d q = (stroke.points[(i + 1) % n] - base) / organ.length_px;
    const Eigen::Vector2d pu(p.dot(along), p.dot(left)), qu(q.dot(along), q.dot(left));
    for (int k = 1; k + 1 < kOrganStations; ++k) {
      const double u = static_cast<double>(k) / (kOrganStations - 1);
      if ((pu.x() - u) * (qu.x() - u) > 0 || pu.x() == qu.x()) continue;
      const double v = pu.y() + (u - pu.x()) / (qu.x() - pu.x()) * (qu.y() - pu.y());
      organ.left[k] = std::max(organ.left[k], v);
      organ.right[k] = std::max(organ.right[k], -v);
    }
  }
  return organ;
}

ConceptOrganTemplate LineTemplate(const Polyline& stem, const SketchStroke& stroke,
                                  const std::string& source) {
  Polyline line = stroke.points;
  if (!BaseIsFirst(stem, line.front(), line.back())) std::reverse(line.begin(), line.end());
  ConceptOrganTemplate organ;
  organ.blade = false;
  organ.length_px = (line.back() - line.front()).norm();
  SYLVA_CHECK_INPUT(organ.length_px > 0, source)
      << "an organ line (" << stroke.name << ") ends where it starts";
  const Eigen::Vector2d along = (line.back() - line.front()) / organ.length_px;
  const Eigen::Vector2d left = LeftOf(along);
  const double length = PolylineLengthPx(line);
  for (int k = 0; k < kOrganStations; ++k) {
    const Eigen::Vector2d p =
        (PointAtArc(line, length * k / (kOrganStations - 1)) - line.front()) / organ.length_px;
    organ.centre.emplace_back(p.dot(along), p.dot(left));
  }
  return organ;
}

void ReadOrgans(const SketchDrawing& drawing, ConceptStructure* structure) {
  StrokeRole role = StrokeRole::kOrgan;
  if (drawing.CountRole(role) == 0) role = StrokeRole::kCrown;
  bool any_blade = false;
  for (const SketchStroke& s : drawing.strokes) any_blade |= s.role == role && s.closed;
  for (const SketchStroke& s : drawing.strokes) {
    if (s.role != role || s.closed != any_blade || structure->organs.size() == 2) continue;
    structure->organs.push_back(any_blade ? BladeTemplate(structure->stem, s, drawing.source)
                                          : LineTemplate(structure->stem, s, drawing.source));
  }
}

std::optional<ConceptPattern> DrawnPattern(const SketchDrawing& drawing) {
  std::vector<std::string> texts = drawing.texts;
  for (const SketchStroke& s : drawing.strokes) texts.push_back(s.name);
  for (const std::string& text : texts) {
    for (const std::string& word : Words(text)) {
      if (auto pattern = ConceptPatternFromName(word)) return pattern;
    }
  }
  return std::nullopt;
}

}  // namespace

double ConceptDivergenceDeg(ConceptPattern pattern) {
  switch (pattern) {
    case ConceptPattern::kSpiral:
      return 137.5;
    case ConceptPattern::kMonostichous:
      return 30.0;
    case ConceptPattern::kDistichous:
      return 180.0;
    case ConceptPattern::kTristichous:
      return 120.0;
    case ConceptPattern::kTetrastichous:
      return 90.0;
  }
  return 137.5;
}

double PolylineLengthPx(const std::vector<Eigen::Vector2d>& points) {
  double length = 0;
  for (size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

Eigen::Vector2d PointAtArc(const std::vector<Eigen::Vector2d>& points, double s,
                           Eigen::Vector2d* tangent) {
  SYLVA_CHECK(points.size() >= 2) << "a polyline needs two points";
  double walked = 0;
  for (size_t i = 1; i < points.size(); ++i) {
    const double segment = (points[i] - points[i - 1]).norm();
    if (segment <= 0) continue;
    if (walked + segment >= s || i + 1 == points.size()) {
      if (tangent != nullptr) *tangent = (points[i] - points[i - 1]) / segment;
      const double t = std::clamp((s - walked) / segment, 0.0, 1.0);
      return points[i - 1] + t * (points[i] - points[i - 1]);
    }
    walked += segment;
  }
  if (tangent != nullptr) *tangent = Eigen::Vector2d(0, -1);
  return points.front();
}

double CastRay2d(const std::vector<std::vector<Eigen::Vector2d>>& polylines,
                 const Eigen::Vector2d& origin, const Eigen::Vector2d& direction) {
  double best = std::numeric_limits<double>::infinity();
  for (const Polyline& line : polylines) {
    for (size_t i = 1; i < line.size(); ++i) {
      const Eigen::Vector2d edge = line[i] - line[i - 1];
      const double denominator = Cross(direction, edge);
      if (std::abs(denominator) < 1e-15) continue;
      const double t = Cross(line[i - 1] - origin, edge) / denominator;
      const double u = Cross(line[i - 1] - origin, direction) / denominator;
      if (t > 1e-9 && u >= 0 && u <= 1) best = std::min(best, t);
    }
  }
  return best;
}

std::string ConceptStructure::BriefReport() const {
  std::ostringstream out;
  out << "Concept drawing " << source << ": stem " << PolylineLengthPx(stem) << " px, "
      << num_boundaries << " boundary line(s), " << inclinations.size() << " inclination line(s), "
      << organs.size() << " organ template(s)";
  if (!organs.empty()) out << " (" << (organs.front().blade ? "blades" : "lines") << ")";
  if (drawn_pattern) out << ", pattern '" << ConceptPatternName(*drawn_pattern) << "' drawn";
  out << ".";
  return out.str();
}

ConceptStructure InterpretConceptDrawing(const SketchDrawing& drawing) {
  drawing.Check();
  ConceptStructure structure;
  structure.source = drawing.source;
  StrokeRole role = StrokeRole::kConstruction;
  if (drawing.CountRole(role) == 0) role = StrokeRole::kBranch;
  std::vector<Candidate> candidates;
  for (const SketchStroke& s : drawing.strokes) {
    if (s.role == role) candidates.push_back({&s, KindFromName(s.name)});
  }
  SYLVA_CHECK_INPUT(!candidates.empty(), drawing.source)
      << "no construction lines: a concept drawing needs a stem, boundary lines and optional "
         "inclination lines (role 'construction', e.g. an Inkscape layer of that name)";
  ReadConstruction(drawing, candidates, &structure);
  ReadOrgans(drawing, &structure);
  structure.drawn_pattern = DrawnPattern(drawing);
  return structure;
}

}  // namespace sylva
