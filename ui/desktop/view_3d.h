// The tree in 3D without a GPU: the mesh rendered by the report's Embree
// renderer (mesh/tree_preview.h) from an orbiting orthographic camera
// (orbit_camera.h: navigation as in Blender), with the density's voxels as
// points and the skeleton as lines drawn over it (view_3d_scene.h). Renders
// synchronously in the GUI thread (one Embree frame at widget size with 1
// ray per pixel while dragging). The OpenGL view (view_3d_gl.h) shows the
// same scene from the same camera where a context can be made.
#ifndef SYLVA_UI_DESKTOP_VIEW_3D_H_
#define SYLVA_UI_DESKTOP_VIEW_3D_H_

#include <Eigen/Core>
#include <QColor>
#include <QImage>
#include <QWidget>
#include <memory>

#include "ui/desktop/orbit_camera.h"
#include "ui/desktop/view_3d_scene.h"

namespace sylva {

class Project;
class TreePreviewRenderer;

// The 3D views' background (tests count the pixels that differ from it).
constexpr QRgb kView3dBackground = qRgb(58, 60, 66);

// The hint both views write at their foot.
QString View3dHint(bool has_scene);

class View3d : public QWidget {
  Q_OBJECT

 public:
  explicit View3d(QWidget* parent = nullptr);
  ~View3d() override;

  // Reads the project's mesh, density and skeleton (LoadView3dScene) and
  // frames them.
  void LoadProject(const Project& project);
  // Shows `scene` (may be null: nothing), camera unchanged.
  void SetScene(std::shared_ptr<const View3dScene> scene);
  const std::shared_ptr<const View3dScene>& scene() const { return scene_; }
  void Clear();
  void SetShown(bool mesh, bool points, bool skeleton);
  // Frames everything loaded from the default view (azimuth 0, 15 deg up).
  void FrameAll();
  // The last rendered picture (widget size).
  const QImage& picture() const { return picture_; }
  QString status() const { return scene_ ? scene_->status : QString(); }
  bool HasScene() const { return scene_ && !scene_->empty(); }

  const OrbitCamera& camera() const { return camera_; }
  void SetCamera(const OrbitCamera& camera);
  // Orbit state (degrees, world units).
  double azimuth_deg() const { return camera_.azimuth_deg(); }
  double elevation_deg() const { return camera_.elevation_deg(); }
  double radius() const { return camera_.radius(); }
  const Eigen::Vector3d& center() const { return camera_.center(); }

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
  void Redraw(bool changed);

  std::shared_ptr<const View3dScene> scene_;
  std::unique_ptr<TreePreviewRenderer> renderer_;
  bool show_mesh_ = true, show_points_ = true, show_skeleton_ = true;
  OrbitCamera camera_;
  QImage picture_;
  bool dirty_ = true;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_VIEW_3D_H_
