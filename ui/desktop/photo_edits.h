// What a person makes on one photo in the app, in memory, and the files the
// pipeline reads it from (ui/pipeline/project.h):
//
//   edits/density/<photo>.png   painted density: RGBA at the photo's size,
//                               alpha = edit strength, grey = the opacity
//                               painted (255 add, 0 remove)
//                               (reconstruct/density/density_edits.h)
//   edits/trimaps/<photo>.png   painted matting hint: painted pixels opaque,
//                               grey 255 foreground / 0 background; unpainted
//                               pixels transparent (reconstruct/matting/trimap_io.h)
//   edits/<photo>.strokes.json  drawn branch strokes (sketch/strokes.h)
//   edits/<photo>.crown.svg     crown outlines (closed polygons)
//
// (<photo> is the photo's name without its extension.) Every write is atomic;
// a layer with nothing painted has no file, so clearing an edit leaves the
// project's stage keys as they were before it was made.
#ifndef SYLVA_UI_DESKTOP_PHOTO_EDITS_H_
#define SYLVA_UI_DESKTOP_PHOTO_EDITS_H_

#include <QImage>
#include <QPointF>
#include <QRect>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sketch/strokes.h"

namespace sylva {

class Project;

// Which layers of a PhotoEdits a change touched (bit mask).
enum EditLayerBits : unsigned {
  kDensityLayer = 1u << 0,
  kTrimapLayer = 1u << 1,
  kStrokesLayer = 1u << 2,
  kCrownLayer = 1u << 3,
  kAllLayers = 0xfu,
};

// Grey values of the painted layers.
constexpr int kPaintAdd = 255;   // density: add opacity; trimap: foreground
constexpr int kPaintRemove = 0;  // density: remove opacity; trimap: background
constexpr int kTrimapUnpaintedGrey = 128;

struct PhotoEdits {
  int width = 0;  // the photo's size in pixels
  int height = 0;
  QImage density;  // Format_RGBA8888 (straight alpha); null = no edit
  QImage trimap;   // Format_RGBA8888; null = no hint
  std::vector<Stroke> strokes;
  std::optional<QPointF> root;               // the tree base, if marked
  std::vector<std::vector<QPointF>> crowns;  // closed outlines, photo pixels
};

// The files of one photo's edits.
struct PhotoEditFiles {
  std::filesystem::path density, trimap, strokes, crown;
  static PhotoEditFiles Of(const Project& project, const std::string& photo_name);
};

// Reads a photo's edits (missing files give empty layers). A strokes SVG
// (edits/<photo>.strokes.svg) is read too; Throws InputError naming a file
// that cannot be read or has the wrong size.
PhotoEdits LoadPhotoEdits(const Project& project, const std::string& photo_name, int width,
                          int height);

// Writes the layers in `layers` atomically (removing the file of an empty
// layer). Writing strokes moves a strokes SVG aside to
// <photo>.strokes.svg.bak, since the pipeline reads the SVG first.
void SavePhotoEdits(const Project& project, const std::string& photo_name, const PhotoEdits& edits,
                    unsigned layers);

// A round brush: `radius` in photo pixels; full strength within
// hardness x radius of the centre, falling smoothly to 0 at the radius.
struct BrushShape {
  double radius = 12.0;
  double hardness = 0.8;  // [0, 1]
  double strength = 1.0;  // [0, 1], the alpha a full dab paints
};

// The coverage of one stroke: per pixel the maximum of its dabs (so a
// stroke passing twice over a pixel does not paint it twice).
class StrokeMask {
 public:
  StrokeMask(int width, int height) : width_(width), height_(height), mask_(width * height, 0.f) {}
  // Dabs from `from` to `to` (photo pixels; pixel centres at +0.5), spaced
  // by a quarter of the radius. Returns the pixels touched.
  QRect AddSegment(const QPointF& from, const QPointF& to, const BrushShape& brush);
  float at(int x, int y) const { return mask_[static_cast<size_t>(y) * width_ + x]; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  QRect AddDab(const QPointF& center, const BrushShape& brush);

  int width_, height_;
  std::vector<float> mask_;
};

// What a brush does where its stroke covers a pixel with coverage a.
enum class BrushMode {
  kDensityAdd,     // density: paint grey 255 over with alpha a ("over")
  kDensityRemove,  // density: paint grey 0 over with alpha a
  kTrimapForeground,
  kTrimapBackground,
  kTrimapUnknown,  // clears the hint: the automatic trimap decides there
  kEraser,         // lowers density alpha by a, clears the trimap hint
};

// Recomputes `rect` of `*edits` from `before` and the stroke's mask. The
// density compositing is exact "over": painting grey g with alpha a over
// (G, A) gives A' = a + A(1 - a) and G' = (g a + G A (1 - a)) / A', so the
// pipeline's mix(mix(matte, G, A), g, a) equals mix(matte, G', A').
// Trimap labels are set where the coverage is at least 1/2.
void ApplyStroke(const PhotoEdits& before, const StrokeMask& mask, BrushMode mode,
                 const QRect& rect, PhotoEdits* edits);

// Removes the strokes, root and crowns that pass within `radius` of `point`;
// true if any was removed.
bool EraseShapesNear(const QPointF& point, double radius, PhotoEdits* edits);

// True if no pixel of the image has alpha > 0 (a null image too).
bool IsBlank(const QImage& image);

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_PHOTO_EDITS_H_
