#include "ui/desktop/view_3d_gl.h"

#include <QGuiApplication>
#include <QKeyEvent>
#include <QMatrix3x3>
#include <QMatrix4x4>
#include <QMouseEvent>
#include <QOffscreenSurface>
#include <QOpenGLBuffer>
#include <QOpenGLContext>
#include <QOpenGLFunctions>
#include <QOpenGLShaderProgram>
#include <QPainter>
#include <QWheelEvent>
#include <algorithm>
#include <limits>
#include <vector>

#include "core/util/check.h"
#include "ui/desktop/view_3d.h"

namespace sylva {
namespace {

// GLSL 1.20 (OpenGL 2.1), which every desktop driver and Mesa's software
// rasteriser run.
constexpr char kMeshVertex[] = R"(#version 120
attribute vec3 position;
attribute vec3 normal;
attribute vec3 color;
uniform mat4 world_to_clip;
uniform mat3 world_to_cam;
varying vec3 cam_normal;
varying vec3 base_color;
void main() {
  gl_Position = world_to_clip * vec4(position, 1.0);
  cam_normal = world_to_cam * normal;
  base_color = color;
})";

// A headlight (the camera looks along +z) on both faces, with some ambient;
// linear material colours to sRGB.
constexpr char kMeshFragment[] = R"(#version 120
varying vec3 cam_normal;
varying vec3 base_color;
void main() {
  float facing = abs(normalize(cam_normal).z);
  vec3 linear = base_color * (0.3 + 0.7 * facing);
  gl_FragColor = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);
})";

constexpr char kFlatVertex[] = R"(#version 120
attribute vec3 position;
attribute vec4 color;
uniform mat4 world_to_clip;
uniform float point_size;
varying vec4 flat_color;
void main() {
  gl_Position = world_to_clip * vec4(position, 1.0);
  gl_PointSize = point_size;
  flat_color = color;
})";

constexpr char kFlatFragment[] = R"(#version 120
varying vec4 flat_color;
void main() { gl_FragColor = flat_color; })";

constexpr int kMeshFloats = 9;  // position, normal, colour
constexpr int kFlatFloats = 7;  // position, RGBA
// GL_VERTEX_PROGRAM_POINT_SIZE (desktop OpenGL 2.0; not in the ES 2 header).
constexpr GLenum kProgramPointSize = 0x8642;

void Push(std::vector<float>* data, const Eigen::Vector3f& a) {
  data->insert(data->end(), {a.x(), a.y(), a.z()});
}

void Push(std::vector<float>* data, const QColor& color) {
  data->insert(data->end(), {float(color.redF()), float(color.greenF()), float(color.blueF()),
                             float(color.alphaF())});
}

std::vector<float> MeshVertices(const TriangleMesh& mesh) {
  std::vector<float> data;
  data.reserve(size_t(mesh.NumTriangles()) * 3 * kMeshFloats);
  for (int t = 0; t < mesh.NumTriangles(); ++t) {
    const Eigen::Vector3i& triangle = mesh.triangles[t];
    const Eigen::Vector3f& a = mesh.vertices[triangle[0]];
    const Eigen::Vector3f normal =
        (mesh.vertices[triangle[1]] - a).cross(mesh.vertices[triangle[2]] - a).normalized();
    const int material = t < int(mesh.triangle_materials.size()) ? mesh.triangle_materials[t] : -1;
    const Eigen::Vector3f color = material >= 0 && material < int(mesh.materials.size())
                                      ? mesh.materials[material].diffuse_color
                                      : Eigen::Vector3f(0.5f, 0.5f, 0.5f);
    for (int k = 0; k < 3; ++k) {
      Push(&data, mesh.vertices[triangle[k]]);
      Push(&data, normal);
      Push(&data, color);
    }
  }
  return data;
}

// world -> clip for `view`'s orthographic camera on a width x height
// widget: the camera's own pixel mapping, so the picture is the Embree
// view's; depth spans `bounds` in front of the camera.
QMatrix4x4 WorldToClip(const PreviewView& view, int width, int height, const Box3d& bounds) {
  SYLVA_CHECK(view.camera.IsOrthographic());
  const Eigen::Vector2d origin = view.camera.ImgFromCam(Eigen::Vector3d(0, 0, 1));
  const Eigen::Vector2d ex = view.camera.ImgFromCam(Eigen::Vector3d(1, 0, 1)) - origin;
  const Eigen::Vector2d ey = view.camera.ImgFromCam(Eigen::Vector3d(0, 1, 1)) - origin;
  double near = std::numeric_limits<double>::max(), far = -near;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d point(corner & 1 ? bounds.max().x() : bounds.min().x(),
                                corner & 2 ? bounds.max().y() : bounds.min().y(),
                                corner & 4 ? bounds.max().z() : bounds.min().z());
    const double z = (view.cam_from_world * point).z();
    near = std::min(near, z), far = std::max(far, z);
  }
  const double slack = 0.01 * (far - near) + 1e-6;
  near -= slack, far += slack;
  const double w = width, h = height;
  const QMatrix4x4 cam_to_clip(2 * ex.x() / w, 2 * ey.x() / w, 0, 2 * origin.x() / w - 1,
                               -2 * ex.y() / h, -2 * ey.y() / h, 0, 1 - 2 * origin.y() / h,  //
                               0, 0, 2 / (far - near), -(far + near) / (far - near),         //
                               0, 0, 0, 1);
  const Eigen::Matrix3d r = view.cam_from_world.rotation.toRotationMatrix();
  const Eigen::Vector3d& t = view.cam_from_world.translation;
  const QMatrix4x4 world_to_cam(r(0, 0), r(0, 1), r(0, 2), t.x(), r(1, 0), r(1, 1), r(1, 2), t.y(),
                                r(2, 0), r(2, 1), r(2, 2), t.z(), 0, 0, 0, 1);
  return cam_to_clip * world_to_cam;
}

}  // namespace

// The GPU side: one program for the lit mesh, one for coloured points and
// lines; a vertex buffer each for the mesh, the points and the skeleton.
class View3dGl::Gl : public QOpenGLFunctions {
 public:
  QOpenGLShaderProgram mesh_program, flat_program;
  QOpenGLBuffer mesh{QOpenGLBuffer::VertexBuffer}, points{QOpenGLBuffer::VertexBuffer},
      lines{QOpenGLBuffer::VertexBuffer};
  int mesh_vertices = 0, point_vertices = 0, line_vertices = 0;
  QString renderer;

  void Init() {
    initializeOpenGLFunctions();
    SYLVA_CHECK(mesh_program.addShaderFromSourceCode(QOpenGLShader::Vertex, kMeshVertex) &&
                mesh_program.addShaderFromSourceCode(QOpenGLShader::Fragment, kMeshFragment) &&
                mesh_program.link())
        << mesh_program.log().toStdString();
    SYLVA_CHECK(flat_program.addShaderFromSourceCode(QOpenGLShader::Vertex, kFlatVertex) &&
                flat_program.addShaderFromSourceCode(QOpenGLShader::Fragment, kFlatFragment) &&
                flat_program.link())
        << flat_program.log().toStdString();
    for (QOpenGLBuffer* buffer : {&mesh, &points, &lines}) buffer->create();
    renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  }

  static void Fill(QOpenGLBuffer* buffer, const std::vector<float>& data) {
    buffer->bind();
    buffer->allocate(data.data(), static_cast<int>(data.size() * sizeof(float)));
    buffer->release();
  }

  void Upload(const View3dScene* scene) {
    std::vector<float> mesh_data, point_data, line_data;
    if (scene != nullptr) {
      mesh_data = MeshVertices(scene->mesh);
      for (size_t i = 0; i < scene->points.size(); ++i) {
        Push(&point_data, scene->points[i]);
        Push(&point_data, View3dPointColor(scene->point_values[i]));
      }
      for (const auto& [a, b] : scene->skeleton) {
        for (const Eigen::Vector3d& end : {a, b}) {
          Push(&line_data, end.cast<float>().eval());
          Push(&line_data, View3dSkeletonColor());
        }
      }
    }
    Fill(&mesh, mesh_data);
    Fill(&points, point_data);
    Fill(&lines, line_data);
    mesh_vertices = static_cast<int>(mesh_data.size() / kMeshFloats);
    point_vertices = static_cast<int>(point_data.size() / kFlatFloats);
    line_vertices = static_cast<int>(line_data.size() / kFlatFloats);
  }

  void DrawMesh(const QMatrix4x4& world_to_clip, const QMatrix3x3& world_to_cam) {
    if (mesh_vertices == 0) return;
    glEnable(GL_DEPTH_TEST);
    mesh_program.bind();
    mesh_program.setUniformValue("world_to_clip", world_to_clip);
    mesh_program.setUniformValue("world_to_cam", world_to_cam);
    mesh.bind();
    const char* names[] = {"position", "normal", "color"};
    for (int k = 0; k < 3; ++k) {
      mesh_program.enableAttributeArray(names[k]);
      mesh_program.setAttributeBuffer(names[k], GL_FLOAT, 3 * k * sizeof(float), 3,
                                      kMeshFloats * sizeof(float));
    }
    glDrawArrays(GL_TRIANGLES, 0, mesh_vertices);
    for (const char* name : names) mesh_program.disableAttributeArray(name);
    mesh.release();
    mesh_program.release();
    glDisable(GL_DEPTH_TEST);
  }

  // Drawn over the mesh, as the Embree view paints them.
  void DrawFlat(QOpenGLBuffer* buffer, int vertices, GLenum mode, const QMatrix4x4& world_to_clip) {
    if (vertices == 0) return;
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glEnable(kProgramPointSize);
    glLineWidth(1.5f);
    flat_program.bind();
    flat_program.setUniformValue("world_to_clip", world_to_clip);
    flat_program.setUniformValue("point_size", 3.2f);
    buffer->bind();
    flat_program.enableAttributeArray("position");
    flat_program.enableAttributeArray("color");
    flat_program.setAttributeBuffer("position", GL_FLOAT, 0, 3, kFlatFloats * sizeof(float));
    flat_program.setAttributeBuffer("color", GL_FLOAT, 3 * sizeof(float), 4,
                                    kFlatFloats * sizeof(float));
    glDrawArrays(mode, 0, vertices);
    flat_program.disableAttributeArray("position");
    flat_program.disableAttributeArray("color");
    buffer->release();
    flat_program.release();
    glDisable(kProgramPointSize);
    glDisable(GL_BLEND);
  }
};

View3dGl::View3dGl(QWidget* parent) : QOpenGLWidget(parent), gl_(std::make_unique<Gl>()) {
  setFocusPolicy(Qt::StrongFocus);
  setMinimumSize(200, 200);
}

View3dGl::~View3dGl() {
  // The buffers and programs belong to this widget's context.
  makeCurrent();
  gl_.reset();
  doneCurrent();
}

bool View3dGl::Available() {
  const QString platform = QGuiApplication::platformName();
  if (platform == "offscreen" || platform == "minimal") return false;
  QOpenGLContext context;
  if (!context.create() || context.isOpenGLES()) return false;
  QOffscreenSurface surface;
  surface.setFormat(context.format());
  surface.create();
  if (!surface.isValid() || !context.makeCurrent(&surface)) return false;
  const QSurfaceFormat format = context.format();
  context.doneCurrent();
  return format.majorVersion() > 2 || (format.majorVersion() == 2 && format.minorVersion() >= 1);
}

QString View3dGl::renderer_name() const { return gl_ ? gl_->renderer : QString(); }

void View3dGl::SetScene(std::shared_ptr<const View3dScene> scene) {
  scene_ = std::move(scene);
  uploaded_ = false;
  Redraw(true);
}

void View3dGl::SetShown(bool mesh, bool points, bool skeleton) {
  show_mesh_ = mesh;
  show_points_ = points;
  show_skeleton_ = skeleton;
  Redraw(true);
}

void View3dGl::FrameAll() {
  camera_.Frame(scene_ ? scene_->bounds : Box3d());
  Redraw(true);
}

void View3dGl::SetCamera(const OrbitCamera& camera) {
  camera_ = camera;
  Redraw(true);
}

void View3dGl::Redraw(bool changed) {
  if (changed) update();
}

void View3dGl::initializeGL() {
  gl_->Init();
  uploaded_ = false;
}

void View3dGl::paintGL() {
  const QColor background(kView3dBackground);
  gl_->glClearColor(background.redF(), background.greenF(), background.blueF(), 1.0f);
  gl_->glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (!uploaded_) gl_->Upload(scene_.get()), uploaded_ = true;
  if (HasScene()) {
    const PreviewView view = camera_.View(width(), height(), scene_->bounds);
    const QMatrix4x4 world_to_clip = WorldToClip(view, width(), height(), scene_->bounds);
    const Eigen::Matrix3d r = view.cam_from_world.rotation.toRotationMatrix();
    const float rotation[9] = {float(r(0, 0)), float(r(0, 1)), float(r(0, 2)),
                               float(r(1, 0)), float(r(1, 1)), float(r(1, 2)),
                               float(r(2, 0)), float(r(2, 1)), float(r(2, 2))};
    if (show_mesh_) gl_->DrawMesh(world_to_clip, QMatrix3x3(rotation));
    if (show_points_) gl_->DrawFlat(&gl_->points, gl_->point_vertices, GL_POINTS, world_to_clip);
    if (show_skeleton_) gl_->DrawFlat(&gl_->lines, gl_->line_vertices, GL_LINES, world_to_clip);
  }
  QPainter painter(this);
  painter.setPen(QColor(220, 220, 220));
  painter.drawText(rect().adjusted(8, 4, -8, -4), Qt::AlignLeft | Qt::AlignBottom,
                   View3dHint(HasScene()) + " · OpenGL");
}

void View3dGl::mousePressEvent(QMouseEvent* event) { camera_.Press(*event); }

void View3dGl::mouseMoveEvent(QMouseEvent* event) {
  Redraw(camera_.Move(*event, width(), height()));
}

void View3dGl::mouseReleaseEvent(QMouseEvent*) { Redraw(camera_.Release()); }

void View3dGl::wheelEvent(QWheelEvent* event) { Redraw(camera_.Wheel(*event)); }

void View3dGl::keyPressEvent(QKeyEvent* event) {
  if (!camera_.Key(*event, scene_ ? scene_->bounds : Box3d())) {
    QOpenGLWidget::keyPressEvent(event);
    return;
  }
  Redraw(true);
}

}  // namespace sylva
