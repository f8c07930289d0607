#include "sketch/concept_plant.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "core/util/check.h"
#include "core/util/random.h"

namespace sylva {
namespace {

using Polyline2 = std::vector<Eigen::Vector2d>;

constexpr double kDegrees = M_PI / 180.0;
// Samples of the envelope's half widths along the stem.
constexpr int kEnvelopeSamples = 512;
// Points across a blade at each station (odd: one on the midrib).
constexpr int kBladeColumns = 7;
// Bisection steps of an organ's fit into the envelope (2^-30 of its length).
constexpr int kFitIterations = 30;
// An organ fits when no point lies farther outside than this fraction of
// the stem's length (rounding).
constexpr double kFitTolerance = 1e-9;
// Stem nodes of the skeleton are at most this fraction of its length apart.
constexpr double kStemNodeSpacing = 1.0 / 48;
// An organ's axis narrows to this fraction of its base radius at its tip.
constexpr double kAxisTipFraction = 0.4;
// Points of the envelope's cross section drawn at an inclination line.
constexpr int kSectionPoints = 72;
constexpr uint64_t kTemplateStream = 0x636f6e63;  // "conc"

Eigen::Vector2d LeftOf(const Eigen::Vector2d& direction) {
  return Eigen::Vector2d(direction.y(), -direction.x());
}

// A canvas direction in the world frame (the header's).
Eigen::Vector3d WorldDirection(const Eigen::Vector2d& d) {
  return Eigen::Vector3d(d.x(), 0, -d.y()).normalized();
}

// The drawing plane's normal to the stem, pointing right, and the depth axis.
void SectionAxes(const Eigen::Vector3d& tangent, Eigen::Vector3d* e1, Eigen::Vector3d* e2) {
  *e1 = Eigen::Vector3d::UnitY().cross(tangent).normalized();
  *e2 = tangent.cross(*e1);
}

// Paper 6.3: the radius of the two half ellipses about P_C at angle theta
// (right half semi-axis c, left half a, both b = (a + c) / 2 in depth).
double EllipseRadius(double theta_rad, double a, double c) {
  const double b = (a + c) / 2, cos_t = std::cos(theta_rad), sin_t = std::sin(theta_rad);
  const double half = cos_t >= 0 ? c : a;
  if (half <= 0 || b <= 0) return 0;
  return std::sqrt(b * b * half * half / (b * b * cos_t * cos_t + half * half * sin_t * sin_t));
}

double Interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  if (x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const size_t i = std::upper_bound(xs.begin(), xs.end(), x) - xs.begin();
  const double f = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys[i - 1] + f * (ys[i] - ys[i - 1]);
}

// Where segment p-q crosses the stem: its arc length (px), or nullopt.
std::optional<double> StemArcOfCrossing(const Polyline2& stem, const Eigen::Vector2d& p,
                                        const Eigen::Vector2d& q) {
  double arc = 0;
  for (size_t i = 1; i < stem.size(); ++i) {
    const Eigen::Vector2d a = stem[i - 1], da = stem[i] - a, dq = q - p;
    const double denominator = da.x() * dq.y() - da.y() * dq.x();
    const double segment = da.norm();
    if (std::abs(denominator) > 1e-15) {
      const Eigen::Vector2d ap = p - a;
      const double s = (ap.x() * dq.y() - ap.y() * dq.x()) / denominator;
      const double t = (ap.x() * da.y() - ap.y() * da.x()) / denominator;
      if (s >= 0 && s <= 1 && t >= 0 && t <= 1) return arc + s * segment;
    }
    arc += segment;
  }
  return std::nullopt;
}

// One layer between two inclination lines (or the whole stem).
struct Layer {
  double top_px = 0, bottom_px = 0;
  const ConceptStructure::Inclination* upper = nullptr;
  const ConceptStructure::Inclination* lower = nullptr;
};

std::vector<Layer> Layers(const ConceptStructure& structure) {
  const auto& lines = structure.inclinations;
  std::vector<Layer> layers;
  if (lines.size() < 2) {
    const auto* line = lines.empty() ? nullptr : &lines.front();
    layers.push_back({PolylineLengthPx(structure.stem), 0.0, line, line});
    return layers;
  }
  for (size_t i = 0; i + 1 < lines.size(); ++i) {
    if (lines[i].stem_arc_px > lines[i + 1].stem_arc_px) {
      layers.push_back({lines[i].stem_arc_px, lines[i + 1].stem_arc_px, &lines[i], &lines[i + 1]});
    }
  }
  return layers;
}

// Builds the plant (the header's construction), one step per method.
class ConceptPlantBuilder {
 public:
  ConceptPlantBuilder(const ConceptStructure& structure, const ConceptPlantOptions& options)
      : structure_(structure),
        options_(options),
        random_(DeriveSeed(options.seed, kTemplateStream)) {}

  ConceptPlant Build();

 private:
  void SetFrame();
  void SampleEnvelope();
  void PlaceNode(const Layer& layer, double arc_px, int node, int layer_idx);
  bool PlaceOrgan(double arc_px, double phi_left, double phi_right, double theta_deg,
                  ConceptOrgan* organ);
  // The organ's points for length `length` (blade grid or centre line).
  std::vector<Eigen::Vector3d> OrganPoints(const ConceptOrgan& organ, const Eigen::Vector3d& e1,
                                           const Eigen::Vector3d& e2, const Eigen::Vector3d& e3,
                                           double length, std::vector<double>* widths) const;
  double Fit(const ConceptOrgan& organ, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
             const Eigen::Vector3d& e3, double length) const;
  void AddBlade(const std::vector<Eigen::Vector3d>& grid, const std::vector<double>& widths);
  SkeletonGraph BuildSkeleton(bool blade_axes) const;
  void AddConstruction();
  double StemRadius(double arc) const;
  std::string Brief() const;

  const ConceptStructure& structure_;
  const ConceptPlantOptions& options_;
  RandomEngine random_;
  ConceptPlant plant_;
  double stem_length_px_ = 0;
  int blade_material_ = -1;
  double template_t_ = 0;  // of the organ being placed
};

void ConceptPlantBuilder::SetFrame() {
  stem_length_px_ = PolylineLengthPx(structure_.stem);
  plant_.world_per_pixel = options_.stem_length / stem_length_px_;
  plant_.base_px = structure_.stem.front();
  for (const Eigen::Vector2d& p : structure_.stem) plant_.stem.push_back(plant_.ToWorld(p));
}

void ConceptPlantBuilder::SampleEnvelope() {
  for (int j = 0; j <= kEnvelopeSamples; ++j) {
    const double arc_px = stem_length_px_ * j / kEnvelopeSamples;
    Eigen::Vector2d tangent;
    const Eigen::Vector2d p = PointAtArc(structure_.stem, arc_px, &tangent);
    const double left = CastRay2d(structure_.envelope, p, LeftOf(tangent));
    const double right = CastRay2d(structure_.envelope, p, -LeftOf(tangent));
    plant_.envelope_arc.push_back(arc_px * plant_.world_per_pixel);
    plant_.envelope_left.push_back(std::isfinite(left) ? left * plant_.world_per_pixel : 0.0);
    plant_.envelope_right.push_back(std::isfinite(right) ? right * plant_.world_per_pixel : 0.0);
  }
}

std::vector<Eigen::Vector3d> ConceptPlantBuilder::OrganPoints(
    const ConceptOrgan& organ, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
    const Eigen::Vector3d& e3, double length, std::vector<double>* widths) const {
  const auto& templates = structure_.organs;
  const double t = organ.template_t;
  const bool two = templates.size() > 1;
  const auto lerp = [&](const std::vector<double> ConceptOrganTemplate::*field, int k) {
    const double a = (templates.front().*field)[k];
    return two ? (1 - t) * a + t * (templates[1].*field)[k] : a;
  };
  const auto lerp_centre = [&](int k) -> Eigen::Vector2d {
    const Eigen::Vector2d a = templates.front().centre[k];
    return two ? Eigen::Vector2d((1 - t) * a + t * templates[1].centre[k]) : a;
  };
  std::vector<Eigen::Vector3d> points;
  const auto map = [&](double u, double v, double w) {
    return organ.base + length * (u * e3 + v * e1 + w * e2);
  };
  if (!organ.blade) {
    for (int k = 0; k < kOrganStations; ++k) {
      const Eigen::Vector2d uv = lerp_centre(k);
      points.push_back(organ.base + length * (uv.x() * e3 + uv.y() * e2));
    }
    return points;
  }
  const double fold = std::tan(options_.organ_fold_deg * kDegrees);
  for (int k = 0; k < kOrganStations; ++k) {
    const double u = static_cast<double>(k) / (kOrganStations - 1);
    const double left = lerp(&ConceptOrganTemplate::left, k);
    const double right = lerp(&ConceptOrganTemplate::right, k);
    if (widths != nullptr) widths->push_back(left + right);
    for (int j = 0; j < kBladeColumns; ++j) {
      const double v = -right + (left + right) * j / (kBladeColumns - 1);
      points.push_back(map(u, v, -options_.organ_droop * u * u + std::abs(v) * fold));
    }
  }
  return points;
}

double ConceptPlantBuilder::Fit(const ConceptOrgan& organ, const Eigen::Vector3d& e1,
                                const Eigen::Vector3d& e2, const Eigen::Vector3d& e3,
                                double length) const {
  const double tolerance = kFitTolerance * options_.stem_length;
  const auto fits = [&](double scale) {
    for (const Eigen::Vector3d& p : OrganPoints(organ, e1, e2, e3, scale * length, nullptr)) {
      if (plant_.EnvelopeExcess(p) > tolerance) return false;
    }
    return true;
  };
  if (fits(1.0)) return 1.0;
  double lo = 0, hi = 1;
  for (int i = 0; i < kFitIterations; ++i) {
    const double mid = (lo + hi) / 2;
    (fits(mid) ? lo : hi) = mid;
  }
  return lo;
}

bool ConceptPlantBuilder::PlaceOrgan(double arc_px, double phi_left, double phi_right,
                                     double theta_deg, ConceptOrgan* organ) {
  Eigen::Vector2d tangent;
  const Eigen::Vector2d b0 = PointAtArc(structure_.stem, arc_px, &tangent);
  const Eigen::Vector2d down = -tangent, left = LeftOf(tangent);
  // Paper 6.2: the branching rays and their boundary points P_L, P_R.
  const Eigen::Vector2d w_left = std::cos(phi_left) * down + std::sin(phi_left) * left;
  const Eigen::Vector2d w_right = std::cos(phi_right) * down - std::sin(phi_right) * left;
  const double t_left = CastRay2d(structure_.envelope, b0, w_left);
  const double t_right = CastRay2d(structure_.envelope, b0, w_right);
  if (!std::isfinite(t_left) || !std::isfinite(t_right)) return false;
  const double arc_c_px =
      StemArcOfCrossing(structure_.stem, b0 + t_left * w_left, b0 + t_right * w_right)
          .value_or(arc_px);
  // Paper 6.3: B1 on the half ellipses about P_C.
  Eigen::Vector2d tangent_c;
  const Eigen::Vector3d p_c = plant_.ToWorld(PointAtArc(structure_.stem, arc_c_px, &tangent_c));
  Eigen::Vector3d e1, e2;
  SectionAxes(WorldDirection(tangent_c), &e1, &e2);
  const double arc_c = arc_c_px * plant_.world_per_pixel, theta = theta_deg * kDegrees;
  const double r =
      EllipseRadius(theta, Interpolate(plant_.envelope_arc, plant_.envelope_left, arc_c),
                    Interpolate(plant_.envelope_arc, plant_.envelope_right, arc_c));
  if (r <= kFitTolerance * options_.stem_length) return false;
  organ->base = plant_.ToWorld(b0);
  organ->stem_tangent = WorldDirection(tangent);
  organ->stem_arc = arc_px * plant_.world_per_pixel;
  organ->reference_tip = p_c + r * (std::cos(theta) * e1 + std::sin(theta) * e2);
  organ->azimuth_deg = theta_deg;
  organ->branching_deg = (std::cos(theta) < 0 ? phi_left : phi_right) / kDegrees;
  organ->blade = structure_.organs.front().blade;
  organ->template_t = template_t_;
  // Section 7: the organ's frame, and its length fitted into the envelope.
  const double reach = (organ->reference_tip - organ->base).norm();
  const Eigen::Vector3d e3 = (organ->reference_tip - organ->base) / reach;
  Eigen::Vector3d f1 = organ->stem_tangent.cross(e3);
  if (f1.norm() < 1e-9) f1 = e2;
  f1.normalize();
  const Eigen::Vector3d f2 = e3.cross(f1);
  organ->fit = Fit(*organ, f1, f2, e3, reach);
  organ->length = organ->fit * reach;
  organ->tip = organ->base + organ->length * e3;
  std::vector<double> widths;
  const std::vector<Eigen::Vector3d> points =
      OrganPoints(*organ, f1, f2, e3, organ->length, &widths);
  if (organ->blade) {
    AddBlade(points, widths);
    std::vector<Eigen::Vector3d> vein;
    for (int k = 0; k < kOrganStations; ++k)
      vein.push_back(points[k * kBladeColumns + kBladeColumns / 2]);
    plant_.veins.push_back(vein);
    for (int k = 0; k < kOrganStations; k += (kOrganStations - 1) / 4) {
      const double u = static_cast<double>(k) / (kOrganStations - 1);
      organ->centre.push_back(organ->base +
                              organ->length * (u * e3 - options_.organ_droop * u * u * f2));
    }
  } else {
    for (int k = 0; k < kOrganStations; k += 2) organ->centre.push_back(points[k]);
  }
  return true;
}

// A grid of kOrganStations x kBladeColumns points; a station of no width is
// one vertex (so the outline has no slits).
void ConceptPlantBuilder::AddBlade(const std::vector<Eigen::Vector3d>& grid,
                                   const std::vector<double>& widths) {
  TriangleMesh& mesh = plant_.blades;
  std::vector<int> index(grid.size());
  for (int k = 0; k < kOrganStations; ++k) {
    for (int j = 0; j < kBladeColumns; ++j) {
      const int g = k * kBladeColumns + j;
      index[g] =
          (widths[k] <= 1e-9 && j > 0) ? index[g - 1] : mesh.AddVertex(grid[g].cast<float>());
    }
  }
  for (int k = 0; k + 1 < kOrganStations; ++k) {
    for (int j = 0; j + 1 < kBladeColumns; ++j) {
      const int a = index[k * kBladeColumns + j], b = index[(k + 1) * kBladeColumns + j];
      const int c = index[k * kBladeColumns + j + 1], d = index[(k + 1) * kBladeColumns + j + 1];
      if (a != b && b != c && a != c) mesh.AddTriangle(a, b, c, blade_material_);
      if (c != b && b != d && c != d) mesh.AddTriangle(c, b, d, blade_material_);
    }
  }
}

void ConceptPlantBuilder::PlaceNode(const Layer& layer, double arc_px, int node, int layer_idx) {
  const double f = (layer.top_px - arc_px) / std::max(layer.top_px - layer.bottom_px, 1e-12);
  double phi_left = options_.default_branching_deg, phi_right = phi_left;
  if (layer.upper != nullptr) {
    phi_left = layer.upper->left_deg + f * (layer.lower->left_deg - layer.upper->left_deg);
    phi_right = layer.upper->right_deg + f * (layer.lower->right_deg - layer.upper->right_deg);
  }
  const double divergence = plant_.divergence_deg;
  for (int j = 0; j < options_.organs_per_node; ++j) {
    template_t_ = structure_.organs.size() > 1 ? random_.Uniform() : 0.0;
    ConceptOrgan organ;
    organ.node = node;
    organ.layer = layer_idx;
    const double theta =
        options_.first_azimuth_deg + node * divergence + j * 360.0 / options_.organs_per_node;
    if (PlaceOrgan(arc_px, phi_left * kDegrees, phi_right * kDegrees, theta, &organ)) {
      plant_.shrunk_organs += organ.fit < 0.999 ? 1 : 0;
      plant_.organs.push_back(std::move(organ));
    } else {
      ++plant_.nodes_without_room;
    }
  }
}

double ConceptPlantBuilder::StemRadius(double arc) const {
  const double base = structure_.stem_width_px > 0
                          ? structure_.stem_width_px / 2 * plant_.world_per_pixel
                          : options_.stem_radius_fraction * options_.stem_length;
  const double f = std::clamp(arc / options_.stem_length, 0.0, 1.0);
  return base * (1 - (1 - options_.stem_tip_fraction) * f);
}

SkeletonGraph ConceptPlantBuilder::BuildSkeleton(bool blade_axes) const {
  SkeletonGraph skeleton;
  skeleton.radius_source = "drawn (concept sketch construction lines), not a measurement";
  const double length = options_.stem_length;
  std::vector<double> arcs;
  for (double s = 0; s < length; s += kStemNodeSpacing * length) arcs.push_back(s);
  arcs.push_back(length);
  for (const ConceptOrgan& organ : plant_.organs) arcs.push_back(organ.stem_arc);
  std::sort(arcs.begin(), arcs.end());
  std::map<double, int> node_at_arc;
  int previous = -1;
  double previous_arc = -1;
  for (double s : arcs) {
    if (previous >= 0 && s - previous_arc < 1e-9 * length) {
      node_at_arc[s] = previous;
      continue;
    }
    const Eigen::Vector2d p = PointAtArc(structure_.stem, s / plant_.world_per_pixel);
    previous = skeleton.AddNode(plant_.ToWorld(p), StemRadius(s), previous, 0);
    previous_arc = s;
    node_at_arc[s] = previous;
  }
  for (const ConceptOrgan& organ : plant_.organs) {
    if (organ.blade && !blade_axes) continue;
    const double radius = std::min(options_.organ_axis_radius_fraction * organ.length,
                                   0.5 * StemRadius(organ.stem_arc));
    int parent = node_at_arc.at(organ.stem_arc);
    for (size_t i = 1; i < organ.centre.size(); ++i) {
      const double f = static_cast<double>(i) / (organ.centre.size() - 1);
      parent =
          skeleton.AddNode(organ.centre[i], radius * (1 - (1 - kAxisTipFraction) * f), parent, 1);
    }
  }
  skeleton.Check();
  return skeleton;
}

void ConceptPlantBuilder::AddConstruction() {
  plant_.construction.push_back(plant_.stem);
  const auto to_world = [&](const Polyline2& line) {
    std::vector<Eigen::Vector3d> world;
    for (const Eigen::Vector2d& p : line) world.push_back(plant_.ToWorld(p));
    return world;
  };
  for (int k = 0; k < structure_.num_boundaries; ++k) {
    plant_.construction.push_back(to_world(structure_.envelope[k]));
  }
  for (const auto& line : structure_.inclinations) {
    plant_.construction.push_back(to_world(line.points));
    Eigen::Vector2d tangent;
    const Eigen::Vector3d centre =
        plant_.ToWorld(PointAtArc(structure_.stem, line.stem_arc_px, &tangent));
    Eigen::Vector3d e1, e2;
    SectionAxes(WorldDirection(tangent), &e1, &e2);
    const double arc = line.stem_arc_px * plant_.world_per_pixel;
    const double a = Interpolate(plant_.envelope_arc, plant_.envelope_left, arc);
    const double c = Interpolate(plant_.envelope_arc, plant_.envelope_right, arc);
    std::vector<Eigen::Vector3d> section;
    for (int i = 0; i <= kSectionPoints; ++i) {
      const double theta = 2 * M_PI * i / kSectionPoints;
      section.push_back(centre +
                        EllipseRadius(theta, a, c) * (std::cos(theta) * e1 + std::sin(theta) * e2));
    }
    plant_.construction.push_back(section);
  }
}

std::string ConceptPlantBuilder::Brief() const {
  double fit_sum = 0;
  for (const ConceptOrgan& organ : plant_.organs) fit_sum += organ.fit;
  std::ostringstream out;
  out << "Concept plant: " << ConceptPatternName(plant_.pattern) << " phyllotaxis, divergence "
      << plant_.divergence_deg << " deg, " << plant_.organs.size() << " organs ("
      << (structure_.organs.front().blade ? "blades" : "lines") << ") on a stem of "
      << options_.stem_length << " m; " << plant_.nodes_without_room
      << " organ place(s) without room in the envelope; " << plant_.shrunk_organs
      << " organ(s) shortened to fit it (mean length / reach "
      << (plant_.organs.empty() ? 1.0 : fit_sum / plant_.organs.size()) << ").";
  return out.str();
}

ConceptPlant ConceptPlantBuilder::Build() {
  const std::string& phyllotaxis = options_.phyllotaxis;
  plant_.pattern = phyllotaxis == "auto"
                       ? structure_.drawn_pattern.value_or(ConceptPattern::kSpiral)
                       : *ConceptPatternFromName(phyllotaxis);
  plant_.divergence_deg =
      options_.divergence_deg >= 0 ? options_.divergence_deg : ConceptDivergenceDeg(plant_.pattern);
  blade_material_ =
      plant_.blades.AddMaterial({"leaves", Eigen::Vector3f(0.18f, 0.42f, 0.12f), true});
  SetFrame();
  SampleEnvelope();
  int node = 0, layer_idx = 0;
  for (const Layer& layer : Layers(structure_)) {
    const double spacing = (layer.top_px - layer.bottom_px) / options_.organs_per_layer;
    for (int k = 0; k < options_.organs_per_layer; ++k) {
      PlaceNode(layer, layer.top_px - (k + 0.5) * spacing, node++, layer_idx);
    }
    ++layer_idx;
  }
  SYLVA_CHECK_INPUT(!plant_.organs.empty(), structure_.source)
      << "no organ fits between the stem and the boundary lines (do the boundaries lie beside "
         "the stem?)";
  plant_.skeleton = BuildSkeleton(options_.organ_axes);
  plant_.wood_skeleton = BuildSkeleton(false);
  AddConstruction();
  plant_.brief = Brief();
  return std::move(plant_);
}

// A blade of the lanceolate shape, when the drawing has no organ strokes.
ConceptOrganTemplate DefaultTemplate() {
  ConceptOrganTemplate organ;
  organ.length_px = 1;
  for (int k = 0; k < kOrganStations; ++k) {
    const double u = static_cast<double>(k) / (kOrganStations - 1);
    const double half = 0.18 * std::sin(M_PI * std::pow(u, 0.7));
    organ.left.push_back(k == 0 || k + 1 == kOrganStations ? 0.0 : half);
    organ.right.push_back(organ.left.back());
  }
  return organ;
}

}  // namespace

Eigen::Vector3d ConceptPlant::ToWorld(const Eigen::Vector2d& point_px) const {
  return Eigen::Vector3d(point_px.x() - base_px.x(), 0, base_px.y() - point_px.y()) *
         world_per_pixel;
}

double ConceptPlant::EnvelopeExcess(const Eigen::Vector3d& point) const {
  double best = std::numeric_limits<double>::infinity(), arc = 0, best_arc = 0, best_t = 0;
  size_t best_segment = 1;
  for (size_t i = 1; i < stem.size(); ++i) {
    const Eigen::Vector3d d = stem[i] - stem[i - 1];
    const double length = d.norm();
    if (length <= 0) continue;
    const double t = (point - stem[i - 1]).dot(d) / (length * length);
    const double distance = (stem[i - 1] + std::clamp(t, 0.0, 1.0) * d - point).norm();
    if (distance < best) best = distance, best_segment = i, best_t = t, best_arc = arc;
    arc += length;
  }
  const Eigen::Vector3d d = stem[best_segment] - stem[best_segment - 1];
  const double length = d.norm();
  const Eigen::Vector3d tangent = d / length;
  const Eigen::Vector3d foot = stem[best_segment - 1] + std::clamp(best_t, 0.0, 1.0) * d;
  const Eigen::Vector3d offset = point - foot;
  double beyond = 0;
  if ((best_segment == 1 && best_t < 0) || (best_segment + 1 == stem.size() && best_t > 1)) {
    beyond = std::abs(offset.dot(tangent));
  }
  const Eigen::Vector3d radial = offset - offset.dot(tangent) * tangent;
  Eigen::Vector3d e1, e2;
  SectionAxes(tangent, &e1, &e2);
  const double s = best_arc + std::clamp(best_t, 0.0, 1.0) * length;
  const double r = EllipseRadius(std::atan2(radial.dot(e2), radial.dot(e1)),
                                 Interpolate(envelope_arc, envelope_left, s),
                                 Interpolate(envelope_arc, envelope_right, s));
  return std::max(radial.norm() - r, beyond > 0 ? beyond : -INFINITY);
}

ConceptPlant BuildConceptPlant(const ConceptStructure& structure,
                               const ConceptPlantOptions& options) {
  options.Check();
  SYLVA_CHECK(structure.stem.size() >= 2) << "a concept structure needs a stem";
  if (!structure.organs.empty()) return ConceptPlantBuilder(structure, options).Build();
  ConceptStructure with_default = structure;
  with_default.organs.push_back(DefaultTemplate());
  return ConceptPlantBuilder(with_default, options).Build();
}

double MeasuredDivergenceDeg(const ConceptOrgan& a, const ConceptOrgan& b) {
  const Eigen::Vector3d& t = a.stem_tangent;
  Eigen::Vector3d da = a.tip - a.base, db = b.tip - b.base;
  da -= da.dot(t) * t;
  db -= db.dot(t) * t;
  const double c = da.normalized().dot(db.normalized());
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace sylva
