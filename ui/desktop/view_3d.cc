#include "ui/desktop/view_3d.h"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>

#include "mesh/tree_preview.h"

namespace sylva {

QString View3dHint(bool has_scene) {
  return has_scene ? "MMB orbit · Shift+MMB pan · wheel zoom · Home frame"
                   : "No reconstruction yet: run the pipeline";
}

View3d::View3d(QWidget* parent) : QWidget(parent) {
  setFocusPolicy(Qt::StrongFocus);
  setMinimumSize(200, 200);
}

View3d::~View3d() = default;

void View3d::Clear() { SetScene(nullptr); }

void View3d::LoadProject(const Project& project) {
  SetScene(LoadView3dScene(project));
  FrameAll();
}

void View3d::SetScene(std::shared_ptr<const View3dScene> scene) {
  scene_ = std::move(scene);
  renderer_.reset();
  if (scene_ && scene_->mesh.NumTriangles() > 0) {
    renderer_ = std::make_unique<TreePreviewRenderer>(scene_->mesh, nullptr);
  }
  Redraw(true);
}

void View3d::SetShown(bool mesh, bool points, bool skeleton) {
  show_mesh_ = mesh;
  show_points_ = points;
  show_skeleton_ = skeleton;
  Redraw(true);
}

void View3d::FrameAll() {
  camera_.Frame(scene_ ? scene_->bounds : Box3d());
  Redraw(true);
}

void View3d::SetCamera(const OrbitCamera& camera) {
  camera_ = camera;
  Redraw(true);
}

void View3d::Redraw(bool changed) {
  if (!changed) return;
  dirty_ = true;
  update();
}

void View3d::Render(bool fast) {
  picture_ = QImage(std::max(16, width()), std::max(16, height()), QImage::Format_ARGB32);
  picture_.fill(kView3dBackground);
  dirty_ = false;
  if (!HasScene()) return;
  TreePreviewOptions options = OrbitViewOptions(picture_.width(), picture_.height());
  options.samples_per_axis = fast ? 1 : 2;
  options.shadows = !fast;
  const PreviewView view = camera_.View(picture_.width(), picture_.height(), scene_->bounds);
  QPainter painter(&picture_);
  painter.setRenderHint(QPainter::Antialiasing);
  if (show_mesh_ && renderer_) {
    const FloatImage rgba = renderer_->Render(view, options);
    QImage layer(rgba.width(), rgba.height(), QImage::Format_ARGB32);
    for (int y = 0; y < rgba.height(); ++y) {
      QRgb* row = reinterpret_cast<QRgb*>(layer.scanLine(y));
      for (int x = 0; x < rgba.width(); ++x) {
        const auto v = [&](int c) {
          return static_cast<int>(std::lround(std::clamp(rgba.at(x, y, c), 0.f, 1.f) * 255));
        };
        row[x] = qRgba(v(0), v(1), v(2), v(3));
      }
    }
    painter.drawImage(0, 0, layer);
  }
  const auto to_pixel = [&](const Eigen::Vector3d& point) {
    const Eigen::Vector2d p = view.camera.ImgFromCam(view.cam_from_world * point);
    return QPointF(p.x(), p.y());
  };
  if (show_points_) {
    painter.setPen(Qt::NoPen);
    for (size_t i = 0; i < scene_->points.size(); ++i) {
      painter.setBrush(View3dPointColor(scene_->point_values[i]));
      painter.drawEllipse(to_pixel(scene_->points[i].cast<double>()), 1.6, 1.6);
    }
  }
  if (show_skeleton_) {
    painter.setPen(QPen(View3dSkeletonColor(), 1.5));
    for (const auto& [a, b] : scene_->skeleton) painter.drawLine(to_pixel(a), to_pixel(b));
  }
}

void View3d::paintEvent(QPaintEvent*) {
  if (dirty_ || picture_.size() != size()) Render(camera_.dragging());
  QPainter painter(this);
  painter.drawImage(0, 0, picture_);
  painter.setPen(QColor(220, 220, 220));
  painter.drawText(rect().adjusted(8, 4, -8, -4), Qt::AlignLeft | Qt::AlignBottom,
                   View3dHint(HasScene()));
}

void View3d::resizeEvent(QResizeEvent*) { dirty_ = true; }

void View3d::mousePressEvent(QMouseEvent* event) { camera_.Press(*event); }

void View3d::mouseMoveEvent(QMouseEvent* event) { Redraw(camera_.Move(*event, width(), height())); }

// Full quality again.
void View3d::mouseReleaseEvent(QMouseEvent*) { Redraw(camera_.Release()); }

void View3d::wheelEvent(QWheelEvent* event) { Redraw(camera_.Wheel(*event)); }

void View3d::keyPressEvent(QKeyEvent* event) {
  if (!camera_.Key(*event, scene_ ? scene_->bounds : Box3d())) {
    QWidget::keyPressEvent(event);
    return;
  }
  Redraw(true);
}

}  // namespace sylva
