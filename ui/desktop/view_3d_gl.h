// The tree in 3D on the GPU: the scene of the Embree view (view_3d.h,
// view_3d_scene.h) drawn by OpenGL from the same orbit camera
// (orbit_camera.h), so both views show the same picture; interactive at any
// mesh size. Used where a context can be made (Available()): not on the
// offscreen platform, where QOpenGLWidget crashes on Debian 12's Qt 6.4,
// and not without a display (under a headless X server, xvfb-run, Mesa's
// software rasteriser makes one).
#ifndef SYLVA_UI_DESKTOP_VIEW_3D_GL_H_
#define SYLVA_UI_DESKTOP_VIEW_3D_GL_H_

#include <QOpenGLWidget>
#include <memory>

#include "ui/desktop/orbit_camera.h"
#include "ui/desktop/view_3d_scene.h"

namespace sylva {

class View3dGl : public QOpenGLWidget {
  Q_OBJECT

 public:
  explicit View3dGl(QWidget* parent = nullptr);
  ~View3dGl() override;

  // True if an OpenGL 2.1 context can be made on this platform.
  static bool Available();

  // Shows `scene` (may be null: nothing), camera unchanged.
  void SetScene(std::shared_ptr<const View3dScene> scene);
  void SetShown(bool mesh, bool points, bool skeleton);
  void FrameAll();
  bool HasScene() const { return scene_ && !scene_->empty(); }
  const OrbitCamera& camera() const { return camera_; }
  void SetCamera(const OrbitCamera& camera);
  // The GL renderer's name ("" before the first frame), for the status bar.
  QString renderer_name() const;

 protected:
  void initializeGL() override;
  void paintGL() override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;

 private:
  class Gl;  // the buffers and programs (Qt's GL headers stay in the .cc)
  void Redraw(bool changed);

  std::shared_ptr<const View3dScene> scene_;
  std::unique_ptr<Gl> gl_;
  bool uploaded_ = false;
  bool show_mesh_ = true, show_points_ = true, show_skeleton_ = true;
  OrbitCamera camera_;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_VIEW_3D_GL_H_
