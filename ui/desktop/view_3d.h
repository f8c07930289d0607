// The tree in 3D without a GPU: the mesh (out/tree.obj) rendered by the
// report's Embree renderer (mesh/tree_preview.h) from an orbiting
// orthographic camera, with the density's voxels (out/density.vdb) as
// points and the skeleton (out/skeleton.json) as lines drawn over it.
//
// Navigation as in Blender: middle button drag orbits, Shift+middle pans,
// Ctrl+middle or the wheel zooms; Home frames the tree; keys 1 / 3 / 7 look
// from the front / right / top (numpad or not). Alt+left button emulates
// the middle button. Renders synchronously in the GUI thread (one Embree
// frame at widget size with 1 ray per pixel while dragging).
#ifndef SYLVA_UI_DESKTOP_VIEW_3D_H_
#define SYLVA_UI_DESKTOP_VIEW_3D_H_

#include <Eigen/Core>
#include <QColor>
#include <QImage>
#include <QWidget>
#include <memory>
#include <vector>

#include "core/geometry/box.h"

namespace sylva {

class Project;
class TreePreviewRenderer;

// The 3D view's background (tests count the pixels that differ from it).
constexpr QRgb kView3dBackground = qRgb(58, 60, 66);

class View3d : public QWidget {
  Q_OBJECT

 public:
  explicit View3d(QWidget* parent = nullptr);
  ~View3d() override;

  // Reads the project's mesh, density and skeleton (whichever exist; a
  // file that cannot be read is skipped and reported in status()).
  void LoadProject(const Project& project);
  void Clear();
  void SetShown(bool mesh, bool points, bool skeleton);
  // Frames everything loaded from the default view (azimuth 0, 15 deg up).
  void FrameAll();
  // The last rendered picture (widget size).
  const QImage& picture() const { return picture_; }
  QString status() const { return status_; }
  bool HasScene() const;

  // Orbit state (degrees, world units).
  double azimuth_deg() const { return azimuth_deg_; }
  double elevation_deg() const { return elevation_deg_; }
  double radius() const { return radius_; }
  const Eigen::Vector3d& center() const { return center_; }

 protected:
  void paintEvent(QPaintEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;

 private:
  void Render(bool fast);

  std::unique_ptr<TreePreviewRenderer> renderer_;
  std::vector<Eigen::Vector3f> points_;  // density voxels, world
  std::vector<float> point_values_;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> skeleton_;  // segments
  Box3d bounds_;
  bool show_mesh_ = true, show_points_ = true, show_skeleton_ = true;

  double azimuth_deg_ = 0.0, elevation_deg_ = 15.0, radius_ = 1.0;
  Eigen::Vector3d center_ = Eigen::Vector3d::Zero();
  QImage picture_;
  QString status_;
  bool dirty_ = true;

  enum class Drag { kNone, kOrbit, kPan, kZoom } drag_ = Drag::kNone;
  QPoint last_mouse_;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_VIEW_3D_H_
