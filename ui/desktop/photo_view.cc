#include "ui/desktop/photo_view.h"

#include <QGraphicsEllipseItem>
#include <QGraphicsPathItem>
#include <QGraphicsPixmapItem>
#include <QGraphicsScene>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QPen>
#include <QScrollBar>
#include <QWheelEvent>
#include <cmath>
#include <map>

#include "ui/desktop/edit_document.h"

namespace sylva {
namespace {

// Colours of the edit layers: painted density in green (add) or red
// (remove), trimap hints in yellow (foreground) or blue (background).
constexpr QRgb kAddColor = qRgb(40, 230, 70);
constexpr QRgb kRemoveColor = qRgb(240, 40, 40);
constexpr QRgb kForegroundColor = qRgb(255, 230, 0);
constexpr QRgb kBackgroundColor = qRgb(30, 80, 255);
constexpr double kLayerOpacity = 0.6;
// Freehand points closer than this (photo pixels) are merged.
constexpr double kMinPointSpacing = 1.5;

QRgb Tinted(QRgb color, double alpha) {
  return qRgba(qRed(color), qGreen(color), qBlue(color),
               static_cast<int>(std::lround(255 * kLayerOpacity * alpha)));
}

// The picture of a density or trimap layer within `rect`.
void PaintLayerPicture(const QImage& layer, bool density, const QRect& rect, QImage* picture) {
  for (int y = rect.top(); y <= rect.bottom(); ++y) {
    const uchar* in = layer.constScanLine(y);
    QRgb* out = reinterpret_cast<QRgb*>(picture->scanLine(y));
    for (int x = rect.left(); x <= rect.right(); ++x) {
      const uchar grey = in[4 * x], alpha = in[4 * x + 3];
      const QRgb color = density ? (grey >= 128 ? kAddColor : kRemoveColor)
                                 : (grey >= 128 ? kForegroundColor : kBackgroundColor);
      out[x] = alpha ? Tinted(color, alpha / 255.0) : 0;
    }
  }
}

QPainterPath PolylinePath(const std::vector<QPointF>& points, bool closed) {
  QPainterPath path;
  if (points.empty()) return path;
  path.moveTo(points[0]);
  for (size_t i = 1; i < points.size(); ++i) path.lineTo(points[i]);
  if (closed) path.closeSubpath();
  return path;
}

QPen CosmeticPen(QColor color, double width) {
  QPen pen(color, width);
  pen.setCosmetic(true);
  pen.setCapStyle(Qt::RoundCap);
  pen.setJoinStyle(Qt::RoundJoin);
  return pen;
}

}  // namespace

PhotoView::PhotoView(QWidget* parent) : QGraphicsView(parent) {
  setScene(new QGraphicsScene(this));
  setBackgroundBrush(QColor(48, 48, 52));
  setTransformationAnchor(QGraphicsView::AnchorUnderMouse);
  setMouseTracking(true);
  setFocusPolicy(Qt::StrongFocus);  // Enter, Backspace and Escape for polylines
  photo_item_ = scene()->addPixmap(QPixmap());
  for (auto& item : overlay_items_) {
    item = scene()->addPixmap(QPixmap());
    item->setTransformationMode(Qt::SmoothTransformation);
  }
  attractor_item_ = scene()->addPath(QPainterPath(), CosmeticPen(QColor(255, 200, 0), 1.5));
  density_item_ = scene()->addPixmap(QPixmap());
  trimap_item_ = scene()->addPixmap(QPixmap());
  strokes_item_ = scene()->addPath(QPainterPath(), CosmeticPen(QColor(255, 120, 20), 2.5));
  crowns_item_ = scene()->addPath(QPainterPath(), CosmeticPen(QColor(60, 220, 90), 2.0));
  live_item_ = scene()->addPath(QPainterPath(), CosmeticPen(QColor(255, 255, 255), 1.5));
  cursor_item_ = scene()->addEllipse(QRectF(), CosmeticPen(QColor(255, 255, 255), 1.0));
  cursor_item_->setVisible(false);
  // Overlays above the photo, edits above the overlays, in that order.
  double z = 1;
  for (auto* item : overlay_items_) item->setZValue(z++);
  for (QGraphicsItem* item : std::initializer_list<QGraphicsItem*>{
           attractor_item_, density_item_, trimap_item_, strokes_item_, crowns_item_, live_item_,
           cursor_item_}) {
    item->setZValue(z++);
  }
}

PhotoView::~PhotoView() = default;

void PhotoView::SetPhoto(EditDocument* document, const std::string& photo_name,
                         const QImage& photo) {
  DropStroke();
  document_ = document;
  photo_name_ = photo_name;
  photo_item_->setPixmap(QPixmap::fromImage(photo));
  scene()->setSceneRect(QRectF(0, 0, photo.width(), photo.height()));
  for (auto* item : overlay_items_) item->setPixmap(QPixmap());
  attractor_item_->setPath(QPainterPath());
  RefreshEdits();
  FitPhoto();
}

void PhotoView::SetOverlayImage(Overlay overlay, const QImage& image) {
  if (overlay == Overlay::kAttractors) return;
  QGraphicsPixmapItem* item = overlay_items_[static_cast<int>(overlay)];
  item->setPixmap(QPixmap::fromImage(image));
  const QRectF rect = scene()->sceneRect();
  item->setTransform(image.isNull() ? QTransform()
                                    : QTransform::fromScale(rect.width() / image.width(),
                                                            rect.height() / image.height()));
}

void PhotoView::SetAttractorPath(const QPainterPath& path) { attractor_item_->setPath(path); }

void PhotoView::SetOverlayVisible(Overlay overlay, bool visible) {
  if (overlay == Overlay::kAttractors) {
    attractor_item_->setVisible(visible);
  } else {
    overlay_items_[static_cast<int>(overlay)]->setVisible(visible);
  }
}

void PhotoView::SetEditsVisible(bool visible) {
  for (QGraphicsItem* item : std::initializer_list<QGraphicsItem*>{density_item_, trimap_item_,
                                                                   strokes_item_, crowns_item_}) {
    item->setVisible(visible);
  }
}

void PhotoView::SetTool(Tool tool) {
  if (tool != tool_) DropStroke();
  tool_ = tool;
  cursor_item_->setVisible(false);
  setCursor(tool == Tool::kNavigate ? Qt::OpenHandCursor : Qt::CrossCursor);
}

void PhotoView::RefreshEdits() {
  if (document_ == nullptr || stroking_) return;
  const QRectF rect = scene()->sceneRect();
  working_ = document_->Edits(photo_name_, static_cast<int>(rect.width()),
                              static_cast<int>(rect.height()));
  density_picture_ = QImage(working_.width, working_.height, QImage::Format_ARGB32);
  trimap_picture_ = QImage(working_.width, working_.height, QImage::Format_ARGB32);
  density_picture_.fill(0);
  trimap_picture_.fill(0);
  UpdateLayerPictures(QRect(0, 0, working_.width, working_.height));
  UpdateShapes();
}

void PhotoView::FitPhoto() {
  if (!scene()->sceneRect().isEmpty()) fitInView(scene()->sceneRect(), Qt::KeepAspectRatio);
}

void PhotoView::UpdateLayerPictures(const QRect& rect) {
  if (!working_.density.isNull())
    PaintLayerPicture(working_.density, true, rect, &density_picture_);
  if (!working_.trimap.isNull()) PaintLayerPicture(working_.trimap, false, rect, &trimap_picture_);
  density_item_->setPixmap(QPixmap::fromImage(density_picture_));
  trimap_item_->setPixmap(QPixmap::fromImage(trimap_picture_));
}

void PhotoView::UpdateShapes() {
  QPainterPath strokes;
  for (const Stroke& stroke : working_.strokes) {
    std::vector<QPointF> points;
    for (const auto& p : stroke.points) points.emplace_back(p.x(), p.y());
    strokes.addPath(PolylinePath(points, false));
  }
  if (working_.root) strokes.addEllipse(*working_.root, 4, 4);
  strokes_item_->setPath(strokes);
  QPainterPath crowns;
  for (const auto& outline : working_.crowns) crowns.addPath(PolylinePath(outline, true));
  crowns_item_->setPath(crowns);
}

bool PhotoView::IsBrush() const {
  return tool_ != Tool::kNavigate && tool_ != Tool::kStrokes && tool_ != Tool::kPolyline &&
         tool_ != Tool::kCrown;
}

void PhotoView::UpdateCursor(const QPointF& point) {
  const bool show = IsBrush();
  cursor_item_->setVisible(show);
  if (show) {
    const double r = brush_.radius;
    cursor_item_->setRect(QRectF(point.x() - r, point.y() - r, 2 * r, 2 * r));
  }
}

void PhotoView::BeginStroke(const QPointF& point) {
  stroking_ = true;
  before_ = working_;
  mask_ = std::make_unique<StrokeMask>(working_.width, working_.height);
  live_points_ = {point};
  last_point_ = point;
  erased_shapes_ = false;
  ContinueStroke(point);
}

void PhotoView::ContinueStroke(const QPointF& point) {
  if (tool_ == Tool::kStrokes || tool_ == Tool::kCrown) {
    const QPointF d = point - live_points_.back();
    if (std::hypot(d.x(), d.y()) >= kMinPointSpacing) live_points_.push_back(point);
    live_item_->setPath(PolylinePath(live_points_, tool_ == Tool::kCrown));
    return;
  }
  static const std::map<Tool, BrushMode> kModes = {
      {Tool::kDensityAdd, BrushMode::kDensityAdd},
      {Tool::kDensityRemove, BrushMode::kDensityRemove},
      {Tool::kTrimapForeground, BrushMode::kTrimapForeground},
      {Tool::kTrimapBackground, BrushMode::kTrimapBackground},
      {Tool::kTrimapUnknown, BrushMode::kTrimapUnknown},
      {Tool::kEraser, BrushMode::kEraser}};
  const QRect rect = mask_->AddSegment(last_point_, point, brush_);
  last_point_ = point;
  if (rect.isEmpty()) return;
  ApplyStroke(before_, *mask_, kModes.at(tool_), rect, &working_);
  if (tool_ == Tool::kEraser && EraseShapesNear(point, brush_.radius, &working_)) {
    erased_shapes_ = true;
    UpdateShapes();
  }
  UpdateLayerPictures(rect);
}

void PhotoView::EndStroke() {
  stroking_ = false;
  live_item_->setPath(QPainterPath());
  unsigned layers = 0;
  QString text;
  switch (tool_) {
    case Tool::kDensityAdd:
    case Tool::kDensityRemove:
      layers = kDensityLayer;
      text = tool_ == Tool::kDensityAdd ? "Paint density in" : "Paint density out";
      break;
    case Tool::kTrimapForeground:
    case Tool::kTrimapBackground:
    case Tool::kTrimapUnknown:
      layers = kTrimapLayer;
      text = "Paint trimap hint";
      break;
    case Tool::kEraser:
      layers = kDensityLayer | kTrimapLayer | (erased_shapes_ ? kStrokesLayer | kCrownLayer : 0);
      text = "Erase";
      break;
    case Tool::kStrokes:
    case Tool::kPolyline:
    case Tool::kCrown: {
      std::vector<QPointF> points = live_points_;
      live_points_.clear();
      if (points.size() < (tool_ == Tool::kCrown ? 3u : 2u)) return;
      if (tool_ == Tool::kCrown) {
        working_.crowns.push_back(points);
        layers = kCrownLayer;
        text = "Draw crown outline";
      } else {
        Stroke stroke;
        for (const QPointF& p : points) stroke.points.emplace_back(p.x(), p.y());
        working_.strokes.push_back(stroke);
        layers = kStrokesLayer;
        text = tool_ == Tool::kPolyline ? "Draw branch polyline" : "Draw branch stroke";
      }
      break;
    }
    case Tool::kNavigate:
      return;
  }
  mask_.reset();
  document_->Commit(photo_name_, before_, working_, layers, text);
}

void PhotoView::mousePressEvent(QMouseEvent* event) {
  const QPointF point = mapToScene(event->position().toPoint());
  const bool pan = event->button() == Qt::MiddleButton ||
                   (event->button() == Qt::LeftButton && tool_ == Tool::kNavigate);
  if (pan) {
    panning_ = true;
    pan_origin_ = event->position().toPoint();
    viewport()->setCursor(Qt::ClosedHandCursor);
    event->accept();
    return;
  }
  if (event->button() != Qt::LeftButton || document_ == nullptr || !HasPhoto()) {
    QGraphicsView::mousePressEvent(event);
    return;
  }
  const bool strokes = tool_ == Tool::kStrokes || tool_ == Tool::kPolyline;
  if (strokes && (event->modifiers() & Qt::ShiftModifier)) {
    MarkRoot(point);
  } else if (tool_ == Tool::kPolyline) {
    AddPolylinePoint(point);
  } else {
    BeginStroke(point);
  }
  event->accept();
}

void PhotoView::mouseMoveEvent(QMouseEvent* event) {
  const QPointF point = mapToScene(event->position().toPoint());
  if (panning_) {
    const QPoint delta = event->position().toPoint() - pan_origin_;
    pan_origin_ = event->position().toPoint();
    horizontalScrollBar()->setValue(horizontalScrollBar()->value() - delta.x());
    verticalScrollBar()->setValue(verticalScrollBar()->value() - delta.y());
    return;
  }
  UpdateCursor(point);
  if (stroking_ && tool_ == Tool::kPolyline) {  // the next segment follows the cursor
    std::vector<QPointF> points = live_points_;
    points.push_back(point);
    live_item_->setPath(PolylinePath(points, false));
  } else if (stroking_) {
    ContinueStroke(point);
  }
}

void PhotoView::mouseReleaseEvent(QMouseEvent* event) {
  if (panning_) {
    panning_ = false;
    viewport()->setCursor(tool_ == Tool::kNavigate ? Qt::OpenHandCursor : Qt::CrossCursor);
    return;
  }
  if (stroking_ && event->button() == Qt::LeftButton && tool_ != Tool::kPolyline) {
    ContinueStroke(mapToScene(event->position().toPoint()));
    EndStroke();
  }
}

void PhotoView::mouseDoubleClickEvent(QMouseEvent* event) {
  // A double click's first click added its point already.
  if (tool_ == Tool::kPolyline && event->button() == Qt::LeftButton && stroking_) {
    AddPolylinePoint(mapToScene(event->position().toPoint()));
    FinishPolyline();
    event->accept();
    return;
  }
  QGraphicsView::mouseDoubleClickEvent(event);
}

void PhotoView::keyPressEvent(QKeyEvent* event) {
  if (tool_ != Tool::kPolyline || !stroking_) {
    QGraphicsView::keyPressEvent(event);
    return;
  }
  switch (event->key()) {
    case Qt::Key_Return:
    case Qt::Key_Enter:
      FinishPolyline();
      break;
    case Qt::Key_Escape:
      DropStroke();
      break;
    case Qt::Key_Backspace:
      live_points_.pop_back();
      if (live_points_.empty()) DropStroke();
      live_item_->setPath(PolylinePath(live_points_, false));
      break;
    default:
      QGraphicsView::keyPressEvent(event);
      return;
  }
  event->accept();
}

void PhotoView::AddPolylinePoint(const QPointF& point) {
  if (!stroking_) {
    stroking_ = true;
    before_ = working_;
    live_points_ = {point};
  } else {
    const QPointF d = point - live_points_.back();
    if (std::hypot(d.x(), d.y()) >= kMinPointSpacing) live_points_.push_back(point);
  }
  live_item_->setPath(PolylinePath(live_points_, false));
}

void PhotoView::FinishPolyline() {
  if (stroking_) EndStroke();  // fewer than 2 points: no stroke
}

void PhotoView::DropStroke() {
  if (!stroking_) return;
  stroking_ = false;
  live_points_.clear();
  live_item_->setPath(QPainterPath());
  mask_.reset();
  RefreshEdits();  // the document's edits, without the dropped stroke
}

void PhotoView::MarkRoot(const QPointF& point) {
  const PhotoEdits before = working_;
  working_.root = point;
  UpdateShapes();
  document_->Commit(photo_name_, before, working_, kStrokesLayer, "Mark tree base");
}

void PhotoView::wheelEvent(QWheelEvent* event) {
  const double steps = event->angleDelta().y() / 120.0;
  const double factor = std::pow(1.2, steps);
  scale(factor, factor);
}

void PhotoView::resizeEvent(QResizeEvent* event) {
  QGraphicsView::resizeEvent(event);
  FitPhoto();
}

}  // namespace sylva
