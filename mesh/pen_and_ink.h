// Pen-and-ink line drawings of triangle meshes (Anastacio et al. 2006,
// section 7: organ boundaries and silhouettes as ink lines, hidden lines
// removed; Sousa and Prusinkiewicz 2003), in an orthographic view:
//   - outlines: the mesh's boundary edges (a leaf's rim), silhouette edges
//     (between a face turned to the viewer and one turned away) and creases
//     (faces meeting at more than crease_deg), sampled every
//     sample_spacing_px and kept where an Embree ray from the viewer reaches
//     them first (within a depth tolerance: the paper's offset of strokes
//     along the normal);
//   - hatching: parallel lines across the picture, kept where the surface
//     they fall on is darker than a tone (Lambert shading from
//     light_direction), a second family across the first where it is darker
//     still; lines break where the surface under them jumps in depth;
//   - feature lines: given 3D polylines on the surface (e.g. leaf veins),
//     sampled and kept where visible like the outlines, drawn with them;
//   - construction: given 3D polylines (e.g. a concept sketch's
//     construction lines), drawn unoccluded.
// Written as an SVG with one Inkscape layer per kind (`hatching`, `outline`,
// `construction`) and rasterised to a picture.
#ifndef SYLVA_MESH_PEN_AND_INK_H_
#define SYLVA_MESH_PEN_AND_INK_H_

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/triangle_mesh.h"

namespace sylva {

struct PenAndInkOptions {
  // The picture's longer side, pixels, in [64, 8192].
  int image_size = 900;
  // Empty border around the drawing, fraction of the image size, [0, 0.4].
  double margin = 0.05;
  // Outline samples this far apart along an edge, pixels, (0, 10].
  double sample_spacing_px = 0.75;
  // Faces meeting at more than this angle draw a crease line, degrees.
  double crease_deg = 60.0;
  // Distance between hatching lines, pixels, [1, 100].
  double hatch_spacing_px = 5.0;
  // Surfaces darker than this tone (0 white, 1 black) are hatched once,
  // darker than cross_hatch_tone twice; in [0, 1].
  double hatch_tone = 0.45;
  double cross_hatch_tone = 0.7;
  // Direction towards the light, in world coordinates (non-zero).
  Eigen::Vector3d light_direction = Eigen::Vector3d(-0.5, -0.6, 0.8);
  // Ink widths, pixels.
  double outline_width_px = 1.4;
  double hatch_width_px = 0.6;
  double construction_width_px = 0.8;
  // Draw the construction lines given to DrawPenAndInk.
  bool construction = true;

  // Throws InputError("PenAndInk.<field>", ...).
  void Check() const;
};

// An orthographic view: looking along `view_direction` (from the eye into
// the scene), `up` the picture's up (made perpendicular to it).
struct PenAndInkView {
  Eigen::Vector3d view_direction = Eigen::Vector3d::UnitY();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  // A view from azimuth and elevation (degrees): azimuth 0 looks along +y
  // (the front of a concept sketch), 90 along -x; elevation 90 looks down.
  static PenAndInkView FromAngles(double azimuth_deg, double elevation_deg);
};

struct PenAndInkDrawing {
  int width = 0, height = 0;                      // pixels
  using Polyline = std::vector<Eigen::Vector2d>;  // picture pixels, y down
  std::vector<Polyline> outline, hatching, construction;
  int outline_samples = 0;                 // outline samples tested
  int hidden_outline_samples = 0;          // of which hidden
  double line_width[3] = {1.4, 0.6, 0.8};  // outline, hatching, construction
  std::string BriefReport() const;
};

// Draws `mesh` (may be empty only if `construction` is not) fitted into
// the picture. Deterministic; throws InputError for bad options.
PenAndInkDrawing DrawPenAndInk(const TriangleMesh& mesh,
                               const std::vector<std::vector<Eigen::Vector3d>>& feature_lines,
                               const std::vector<std::vector<Eigen::Vector3d>>& construction,
                               const PenAndInkView& view, const PenAndInkOptions& options);

// The SVG text: a white background and the layers hatching, outline,
// construction (Inkscape layers: <g inkscape:groupmode="layer"
// inkscape:label="outline" id="outline">), one <polyline> per line.
std::string PenAndInkSvg(const PenAndInkDrawing& drawing);
// Writes PenAndInkSvg atomically.
void WritePenAndInkSvg(const std::filesystem::path& path, const PenAndInkDrawing& drawing);

// The lines as anti-aliased black (construction: grey) ink on white, RGB.
FloatImage RasterizePenAndInk(const PenAndInkDrawing& drawing);

}  // namespace sylva

#endif  // SYLVA_MESH_PEN_AND_INK_H_
