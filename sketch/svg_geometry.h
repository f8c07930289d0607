// The geometry parts of SVG 1.1 that stroke files use: numbers, lengths,
// `transform` lists and path data (every command, curves and arcs flattened
// to polylines). Used by ReadStrokesSvg (strokes.h), which adds the file and
// element to the messages.
//
// Errors throw InputError with an empty source and a message that says what
// is wrong and where in the attribute value (a character offset).
#ifndef SYLVA_SKETCH_SVG_GEOMETRY_H_
#define SYLVA_SKETCH_SVG_GEOMETRY_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string_view>
#include <vector>

namespace sylva {

// A list of numbers separated by whitespace and/or commas, in SVG's number
// syntax ("10,20 -3.5e1-.5" is 10, 20, -35, -0.5). Every number must be finite.
std::vector<double> ParseSvgNumbers(std::string_view text);

// A length in user units (CSS pixels): a number with an optional unit px,
// pt, pc, mm, cm or in (96 px per inch). Percentages and font-relative units
// (em, ex) are rejected.
double ParseSvgLength(std::string_view text);

// A `transform` attribute: matrix(a b c d e f), translate(x [y]),
// scale(x [y]), rotate(angle [cx cy]) (degrees), skewX(angle), skewY(angle),
// separated by whitespace or commas and applied right to left as in SVG.
// Returns parent_from_element; an empty string gives the identity.
Eigen::Affine2d ParseSvgTransform(std::string_view text);

// Path data (the `d` attribute) with every command: M m L l H h V v C c S s
// Q q T t A a Z z, including implicit repeats and the numbers packed without
// separators that SVG allows. Returns one polyline per subpath, its points
// mapped by `target_from_user`. Curves are flattened in the target space so
// that every point of the exact (transformed) curve lies within `tolerance`
// of the polyline: Bezier segments are split uniformly in their parameter,
// with a count from the bound on their second derivative; elliptical arcs
// are converted to centre form (SVG 1.1 appendix F.6.5, radii scaled up when
// too small, F.6.6) and split uniformly in angle. Consecutive equal points
// are merged, so a subpath may come out with a single point. Z closes the
// polyline back to the subpath's first point.
std::vector<std::vector<Eigen::Vector2d>> FlattenSvgPath(std::string_view path_data,
                                                         const Eigen::Affine2d& target_from_user,
                                                         double tolerance);

}  // namespace sylva

#endif  // SYLVA_SKETCH_SVG_GEOMETRY_H_
