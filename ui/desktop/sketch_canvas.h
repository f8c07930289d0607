// The sketch canvas: draw a tree (branch strokes, crown outlines or cloud
// strokes, the root) on a blank page and save it as the SVG `sylva sketch`
// reads (sketch/drawing_io.h, WriteSketchSvg), or open such a drawing.
//
// Mouse: the left button draws one freehand stroke of the current role per
// press; a crown stroke that ends near its start (within a fifth of its
// length) is a closed outline; Shift+click marks the root. The canvas keeps
// its size in canvas pixels (the SVG's viewBox) and is shown scaled to fit.
#ifndef SYLVA_UI_DESKTOP_SKETCH_CANVAS_H_
#define SYLVA_UI_DESKTOP_SKETCH_CANVAS_H_

#include <QPointF>
#include <QTransform>
#include <QWidget>
#include <filesystem>
#include <vector>

#include "sketch/drawing.h"

namespace sylva {

class SketchCanvas : public QWidget {
  Q_OBJECT

 public:
  explicit SketchCanvas(QWidget* parent = nullptr);

  // The role of the strokes drawn from now on (branch or crown).
  void SetRole(StrokeRole role) { role_ = role; }
  StrokeRole role() const { return role_; }
  // Stroke width written for new strokes, canvas pixels.
  void SetStrokeWidth(double width) { stroke_width_ = width; }

  // The drawing so far (its width and height are the canvas size).
  const SketchDrawing& drawing() const { return drawing_; }
  bool IsEmpty() const { return drawing_.strokes.empty(); }
  // Replaces the drawing (e.g. one read by ReadSketchSvg).
  void SetDrawing(const SketchDrawing& drawing);
  void UndoLastStroke();
  void Clear();
  // Reads an SVG drawing / writes the drawing as SVG (atomic); both throw
  // InputError naming the file.
  void OpenSvg(const std::filesystem::path& path);
  void SaveSvg(const std::filesystem::path& path) const;

  // Where canvas point `point` is on the widget (for tests and painting).
  QPointF ToWidget(const QPointF& point) const { return widget_from_canvas_.map(point); }

 signals:
  void Changed();

 protected:
  void paintEvent(QPaintEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;

 private:
  void UpdateTransform();
  QPointF ToCanvas(const QPointF& widget_point) const;
  void FinishStroke();

  SketchDrawing drawing_;
  StrokeRole role_ = StrokeRole::kBranch;
  double stroke_width_ = 3.0;
  QTransform widget_from_canvas_;
  bool drawing_stroke_ = false;
  std::vector<QPointF> live_points_;  // canvas pixels
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_SKETCH_CANVAS_H_
