// The SVG document and element handling shared by the two SVG readers:
// strokes drawn on a photo (strokes.h) and drawings of trees (drawing_io.h).
// Each reader walks the element tree its own way; both open the document,
// find its viewport and turn shapes into polylines with these functions, so
// there is one SVG path parser (svg_geometry.h) and one shape converter.
//
// Internal to sylva_sketch: includes tinyxml2, so only .cc files include it.
// Errors throw InputError with an empty source (the reader adds the file and
// the element, see AtSvgElement).
#ifndef SYLVA_SKETCH_SVG_ELEMENT_H_
#define SYLVA_SKETCH_SVG_ELEMENT_H_

#include <tinyxml2.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/util/check.h"

namespace sylva {

// Parses `path` into `document` and returns its root <svg> element; throws
// InputError naming the file if it is not XML or the root is not <svg>.
const tinyxml2::XMLElement& ReadSvgDocument(const std::filesystem::path& path,
                                            tinyxml2::XMLDocument* document);

// The element name without a namespace prefix ("svg:path" -> "path").
std::string SvgLocalName(const tinyxml2::XMLElement& element);

// <g>, <a> and nested <svg>: elements whose children are drawn.
bool IsSvgContainer(const std::string& local_name);

// display="none" or style "display:none" (e.g. a hidden Inkscape layer).
bool IsSvgHidden(const tinyxml2::XMLElement& element);

// Whether `word` is the element's id or one of its classes.
bool SvgHasIdOrClass(const tinyxml2::XMLElement& element, const std::string& word);

// The value of the CSS property `property` in the element's `style`
// attribute, else its presentation attribute of the same name; nullopt if
// neither is given. Whitespace around the value is trimmed.
std::optional<std::string> SvgStyleProperty(const tinyxml2::XMLElement& element,
                                            const std::string& property);

// "<path id="p7"> on line 12": how errors name an element.
std::string DescribeSvgElement(const tinyxml2::XMLElement& element);

// Parses attribute `name` (an empty string if absent) with `parse`, adding
// the attribute's name to a syntax error.
template <typename Parse>
auto ParseSvgAttribute(const tinyxml2::XMLElement& element, const char* name, Parse parse) {
  const char* value = element.Attribute(name);
  try {
    return parse(std::string_view(value == nullptr ? "" : value));
  } catch (const InputError& error) {
    throw InputError("", std::string("attribute ") + name + ": " + error.message());
  }
}

// A length attribute in user units; 0 if absent (SVG's default for x1, cx, ...).
double SvgLengthAttribute(const tinyxml2::XMLElement& element, const char* name);

// Runs `f`, adding the file `source` and the element to an InputError.
template <typename F>
auto AtSvgElement(const std::string& source, const tinyxml2::XMLElement& element, F f)
    -> decltype(f()) {
  try {
    return f();
  } catch (const InputError& error) {
    throw InputError(source, DescribeSvgElement(element) + ": " + error.message());
  }
}

// The root <svg>'s viewport in user units: the viewBox's origin and size,
// or without a viewBox the origin (0, 0) and the width and height (px, mm,
// cm, in, pt, pc). nullopt if neither is given (or they are percentages).
struct SvgViewport {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  Eigen::Vector2d size = Eigen::Vector2d::Zero();
};
std::optional<SvgViewport> ReadSvgViewport(const tinyxml2::XMLElement& svg);

// One polyline of a shape, in target coordinates.
struct SvgPolyline {
  std::vector<Eigen::Vector2d> points;  // closed ones end at their first point
  bool closed = false;                  // polygon, rect, circle, ellipse, subpath back at its start
  std::string what;                     // "subpath 2", "the points", ... for errors
};

// The polylines of a <path> (one per subpath), <polyline>, <polygon>,
// <line>, <rect> (rounded corners ignored), <circle> or <ellipse>, mapped by
// `target_from_user`; curves are flattened to within `tolerance` (target
// units) by FlattenSvgPath. Empty for any other element.
std::vector<SvgPolyline> FlattenSvgShape(const tinyxml2::XMLElement& element,
                                         const Eigen::Affine2d& target_from_user, double tolerance);

}  // namespace sylva

#endif  // SYLVA_SKETCH_SVG_ELEMENT_H_
