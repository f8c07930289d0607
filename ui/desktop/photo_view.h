// The photo of the current view with its overlays and the brushes that paint
// on it (a QGraphicsView whose scene coordinates are photo pixels: pixel
// (i, j) covers [i, i + 1] x [j, j + 1], as in strokes.h).
//
// Mouse: with a brush, the left button paints one stroke per press; the
// middle button pans and the wheel zooms (any tool); with the navigate tool
// the left button pans too. Strokes tools: Shift+click marks the tree base.
// Polyline tool: each click adds a point; a double click or Enter finishes
// the stroke (one undo step, as a freehand stroke), Backspace removes the
// last point, Escape drops the stroke.
#ifndef SYLVA_UI_DESKTOP_PHOTO_VIEW_H_
#define SYLVA_UI_DESKTOP_PHOTO_VIEW_H_

#include <QGraphicsView>
#include <QImage>
#include <QPainterPath>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ui/desktop/photo_edits.h"

class QGraphicsPixmapItem;
class QGraphicsPathItem;
class QGraphicsEllipseItem;

namespace sylva {

class EditDocument;

enum class Tool {
  kNavigate,
  kDensityAdd,
  kDensityRemove,
  kTrimapForeground,
  kTrimapBackground,
  kTrimapUnknown,
  kStrokes,
  kPolyline,  // a branch stroke clicked point by point
  kCrown,
  kEraser,
};

// Overlays drawn from the pipeline's outputs, bottom to top.
enum class Overlay { kMatte, kDensityProjection, kMeshSilhouette, kAttractors, kCount };

class PhotoView : public QGraphicsView {
  Q_OBJECT

 public:
  explicit PhotoView(QWidget* parent = nullptr);
  ~PhotoView() override;

  // Shows `photo` (RGB(A)) of view `photo_name`, whose edits live in
  // `document` (kept alive by the caller); clears the overlays.
  void SetPhoto(EditDocument* document, const std::string& photo_name, const QImage& photo);
  const std::string& photo_name() const { return photo_name_; }
  bool HasPhoto() const { return !photo_name_.empty(); }

  // An overlay picture (stretched onto the photo) or path; null = none.
  void SetOverlayImage(Overlay overlay, const QImage& image);
  void SetAttractorPath(const QPainterPath& path);
  void SetOverlayVisible(Overlay overlay, bool visible);
  void SetEditsVisible(bool visible);

  void SetTool(Tool tool);
  Tool tool() const { return tool_; }
  BrushShape& brush() { return brush_; }

  // Rebuilds the edit layers' pictures from the document (after undo/redo).
  void RefreshEdits();
  // Zooms so that the whole photo is visible.
  void FitPhoto();

 protected:
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void mouseDoubleClickEvent(QMouseEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;

 private:
  bool IsBrush() const;
  void BeginStroke(const QPointF& point);
  void ContinueStroke(const QPointF& point);
  void EndStroke();
  // The polyline tool: adds a clicked point (starting a stroke), finishes
  // or drops the stroke in progress.
  void AddPolylinePoint(const QPointF& point);
  void FinishPolyline();
  void DropStroke();
  void MarkRoot(const QPointF& point);
  void UpdateLayerPictures(const QRect& rect);
  void UpdateShapes();
  void UpdateCursor(const QPointF& point);

  EditDocument* document_ = nullptr;
  std::string photo_name_;
  QGraphicsPixmapItem* photo_item_ = nullptr;
  std::array<QGraphicsPixmapItem*, 3> overlay_items_{};  // image overlays
  QGraphicsPathItem* attractor_item_ = nullptr;
  QGraphicsPixmapItem* density_item_ = nullptr;
  QGraphicsPixmapItem* trimap_item_ = nullptr;
  QGraphicsPathItem* strokes_item_ = nullptr;
  QGraphicsPathItem* crowns_item_ = nullptr;
  QGraphicsPathItem* live_item_ = nullptr;
  QGraphicsEllipseItem* cursor_item_ = nullptr;
  QImage density_picture_, trimap_picture_;

  Tool tool_ = Tool::kNavigate;
  BrushShape brush_;
  // The stroke in progress.
  bool stroking_ = false;
  PhotoEdits before_, working_;
  std::unique_ptr<StrokeMask> mask_;
  std::vector<QPointF> live_points_;
  QPointF last_point_;
  bool erased_shapes_ = false;
  // Panning with the middle button (or left with the navigate tool).
  bool panning_ = false;
  QPoint pan_origin_;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_PHOTO_VIEW_H_
