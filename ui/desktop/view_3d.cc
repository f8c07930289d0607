#include "ui/desktop/view_3d.h"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>

#include "core/io/mesh_io.h"
#include "core/io/skeleton_io.h"
#include "core/io/vdb_io.h"
#include "core/types/density_grid.h"
#include "core/types/skeleton_graph.h"
#include "mesh/tree_preview.h"
#include "ui/pipeline/project.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// Voxels at least this opaque are drawn, at most kMaxPoints of them.
constexpr float kPointOpacityMin = 0.05f;
constexpr size_t kMaxPoints = 40000;
// Degrees of orbit per pixel dragged; zoom factor per wheel notch.
constexpr double kOrbitDegPerPixel = 0.4;
constexpr double kZoomPerNotch = 1.15;

bool IsFile(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

TreePreviewOptions RenderOptions(int width, int height, bool fast) {
  TreePreviewOptions options;
  options.width = std::max(16, width);
  options.height = std::max(16, height);
  options.samples_per_axis = fast ? 1 : 2;
  options.shadows = !fast;
  options.white_background = false;
  options.margin = 0.05;
  return options;
}

}  // namespace

View3d::View3d(QWidget* parent) : QWidget(parent) {
  setFocusPolicy(Qt::StrongFocus);
  setMinimumSize(200, 200);
}

View3d::~View3d() = default;

bool View3d::HasScene() const { return !bounds_.isEmpty(); }

void View3d::Clear() {
  renderer_.reset();
  points_.clear();
  point_values_.clear();
  skeleton_.clear();
  bounds_.setEmpty();
  status_.clear();
  dirty_ = true;
  update();
}

void View3d::LoadProject(const Project& project) {
  Clear();
  QStringList loaded, failed;
  const fs::path mesh = project.OutDir() / "tree.obj";
  if (IsFile(mesh)) {
    try {
      renderer_ = std::make_unique<TreePreviewRenderer>(ReadObj(mesh), nullptr);
      if (renderer_->Bounds().isEmpty()) renderer_.reset();
      if (renderer_) bounds_.extend(renderer_->Bounds()), loaded << "mesh";
    } catch (const std::exception& error) {
      failed << QString::fromStdString(error.what());
    }
  }
  const fs::path density = project.OutDir() / "density.vdb";
  if (IsFile(density)) {
    try {
      const DensityGrid grid = ReadDensityGrid(density);
      std::vector<std::pair<Eigen::Vector3f, float>> all;
      grid.ForEachActive([&](const Eigen::Vector3i& ijk, float value) {
        if (value >= kPointOpacityMin) {
          all.emplace_back(grid.WorldFromIndex(ijk.cast<double>()).cast<float>(), value);
        }
      });
      const size_t step = std::max<size_t>(1, (all.size() + kMaxPoints - 1) / kMaxPoints);
      for (size_t i = 0; i < all.size(); i += step) {
        points_.push_back(all[i].first);
        point_values_.push_back(all[i].second);
        bounds_.extend(all[i].first.cast<double>());
      }
      loaded << QString("%1 voxels").arg(all.size());
    } catch (const std::exception& error) {
      failed << QString::fromStdString(error.what());
    }
  }
  const fs::path skeleton = project.OutDir() / "skeleton.json";
  if (IsFile(skeleton)) {
    try {
      const SkeletonGraph graph = ReadSkeletonJson(skeleton);
      for (const SkeletonNode& node : graph.nodes) {
        bounds_.extend(node.position);
        if (node.parent_idx >= 0) {
          skeleton_.emplace_back(node.position, graph.nodes[node.parent_idx].position);
        }
      }
      loaded << QString("skeleton of %1 nodes").arg(graph.nodes.size());
    } catch (const std::exception& error) {
      failed << QString::fromStdString(error.what());
    }
  }
  status_ = loaded.isEmpty() ? "nothing reconstructed yet" : "3D: " + loaded.join(", ");
  if (!failed.isEmpty()) status_ += "; unreadable: " + failed.join("; ");
  FrameAll();
}

void View3d::SetShown(bool mesh, bool points, bool skeleton) {
  show_mesh_ = mesh;
  show_points_ = points;
  show_skeleton_ = skeleton;
  dirty_ = true;
  update();
}

void View3d::FrameAll() {
  azimuth_deg_ = 0.0;
  elevation_deg_ = 15.0;
  if (HasScene()) {
    center_ = bounds_.center();
    radius_ = std::max(1e-6, 0.5 * bounds_.diagonal().norm());
  }
  dirty_ = true;
  update();
}

void View3d::Render(bool fast) {
  picture_ = QImage(std::max(16, width()), std::max(16, height()), QImage::Format_ARGB32);
  picture_.fill(kView3dBackground);
  dirty_ = false;
  if (!HasScene()) return;
  const TreePreviewOptions options = RenderOptions(picture_.width(), picture_.height(), fast);
  PreviewView view = CloseUpView(center_, radius_, azimuth_deg_, elevation_deg_, options);
  // Orthographic: moving the image plane back changes nothing in the
  // picture but keeps the whole tree in front of it when zoomed in.
  view.cam_from_world.translation.z() += 2.0 * bounds_.diagonal().norm() + radius_;
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
    for (size_t i = 0; i < points_.size(); ++i) {
      const int alpha = static_cast<int>(40 + 120 * std::min(1.0f, point_values_[i]));
      painter.setBrush(QColor(110, 220, 120, alpha));
      painter.drawEllipse(to_pixel(points_[i].cast<double>()), 1.6, 1.6);
    }
  }
  if (show_skeleton_) {
    painter.setPen(QPen(QColor(255, 150, 40), 1.5));
    for (const auto& [a, b] : skeleton_) painter.drawLine(to_pixel(a), to_pixel(b));
  }
}

void View3d::paintEvent(QPaintEvent*) {
  if (dirty_ || picture_.size() != size()) Render(drag_ != Drag::kNone);
  QPainter painter(this);
  painter.drawImage(0, 0, picture_);
  painter.setPen(QColor(220, 220, 220));
  painter.drawText(rect().adjusted(8, 4, -8, -4), Qt::AlignLeft | Qt::AlignBottom,
                   HasScene() ? "MMB orbit · Shift+MMB pan · wheel zoom · Home frame"
                              : "No reconstruction yet: run the pipeline");
}

void View3d::resizeEvent(QResizeEvent*) { dirty_ = true; }

void View3d::mousePressEvent(QMouseEvent* event) {
  const bool middle = event->button() == Qt::MiddleButton ||
                      (event->button() == Qt::LeftButton && (event->modifiers() & Qt::AltModifier));
  if (!middle) return;
  drag_ = (event->modifiers() & Qt::ShiftModifier)     ? Drag::kPan
          : (event->modifiers() & Qt::ControlModifier) ? Drag::kZoom
                                                       : Drag::kOrbit;
  last_mouse_ = event->position().toPoint();
}

void View3d::mouseMoveEvent(QMouseEvent* event) {
  if (drag_ == Drag::kNone) return;
  const QPoint delta = event->position().toPoint() - last_mouse_;
  last_mouse_ = event->position().toPoint();
  if (drag_ == Drag::kOrbit) {
    azimuth_deg_ -= kOrbitDegPerPixel * delta.x();
    elevation_deg_ = std::clamp(elevation_deg_ + kOrbitDegPerPixel * delta.y(), -89.0, 89.0);
  } else if (drag_ == Drag::kZoom) {
    radius_ *= std::pow(kZoomPerNotch, delta.y() / 20.0);
  } else {
    const TreePreviewOptions options = RenderOptions(width(), height(), true);
    const PreviewView view = CloseUpView(center_, radius_, azimuth_deg_, elevation_deg_, options);
    const double world_per_pixel = view.camera.WorldPerPixel(Eigen::Vector3d(0, 0, 1));
    const Eigen::Vector3d shift_in_cam(delta.x() * world_per_pixel, delta.y() * world_per_pixel, 0);
    center_ -= view.cam_from_world.rotation.inverse() * shift_in_cam;
  }
  dirty_ = true;
  update();
}

void View3d::mouseReleaseEvent(QMouseEvent*) {
  if (drag_ == Drag::kNone) return;
  drag_ = Drag::kNone;
  dirty_ = true;  // full quality again
  update();
}

void View3d::wheelEvent(QWheelEvent* event) {
  radius_ *= std::pow(kZoomPerNotch, -event->angleDelta().y() / 120.0);
  dirty_ = true;
  update();
}

void View3d::keyPressEvent(QKeyEvent* event) {
  switch (event->key()) {
    case Qt::Key_Home:
      FrameAll();
      return;
    case Qt::Key_1:
      azimuth_deg_ = 0, elevation_deg_ = 0;
      break;
    case Qt::Key_3:
      azimuth_deg_ = 90, elevation_deg_ = 0;
      break;
    case Qt::Key_7:
      elevation_deg_ = 89;
      break;
    default:
      QWidget::keyPressEvent(event);
      return;
  }
  dirty_ = true;
  update();
}

}  // namespace sylva
