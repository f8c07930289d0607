#include "sketch/svg_element.h"

#include <cctype>
#include <sstream>

#include "core/util/file_util.h"
#include "sketch/svg_geometry.h"

namespace sylva {
namespace {

using tinyxml2::XMLElement;

std::string Trim(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
}

// Path data for the basic shapes, so that they are flattened (and
// transformed) by the one path flattener. Numbers are written exactly.
std::string PathNumbers(std::initializer_list<double> values) {
  std::ostringstream out;
  out.precision(17);
  for (double v : values) out << v << ' ';
  return out.str();
}

// A rectangle as a closed path; "" for a zero size (not rendered in SVG).
std::string RectPathData(const XMLElement& rect) {
  const double x = SvgLengthAttribute(rect, "x"), y = SvgLengthAttribute(rect, "y");
  const double w = SvgLengthAttribute(rect, "width"), h = SvgLengthAttribute(rect, "height");
  if (w <= 0 || h <= 0) return "";
  return "M " + PathNumbers({x, y}) + "h " + PathNumbers({w}) + "v " + PathNumbers({h}) + "h " +
         PathNumbers({-w}) + "Z";
}

// An ellipse (a circle when rx = ry) as two half arcs; "" for a zero radius.
std::string EllipsePathData(double cx, double cy, double rx, double ry) {
  if (rx <= 0 || ry <= 0) return "";
  const std::string radii = PathNumbers({rx, ry}) + "0 1 0 ";
  return "M " + PathNumbers({cx - rx, cy}) + "A " + radii + PathNumbers({cx + rx, cy}) + "A " +
         radii + PathNumbers({cx - rx, cy}) + "Z";
}

// The shapes that are not <path> as path data ("" for none or nothing drawn).
std::string ShapePathData(const XMLElement& element, const std::string& name) {
  if (name == "rect") return RectPathData(element);
  const double cx = SvgLengthAttribute(element, "cx"), cy = SvgLengthAttribute(element, "cy");
  if (name == "circle") {
    const double r = SvgLengthAttribute(element, "r");
    return EllipsePathData(cx, cy, r, r);
  }
  if (name == "ellipse") {
    return EllipsePathData(cx, cy, SvgLengthAttribute(element, "rx"),
                           SvgLengthAttribute(element, "ry"));
  }
  return "";
}

std::vector<SvgPolyline> FlattenPathData(std::string_view path_data, bool always_closed,
                                         const Eigen::Affine2d& target_from_user,
                                         double tolerance) {
  const auto subpaths = FlattenSvgPath(path_data, target_from_user, tolerance);
  std::vector<SvgPolyline> polylines;
  for (size_t k = 0; k < subpaths.size(); ++k) {
    const std::vector<Eigen::Vector2d>& points = subpaths[k];
    const bool back_at_start = points.size() > 2 && points.front() == points.back();
    polylines.push_back(
        {points, always_closed || back_at_start, "subpath " + std::to_string(k + 1)});
  }
  return polylines;
}

SvgPolyline PointsPolyline(const XMLElement& element, bool closed,
                           const Eigen::Affine2d& target_from_user) {
  const std::vector<double> xy = ParseSvgAttribute(element, "points", ParseSvgNumbers);
  if (xy.size() % 2 != 0) throw InputError("", "points: an odd number of coordinates");
  SvgPolyline polyline{{}, closed, "the points"};
  for (size_t i = 0; i + 1 < xy.size(); i += 2) {
    polyline.points.push_back(target_from_user * Eigen::Vector2d(xy[i], xy[i + 1]));
  }
  if (closed && !polyline.points.empty()) polyline.points.push_back(polyline.points.front());
  return polyline;
}

SvgPolyline LinePolyline(const XMLElement& element, const Eigen::Affine2d& target_from_user) {
  const auto point = [&](const char* x, const char* y) -> Eigen::Vector2d {
    return target_from_user *
           Eigen::Vector2d(SvgLengthAttribute(element, x), SvgLengthAttribute(element, y));
  };
  return {{point("x1", "y1"), point("x2", "y2")}, false, "the line"};
}

}  // namespace

const XMLElement& ReadSvgDocument(const std::filesystem::path& path,
                                  tinyxml2::XMLDocument* document) {
  const std::string source = path.string();
  const std::string text = ReadFileToString(path);
  if (document->Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    SYLVA_INPUT_ERROR(source) << "not valid XML (line " << document->ErrorLineNum()
                              << "): " << document->ErrorStr();
  }
  const XMLElement* svg = document->RootElement();
  SYLVA_CHECK_INPUT(svg != nullptr && SvgLocalName(*svg) == "svg", source)
      << "not an SVG file: the root element is not <svg>";
  return *svg;
}

std::string SvgLocalName(const XMLElement& element) {
  const std::string name = element.Name();
  const size_t colon = name.find(':');
  return colon == std::string::npos ? name : name.substr(colon + 1);
}

bool IsSvgContainer(const std::string& local_name) {
  return local_name == "g" || local_name == "a" || local_name == "svg";
}

bool IsSvgHidden(const XMLElement& element) {
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

bool SvgHasIdOrClass(const XMLElement& element, const std::string& word) {
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

std::optional<std::string> SvgStyleProperty(const XMLElement& element,
                                            const std::string& property) {
  // CSS declarations "name: value; name: value"; the style attribute wins
  // over the presentation attribute, as in SVG.
  if (const char* style = element.Attribute("style")) {
    std::istringstream declarations(style);
    std::string declaration;
    while (std::getline(declarations, declaration, ';')) {
      const size_t colon = declaration.find(':');
      if (colon == std::string::npos) continue;
      if (Trim(declaration.substr(0, colon)) == property) {
        return Trim(declaration.substr(colon + 1));
      }
    }
  }
  if (const char* value = element.Attribute(property.c_str())) return Trim(value);
  return std::nullopt;
}

std::string DescribeSvgElement(const XMLElement& element) {
  const char* id = element.Attribute("id");
  return "<" + std::string(element.Name()) +
         (id == nullptr ? "" : " id=\"" + std::string(id) + "\"") + "> on line " +
         std::to_string(element.GetLineNum());
}

double SvgLengthAttribute(const XMLElement& element, const char* name) {
  if (element.Attribute(name) == nullptr) return 0;
  return ParseSvgAttribute(element, name, ParseSvgLength);
}

std::optional<SvgViewport> ReadSvgViewport(const XMLElement& svg) {
  SvgViewport viewport;
  if (svg.Attribute("viewBox") != nullptr) {
    const std::vector<double> box = ParseSvgAttribute(svg, "viewBox", ParseSvgNumbers);
    if (box.size() != 4 || box[2] <= 0 || box[3] <= 0) {
      throw InputError("", "viewBox must be 'min-x min-y width height' with a positive size");
    }
    viewport.origin = Eigen::Vector2d(box[0], box[1]);
    viewport.size = Eigen::Vector2d(box[2], box[3]);
    return viewport;
  }
  const char* width = svg.Attribute("width");
  const char* height = svg.Attribute("height");
  if (width == nullptr || height == nullptr || std::string(width).find('%') != std::string::npos ||
      std::string(height).find('%') != std::string::npos) {
    return std::nullopt;
  }
  viewport.size =
      Eigen::Vector2d(SvgLengthAttribute(svg, "width"), SvgLengthAttribute(svg, "height"));
  if (viewport.size.minCoeff() <= 0) throw InputError("", "width and height must be positive");
  return viewport;
}

std::vector<SvgPolyline> FlattenSvgShape(const XMLElement& element,
                                         const Eigen::Affine2d& target_from_user,
                                         double tolerance) {
  const std::string name = SvgLocalName(element);
  if (name == "path") {
    return ParseSvgAttribute(element, "d", [&](std::string_view d) {
      return FlattenPathData(d, false, target_from_user, tolerance);
    });
  }
  if (name == "polyline" || name == "polygon") {
    return {PointsPolyline(element, name == "polygon", target_from_user)};
  }
  if (name == "line") return {LinePolyline(element, target_from_user)};
  const std::string path_data = ShapePathData(element, name);
  if (path_data.empty()) return {};
  return FlattenPathData(path_data, true, target_from_user, tolerance);
}

}  // namespace sylva
