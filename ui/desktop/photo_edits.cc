#include "ui/desktop/photo_edits.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/io/image_io.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "sketch/drawing_io.h"
#include "ui/pipeline/project.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// edits/<name without extension><suffix>.
fs::path EditBeside(const Project& project, const std::string& photo_name, const char* suffix) {
  fs::path path = project.EditsDir() / fs::path(photo_name).replace_extension();
  path += suffix;
  return path;
}

// An image file as RGBA8888 of the photo's size; null if `path` is empty.
QImage ReadRgba(const fs::path& path, int width, int height) {
  if (path.empty()) return {};
  QImage image(QString::fromStdString(path.string()));
  if (image.isNull()) {
    // Formats Qt does not read (TIFF, EXR): through OpenImageIO.
    const FloatImage pixels = ReadImage(path);
    image = QImage(pixels.width(), pixels.height(), QImage::Format_RGBA8888);
    const int c = pixels.channels();
    for (int y = 0; y < pixels.height(); ++y) {
      uchar* row = image.scanLine(y);
      for (int x = 0; x < pixels.width(); ++x) {
        const float grey = c >= 3 ? pixels.at(x, y, 0) : pixels.at(x, y, 0);
        const float a = (c == 2 || c == 4) ? pixels.at(x, y, c - 1) : 1.0f;
        for (int k = 0; k < 3; ++k) {
          const float v = c >= 3 ? pixels.at(x, y, k) : grey;
          row[4 * x + k] = static_cast<uchar>(std::lround(std::clamp(v, 0.f, 1.f) * 255));
        }
        row[4 * x + 3] = static_cast<uchar>(std::lround(std::clamp(a, 0.f, 1.f) * 255));
      }
    }
  }
  SYLVA_CHECK_INPUT(image.width() == width && image.height() == height, path.string())
      << "is " << image.width() << "x" << image.height() << ", the photo " << width << "x"
      << height;
  return image.convertToFormat(QImage::Format_RGBA8888);
}

void WriteOrRemove(const QImage& image, const fs::path& path) {
  if (IsBlank(image)) {
    std::error_code ec;
    fs::remove(path, ec);
    return;
  }
  fs::create_directories(path.parent_path());
  AtomicWriteWith(path, [&](const fs::path& temp) {
    SYLVA_CHECK(image.save(QString::fromStdString(temp.string()), "PNG"))
        << "cannot write " << temp.string();
  });
}

// The crown outlines as SVG polygons on a canvas of the photo's size.
std::string CrownSvg(const PhotoEdits& edits) {
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << edits.width << "\" height=\""
      << edits.height << "\" viewBox=\"0 0 " << edits.width << " " << edits.height << "\">\n";
  for (const auto& outline : edits.crowns) {
    svg << "  <polygon class=\"crown\" fill=\"none\" stroke=\"green\" points=\"";
    for (size_t i = 0; i < outline.size(); ++i) {
      svg << (i ? " " : "") << outline[i].x() << "," << outline[i].y();
    }
    svg << "\"/>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

std::vector<std::vector<QPointF>> ReadCrowns(const fs::path& path, int width, int height) {
  std::vector<std::vector<QPointF>> crowns;
  if (path.empty()) return crowns;
  const SketchDrawing drawing = ReadSketchSvg(path);
  const double sx = width / drawing.width, sy = height / drawing.height;
  for (const SketchStroke& stroke : drawing.strokes) {
    std::vector<QPointF> outline;
    for (const Eigen::Vector2d& p : stroke.points) outline.emplace_back(p.x() * sx, p.y() * sy);
    crowns.push_back(std::move(outline));
  }
  return crowns;
}

// Pixels (x0..x1, y0..y1) within the image, as a QRect.
QRect Clipped(double x0, double y0, double x1, double y1, int width, int height) {
  const int left = std::max(0, static_cast<int>(std::floor(x0)));
  const int top = std::max(0, static_cast<int>(std::floor(y0)));
  const int right = std::min(width - 1, static_cast<int>(std::ceil(x1)));
  const int bottom = std::min(height - 1, static_cast<int>(std::ceil(y1)));
  return QRect(QPoint(left, top), QPoint(right, bottom));
}

QImage BlankLayer(int width, int height, int grey) {
  QImage image(width, height, QImage::Format_RGBA8888);
  image.fill(QColor(grey, grey, grey, 0));
  return image;
}

double DistanceToSegment(const QPointF& p, const QPointF& a, const QPointF& b) {
  const QPointF ab = b - a;
  const double length2 = QPointF::dotProduct(ab, ab);
  const double t =
      length2 > 0 ? std::clamp(QPointF::dotProduct(p - a, ab) / length2, 0.0, 1.0) : 0.0;
  const QPointF d = p - (a + t * ab);
  return std::hypot(d.x(), d.y());
}

template <typename Points, typename ToQ>
bool NearPolyline(const Points& points, const ToQ& to_q, const QPointF& p, double radius,
                  bool closed) {
  const size_t n = points.size();
  for (size_t i = 0; i + 1 < n + (closed ? 1 : 0); ++i) {
    if (DistanceToSegment(p, to_q(points[i]), to_q(points[(i + 1) % n])) <= radius) return true;
  }
  return n == 1 && DistanceToSegment(p, to_q(points[0]), to_q(points[0])) <= radius;
}

}  // namespace

PhotoEditFiles PhotoEditFiles::Of(const Project& project, const std::string& photo_name) {
  PhotoEditFiles files;
  const fs::path stem = fs::path(photo_name).replace_extension(".png");
  files.density = project.EditsDir() / "density" / stem;
  files.trimap = project.EditsDir() / "trimaps" / stem;
  files.strokes = EditBeside(project, photo_name, ".strokes.json");
  files.crown = EditBeside(project, photo_name, ".crown.svg");
  return files;
}

PhotoEdits LoadPhotoEdits(const Project& project, const std::string& photo_name, int width,
                          int height) {
  PhotoEdits edits;
  edits.width = width;
  edits.height = height;
  edits.density = ReadRgba(project.DensityEditPath(photo_name), width, height);
  edits.trimap = ReadRgba(project.TrimapHintPath(photo_name), width, height);
  const fs::path strokes = project.StrokesPath(photo_name);
  if (!strokes.empty()) {
    const StrokeSet set = ReadStrokes(strokes, width, height);
    edits.strokes = set.strokes;
    if (set.root) edits.root = QPointF(set.root->x(), set.root->y());
  }
  edits.crowns = ReadCrowns(project.CrownEditPath(photo_name), width, height);
  return edits;
}

void SavePhotoEdits(const Project& project, const std::string& photo_name, const PhotoEdits& edits,
                    unsigned layers) {
  const PhotoEditFiles files = PhotoEditFiles::Of(project, photo_name);
  std::error_code ec;
  if (layers & kDensityLayer) {
    // An edit of another extension would shadow or be shadowed by ours.
    const fs::path existing = project.DensityEditPath(photo_name);
    WriteOrRemove(edits.density, files.density);
    if (!existing.empty() && existing != files.density) fs::remove(existing, ec);
  }
  if (layers & kTrimapLayer) {
    const fs::path existing = project.TrimapHintPath(photo_name);
    WriteOrRemove(edits.trimap, files.trimap);
    if (!existing.empty() && existing != files.trimap) fs::remove(existing, ec);
  }
  if (layers & kStrokesLayer) {
    const fs::path svg = EditBeside(project, photo_name, ".strokes.svg");
    if (fs::is_regular_file(svg, ec)) fs::rename(svg, fs::path(svg.string() + ".bak"));
    if (edits.strokes.empty()) {
      fs::remove(files.strokes, ec);
    } else {
      StrokeSet set;
      set.width = edits.width;
      set.height = edits.height;
      set.strokes = edits.strokes;
      if (edits.root) set.root = Eigen::Vector2d(edits.root->x(), edits.root->y());
      fs::create_directories(files.strokes.parent_path());
      WriteStrokesJson(files.strokes, set);
    }
  }
  if (layers & kCrownLayer) {
    if (edits.crowns.empty()) {
      fs::remove(files.crown, ec);
    } else {
      fs::create_directories(files.crown.parent_path());
      AtomicWriteString(files.crown, CrownSvg(edits));
    }
  }
}

QRect StrokeMask::AddDab(const QPointF& center, const BrushShape& brush) {
  const double r = std::max(0.5, brush.radius);
  const double inner = std::clamp(brush.hardness, 0.0, 1.0) * r;
  const QRect rect =
      Clipped(center.x() - r, center.y() - r, center.x() + r, center.y() + r, width_, height_);
  for (int y = rect.top(); y <= rect.bottom(); ++y) {
    for (int x = rect.left(); x <= rect.right(); ++x) {
      const double d = std::hypot(x + 0.5 - center.x(), y + 0.5 - center.y());
      if (d >= r) continue;
      double coverage = 1.0;
      if (d > inner) {
        const double t = (d - inner) / (r - inner);
        coverage = 1.0 - t * t * (3.0 - 2.0 * t);  // smoothstep fall-off
      }
      float& value = mask_[static_cast<size_t>(y) * width_ + x];
      value = std::max(value, static_cast<float>(coverage * brush.strength));
    }
  }
  return rect;
}

QRect StrokeMask::AddSegment(const QPointF& from, const QPointF& to, const BrushShape& brush) {
  const QPointF delta = to - from;
  const double length = std::hypot(delta.x(), delta.y());
  const int steps =
      std::max(1, static_cast<int>(std::ceil(length / std::max(0.5, brush.radius / 4))));
  QRect touched;
  for (int i = 0; i <= steps; ++i) touched |= AddDab(from + delta * (double(i) / steps), brush);
  return touched;
}

void ApplyStroke(const PhotoEdits& before, const StrokeMask& mask, BrushMode mode,
                 const QRect& rect, PhotoEdits* edits) {
  const bool density = mode == BrushMode::kDensityAdd || mode == BrushMode::kDensityRemove;
  const bool trimap = !density && mode != BrushMode::kEraser;
  const bool erase = mode == BrushMode::kEraser;
  if ((density || erase) && edits->density.isNull()) {
    edits->density = BlankLayer(edits->width, edits->height, 0);
  }
  if ((trimap || erase) && edits->trimap.isNull()) {
    edits->trimap = BlankLayer(edits->width, edits->height, kTrimapUnpaintedGrey);
  }
  const QImage old_density =
      before.density.isNull() ? BlankLayer(edits->width, edits->height, 0) : before.density;
  const QImage old_trimap = before.trimap.isNull()
                                ? BlankLayer(edits->width, edits->height, kTrimapUnpaintedGrey)
                                : before.trimap;
  const double g = mode == BrushMode::kDensityAdd ? 1.0 : 0.0;
  for (int y = rect.top(); y <= rect.bottom(); ++y) {
    for (int x = rect.left(); x <= rect.right(); ++x) {
      const double a = mask.at(x, y);
      if (density || erase) {
        const uchar* in = old_density.constScanLine(y) + 4 * x;
        uchar* out = edits->density.scanLine(y) + 4 * x;
        const double old_a = in[3] / 255.0, old_g = in[0] / 255.0;
        double new_a = old_a * (1.0 - a), new_g = old_g;
        if (density) {
          new_a = a + old_a * (1.0 - a);
          new_g = new_a > 0 ? (g * a + old_g * old_a * (1.0 - a)) / new_a : old_g;
        }
        const uchar grey = static_cast<uchar>(std::lround(std::clamp(new_g, 0.0, 1.0) * 255));
        out[0] = out[1] = out[2] = grey;
        out[3] = static_cast<uchar>(std::lround(std::clamp(new_a, 0.0, 1.0) * 255));
      }
      if (trimap || erase) {
        const uchar* in = old_trimap.constScanLine(y) + 4 * x;
        uchar* out = edits->trimap.scanLine(y) + 4 * x;
        std::copy(in, in + 4, out);
        if (a < 0.5) continue;
        const bool clear = erase || mode == BrushMode::kTrimapUnknown;
        const uchar grey = clear
                               ? kTrimapUnpaintedGrey
                               : (mode == BrushMode::kTrimapForeground ? kPaintAdd : kPaintRemove);
        out[0] = out[1] = out[2] = grey;
        out[3] = clear ? 0 : 255;
      }
    }
  }
}

bool EraseShapesNear(const QPointF& point, double radius, PhotoEdits* edits) {
  const size_t before = edits->strokes.size() + edits->crowns.size() + (edits->root ? 1 : 0);
  const auto from_eigen = [](const Eigen::Vector2d& p) { return QPointF(p.x(), p.y()); };
  const auto same = [](const QPointF& p) { return p; };
  edits->strokes.erase(std::remove_if(edits->strokes.begin(), edits->strokes.end(),
                                      [&](const Stroke& s) {
                                        return NearPolyline(s.points, from_eigen, point, radius,
                                                            false);
                                      }),
                       edits->strokes.end());
  edits->crowns.erase(std::remove_if(edits->crowns.begin(), edits->crowns.end(),
                                     [&](const std::vector<QPointF>& outline) {
                                       return NearPolyline(outline, same, point, radius, true);
                                     }),
                      edits->crowns.end());
  if (edits->root && DistanceToSegment(point, *edits->root, *edits->root) <= radius) {
    edits->root.reset();
  }
  return edits->strokes.size() + edits->crowns.size() + (edits->root ? 1 : 0) != before;
}

bool IsBlank(const QImage& image) {
  if (image.isNull()) return true;
  for (int y = 0; y < image.height(); ++y) {
    const uchar* row = image.constScanLine(y);
    for (int x = 0; x < image.width(); ++x) {
      if (row[4 * x + 3] != 0) return false;
    }
  }
  return true;
}

}  // namespace sylva
