// The app's OpenGL 3D view (view_3d_gl.h), under a headless X server
// (xvfb-run, Mesa's software rasteriser): it can be made, it draws the same
// tree as the Embree view from the same camera, navigates as it does, and
// `sylva-app --view3d opengl --screenshot` shows it.
#include <QElapsedTimer>
#include <QProcess>
#include <QTemporaryDir>
#include <QtTest>
#include <filesystem>

#include "ui/desktop/app_test_util.h"
#include "ui/desktop/main_window.h"
#include "ui/desktop/view_3d.h"
#include "ui/desktop/view_3d_gl.h"

namespace sylva {
namespace fs = std::filesystem;

// Rows at the foot of a 3D view left out of comparisons (its help text).
constexpr int kHintRows = 30;

bool IsTree(QRgb pixel) {
  const QRgb background = kView3dBackground;
  return std::abs(qRed(pixel) - qRed(background)) + std::abs(qGreen(pixel) - qGreen(background)) +
             std::abs(qBlue(pixel) - qBlue(background)) >
         24;
}

// The share of `a`'s tree pixels that have a tree pixel of `b` within one
// pixel (the renderers sample thin twigs and leaf edges differently: Embree
// 2 x 2 rays per pixel, OpenGL one sample).
double MatchedShare(const QImage& a, const QImage& b) {
  int tree = 0, matched = 0;
  const int width = std::min(a.width(), b.width());
  const int height = std::min(a.height(), b.height()) - kHintRows;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (!IsTree(a.pixel(x, y))) continue;
      ++tree;
      bool near = false;
      for (int dy = -1; dy <= 1 && !near; ++dy) {
        for (int dx = -1; dx <= 1 && !near; ++dx) {
          const int xx = x + dx, yy = y + dy;
          near = xx >= 0 && yy >= 0 && xx < width && yy < height && IsTree(b.pixel(xx, yy));
        }
      }
      matched += near;
    }
  }
  return tree > 0 ? double(matched) / tree : 0.0;
}

// The share of tree pixels in `picture`.
double TreeShare(const QImage& picture) {
  int tree = 0;
  for (int y = 0; y < picture.height() - kHintRows; ++y) {
    for (int x = 0; x < picture.width(); ++x) tree += IsTree(picture.pixel(x, y));
  }
  return double(tree) / (picture.width() * (picture.height() - kHintRows));
}

class AppGlTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase();
  void openGlViewDrawsWhatTheEmbreeViewDraws();
  void openGlViewNavigatesAndKeepsTheCameraWhenSwitched();
  void screenshotCommandShowsTheOpenGlView();

 private:
  QTemporaryDir temp_;
  fs::path project_;
};

void AppGlTest::initTestCase() {
  QVERIFY(temp_.isValid());
  qputenv("XDG_CONFIG_HOME", (temp_.path() + "/config").toUtf8());
  QCOMPARE(QGuiApplication::platformName(), QString("xcb"));  // run by xvfb-run
  QVERIFY2(View3dGl::Available(), "no OpenGL context under xvfb-run");
  const fs::path data = fs::path(temp_.path().toStdString()) / "data";
  WriteTinySyntheticSet(data, 96);
  project_ = fs::path(temp_.path().toStdString()) / "project";
  CreateSmallProject(data, project_);
  RunSmallPipeline(project_);
  const Project project = Project::Open(project_);
  QVERIFY(fs::is_regular_file(project.OutDir() / "tree.obj"));
}

void AppGlTest::openGlViewDrawsWhatTheEmbreeViewDraws() {
  MainWindow window(false);
  QVERIFY(ShowWithProject(&window, project_));
  QVERIFY(window.UseOpenGlView(true));
  QVERIFY(window.opengl_view_shown());
  View3dGl* gl = window.view_3d_gl();
  QVERIFY(gl != nullptr && gl->HasScene());
  QVERIFY(QTest::qWaitForWindowExposed(gl));
  const QImage gl_picture = gl->grabFramebuffer().convertToFormat(QImage::Format_RGB32);
  qInfo("OpenGL renderer: %s", qPrintable(gl->renderer_name()));
  // The Embree view of the same scene and camera, at the same size.
  View3d embree;
  embree.resize(gl->size());
  embree.SetScene(window.view_3d()->scene());
  embree.SetShown(true, false, false);  // as the window's layer boxes
  embree.SetCamera(gl->camera());
  const QImage embree_picture = embree.grab().toImage().convertToFormat(QImage::Format_RGB32);
  QCOMPARE(embree_picture.size(), gl_picture.size());
  const double share = TreeShare(gl_picture);
  const double gl_in_embree = MatchedShare(gl_picture, embree_picture);
  const double embree_in_gl = MatchedShare(embree_picture, gl_picture);
  qInfo(
      "tree pixels: %.1f %% of the OpenGL view, %.1f %% of the Embree view; within 1 px of "
      "the other's: %.3f (OpenGL), %.3f (Embree)",
      100 * share, 100 * TreeShare(embree_picture), gl_in_embree, embree_in_gl);
  QVERIFY(share > 0.02);
  QVERIFY(gl_in_embree > 0.9);
  QVERIFY(embree_in_gl > 0.9);

  // The skeleton alone, in its colour.
  gl->SetShown(false, false, true);
  const QImage skeleton = gl->grabFramebuffer().convertToFormat(QImage::Format_RGB32);
  int orange = 0;
  for (int y = 0; y < skeleton.height(); ++y) {
    for (int x = 0; x < skeleton.width(); ++x) {
      const QColor c = skeleton.pixelColor(x, y);
      orange += c.red() > 200 && c.green() > 100 && c.green() < 200 && c.blue() < 100;
    }
  }
  qInfo("skeleton alone: %d orange pixels", orange);
  QVERIFY(orange > 50);
}

void AppGlTest::openGlViewNavigatesAndKeepsTheCameraWhenSwitched() {
  MainWindow window(false);
  QVERIFY(ShowWithProject(&window, project_));
  QVERIFY(window.UseOpenGlView(true));
  View3dGl* gl = window.view_3d_gl();
  QVERIFY(QTest::qWaitForWindowExposed(gl));
  const QImage before = gl->grabFramebuffer();
  const QPoint middle(gl->width() / 2, gl->height() / 2);
  QTest::mousePress(gl, Qt::MiddleButton, Qt::NoModifier, middle);
  QMouseEvent move(QEvent::MouseMove, middle + QPoint(100, 0),
                   gl->mapToGlobal(middle + QPoint(100, 0)), Qt::NoButton, Qt::MiddleButton,
                   Qt::NoModifier);
  QApplication::sendEvent(gl, &move);
  QTest::mouseRelease(gl, Qt::MiddleButton, Qt::NoModifier, middle + QPoint(100, 0));
  QCOMPARE(gl->camera().azimuth_deg(), -40.0);
  const QImage after = gl->grabFramebuffer();
  QVERIFY(after != before);
  // Back to Embree: the same camera.
  QVERIFY(window.UseOpenGlView(false));
  QVERIFY(!window.opengl_view_shown());
  QCOMPARE(window.view_3d()->azimuth_deg(), -40.0);
}

void AppGlTest::screenshotCommandShowsTheOpenGlView() {
  const QString out = temp_.path() + "/gl.png";
  QProcess app;
  app.start(SYLVA_BINARY_DIR "/bin/sylva-app",
            {QString::fromStdString(project_.string()), "--view3d", "opengl", "--screenshot", out});
  QVERIFY(app.waitForFinished(60000));
  QVERIFY2(app.exitCode() == 0, app.readAllStandardError().constData());
  const QImage shot(out);
  QVERIFY(!shot.isNull());
  // The 3D view is where its background colour is (the photo view's is
  // darker); the tree is drawn inside it.
  QRect view;
  for (int y = 0; y < shot.height(); ++y) {
    for (int x = 0; x < shot.width(); ++x) {
      if (shot.pixel(x, y) == kView3dBackground) view |= QRect(x, y, 1, 1);
    }
  }
  QVERIFY(view.width() > 100 && view.height() > 100);
  int tree = 0;
  for (int y = view.top(); y < view.bottom() - kHintRows; ++y) {
    for (int x = view.left(); x <= view.right(); ++x) tree += IsTree(shot.pixel(x, y));
  }
  const double share = double(tree) / (view.width() * (view.height() - kHintRows));
  qInfo("screenshot: 3D view %dx%d, %.1f %% tree pixels", view.width(), view.height(), 100 * share);
  QVERIFY(share > 0.02);
}

}  // namespace sylva

QTEST_MAIN(sylva::AppGlTest)
#include "app_gl_test.moc"
