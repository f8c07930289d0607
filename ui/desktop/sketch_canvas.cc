#include "ui/desktop/sketch_canvas.h"

#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <cmath>

#include "sketch/drawing_io.h"

namespace sylva {
namespace {

// The blank page, in canvas pixels (portrait, as most tree drawings).
constexpr double kDefaultCanvasWidth = 400;
constexpr double kDefaultCanvasHeight = 600;
// Freehand points closer than this (canvas pixels) are merged.
constexpr double kMinPointSpacing = 1.5;
// A crown stroke whose end is within this fraction of its length of its
// start is a closed outline.
constexpr double kCloseFraction = 0.2;
constexpr int kMarginPixels = 8;

const QColor kBranchColor(107, 66, 38);
const QColor kCrownColor(46, 139, 58);

Eigen::Vector2d ToEigen(const QPointF& p) { return {p.x(), p.y()}; }

QPainterPath StrokePath(const std::vector<Eigen::Vector2d>& points, bool closed) {
  QPainterPath path;
  if (points.empty()) return path;
  path.moveTo(points[0].x(), points[0].y());
  for (size_t i = 1; i < points.size(); ++i) path.lineTo(points[i].x(), points[i].y());
  if (closed) path.closeSubpath();
  return path;
}

}  // namespace

SketchCanvas::SketchCanvas(QWidget* parent) : QWidget(parent) {
  setMinimumSize(200, 250);
  setCursor(Qt::CrossCursor);
  Clear();
}

void SketchCanvas::SetDrawing(const SketchDrawing& drawing) {
  drawing_ = drawing;
  drawing_stroke_ = false;
  live_points_.clear();
  UpdateTransform();
  update();
  emit Changed();
}

void SketchCanvas::UndoLastStroke() {
  if (drawing_.strokes.empty()) return;
  drawing_.strokes.pop_back();
  update();
  emit Changed();
}

void SketchCanvas::Clear() {
  SketchDrawing blank;
  blank.source = "sketch canvas";
  blank.width = kDefaultCanvasWidth;
  blank.height = kDefaultCanvasHeight;
  SetDrawing(blank);
}

void SketchCanvas::OpenSvg(const std::filesystem::path& path) { SetDrawing(ReadSketchSvg(path)); }

void SketchCanvas::SaveSvg(const std::filesystem::path& path) const {
  SketchDrawing drawing = drawing_;
  drawing.source = path.string();  // named by Check()'s errors
  WriteSketchSvg(path, drawing);
}

void SketchCanvas::UpdateTransform() {
  const double scale = std::max(1e-3, std::min((width() - 2.0 * kMarginPixels) / drawing_.width,
                                               (height() - 2.0 * kMarginPixels) / drawing_.height));
  const double dx = 0.5 * (width() - scale * drawing_.width);
  const double dy = 0.5 * (height() - scale * drawing_.height);
  widget_from_canvas_ = QTransform(scale, 0, 0, scale, dx, dy);
}

QPointF SketchCanvas::ToCanvas(const QPointF& widget_point) const {
  return widget_from_canvas_.inverted().map(widget_point);
}

void SketchCanvas::resizeEvent(QResizeEvent* event) {
  QWidget::resizeEvent(event);
  UpdateTransform();
}

void SketchCanvas::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.fillRect(rect(), QColor(48, 48, 52));
  painter.setRenderHint(QPainter::Antialiasing);
  painter.setTransform(widget_from_canvas_);
  painter.fillRect(QRectF(0, 0, drawing_.width, drawing_.height), Qt::white);
  for (const SketchStroke& stroke : drawing_.strokes) {
    QPen pen(stroke.role == StrokeRole::kCrown ? kCrownColor : kBranchColor,
             std::max(1.0, stroke.width));
    pen.setCapStyle(Qt::RoundCap);
    pen.setJoinStyle(Qt::RoundJoin);
    painter.setPen(pen);
    painter.drawPath(StrokePath(stroke.points, stroke.closed));
  }
  if (drawing_.root) {
    painter.setPen(Qt::NoPen);
    painter.setBrush(QColor(192, 48, 48));
    painter.drawEllipse(QPointF(drawing_.root->x(), drawing_.root->y()), 4, 4);
  }
  if (live_points_.size() >= 2) {
    painter.setPen(QPen(role_ == StrokeRole::kCrown ? kCrownColor : kBranchColor, stroke_width_,
                        Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
    painter.drawPolyline(live_points_.data(), static_cast<int>(live_points_.size()));
  }
}

void SketchCanvas::mousePressEvent(QMouseEvent* event) {
  if (event->button() != Qt::LeftButton) return;
  const QPointF point = ToCanvas(event->position());
  if (event->modifiers() & Qt::ShiftModifier) {
    drawing_.root = ToEigen(point);
    update();
    emit Changed();
    return;
  }
  drawing_stroke_ = true;
  live_points_ = {point};
}

void SketchCanvas::mouseMoveEvent(QMouseEvent* event) {
  if (!drawing_stroke_) return;
  const QPointF point = ToCanvas(event->position());
  const QPointF d = point - live_points_.back();
  if (std::hypot(d.x(), d.y()) < kMinPointSpacing) return;
  live_points_.push_back(point);
  update();
}

void SketchCanvas::mouseReleaseEvent(QMouseEvent* event) {
  if (!drawing_stroke_ || event->button() != Qt::LeftButton) return;
  mouseMoveEvent(event);
  FinishStroke();
}

void SketchCanvas::FinishStroke() {
  drawing_stroke_ = false;
  std::vector<QPointF> points;
  points.swap(live_points_);
  update();
  if (points.size() < 2) return;
  SketchStroke stroke;
  stroke.role = role_;
  stroke.width = stroke_width_;
  double length = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    stroke.points.push_back(ToEigen(points[i]));
    if (i > 0) length += (stroke.points[i] - stroke.points[i - 1]).norm();
  }
  const double gap = (stroke.points.back() - stroke.points.front()).norm();
  if (role_ == StrokeRole::kCrown && points.size() >= 4 && gap <= kCloseFraction * length) {
    stroke.closed = true;
    if (gap < kMinPointSpacing) stroke.points.pop_back();  // not repeated when closed
  }
  drawing_.strokes.push_back(stroke);
  emit Changed();
}

}  // namespace sylva
