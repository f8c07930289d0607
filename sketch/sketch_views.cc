#include "sketch/sketch_views.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include "core/geometry/polyline.h"
#include "core/util/check.h"

namespace sylva {
namespace {

// A tree drawn on a 2,000-pixel page is about this far from its camera
// (orthographic: only the order of depths matters), in tree heights.
constexpr double kCameraDistanceHeights = 2.0;
// Stroke ends within this share of the drawn height above the lowest one
// stand on the ground: the trunk (one centre line or two outlines).
constexpr double kGroundShare = 0.1;
// Two strokes standing on the ground are a trunk's outlines if they are
// closer than this share of the drawn height halfway up.
constexpr double kMaxTrunkWidthShare = 0.3;
// Points along a trunk's middle line.
constexpr int kTrunkSamples = 24;
constexpr int kMaxDrawings = 4;

// Where the drawn tree stands and how tall it is, in drawing pixels.
struct DrawnFrame {
  Eigen::Vector2d base;  // the tree base
  double height = 0.0;   // from the base up to the highest stroke point
};

// The lowest point of a stroke.
Eigen::Vector2d Lowest(const SketchStroke& stroke) {
  Eigen::Vector2d low = stroke.points[0];
  for (const Eigen::Vector2d& p : stroke.points) {
    if (p.y() > low.y()) low = p;
  }
  return low;
}

// The stroke's point at `t` in [0, 1] of its length, walked from its lower
// end.
Eigen::Vector2d AlongFromBottom(const SketchStroke& stroke, double t) {
  std::vector<Eigen::Vector2d> points = stroke.points;
  if (points.front().y() < points.back().y()) std::reverse(points.begin(), points.end());
  double length = 0.0;
  for (size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  double left = t * length;
  for (size_t i = 1; i < points.size(); ++i) {
    const double step = (points[i] - points[i - 1]).norm();
    if (left <= step && step > 0.0)
      return points[i - 1] + (left / step) * (points[i] - points[i - 1]);
    left -= step;
  }
  return points.back();
}

// A trunk drawn as two outlines (a doodle's usual trunk): the two branch
// strokes standing on the ground that are closest together halfway up, if
// closer than kMaxTrunkWidthShare of the drawn height, are replaced by their
// middle line with their distance as its width. `ground` receives the
// segment joining their feet, which closes the trunk in the matte, and
// `trunk` the region between them (the wood, opaque in the matte).
bool MergeTrunkOutlines(SketchDrawing* drawing, std::vector<Eigen::Vector2d>* ground,
                        SketchStroke* trunk) {
  double top = drawing->height, bottom = 0.0;
  for (const SketchStroke& stroke : drawing->strokes) {
    for (const Eigen::Vector2d& p : stroke.points) {
      top = std::min(top, p.y());
      if (stroke.role == StrokeRole::kBranch) bottom = std::max(bottom, p.y());
    }
  }
  std::vector<int> standing;
  for (int i = 0; i < static_cast<int>(drawing->strokes.size()); ++i) {
    const SketchStroke& stroke = drawing->strokes[i];
    if (stroke.role == StrokeRole::kBranch && !stroke.closed &&
        Lowest(stroke).y() >= bottom - kGroundShare * (bottom - top)) {
      standing.push_back(i);
    }
  }
  double best = kMaxTrunkWidthShare * (bottom - top);
  int a = -1, b = -1;
  for (size_t i = 0; i < standing.size(); ++i) {
    for (size_t j = i + 1; j < standing.size(); ++j) {
      const double apart = (AlongFromBottom(drawing->strokes[standing[i]], 0.5) -
                            AlongFromBottom(drawing->strokes[standing[j]], 0.5))
                               .norm();
      if (apart < best) {
        best = apart;
        a = standing[i];
        b = standing[j];
      }
    }
  }
  if (a < 0) return false;
  SketchStroke middle;
  double width = 0.0;
  std::vector<Eigen::Vector2d> side_b;
  for (int k = 0; k <= kTrunkSamples; ++k) {
    const double t = static_cast<double>(k) / kTrunkSamples;
    const Eigen::Vector2d pa = AlongFromBottom(drawing->strokes[a], t);
    const Eigen::Vector2d pb = AlongFromBottom(drawing->strokes[b], t);
    middle.points.push_back(0.5 * (pa + pb));
    width += (pa - pb).norm() / (kTrunkSamples + 1);
    trunk->points.push_back(pa);
    side_b.push_back(pb);
  }
  trunk->points.insert(trunk->points.end(), side_b.rbegin(), side_b.rend());
  trunk->closed = true;
  middle.width = width;
  *ground = {AlongFromBottom(drawing->strokes[a], 0.0), AlongFromBottom(drawing->strokes[b], 0.0)};
  drawing->strokes.erase(drawing->strokes.begin() + std::max(a, b));
  drawing->strokes.erase(drawing->strokes.begin() + std::min(a, b));
  drawing->strokes.push_back(std::move(middle));
  return true;
}

DrawnFrame FrameOf(const SketchDrawing& drawing) {
  const bool has_branches = drawing.CountRole(StrokeRole::kBranch) > 0;
  auto stands = [&](const SketchStroke& stroke) {
    return !has_branches || stroke.role == StrokeRole::kBranch;
  };
  double top = drawing.height, bottom = 0.0;
  for (const SketchStroke& stroke : drawing.strokes) {
    for (const Eigen::Vector2d& p : stroke.points) {
      top = std::min(top, p.y());
      if (stands(stroke)) bottom = std::max(bottom, p.y());
    }
  }
  DrawnFrame frame;
  if (drawing.root) {
    frame.base = *drawing.root;
    // A root marked a little below where the strokes end (the ground under
    // the trunk) is lifted onto that line: the tree's density starts at the
    // strokes, and a base below it is outside the tree.
    if (frame.base.y() > bottom && frame.base.y() - bottom <= kGroundShare * (bottom - top)) {
      frame.base.y() = bottom;
    }
  } else {
    // The mean over the strokes that reach the ground of the middle of
    // their points there: a trunk's centre line ends there, two outlines
    // have the trunk between them, an outline closed at its foot has the
    // trunk above the middle of its foot.
    const double ground = bottom - kGroundShare * (bottom - top);
    double sum_x = 0.0;
    int count = 0;
    for (const SketchStroke& stroke : drawing.strokes) {
      if (!stands(stroke)) continue;
      double min_x = std::numeric_limits<double>::infinity(), max_x = -min_x;
      for (const Eigen::Vector2d& p : stroke.points) {
        if (p.y() < ground) continue;
        min_x = std::min(min_x, p.x());
        max_x = std::max(max_x, p.x());
      }
      if (min_x > max_x) continue;
      sum_x += 0.5 * (min_x + max_x);
      ++count;
    }
    frame.base = Eigen::Vector2d(sum_x / count, bottom);
  }
  frame.height = frame.base.y() - top;
  SYLVA_CHECK_INPUT(frame.height > 0.0, drawing.source)
      << "the drawing has no height: nothing is drawn above the tree base";
  return frame;
}

// cam_from_world of an orthographic view from azimuth `degrees` (0: looking
// along +y, 90: along -x; z up), placing the world origin at `base_px` of
// a camera of `camera`'s intrinsics.
Rigid3d PoseAt(double degrees, const Camera& camera, const Eigen::Vector2d& base_px,
               double distance) {
  const double a = degrees * M_PI / 180.0;
  const Eigen::Vector3d forward(-std::sin(a), std::cos(a), 0.0);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d rotation;
  rotation.row(0) = forward.cross(up).transpose();
  rotation.row(1) = -up.transpose();
  rotation.row(2) = forward.transpose();
  const std::vector<double>& p = camera.params();  // fx, fy, cx, cy
  const Eigen::Vector3d translation((base_px.x() - p[2]) / p[0], (base_px.y() - p[3]) / p[1],
                                    distance);
  return Rigid3d(Eigen::Quaterniond(rotation), translation);
}

// OpenCV drawing coordinates of a stroke at `scale` render pixels per drawing
// pixel, with kCvShift fractional bits: OpenCV puts pixel centres at whole
// coordinates, sylva at halves.
constexpr int kCvShift = 4;
std::vector<cv::Point> CvPoints(const SketchStroke& stroke, double scale) {
  std::vector<cv::Point> points;
  for (const Eigen::Vector2d& p : stroke.points) {
    points.emplace_back(static_cast<int>(std::lround((1 << kCvShift) * (scale * p.x() - 0.5))),
                        static_cast<int>(std::lround((1 << kCvShift) * (scale * p.y() - 0.5))));
  }
  return points;
}

// The drawing's lines at `scale` render pixels per drawing pixel, in an
// 8-bit coverage image (anti-aliased).
cv::Mat DrawLines(const SketchDrawing& drawing, double scale, const cv::Size& size,
                  const SketchViewOptions& options) {
  cv::Mat lines = cv::Mat::zeros(size, CV_8U);
  const double default_width = options.line_width * options.image_size;
  for (const SketchStroke& stroke : drawing.strokes) {
    const std::vector<cv::Point> points = CvPoints(stroke, scale);
    const double width = stroke.width > 0.0 ? stroke.width * scale : default_width;
    const int thickness = std::max(1, static_cast<int>(std::lround(width)));
    cv::polylines(lines, std::vector<std::vector<cv::Point>>{points}, stroke.closed,
                  cv::Scalar(255), thickness, cv::LINE_AA, kCvShift);
  }
  return lines;
}

// The regions `lines` enclose (after closing gaps narrower than `gap`
// pixels): 255 inside, 0 where the page's border can be reached.
cv::Mat EnclosedRegions(const cv::Mat& lines, int gap) {
  cv::Mat walls;
  cv::threshold(lines, walls, 0, 255, cv::THRESH_BINARY);
  if (gap > 1) {
    const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(gap, gap));
    cv::morphologyEx(walls, walls, cv::MORPH_CLOSE, disc);
  }
  // A one-pixel frame of background lets the fill start outside every stroke.
  cv::Mat padded;
  cv::copyMakeBorder(walls, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::floodFill(padded, cv::Point(0, 0), cv::Scalar(128));
  cv::Mat enclosed;
  cv::compare(padded(cv::Rect(1, 1, lines.cols, lines.rows)), 128, enclosed, cv::CMP_NE);
  return enclosed;
}

// Sets `mask` (CV_8U) to 255 inside the polygon of `stroke` at `scale`,
// closed by the chord from its end to its start; strokes of fewer than 3
// points enclose nothing.
void FillPolygon(const SketchStroke& stroke, double scale, cv::Mat* mask) {
  if (stroke.points.size() < 3) return;
  cv::fillPoly(*mask, std::vector<std::vector<cv::Point>>{CvPoints(stroke, scale)}, cv::Scalar(255),
               cv::LINE_8, kCvShift);
}

// Adds to `enclosed` the polygon of every crown stroke: a crown outline left
// open (where the trunk enters, or a doodle's gap) still covers the crown.
void FillCrownStrokes(const SketchDrawing& drawing, double scale, cv::Mat* enclosed) {
  for (const SketchStroke& stroke : drawing.strokes) {
    if (stroke.role == StrokeRole::kCrown) FillPolygon(stroke, scale, enclosed);
  }
}

FloatImage MatteFrom(const cv::Mat& lines, const cv::Mat& enclosed, double crown_opacity) {
  FloatImage matte(lines.cols, lines.rows, 1);
  for (int y = 0; y < lines.rows; ++y) {
    for (int x = 0; x < lines.cols; ++x) {
      const float line = lines.at<uchar>(y, x) / 255.0f;
      const float inside = enclosed.at<uchar>(y, x) ? static_cast<float>(crown_opacity) : 0.0f;
      matte.at(x, y) = std::max(line, inside);
    }
  }
  return matte;
}

// Sets the matte to 1 inside the polygon of `stroke` (if any).
void FillOpaque(const SketchStroke& stroke, double scale, FloatImage* matte) {
  cv::Mat inside = cv::Mat::zeros(matte->height(), matte->width(), CV_8U);
  FillPolygon(stroke, scale, &inside);
  for (int y = 0; y < matte->height(); ++y) {
    for (int x = 0; x < matte->width(); ++x) {
      if (inside.at<uchar>(y, x)) matte->at(x, y) = 1.0f;
    }
  }
}

// Black where the matte is opaque, on white.
FloatImage PhotoFrom(const FloatImage& matte) {
  FloatImage photo(matte.width(), matte.height(), 3);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      for (int c = 0; c < 3; ++c) photo.at(x, y, c) = 1.0f - matte.at(x, y);
    }
  }
  return photo;
}

// The matte made symmetric about the vertical line x = axis: at each pixel,
// the larger of the values at the same distance on either side.
FloatImage SymmetricAbout(const FloatImage& matte, double axis) {
  FloatImage symmetric(matte.width(), matte.height(), 1);
  auto value = [&](double x, int y) {
    const int i = static_cast<int>(std::floor(x));
    return i >= 0 && i < matte.width() ? matte.at(i, y) : 0.0f;
  };
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      const double r = x + 0.5 - axis;
      symmetric.at(x, y) = std::max(value(axis + r, y), value(axis - r, y));
    }
  }
  return symmetric;
}

StrokeSet BranchStrokes(const SketchDrawing& drawing, double scale, const cv::Size& size,
                        const Eigen::Vector2d& base) {
  StrokeSet strokes;
  strokes.width = size.width;
  strokes.height = size.height;
  for (const SketchStroke& drawn : drawing.strokes) {
    if (drawn.role != StrokeRole::kBranch) continue;
    Stroke stroke;
    for (const Eigen::Vector2d& p : drawn.points) {
      const Eigen::Vector2d q = scale * p;
      if (stroke.points.empty() || (q - stroke.points.back()).norm() > 1e-6) {
        stroke.points.push_back(q);
      }
    }
    if (stroke.points.size() >= 2) strokes.strokes.push_back(std::move(stroke));
  }
  strokes.root = scale * base;
  return strokes;
}

// The point where the drawn trunk ends: the top end of the branch stroke
// that starts nearest the base (in view pixels).
Eigen::Vector2d TrunkTop(const StrokeSet& strokes) {
  const Stroke* trunk = nullptr;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Stroke& stroke : strokes.strokes) {
    for (const Eigen::Vector2d& end : {stroke.points.front(), stroke.points.back()}) {
      const double d = (end - *strokes.root).norm();
      if (d < nearest) {
        nearest = d;
        trunk = &stroke;
      }
    }
  }
  const Eigen::Vector2d& a = trunk->points.front();
  const Eigen::Vector2d& b = trunk->points.back();
  return a.y() < b.y() ? a : b;
}

// The outline of the largest region the matte fills (its enclosed regions),
// in OpenCV pixel coordinates; empty if there is none.
std::vector<cv::Point> CrownOutline(const FloatImage& matte, double crown_opacity) {
  cv::Mat filled(matte.height(), matte.width(), CV_8U);
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      filled.at<uchar>(y, x) = matte.at(x, y) >= 0.5 * crown_opacity ? 255 : 0;
    }
  }
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(filled, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  std::vector<cv::Point> largest;
  double largest_area = 0.0;
  for (const std::vector<cv::Point>& contour : contours) {
    const double area = cv::contourArea(contour);
    if (area > largest_area) {
      largest_area = area;
      largest = contour;
    }
  }
  return largest;
}

// A cubic Hermite curve from p0 (tangent m0) to p1 (tangent m1).
Stroke HermiteStroke(const Eigen::Vector2d& p0, const Eigen::Vector2d& m0,
                     const Eigen::Vector2d& p1, const Eigen::Vector2d& m1) {
  constexpr int kSamples = 12;
  return Stroke{HermiteCurve(p0, m0, p1, m1, kSamples)};
}

}  // namespace

std::vector<Stroke> InferMajorBranches(const FloatImage& matte, const SketchViewOptions& options,
                                       const Eigen::Vector2d& trunk_top) {
  const std::vector<cv::Point> outline = CrownOutline(matte, options.crown_opacity);
  if (outline.size() < 8) return {};
  const cv::Rect box = cv::boundingRect(outline);
  const double crown_size = std::max(box.width, box.height);
  // A bump whose apex is nearer the trunk's top than this share of the
  // crown's size is a ripple of the outline, not a branch's end.
  constexpr double kMinApexShare = 0.1;
  // Hermite tangents, in branch lengths: the branch leaves the trunk
  // upwards and arrives along the direction to the apex.
  constexpr double kTangentLengths = 0.8;
  std::vector<int> hull;
  cv::convexHull(outline, hull, /*clockwise=*/false, /*returnPoints=*/false);
  std::vector<int> valleys;
  if (hull.size() >= 3) {
    std::sort(hull.begin(), hull.end());
    std::vector<cv::Vec4i> defects;
    cv::convexityDefects(outline, hull, defects);
    for (const cv::Vec4i& defect : defects) {
      if (defect[3] / 256.0 > options.valley_depth * crown_size) {
        valleys.push_back(defect[2]);
      }
    }
  }
  std::sort(valleys.begin(), valleys.end());
  const int n = static_cast<int>(outline.size());
  if (valleys.empty()) valleys.push_back(0);
  // Bumps whose apex is not above the trunk's top (the crown's underside,
  // the trunk's own outline) carry no major branch.
  const Eigen::Vector2d top = trunk_top - Eigen::Vector2d(0.5, 0.5);  // OpenCV pixels
  std::vector<Stroke> branches;
  for (size_t k = 0; k < valleys.size(); ++k) {
    const int begin = valleys[k];
    const int end = k + 1 < valleys.size() ? valleys[k + 1] : valleys[0] + n;
    Eigen::Vector2d apex = top;
    double farthest = 0.0;
    for (int i = begin; i < end; ++i) {
      const cv::Point& p = outline[i % n];
      const Eigen::Vector2d q(p.x, p.y);
      if (q.y() >= top.y()) continue;
      const double d = (q - top).norm();
      if (d > farthest) {
        farthest = d;
        apex = q;
      }
    }
    if (farthest < kMinApexShare * crown_size) continue;
    const Eigen::Vector2d tip = top + options.branch_reach * (apex - top);
    const double length = (tip - top).norm();
    Stroke branch = HermiteStroke(top, Eigen::Vector2d(0, -kTangentLengths * length), tip,
                                  kTangentLengths * length * (apex - top).normalized());
    for (Eigen::Vector2d& p : branch.points) p += Eigen::Vector2d(0.5, 0.5);
    branches.push_back(std::move(branch));
  }
  return branches;
}

namespace {

// Adds the major branches InferMajorBranches finds in the view's matte to
// its strokes when the drawing gives no branch but the trunk.
void AddInferredBranches(const SketchViewOptions& options, SketchView* view) {
  if (view->strokes.strokes.size() > 1 || !view->strokes.root) return;
  const Eigen::Vector2d top =
      view->strokes.strokes.empty() ? *view->strokes.root : TrunkTop(view->strokes);
  for (Stroke& branch : InferMajorBranches(view->matte, options, top)) {
    view->strokes.strokes.push_back(std::move(branch));
  }
}

}  // namespace

std::vector<Eigen::Vector2d> CrownOutlineOf(const FloatImage& matte, double crown_opacity) {
  std::vector<Eigen::Vector2d> outline;
  for (const cv::Point& p : CrownOutline(matte, crown_opacity))
    outline.emplace_back(p.x + 0.5, p.y + 0.5);
  return outline;
}

FloatImage OutlinedRegions(const SketchDrawing& drawing, int width, int height) {
  SYLVA_CHECK(width > 0 && height > 0);
  cv::Mat inside = cv::Mat::zeros(height, width, CV_8U);
  const Eigen::Vector2d scale(width / drawing.width, height / drawing.height);
  for (const SketchStroke& stroke : drawing.strokes) {
    SketchStroke stretched = stroke;
    for (Eigen::Vector2d& p : stretched.points) p = p.cwiseProduct(scale);
    FillPolygon(stretched, 1.0, &inside);
  }
  FloatImage regions(width, height, 1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) regions.at(x, y) = inside.at<uchar>(y, x) ? 1.0f : 0.0f;
  }
  return regions;
}

// The depth prior of a single drawing: a crown of revolution seen from the
// side, a virtual view at right angles whose tree base is `base` (view
// pixels).
void AddDepthPrior(const SketchViewOptions& options, const Eigen::Vector2d& base, double distance,
                   SketchViews* result) {
  const SketchView& front = result->views[0];
  const Camera& camera = result->cameras.cameras.at(1);
  SketchView side;
  side.name = std::filesystem::path(front.name).stem().string() + ".depth.png";
  side.matte = SymmetricAbout(front.matte, base.x());
  side.photo = PhotoFrom(side.matte);
  side.is_virtual = true;
  // The trunk up the axis to the front's trunk top, then the major
  // branches of the symmetric crown.
  side.strokes.width = front.strokes.width;
  side.strokes.height = front.strokes.height;
  side.strokes.root = base;
  const Eigen::Vector2d top(base.x(),
                            front.strokes.strokes.empty() ? base.y() : TrunkTop(front.strokes).y());
  if (base.y() - top.y() > 1.0) side.strokes.strokes.push_back({{base, top}});
  for (Stroke& branch : InferMajorBranches(side.matte, options, top)) {
    side.strokes.strokes.push_back(std::move(branch));
  }
  result->cameras.cameras.emplace(2, camera);
  result->cameras.views.push_back({2, side.name, 2, PoseAt(90.0, camera, base, distance)});
  result->views.push_back(std::move(side));
}

SketchViews MakeSketchViews(const std::vector<SketchDrawing>& drawings,
                            const SketchViewOptions& options) {
  options.Check();
  SYLVA_CHECK_INPUT(!drawings.empty() && drawings.size() <= kMaxDrawings, "drawings")
      << "a sketch has 1 to " << kMaxDrawings << " drawings (front, side, back, other side), got "
      << drawings.size();
  SketchViews result;
  std::set<std::string> names;
  Eigen::Vector2d first_base;  // the first view's tree base, in its pixels
  const double distance = kCameraDistanceHeights * options.tree_height;
  for (size_t i = 0; i < drawings.size(); ++i) {
    const SketchDrawing& drawing = drawings[i];
    drawing.Check();
    // What the strokes stand for (the attractors, the base) and what the
    // drawing covers (the matte): a trunk's outlines are closed at its foot.
    SketchDrawing interpreted = drawing;
    SketchDrawing outlined = drawing;
    SketchStroke foot, trunk;
    if (MergeTrunkOutlines(&interpreted, &foot.points, &trunk)) outlined.strokes.push_back(foot);
    const DrawnFrame frame = FrameOf(interpreted);
    const double scale = options.image_size / std::max(drawing.width, drawing.height);
    const cv::Size size(std::max(1, static_cast<int>(std::lround(scale * drawing.width))),
                        std::max(1, static_cast<int>(std::lround(scale * drawing.height))));
    const double world_per_pixel = options.tree_height / frame.height;  // drawing pixels

    SketchView view;
    view.name = std::filesystem::path(drawing.source).stem().string() + ".png";
    SYLVA_CHECK_INPUT(names.insert(view.name).second, drawing.source)
        << "two drawings would both be the view '" << view.name << "': rename one";
    const cv::Mat lines = DrawLines(outlined, scale, size, options);
    const int gap = static_cast<int>(std::lround(options.gap_closing * options.image_size));
    cv::Mat enclosed = EnclosedRegions(lines, gap);
    FillCrownStrokes(outlined, scale, &enclosed);
    view.matte = MatteFrom(lines, enclosed, options.crown_opacity);
    FillOpaque(trunk, scale, &view.matte);
    view.photo = PhotoFrom(view.matte);
    view.strokes = BranchStrokes(interpreted, scale, size, frame.base);
    AddInferredBranches(options, &view);

    const double azimuth = 90.0 * i;
    const Camera camera = Camera::Orthographic(size.width, size.height, scale / world_per_pixel);
    const int id = static_cast<int>(i) + 1;
    result.cameras.cameras.emplace(id, camera);
    result.cameras.views.push_back(
        {id, view.name, id, PoseAt(azimuth, camera, scale * frame.base, distance)});
    const Camera canvas =
        Camera::Orthographic(static_cast<int>(std::lround(drawing.width)),
                             static_cast<int>(std::lround(drawing.height)), 1.0 / world_per_pixel);
    result.drawing_cameras.cameras.emplace(id, canvas);
    result.drawing_cameras.views.push_back(
        {id, view.name, id, PoseAt(azimuth, canvas, frame.base, distance)});
    result.bases.push_back(frame.base);
    if (i == 0) first_base = scale * frame.base;
    result.views.push_back(std::move(view));
  }
  if (drawings.size() == 1) AddDepthPrior(options, first_base, distance, &result);
  return result;
}

}  // namespace sylva
