#include "sketch/drawing_io.h"

#include <tinyxml2.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "sketch/scan_tracing.h"
#include "sketch/svg_element.h"
#include "sketch/svg_geometry.h"

namespace sylva {
namespace {

using tinyxml2::XMLElement;

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// Drops consecutive repeats of a point and, for a closed outline, the
// repeated first point at its end.
std::vector<Eigen::Vector2d> DistinctPoints(const std::vector<Eigen::Vector2d>& points,
                                            bool closed) {
  std::vector<Eigen::Vector2d> distinct;
  for (const Eigen::Vector2d& p : points) {
    if (distinct.empty() || distinct.back() != p) distinct.push_back(p);
  }
  if (closed && distinct.size() > 1 && distinct.front() == distinct.back()) distinct.pop_back();
  return distinct;
}

// ================================================================ SVG

// Curves are flattened to within this distance of the exact curve, in canvas
// pixels: far below the accuracy of a drawn stroke (as in strokes.cc).
constexpr double kFlattenTolerancePixels = 0.25;

// ------------------------------------------------- roles from names

// A role named by a layer label or class word: "Crown", "branches", ...
std::optional<StrokeRole> RoleFromWord(const std::string& word) {
  if (auto role = StrokeRoleFromName(word)) return role;
  const std::string lower = Lower(word);
  for (const char* plural : {"es", "s"}) {
    const std::string suffix = plural;
    if (lower.size() > suffix.size() &&
        lower.compare(lower.size() - suffix.size(), suffix.size(), suffix) == 0) {
      if (auto role = StrokeRoleFromName(lower.substr(0, lower.size() - suffix.size()))) {
        return role;
      }
    }
  }
  return std::nullopt;
}

// The role the element's own inkscape:label or class names, if any.
std::optional<StrokeRole> RoleOfElement(const XMLElement& element) {
  if (const char* label = element.Attribute("inkscape:label")) {
    std::istringstream words(label);
    std::string word;
    while (words >> word) {
      if (auto role = RoleFromWord(word)) return role;
    }
  }
  if (const char* classes = element.Attribute("class")) {
    std::istringstream words(classes);
    std::string word;
    while (words >> word) {
      if (auto role = RoleFromWord(word)) return role;
    }
  }
  return std::nullopt;
}

// ------------------------------------------------- roles from colours

using Rgb = Eigen::Vector3d;  // each channel in [0, 1]

std::optional<Rgb> NamedColour(const std::string& name) {
  // The CSS names a tree is likely drawn in; others give no colour cue.
  static const std::map<std::string, std::array<int, 3>> kNames = {
      {"black", {0, 0, 0}},           {"white", {255, 255, 255}},     {"gray", {128, 128, 128}},
      {"grey", {128, 128, 128}},      {"green", {0, 128, 0}},         {"darkgreen", {0, 100, 0}},
      {"forestgreen", {34, 139, 34}}, {"lime", {0, 255, 0}},          {"limegreen", {50, 205, 50}},
      {"seagreen", {46, 139, 87}},    {"olivedrab", {107, 142, 35}},  {"olive", {128, 128, 0}},
      {"brown", {165, 42, 42}},       {"saddlebrown", {139, 69, 19}}, {"sienna", {160, 82, 45}},
      {"chocolate", {210, 105, 30}},  {"maroon", {128, 0, 0}},        {"tan", {210, 180, 140}},
      {"red", {255, 0, 0}},           {"blue", {0, 0, 255}},          {"yellow", {255, 255, 0}},
  };
  const auto it = kNames.find(name);
  if (it == kNames.end()) return std::nullopt;
  return Rgb(it->second[0], it->second[1], it->second[2]) / 255.0;
}

std::optional<Rgb> HexColour(const std::string& hex) {
  if (hex.size() != 3 && hex.size() != 6) return std::nullopt;
  if (!std::all_of(hex.begin(), hex.end(), [](unsigned char c) { return std::isxdigit(c); })) {
    return std::nullopt;
  }
  Rgb rgb;
  for (int i = 0; i < 3; ++i) {
    // #abc is #aabbcc.
    const std::string digits = hex.size() == 3 ? std::string(2, hex[i]) : hex.substr(2 * i, 2);
    rgb[i] = std::stoi(digits, nullptr, 16) / 255.0;
  }
  return rgb;
}

// rgb(r, g, b) with numbers 0-255 or percentages.
std::optional<Rgb> FunctionalColour(const std::string& text) {
  if (text.rfind("rgb(", 0) != 0 || text.back() != ')') return std::nullopt;
  std::istringstream channels(text.substr(4, text.size() - 5));
  Rgb rgb;
  std::string channel;
  for (int i = 0; i < 3; ++i) {
    if (!std::getline(channels, channel, ',')) return std::nullopt;
    const bool percent = channel.find('%') != std::string::npos;
    try {
      const double v = std::stod(channel);
      if (!std::isfinite(v)) return std::nullopt;
      rgb[i] = std::clamp(v / (percent ? 100.0 : 255.0), 0.0, 1.0);
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  return rgb;
}

// A CSS colour; nullopt for none, gradients (url(...)) and unknown names.
std::optional<Rgb> ParseColour(const std::string& text) {
  const std::string lower = Lower(text);
  if (lower.empty()) return std::nullopt;
  if (lower[0] == '#') return HexColour(lower.substr(1));
  if (auto rgb = FunctionalColour(lower)) return rgb;
  return NamedColour(lower);
}

// Green-ish (see drawing_io.h): a hue between yellow-green and green-cyan,
// clearly coloured and not black.
constexpr double kCrownHueMinDegrees = 75, kCrownHueMaxDegrees = 165;
constexpr double kCrownMinSaturation = 0.2, kCrownMinValue = 0.1;

bool IsGreenish(const Rgb& rgb) {
  const double value = rgb.maxCoeff(), chroma = value - rgb.minCoeff();
  if (value < kCrownMinValue || chroma / value < kCrownMinSaturation) return false;
  // HSV hue; green is the largest channel between 60 and 180 degrees.
  double hue_degrees;
  if (value == rgb.x()) {
    hue_degrees = 60 * std::fmod((rgb.y() - rgb.z()) / chroma + 6, 6);
  } else if (value == rgb.y()) {
    hue_degrees = 60 * ((rgb.z() - rgb.x()) / chroma + 2);
  } else {
    hue_degrees = 60 * ((rgb.x() - rgb.y()) / chroma + 4);
  }
  return hue_degrees >= kCrownHueMinDegrees && hue_degrees <= kCrownHueMaxDegrees;
}

// ------------------------------------------------- the walk

// What an element inherits from its ancestors.
struct SvgContext {
  Eigen::Affine2d canvas_from_user = Eigen::Affine2d::Identity();
  std::optional<StrokeRole> role;     // from the nearest label or class naming one
  std::optional<std::string> stroke;  // CSS `stroke` (a colour or "none")
  std::optional<std::string> fill;
  // In the user units of the shape that is stroked (SVG inherits the number).
  std::optional<double> stroke_width;
  // Words of the ids, labels and classes on the way down (SketchStroke::name).
  std::string name;
};

// The element's id and its inkscape:label and class words, lower-case.
std::string NameWordsOf(const XMLElement& element) {
  std::string words;
  for (const char* attribute : {"id", "inkscape:label", "class"}) {
    if (const char* value = element.Attribute(attribute)) {
      if (!words.empty()) words += ' ';
      words += Lower(value);
    }
  }
  return words;
}

SvgContext EnterElement(const SvgContext& parent, const XMLElement& element) {
  SvgContext context = parent;
  context.canvas_from_user =
      parent.canvas_from_user * ParseSvgAttribute(element, "transform", ParseSvgTransform);
  if (auto role = RoleOfElement(element)) context.role = role;
  const std::string words = NameWordsOf(element);
  if (!words.empty()) context.name = words + (parent.name.empty() ? "" : " " + parent.name);
  if (auto stroke = SvgStyleProperty(element, "stroke"); stroke && *stroke != "inherit") {
    context.stroke = stroke;
  }
  if (auto fill = SvgStyleProperty(element, "fill"); fill && *fill != "inherit") {
    context.fill = fill;
  }
  if (auto width = SvgStyleProperty(element, "stroke-width"); width && *width != "inherit") {
    try {
      context.stroke_width = ParseSvgLength(*width);
    } catch (const InputError& error) {
      throw InputError("", "stroke-width: " + error.message());
    }
    if (*context.stroke_width < 0) throw InputError("", "stroke-width is negative: " + *width);
  }
  return context;
}

// SVG draws no stroke by default; "none" says so explicitly.
bool HasStroke(const SvgContext& context) { return context.stroke && *context.stroke != "none"; }

StrokeRole ShapeRole(const SvgContext& context, bool closed) {
  if (context.role) return *context.role;
  if (closed) return StrokeRole::kCrown;
  // The stroke colour, or the fill's for a shape drawn without a stroke.
  std::optional<Rgb> colour;
  if (HasStroke(context)) {
    colour = ParseColour(*context.stroke);
  } else if (context.fill) {
    colour = ParseColour(*context.fill);
  }
  if (colour && IsGreenish(*colour)) return StrokeRole::kCrown;
  return StrokeRole::kBranch;
}

// stroke-width in canvas pixels; 0 = unknown. A hand-written file often
// gives a width without a stroke colour, so only an explicit "none" drops it.
double ShapeWidth(const SvgContext& context) {
  if (!context.stroke_width || (context.stroke && *context.stroke == "none")) return 0;
  const double scale = std::sqrt(std::abs(context.canvas_from_user.linear().determinant()));
  return *context.stroke_width * scale;
}

bool IsDrawnShape(const std::string& name) {
  return name == "path" || name == "polyline" || name == "polygon" || name == "line" ||
         name == "rect" || name == "circle" || name == "ellipse";
}

// Walks the element tree, collecting strokes and the root in canvas pixels;
// errors name the file, the element and its line.
class SvgDrawingCollector {
 public:
  explicit SvgDrawingCollector(SketchDrawing* drawing) : drawing_(drawing) {}

  void Walk(const XMLElement& parent, const SvgContext& parent_context) {
    for (const XMLElement* child = parent.FirstChildElement(); child != nullptr;
         child = child->NextSiblingElement()) {
      const std::string name = SvgLocalName(*child);
      if (name == "text" && !IsSvgHidden(*child)) AddText(*child);
      if (!(IsSvgContainer(name) || IsDrawnShape(name)) || IsSvgHidden(*child)) continue;
      const SvgContext context = AtSvgElement(drawing_->source, *child,
                                              [&] { return EnterElement(parent_context, *child); });
      if (IsSvgContainer(name)) {
        Walk(*child, context);
      } else {
        AtSvgElement(drawing_->source, *child, [&] { AddShape(*child, context); });
      }
    }
  }

 private:
  // The text of a <text> element and its <tspan>s.
  static void CollectText(const XMLElement& element, std::string* text) {
    for (const tinyxml2::XMLNode* node = element.FirstChild(); node != nullptr;
         node = node->NextSibling()) {
      if (const tinyxml2::XMLText* piece = node->ToText()) {
        *text += std::string(piece->Value()) + " ";
      } else if (const XMLElement* child = node->ToElement()) {
        CollectText(*child, text);
      }
    }
  }

  void AddText(const XMLElement& element) {
    std::string text;
    CollectText(element, &text);
    const size_t begin = text.find_first_not_of(" \t\r\n");
    if (begin == std::string::npos) return;
    drawing_->texts.push_back(text.substr(begin, text.find_last_not_of(" \t\r\n") - begin + 1));
  }

  void AddShape(const XMLElement& element, const SvgContext& context) {
    if (SvgLocalName(element) == "circle" && SvgHasIdOrClass(element, "root")) {
      if (drawing_->root) throw InputError("", "a second root circle (there may be only one)");
      drawing_->root =
          context.canvas_from_user *
          Eigen::Vector2d(SvgLengthAttribute(element, "cx"), SvgLengthAttribute(element, "cy"));
      return;
    }
    for (const SvgPolyline& polyline :
         FlattenSvgShape(element, context.canvas_from_user, kFlattenTolerancePixels)) {
      AddStroke(polyline, context);
    }
  }

  void AddStroke(const SvgPolyline& polyline, const SvgContext& context) {
    SketchStroke stroke;
    stroke.points = DistinctPoints(polyline.points, polyline.closed);
    // Closed back and forth along one segment is just a line.
    stroke.closed = polyline.closed && stroke.points.size() >= 3;
    if (stroke.points.size() < 2) {
      throw InputError("", polyline.what + " has fewer than two distinct points: not a stroke");
    }
    for (const Eigen::Vector2d& p : stroke.points) CheckNearCanvas(p, polyline.what);
    stroke.role = ShapeRole(context, stroke.closed);
    stroke.width = ShapeWidth(context);
    stroke.name = context.name;
    if (!std::isfinite(stroke.width)) throw InputError("", "the stroke width overflows");
    drawing_->strokes.push_back(std::move(stroke));
  }

  // Points farther out than the canvas' own size mean a broken file or a
  // transform gone wrong (SketchDrawing::Check's rule, here with the element).
  void CheckNearCanvas(const Eigen::Vector2d& p, const std::string& what) const {
    const double w = drawing_->width, h = drawing_->height;
    if (p.x() >= -w && p.x() <= 2 * w && p.y() >= -h && p.y() <= 2 * h) return;
    std::ostringstream message;
    message << what << " reaches (" << p.x() << ", " << p.y() << "), far outside the " << w << " x "
            << h << " canvas";
    throw InputError("", message.str());
  }

  SketchDrawing* drawing_;
};

// The canvas from the root's viewport (drawing_io.h); returns canvas_from_document.
Eigen::Affine2d SetCanvas(const XMLElement& svg, SketchDrawing* drawing) {
  const std::optional<SvgViewport> viewport = ReadSvgViewport(svg);
  if (!viewport) {
    throw InputError("", "no viewBox and no width and height: the canvas size is unknown");
  }
  drawing->width = viewport->size.x();
  drawing->height = viewport->size.y();
  return Eigen::Affine2d(Eigen::Translation2d(-viewport->origin));
}

// ================================================================ Quick, Draw!

constexpr double kQuickDrawCanvasPixels = 256;
constexpr double kQuickDrawMaxCoordinate = 255;

// The crown rule (drawing_io.h).
constexpr double kCrownMinAreaFraction = 0.10;     // of the drawing's bounding box
constexpr double kNearlyClosedGapFraction = 0.10;  // of the stroke's length
constexpr double kGroundBandFraction = 0.05;       // of the drawing's height
constexpr double kAboveMinPointFraction = 0.75;    // of the stroke's points
constexpr double kAboveMarginFraction = 0.05;      // of the drawing's height
// An outline drawn in pieces (drawing_io.h).
constexpr double kOutlineMaxGapFraction = 0.4;    // of the drawing's larger side
constexpr double kOutlineMinAreaFraction = 0.25;  // of the drawing's bounding box
constexpr double kOutlineMinInkFraction = 0.6;    // of all strokes' length
constexpr double kOutlineMinAspect = 0.25;        // width over height (not a trunk)

double PolylineLength(const std::vector<Eigen::Vector2d>& points) {
  double length = 0;
  for (size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

// The area of the polygon closed by the chord from the last point to the first.
double ChordClosedArea(const std::vector<Eigen::Vector2d>& points) {
  double twice_area = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& a = points[i];
    const Eigen::Vector2d& b = points[(i + 1) % points.size()];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  return std::abs(twice_area) / 2;
}

// Its end within kNearlyClosedGapFraction of its length of its start.
bool IsNearlyClosed(const SketchStroke& stroke) {
  const double gap = (stroke.points.back() - stroke.points.front()).norm();
  return stroke.points.size() >= 3 &&
         gap <= kNearlyClosedGapFraction * PolylineLength(stroke.points);
}

double MinY(const SketchStroke& s) {
  double y = s.points.front().y();
  for (const Eigen::Vector2d& p : s.points) y = std::min(y, p.y());
  return y;
}
double MaxY(const SketchStroke& s) {
  double y = s.points.front().y();
  for (const Eigen::Vector2d& p : s.points) y = std::max(y, p.y());
  return y;
}

// Bounding-box figures of the whole drawing the rule is relative to.
struct DrawingExtent {
  Eigen::Vector2d min, max;
  double Area() const {
    return std::max(max.x() - min.x(), 1.0) * std::max(max.y() - min.y(), 1.0);
  }
  double Height() const { return std::max(max.y() - min.y(), 1.0); }
};

DrawingExtent ExtentOf(const std::vector<SketchStroke>& strokes) {
  DrawingExtent extent{strokes.front().points.front(), strokes.front().points.front()};
  for (const SketchStroke& s : strokes) {
    for (const Eigen::Vector2d& p : s.points) {
      extent.min = extent.min.cwiseMin(p);
      extent.max = extent.max.cwiseMax(p);
    }
  }
  return extent;
}

bool StandsOnGround(const SketchStroke& s, const DrawingExtent& extent) {
  return MaxY(s) >= extent.max.y() - kGroundBandFraction * extent.Height();
}

// The top (smallest y) of the strokes other than `k` that stand on the
// ground (the trunk's top); nullopt if none does.
std::optional<double> GroundTop(const std::vector<SketchStroke>& strokes, size_t k,
                                const DrawingExtent& extent) {
  std::optional<double> top;
  for (size_t j = 0; j < strokes.size(); ++j) {
    if (j == k || !StandsOnGround(strokes[j], extent)) continue;
    top = std::min(top.value_or(MinY(strokes[j])), MinY(strokes[j]));
  }
  return top;
}

bool AnotherStartsHigher(const std::vector<SketchStroke>& strokes, size_t k) {
  for (size_t j = 0; j < strokes.size(); ++j) {
    if (j != k && MinY(strokes[j]) < MinY(strokes[k])) return true;
  }
  return false;
}

// Whether stroke `k` is a crown outline by the rule in drawing_io.h.
bool IsQuickDrawCrown(const std::vector<SketchStroke>& strokes, size_t k,
                      const DrawingExtent& extent) {
  const SketchStroke& stroke = strokes[k];
  if (ChordClosedArea(stroke.points) < kCrownMinAreaFraction * extent.Area()) return false;
  // A closed shape on the ground under another stroke: a trunk drawn as an outline.
  if (StandsOnGround(stroke, extent) && AnotherStartsHigher(strokes, k)) return false;
  if (IsNearlyClosed(stroke)) return true;
  // An open stroke is a crown only above a trunk: without one it may be anything.
  const std::optional<double> ground_top = GroundTop(strokes, k, extent);
  if (!ground_top) return false;
  const double above_y = *ground_top + kAboveMarginFraction * extent.Height();
  const auto above =
      std::count_if(stroke.points.begin(), stroke.points.end(),
                    [above_y](const Eigen::Vector2d& p) { return p.y() <= above_y; });
  return above >= kAboveMinPointFraction * stroke.points.size();
}

// The pieces of an outline (drawing_io.h) joined into one closed crown
// stroke, in place of the first of them; how many were joined (0: none,
// nothing changed).
int JoinOutlinePieces(std::vector<SketchStroke>* strokes, const DrawingExtent& extent) {
  const auto end_of = [&](size_t k, bool back) -> const Eigen::Vector2d& {
    const std::vector<Eigen::Vector2d>& points = (*strokes)[k].points;
    return back ? points.back() : points.front();
  };
  const Eigen::Vector2d size = extent.max - extent.min;
  const double reach = kOutlineMaxGapFraction * std::max(size.x(), size.y());
  // From the lowest stroke end (a foot on the ground), walking away from it.
  size_t first = 0;
  bool reversed = false;  // walk the first stroke from its back end
  double lowest = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < strokes->size(); ++k) {
    for (bool from_back : {false, true}) {
      if (end_of(k, from_back).y() > lowest) {
        lowest = end_of(k, from_back).y();
        first = k;
        reversed = from_back;
      }
    }
  }
  std::vector<bool> used(strokes->size(), false);
  std::vector<size_t> members = {first};
  used[first] = true;
  std::vector<Eigen::Vector2d> chain = (*strokes)[first].points;
  if (reversed) std::reverse(chain.begin(), chain.end());
  double ink = PolylineLength(chain), all_ink = 0.0;
  for (const SketchStroke& s : *strokes) all_ink += PolylineLength(s.points);
  for (;;) {
    // The stroke whose nearer end is closest to the chain's end.
    size_t next = strokes->size();
    bool next_reversed = false;
    double gap = reach;
    for (size_t k = 0; k < strokes->size(); ++k) {
      if (used[k]) continue;
      for (bool from_back : {false, true}) {
        const double d = (chain.back() - end_of(k, from_back)).norm();
        if (d < gap) {
          gap = d;
          next = k;
          next_reversed = from_back;
        }
      }
    }
    if (next == strokes->size()) break;
    std::vector<Eigen::Vector2d> piece = (*strokes)[next].points;
    if (next_reversed) std::reverse(piece.begin(), piece.end());
    chain.insert(chain.end(), piece.begin(), piece.end());
    ink += PolylineLength(piece);
    used[next] = true;
    members.push_back(next);
  }
  Eigen::Vector2d low = chain.front(), high = chain.front();
  for (const Eigen::Vector2d& p : chain) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  if (members.size() < 2 || ChordClosedArea(chain) < kOutlineMinAreaFraction * extent.Area() ||
      ink < kOutlineMinInkFraction * all_ink ||
      high.x() - low.x() < kOutlineMinAspect * (high.y() - low.y())) {
    return 0;
  }
  SketchStroke outline;
  outline.points = DistinctPoints(chain, false);
  outline.role = StrokeRole::kCrown;
  outline.closed = true;
  const size_t place = *std::min_element(members.begin(), members.end());
  std::vector<SketchStroke> joined;
  for (size_t k = 0; k < strokes->size(); ++k) {
    if (k == place) joined.push_back(outline);
    if (!used[k]) joined.push_back(std::move((*strokes)[k]));
  }
  *strokes = std::move(joined);
  return static_cast<int>(members.size());
}

// Sets the strokes' roles by the rule in drawing_io.h; notes an outline
// joined from pieces in `notes`.
void ClassifyQuickDrawStrokes(std::vector<SketchStroke>* strokes, std::vector<std::string>* notes) {
  const DrawingExtent extent = ExtentOf(*strokes);
  // Decide all before changing any: the rule looks at the other strokes.
  std::vector<bool> crown(strokes->size());
  for (size_t k = 0; k < strokes->size(); ++k) crown[k] = IsQuickDrawCrown(*strokes, k, extent);
  if (std::none_of(crown.begin(), crown.end(), [](bool c) { return c; })) {
    if (const int joined = JoinOutlinePieces(strokes, extent)) {
      notes->push_back("no stroke encloses a crown: " + std::to_string(joined) +
                       " open strokes, joined end to end, are read as one closed outline");
      return;
    }
  }
  for (size_t k = 0; k < strokes->size(); ++k) {
    if (!crown[k]) continue;
    SketchStroke& stroke = (*strokes)[k];
    stroke.role = StrokeRole::kCrown;
    stroke.closed = IsNearlyClosed(stroke);
  }
}

// One stroke [[x0, x1, ...], [y0, y1, ...]]; nullopt for a dot.
std::optional<SketchStroke> QuickDrawStroke(const JsonCursor& json) {
  if (json.Size() != 2) json.Fail("a stroke must be [[x...], [y...]]");
  const std::vector<double> xs = json[0].AsDoubles(), ys = json[1].AsDoubles();
  if (xs.size() != ys.size()) {
    json.Fail(std::to_string(xs.size()) + " x but " + std::to_string(ys.size()) + " y coordinates");
  }
  std::vector<Eigen::Vector2d> points;
  for (size_t i = 0; i < xs.size(); ++i) {
    if (std::min(xs[i], ys[i]) < 0 || std::max(xs[i], ys[i]) > kQuickDrawMaxCoordinate) {
      json.Fail("point " + std::to_string(i) + " lies outside 0-255 (not the simplified format)");
    }
    points.emplace_back(xs[i], ys[i]);
  }
  SketchStroke stroke;
  stroke.points = DistinctPoints(points, false);
  if (stroke.points.size() < 2) return std::nullopt;
  return stroke;
}

// Line `line_number` (1-based, for messages) of the file as a drawing.
SketchDrawing QuickDrawFromLine(const std::string& line, const std::string& source,
                                int line_number) {
  const std::string where = "line " + std::to_string(line_number) + ": ";
  const Json json = Json::parse(line, nullptr, /*allow_exceptions=*/false);
  SYLVA_CHECK_INPUT(!json.is_discarded(), source)
      << where << "not valid JSON (a truncated or corrupt drawing)";
  SketchDrawing drawing;
  drawing.source = source;
  drawing.width = drawing.height = kQuickDrawCanvasPixels;
  try {
    const JsonCursor strokes = JsonCursor(json, source)["drawing"];
    for (size_t k = 0; k < strokes.Size(); ++k) {
      if (auto stroke = QuickDrawStroke(strokes[k])) drawing.strokes.push_back(std::move(*stroke));
    }
  } catch (const InputError& error) {
    throw InputError(source, where + error.message());
  }
  SYLVA_CHECK_INPUT(!drawing.strokes.empty(), source)
      << where << "no strokes of two or more distinct points";
  ClassifyQuickDrawStrokes(&drawing.strokes, &drawing.notes);
  return drawing;
}

}  // namespace

SketchDrawing ReadSketchSvg(const std::filesystem::path& path) {
  tinyxml2::XMLDocument document;
  const XMLElement& svg = ReadSvgDocument(path, &document);
  SketchDrawing drawing;
  drawing.source = path.string();
  // The root's own transform (SVG 2), style, class and label apply too.
  const SvgContext context = AtSvgElement(drawing.source, svg, [&] {
    SvgContext document;
    document.canvas_from_user = SetCanvas(svg, &drawing);
    return EnterElement(document, svg);
  });
  SvgDrawingCollector(&drawing).Walk(svg, context);
  SYLVA_CHECK_INPUT(!drawing.strokes.empty(), drawing.source)
      << "no strokes: no visible <path>, <polyline>, <polygon>, <line>, <rect>, <circle> or "
         "<ellipse> outside <defs>";
  drawing.Check();
  return drawing;
}

SketchDrawing ReadQuickDrawNdjson(const std::filesystem::path& path, int index) {
  const std::string source = path.string();
  std::istringstream lines(ReadFileToString(path));
  std::string line;
  int count = 0;
  while (std::getline(lines, line)) {
    if (count++ != index) continue;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF files
    SketchDrawing drawing = QuickDrawFromLine(line, source, index + 1);
    drawing.Check();
    return drawing;
  }
  SYLVA_INPUT_ERROR(source) << "no drawing " << index << ": the file has " << count
                            << " lines (drawings 0 to " << count - 1 << ")";
  return SketchDrawing();
}

SketchDrawing ReadSketch(const std::filesystem::path& path, int index) {
  const std::string extension = Lower(path.extension().string());
  if (extension == ".svg") return ReadSketchSvg(path);
  if (extension == ".ndjson") return ReadQuickDrawNdjson(path, index);
  for (const char* scan : {".png", ".jpg", ".jpeg", ".tif", ".tiff"}) {
    if (extension == scan) return TraceScannedDrawing(path, ScanTracingOptions());
  }
  SYLVA_INPUT_ERROR(path.string())
      << "unknown drawing file type '" << extension
      << "': expected .svg (Inkscape), .ndjson (Quick, Draw!) or a scanned drawing "
         "(.png, .jpg, .jpeg, .tif, .tiff)";
  return SketchDrawing();
}

namespace {

// A layer's colour by role: green crowns, brown branches, grey others.
const char* RoleColor(StrokeRole role) {
  switch (role) {
    case StrokeRole::kCrown:
      return "#2e8b3a";
    case StrokeRole::kBranch:
      return "#6b4226";
    default:
      return "#808080";
  }
}

void WriteStrokeElement(const SketchStroke& stroke, std::ostream* out) {
  *out << "    <" << (stroke.closed ? "polygon" : "polyline") << " points=\"";
  for (size_t i = 0; i < stroke.points.size(); ++i) {
    *out << (i ? " " : "") << stroke.points[i].x() << "," << stroke.points[i].y();
  }
  *out << "\"";
  if (stroke.width > 0) *out << " stroke-width=\"" << stroke.width << "\"";
  *out << "/>\n";
}

}  // namespace

void WriteSketchSvg(const std::filesystem::path& path, const SketchDrawing& drawing) {
  drawing.Check();
  std::ostringstream out;
  out.precision(9);
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\"\n"
      << "     xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\"\n"
      << "     width=\"" << drawing.width << "\" height=\"" << drawing.height << "\" viewBox=\"0 0 "
      << drawing.width << " " << drawing.height << "\">\n";
  for (StrokeRole role :
       {StrokeRole::kCrown, StrokeRole::kBranch, StrokeRole::kConstruction, StrokeRole::kOrgan}) {
    if (drawing.CountRole(role) == 0) continue;
    out << "  <g inkscape:groupmode=\"layer\" inkscape:label=\"" << StrokeRoleName(role)
        << "\" style=\"fill:none;stroke:" << RoleColor(role) << ";stroke-linecap:round\">\n";
    for (const SketchStroke& stroke : drawing.strokes) {
      if (stroke.role == role) WriteStrokeElement(stroke, &out);
    }
    out << "  </g>\n";
  }
  if (drawing.root) {
    out << "  <circle id=\"root\" cx=\"" << drawing.root->x() << "\" cy=\"" << drawing.root->y()
        << "\" r=\"3\" fill=\"#c03030\"/>\n";
  }
  out << "</svg>\n";
  AtomicWriteString(path, out.str());
}

}  // namespace sylva
