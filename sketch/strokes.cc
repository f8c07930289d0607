#include "sketch/strokes.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
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

// The element name without a namespace prefix ("svg:path" -> "path").
std::string LocalName(const XMLElement& element) {
  const std::string name = element.Name();
  const size_t colon = name.find(':');
  return colon == std::string::npos ? name : name.substr(colon + 1);
}

bool IsContainer(const std::string& name) { return name == "g" || name == "a" || name == "svg"; }
bool IsShape(const std::string& name) {
  return name == "path" || name == "polyline" || name == "polygon" || name == "line" ||
         name == "circle";
}

bool IsHidden(const XMLElement& element) {
  const char* display = element.Attribute("display");
  if (display != nullptr && std::string(display) == "none") return true;
  const char* style = element.Attribute("style");
  if (style == nullptr) return false;
  std::string compact;
  for (const char* c = style; *c != '\0'; ++c) {
    if (!std::isspace(static_cast<unsigned char>(*c))) compact += *c;
  }
  return compact.find("display:none") != std::string::npos;
}

bool HasIdOrClass(const XMLElement& element, const std::string& word) {
  const char* id = element.Attribute("id");
  if (id != nullptr && word == id) return true;
  const char* classes = element.Attribute("class");
  if (classes == nullptr) return false;
  std::istringstream words(classes);
  std::string name;
  while (words >> name) {
    if (name == word) return true;
  }
  return false;
}

// Parses attribute `name` (an empty string if absent) with `parse`, adding
// the attribute's name to a syntax error.
template <typename Parse>
auto ParseAttribute(const XMLElement& element, const char* name, Parse parse) {
  const char* value = element.Attribute(name);
  try {
    return parse(std::string_view(value == nullptr ? "" : value));
  } catch (const InputError& error) {
    throw InputError("", std::string("attribute ") + name + ": " + error.message());
  }
}

double LengthAttribute(const XMLElement& element, const char* name) {
  if (element.Attribute(name) == nullptr) return 0;  // SVG's default for x1, cx, ...
  return ParseAttribute(element, name, ParseSvgLength);
}

// The root <svg>'s user space mapped onto the photo (see strokes.h).
Eigen::Affine2d PixelsFromDocument(const XMLElement& svg, int photo_width, int photo_height) {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero(), size;
  if (svg.Attribute("viewBox") != nullptr) {
    const std::vector<double> box = ParseAttribute(svg, "viewBox", ParseSvgNumbers);
    if (box.size() != 4 || box[2] <= 0 || box[3] <= 0) {
      throw InputError("", "viewBox must be 'min-x min-y width height' with a positive size");
    }
    origin = Eigen::Vector2d(box[0], box[1]);
    size = Eigen::Vector2d(box[2], box[3]);
  } else {
    const char* width = svg.Attribute("width");
    const char* height = svg.Attribute("height");
    if (width == nullptr || height == nullptr ||
        std::string(width).find('%') != std::string::npos ||
        std::string(height).find('%') != std::string::npos) {
      return Eigen::Affine2d::Identity();
    }
    size = Eigen::Vector2d(LengthAttribute(svg, "width"), LengthAttribute(svg, "height"));
    if (size.minCoeff() <= 0) throw InputError("", "width and height must be positive");
  }
  return Eigen::Scaling(photo_width / size.x(), photo_height / size.y()) *
         Eigen::Translation2d(-origin);
}

// Walks the element tree, collecting strokes and the root point in photo
// pixels; errors name the file, the element and its line.
class SvgStrokeCollector {
 public:
  SvgStrokeCollector(std::string source, StrokeSet* set) : source_(std::move(source)), set_(set) {}

  void Walk(const XMLElement& parent, const Eigen::Affine2d& pixels_from_parent) {
    for (const XMLElement* child = parent.FirstChildElement(); child != nullptr;
         child = child->NextSiblingElement()) {
      const std::string name = LocalName(*child);
      if (!(IsContainer(name) || IsShape(name)) || IsHidden(*child)) continue;
      const Eigen::Affine2d pixels_from_child = AtElement(*child, [&] {
        return Eigen::Affine2d(pixels_from_parent *
                               ParseAttribute(*child, "transform", ParseSvgTransform));
      });
      if (IsContainer(name)) {
        Walk(*child, pixels_from_child);
      } else {
        AtElement(*child, [&] { AddShape(*child, name, pixels_from_child); });
      }
    }
  }

  // Runs `f`, adding the file and the element to an InputError.
  template <typename F>
  auto AtElement(const XMLElement& element, F f) -> decltype(f()) {
    try {
      return f();
    } catch (const InputError& error) {
      throw InputError(source_, Describe(element) + ": " + error.message());
    }
  }

 private:
  static std::string Describe(const XMLElement& element) {
    const char* id = element.Attribute("id");
    return "<" + std::string(element.Name()) +
           (id == nullptr ? "" : " id=\"" + std::string(id) + "\"") + "> on line " +
           std::to_string(element.GetLineNum());
  }

  void AddShape(const XMLElement& element, const std::string& name,
                const Eigen::Affine2d& pixels_from_user) {
    if (name == "path") {
      const auto flatten = [&](std::string_view d) {
        return FlattenSvgPath(d, pixels_from_user, kFlattenTolerancePixels);
      };
      const auto subpaths = ParseAttribute(element, "d", flatten);
      for (size_t k = 0; k < subpaths.size(); ++k) {
        AddStroke(subpaths[k], "subpath " + std::to_string(k + 1));
      }
    } else if (name == "polyline" || name == "polygon") {
      const std::vector<double> xy = ParseAttribute(element, "points", ParseSvgNumbers);
      if (xy.size() % 2 != 0) throw InputError("", "points: an odd number of coordinates");
      std::vector<Eigen::Vector2d> points;
      for (size_t i = 0; i + 1 < xy.size(); i += 2) {
        points.push_back(pixels_from_user * Eigen::Vector2d(xy[i], xy[i + 1]));
      }
      if (name == "polygon" && !points.empty()) points.push_back(points.front());
      AddStroke(points, "the points");
    } else if (name == "line") {
      AddStroke({pixels_from_user * Eigen::Vector2d(LengthAttribute(element, "x1"),
                                                    LengthAttribute(element, "y1")),
                 pixels_from_user * Eigen::Vector2d(LengthAttribute(element, "x2"),
                                                    LengthAttribute(element, "y2"))},
                "the line");
    } else if (name == "circle" && HasIdOrClass(element, "root")) {
      if (set_->root) throw InputError("", "a second root circle (there may be only one)");
      set_->root = pixels_from_user *
                   Eigen::Vector2d(LengthAttribute(element, "cx"), LengthAttribute(element, "cy"));
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
  const std::string text = ReadFileToString(path);
  tinyxml2::XMLDocument document;
  if (document.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    SYLVA_INPUT_ERROR(source) << "not valid XML (line " << document.ErrorLineNum()
                              << "): " << document.ErrorStr();
  }
  const XMLElement* svg = document.RootElement();
  SYLVA_CHECK_INPUT(svg != nullptr && LocalName(*svg) == "svg", source)
      << "not an SVG file: the root element is not <svg>";
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
