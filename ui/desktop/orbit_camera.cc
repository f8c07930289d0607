#include "ui/desktop/orbit_camera.h"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>

namespace sylva {
namespace {

// Degrees of orbit per pixel dragged; zoom factor per wheel notch.
constexpr double kOrbitDegPerPixel = 0.4;
constexpr double kZoomPerNotch = 1.15;

}  // namespace

TreePreviewOptions OrbitViewOptions(int width, int height) {
  TreePreviewOptions options;
  options.width = std::max(16, width);
  options.height = std::max(16, height);
  options.white_background = false;
  options.margin = 0.05;
  return options;
}

void OrbitCamera::Frame(const Box3d& bounds) {
  azimuth_deg_ = 0.0;
  elevation_deg_ = 15.0;
  if (bounds.isEmpty()) return;
  center_ = bounds.center();
  radius_ = std::max(1e-6, 0.5 * bounds.diagonal().norm());
}

PreviewView OrbitCamera::View(int width, int height, const Box3d& bounds) const {
  PreviewView view =
      CloseUpView(center_, radius_, azimuth_deg_, elevation_deg_, OrbitViewOptions(width, height));
  // Orthographic: moving the image plane back changes nothing in the
  // picture but keeps the whole tree in front of it when zoomed in.
  const double depth = bounds.isEmpty() ? 0.0 : bounds.diagonal().norm();
  view.cam_from_world.translation.z() += 2.0 * depth + radius_;
  return view;
}

bool OrbitCamera::Press(const QMouseEvent& event) {
  const bool middle = event.button() == Qt::MiddleButton ||
                      (event.button() == Qt::LeftButton && (event.modifiers() & Qt::AltModifier));
  if (!middle) return false;
  drag_ = (event.modifiers() & Qt::ShiftModifier)     ? Drag::kPan
          : (event.modifiers() & Qt::ControlModifier) ? Drag::kZoom
                                                      : Drag::kOrbit;
  last_mouse_ = event.position().toPoint();
  return true;
}

bool OrbitCamera::Move(const QMouseEvent& event, int width, int height) {
  if (drag_ == Drag::kNone) return false;
  const QPoint delta = event.position().toPoint() - last_mouse_;
  last_mouse_ = event.position().toPoint();
  if (drag_ == Drag::kOrbit) {
    azimuth_deg_ -= kOrbitDegPerPixel * delta.x();
    elevation_deg_ = std::clamp(elevation_deg_ + kOrbitDegPerPixel * delta.y(), -89.0, 89.0);
  } else if (drag_ == Drag::kZoom) {
    radius_ *= std::pow(kZoomPerNotch, delta.y() / 20.0);
  } else {
    const PreviewView view = CloseUpView(center_, radius_, azimuth_deg_, elevation_deg_,
                                         OrbitViewOptions(width, height));
    const double world_per_pixel = view.camera.WorldPerPixel(Eigen::Vector3d(0, 0, 1));
    const Eigen::Vector3d shift_in_cam(delta.x() * world_per_pixel, delta.y() * world_per_pixel, 0);
    center_ -= view.cam_from_world.rotation.inverse() * shift_in_cam;
  }
  return true;
}

bool OrbitCamera::Release() {
  if (drag_ == Drag::kNone) return false;
  drag_ = Drag::kNone;
  return true;
}

bool OrbitCamera::Wheel(const QWheelEvent& event) {
  radius_ *= std::pow(kZoomPerNotch, -event.angleDelta().y() / 120.0);
  return true;
}

bool OrbitCamera::Key(const QKeyEvent& event, const Box3d& bounds) {
  switch (event.key()) {
    case Qt::Key_Home:
      Frame(bounds);
      return true;
    case Qt::Key_1:
      azimuth_deg_ = 0, elevation_deg_ = 0;
      return true;
    case Qt::Key_3:
      azimuth_deg_ = 90, elevation_deg_ = 0;
      return true;
    case Qt::Key_7:
      elevation_deg_ = 89;
      return true;
    default:
      return false;
  }
}

}  // namespace sylva
