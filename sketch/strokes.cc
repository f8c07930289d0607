#include "sketch/strokes.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "sketch/svg_element.h"
#include "sketch/svg_geometry.h"

namespace sylva {
namespace {

// Curves are flattened to within this distance of the exact curve, in photo
// pixels: far below the accuracy of a drawn stroke.
constexpr double kFlattenTolerancePixels = 0.25;

using tinyxml2::XMLElement;

// Drops consecutive repeats of a point.
Stroke MakeStroke(const std::vector<Eigen::Vector2d>& points) {
  Stroke stroke;
  for (const Eigen::Vector2d& p : points) {
    if (stroke.points.empty() || stroke.points.back() != p) stroke.points.push_back(p);
  }
  return stroke;
}

// ---------------------------------------------------------------- SVG

bool IsShape(const std::string& name) {
  return name == "path" || name == "polyline" || name == "polygon" || name == "line" ||
         name == "circle";
}

// The root <svg>'s user space mapped onto the photo (see strokes.h).
Eigen::Affine2d PixelsFromDocument(const XMLElement& svg, int photo_width, int photo_height) {
  const std::optional<SvgViewport> viewport = ReadSvgViewport(svg);
  if (!viewport) return Eigen::Affine2d::Identity();
  return Eigen::Scaling(photo_width / viewport->size.x(), photo_height / viewport->size.y()) *
         Eigen::Translation2d(-viewport->origin);
}

// Walks the element tree, collecting strokes and the root point in photo
// pixels; errors name the file, the element and its line.
class SvgStrokeCollector {
 public:
  SvgStrokeCollector(std::string source, StrokeSet* set) : source_(std::move(source)), set_(set) {}

  void Walk(const XMLElement& parent, const Eigen::Affine2d& pixels_from_parent) {
    for (const XMLElement* child = parent.FirstChildElement(); child != nullptr;
         child = child->NextSiblingElement()) {
      const std::string name = SvgLocalName(*child);
      if (!(IsSvgContainer(name) || IsShape(name)) || IsSvgHidden(*child)) continue;
      const Eigen::Affine2d pixels_from_child = AtElement(*child, [&] {
        return Eigen::Affine2d(pixels_from_parent *
                               ParseSvgAttribute(*child, "transform", ParseSvgTransform));
      });
      if (IsSvgContainer(name)) {
        Walk(*child, pixels_from_child);
      } else {
        AtElement(*child, [&] { AddShape(*child, name, pixels_from_child); });
      }
    }
  }

  // Runs `f`, adding the file and the element to an InputError.
  template <typename F>
  auto AtElement(const XMLElement& element, F f) -> decltype(f()) {
    return AtSvgElement(source_, element, f);
  }

 private:
  void AddShape(const XMLElement& element, const std::string& name,
                const Eigen::Affine2d& pixels_from_user) {
    if (name == "circle") {
      if (!SvgHasIdOrClass(element, "root")) return;  // other circles are ignored
      if (set_->root) throw InputError("", "a second root circle (there may be only one)");
      set_->root = pixels_from_user * Eigen::Vector2d(SvgLengthAttribute(element, "cx"),
                                                      SvgLengthAttribute(element, "cy"));
      return;
    }
    for (const SvgPolyline& polyline :
         FlattenSvgShape(element, pixels_from_user, kFlattenTolerancePixels)) {
      AddStroke(polyline.points, polyline.what);
    }
  }

  void AddStroke(const std::vector<Eigen::Vector2d>& points, const std::string& what) {
    Stroke stroke = MakeStroke(points);
    if (stroke.points.size() < 2) {
      throw InputError("", what + " has fewer than two distinct points: not a stroke");
    }
    for (const Eigen::Vector2d& p : stroke.points) {
      if (!set_->NearPhoto(p)) {
        throw InputError("", what + " reaches (" + std::to_string(p.x()) + ", " +
                                 std::to_string(p.y()) + "), far outside the photo");
      }
    }
    set_->strokes.push_back(std::move(stroke));
  }

  std::string source_;
  StrokeSet* set_;
};

// ---------------------------------------------------------------- JSON

constexpr char kJsonFormatName[] = "sylva-strokes";
constexpr int kJsonFormatVersion = 1;

int PositiveInt(const JsonCursor& json) {
  const int value = json.AsInt();
  if (value <= 0) json.Fail("must be positive, got " + std::to_string(value));
  return value;
}

Eigen::Vector2d JsonPoint(const JsonCursor& json, const Eigen::Vector2d& scale) {
  const std::vector<double> xy = json.AsDoubles(2);
  return Eigen::Vector2d(xy[0], xy[1]).cwiseProduct(scale);
}

}  // namespace

bool StrokeSet::NearPhoto(const Eigen::Vector2d& p) const {
  return p.x() >= -width && p.x() <= 2.0 * width && p.y() >= -height && p.y() <= 2.0 * height;
}

void StrokeSet::Check(const std::string& source_name) const {
  SYLVA_CHECK_INPUT(width > 0 && height > 0, source_name)
      << "the photo size must be positive, got " << width << " x " << height;
  SYLVA_CHECK_INPUT(!strokes.empty(), source_name) << "no strokes";
  for (size_t k = 0; k < strokes.size(); ++k) {
    const std::vector<Eigen::Vector2d>& points = strokes[k].points;
    SYLVA_CHECK_INPUT(points.size() >= 2, source_name)
        << "stroke " << k << " has " << points.size() << " points; a stroke needs at least 2";
    for (size_t i = 0; i < points.size(); ++i) {
      SYLVA_CHECK_INPUT(NearPhoto(points[i]), source_name)
          << "stroke " << k << " point " << i << " (" << points[i].x() << ", " << points[i].y()
          << ") is not finite or lies far outside the " << width << " x " << height << " photo";
      SYLVA_CHECK_INPUT(i == 0 || points[i] != points[i - 1], source_name)
          << "stroke " << k << " repeats point " << i - 1;
    }
  }
  SYLVA_CHECK_INPUT(!root || NearPhoto(*root), source_name)
      << "the root point is not finite or lies far outside the photo";
}

StrokeSet ReadStrokesSvg(const std::filesystem::path& path, int photo_width, int photo_height) {
  SYLVA_CHECK(photo_width > 0 && photo_height > 0);
  const std::string source = path.string();
  tinyxml2::XMLDocument document;
  const XMLElement* svg = &ReadSvgDocument(path, &document);
  StrokeSet set;
  set.width = photo_width;
  set.height = photo_height;
  SvgStrokeCollector collector(source, &set);
  const Eigen::Affine2d pixels_from_document = collector.AtElement(
      *svg, [&] { return PixelsFromDocument(*svg, photo_width, photo_height); });
  collector.Walk(*svg, pixels_from_document);
  SYLVA_CHECK_INPUT(!set.strokes.empty(), source)
      << "no strokes: no visible <path>, <polyline>, <polygon> or <line> outside <defs>";
  set.Check(source);
  return set;
}

StrokeSet ReadStrokesJson(const std::filesystem::path& path, int photo_width, int photo_height) {
  SYLVA_CHECK(photo_width > 0 && photo_height > 0);
  const Json json = ReadJsonFile(path);
  const JsonCursor top(json, path.string());
  CheckJsonFormat(top, kJsonFormatName, kJsonFormatVersion);
  const int width = PositiveInt(top["width"]);
  const int height = PositiveInt(top["height"]);
  const Eigen::Vector2d scale(static_cast<double>(photo_width) / width,
                              static_cast<double>(photo_height) / height);
  StrokeSet set;
  set.width = photo_width;
  set.height = photo_height;
  const JsonCursor strokes = top["strokes"];
  if (strokes.Size() == 0) strokes.Fail("no strokes");
  for (size_t k = 0; k < strokes.Size(); ++k) {
    std::vector<Eigen::Vector2d> points;
    for (size_t i = 0; i < strokes[k].Size(); ++i)
      points.push_back(JsonPoint(strokes[k][i], scale));
    set.strokes.push_back(MakeStroke(points));
    if (set.strokes.back().points.size() < 2) {
      strokes[k].Fail("a stroke needs at least two distinct points");
    }
  }
  if (top.Has("root")) set.root = JsonPoint(top["root"], scale);
  set.Check(path.string());
  return set;
}

void WriteStrokesJson(const std::filesystem::path& path, const StrokeSet& strokes) {
  strokes.Check(path.string());
  Json json = {{"format", kJsonFormatName},
               {"version", kJsonFormatVersion},
               {"width", strokes.width},
               {"height", strokes.height},
               {"strokes", Json::array()}};
  for (const Stroke& stroke : strokes.strokes) {
    Json points = Json::array();
    for (const Eigen::Vector2d& p : stroke.points) points.push_back({p.x(), p.y()});
    json["strokes"].push_back(points);
  }
  if (strokes.root) json["root"] = {strokes.root->x(), strokes.root->y()};
  WriteJsonFile(path, json);
}

StrokeSet ReadStrokes(const std::filesystem::path& path, int photo_width, int photo_height) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".svg") return ReadStrokesSvg(path, photo_width, photo_height);
  if (extension == ".json") return ReadStrokesJson(path, photo_width, photo_height);
  SYLVA_INPUT_ERROR(path.string())
      << "unknown stroke file type '" << extension << "': expected .svg or .json";
  return StrokeSet();
}

}  // namespace sylva
