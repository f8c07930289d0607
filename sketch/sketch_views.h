// Drawings as photos (issue 14): a sketch is evidence of the same kind as a
// photo. Each drawing becomes one view of a project with
//   - an orthographic camera: drawing i looks at the tree from azimuth
//     90° x i (front, side, back, other side), the drawn tree base at the
//     world origin, its drawn height scaled to SketchViewOptions::tree_height;
//   - a "photo": the strokes in black on white;
//   - a matte: what the drawing covers with its enclosed regions filled (the
//     strokes opaque, the enclosed regions - the crown - at crown_opacity;
//     a crown stroke left open is closed by the chord between its ends),
//     so the density stage back-projects the crown's silhouette like a
//     photo's;
//   - strokes: the branch strokes as that view's attractor strokes
//     (strokes.h), so the particle flow follows the drawn branches; where
//     the drawing has no branch but the trunk, major branches inferred from
//     the crown's silhouette (InferMajorBranches).
//
// A single drawing does not say how deep the crown is. Its depth prior is a
// crown of revolution about the drawn trunk: a second, virtual view at right
// angles ("<stem>.depth.png") whose matte is the drawing's silhouette made
// symmetric about the trunk (at each height, the drawing's coverage at
// radius r on either side). Trees grown in the open are close to axially
// symmetric, so this gives a crown about as deep as it is wide, and it only
// adds a carving constraint: the drawn view still decides everything it
// shows. With two or more drawings every view is drawn and nothing is
// assumed.
#ifndef SYLVA_SKETCH_SKETCH_VIEWS_H_
#define SYLVA_SKETCH_SKETCH_VIEWS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/types/float_image.h"
#include "core/types/image_set.h"
#include "sketch/drawing.h"
#include "sketch/strokes.h"

namespace sylva {

struct SketchViewOptions {
  // The longest side of the views' images, in pixels (the drawing is scaled
  // to it).
  int image_size = 512;
  // The tree's height in world units (a prior: a drawing has no scale).
  double tree_height = 10.0;
  // Matte value of the drawing's enclosed regions (alpha): how much of the
  // light a drawn crown stops.
  double crown_opacity = 0.6;
  // Width of the drawn lines in the matte, as a fraction of the image size,
  // where the drawing does not give one.
  double line_width = 0.006;
  // Gaps in outlines narrower than this fraction of the image size are
  // closed before the enclosed regions are filled.
  double gap_closing = 0.03;
  // Major branches inferred from a crown's silhouette (InferMajorBranches):
  // concavities of the outline deeper than this fraction of the crown's size
  // split it into bumps, and a branch reaches this fraction of the way from
  // the trunk's top to its bump's apex.
  double valley_depth = 0.04;
  double branch_reach = 0.85;

  // Throws InputError naming the first invalid option.
  void Check() const;
};

struct SketchView {
  std::string name;  // the image name: the drawing's file stem + ".png"
  FloatImage photo;  // 3 channels, strokes black on white
  FloatImage matte;  // 1 channel
  // The branch strokes in this view's pixels, drawn or inferred (may be
  // empty); the root is the tree base.
  StrokeSet strokes;
  bool is_virtual = false;  // the depth prior's view (not drawn)
};

struct SketchViews {
  // Views in drawing order (the virtual view last); `cameras` holds one
  // camera per view with the same names.
  std::vector<SketchView> views;
  ImageSet cameras;
  // The drawn views' cameras at their drawings' canvas sizes (drawing
  // pixels), for projecting the tree back onto the drawings.
  ImageSet drawing_cameras;
  // The drawing-pixel position of the tree base in each drawing.
  std::vector<Eigen::Vector2d> bases;
};

// Major branches inferred from a crown silhouette (Wither et al. 2009,
// section 4.1): the outline of the largest region `matte` fills is cut into
// bumps at its concavities deeper than options.valley_depth of the crown's
// size; a branch grows from `trunk_top` towards the apex of each bump above
// it (the bump's point farthest from the trunk top), reaching
// options.branch_reach of the way, as a cubic
// Hermite curve leaving the trunk upwards and arriving along the direction
// to the apex. Used where a drawing gives no branch but the trunk, and for
// the depth prior's view. In view pixels.
// The crown is what the matte fills at options.crown_opacity or more.
std::vector<Stroke> InferMajorBranches(const FloatImage& matte, const SketchViewOptions& options,
                                       const Eigen::Vector2d& trunk_top);

// The outline of the largest region `matte` fills at half of crown_opacity
// or more (the crown, as InferMajorBranches reads it), in view pixels
// (pixel centres at halves); empty if there is none.
std::vector<Eigen::Vector2d> CrownOutlineOf(const FloatImage& matte, double crown_opacity);

// The regions the strokes of `drawing` outline (each closed by the chord
// from its end to its start), drawn onto an image of width x height pixels
// (the drawing's canvas stretched onto it): 1 inside, 0 outside. For crown
// outlines drawn over a photo (Project::LoadEditedMatte).
FloatImage OutlinedRegions(const SketchDrawing& drawing, int width, int height);

// The views of a tree drawn in `drawings` (1 to 4, each Check()ed, with
// distinct sources). Deterministic. Throws InputError naming the drawing if
// it has no strokes that cover anything.
SketchViews MakeSketchViews(const std::vector<SketchDrawing>& drawings,
                            const SketchViewOptions& options);

}  // namespace sylva

#endif  // SYLVA_SKETCH_SKETCH_VIEWS_H_
