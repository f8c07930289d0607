// The 3D views' camera and navigation (View3d, Embree; View3dGl, OpenGL):
// an orthographic camera orbiting a centre, moved as in Blender: middle
// button drag orbits, Shift+middle pans, Ctrl+middle or the wheel zooms;
// Home frames the tree; keys 1 / 3 / 7 look from the front / right / top
// (numpad or not). Alt+left button emulates the middle button. Both views
// draw through View(), so they show the same picture for the same state.
#ifndef SYLVA_UI_DESKTOP_ORBIT_CAMERA_H_
#define SYLVA_UI_DESKTOP_ORBIT_CAMERA_H_

#include <Eigen/Core>
#include <QPoint>

#include "core/geometry/box.h"
#include "mesh/tree_preview.h"

class QKeyEvent;
class QMouseEvent;
class QWheelEvent;

namespace sylva {

class OrbitCamera {
 public:
  // The whole of `bounds` from the default view (azimuth 0, 15 deg up).
  void Frame(const Box3d& bounds);

  // The orthographic view of a width x height picture; its image plane lies
  // behind `bounds` (the scene's), so zooming in never clips the tree.
  PreviewView View(int width, int height, const Box3d& bounds) const;

  // Navigation; each returns true if the picture must be drawn again.
  // Move() needs the picture's size (panning moves by whole pixels).
  bool Press(const QMouseEvent& event);
  bool Move(const QMouseEvent& event, int width, int height);
  bool Release();
  bool Wheel(const QWheelEvent& event);
  // False for keys it does not use (the widget passes them on).
  bool Key(const QKeyEvent& event, const Box3d& bounds);
  bool dragging() const { return drag_ != Drag::kNone; }

  // Orbit state (degrees, world units).
  double azimuth_deg() const { return azimuth_deg_; }
  double elevation_deg() const { return elevation_deg_; }
  double radius() const { return radius_; }
  const Eigen::Vector3d& center() const { return center_; }

 private:
  double azimuth_deg_ = 0.0, elevation_deg_ = 15.0, radius_ = 1.0;
  Eigen::Vector3d center_ = Eigen::Vector3d::Zero();
  enum class Drag { kNone, kOrbit, kPan, kZoom } drag_ = Drag::kNone;
  QPoint last_mouse_;
};

// The options the views' pictures are framed with (size and margin).
TreePreviewOptions OrbitViewOptions(int width, int height);

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_ORBIT_CAMERA_H_
