// sylva-app: the desktop app (ui/desktop/main_window.h).
//
//   sylva-app [PROJECT] [--photo NAME] [--panel layers|run|options|photos|sketch]
//             [--sketch DRAWING.svg] [--run] [--screenshot FILE.png]
//             [--view3d auto|opengl|embree]
//
// --screenshot renders the main window (photo with overlays, 3D view) for
// PROJECT into FILE.png and exits; it needs no display
// (QT_QPA_PLATFORM=offscreen). --run first runs the out-of-date stages, as
// the Run panel's "Run all" does. --sketch opens a drawing on the sketch
// canvas (and shows it). --view3d chooses the 3D view: OpenGL, or Embree on
// the CPU; auto (the default) takes OpenGL where a context can be made
// (not on the offscreen platform). Exit codes: 0 ok, 2 bad arguments or
// project, or --view3d opengl where OpenGL cannot be used.
#include <QApplication>
#include <QEventLoop>
#include <QStringList>
#include <algorithm>
#include <exception>
#include <iostream>

#include "core/util/memory.h"
#include "ui/desktop/main_window.h"
#include "ui/desktop/run_controller.h"
#include "ui/desktop/sketch_canvas.h"
#include "ui/pipeline/project.h"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;

int Usage(const QString& problem) {
  std::cerr << "sylva-app: " << problem.toStdString()
            << "\nusage: sylva-app [PROJECT] [--photo NAME] "
               "[--panel layers|run|options|photos|sketch] [--sketch DRAWING.svg] [--run] "
               "[--screenshot FILE.png] [--view3d auto|opengl|embree]\n";
  return kExitBadInput;
}

}  // namespace

int main(int argc, char** argv) {
  sylva::KeepFreedMemoryForReuse();
  QApplication app(argc, argv);
  QApplication::setApplicationName("sylva-app");
  QApplication::setOrganizationName("sylva");
  QString project, screenshot, photo, panel, sketch, view3d = "auto";
  bool run = false;
  const QStringList args = QApplication::arguments();
  for (int i = 1; i < args.size(); ++i) {
    const QString& arg = args[i];
    if (arg == "--screenshot" && i + 1 < args.size()) {
      screenshot = args[++i];
    } else if (arg == "--photo" && i + 1 < args.size()) {
      photo = args[++i];
    } else if (arg == "--sketch" && i + 1 < args.size()) {
      sketch = args[++i];
    } else if (arg == "--view3d" && i + 1 < args.size()) {
      view3d = args[++i];
      if (view3d != "auto" && view3d != "opengl" && view3d != "embree") {
        return Usage("--view3d takes auto, opengl or embree, not " + view3d);
      }
    } else if (arg == "--run") {
      run = true;
    } else if (arg == "--panel" && i + 1 < args.size()) {
      panel = args[++i];
    } else if (arg.startsWith("--")) {
      return Usage("unknown or incomplete option " + arg);
    } else if (project.isEmpty()) {
      project = arg;
    } else {
      return Usage("more than one project given");
    }
  }
  if (!screenshot.isEmpty() && project.isEmpty()) return Usage("--screenshot needs a PROJECT");

  sylva::MainWindow window(/*interactive=*/screenshot.isEmpty());
  if (view3d != "embree" && !window.UseOpenGlView(true) && view3d == "opengl") {
    return Usage("--view3d opengl: no OpenGL context can be made on platform '" +
                 QApplication::platformName() + "'");
  }
  if (!project.isEmpty() && !window.OpenProject(project.toStdString())) {
    if (!screenshot.isEmpty()) return kExitBadInput;
  }
  if (!photo.isEmpty() && window.project() != nullptr) {
    const auto& names = window.project()->photo_names();
    const auto it = std::find(names.begin(), names.end(), photo.toStdString());
    if (it == names.end()) return Usage("no photo " + photo + " in the project");
    window.SelectPhoto(static_cast<int>(it - names.begin()));
  }
  if (!sketch.isEmpty()) {
    try {
      window.sketch_canvas()->OpenSvg(sketch.toStdString());
    } catch (const std::exception& error) {
      return Usage(QString::fromStdString(error.what()));
    }
    window.ShowPanel("sketch");
  }
  if (!panel.isEmpty() && !window.ShowPanel(panel)) return Usage("no panel " + panel);
  window.show();
  if (run && window.project() != nullptr) {
    QEventLoop loop;
    QObject::connect(window.run_controller(), &sylva::RunController::Finished, &loop,
                     &QEventLoop::quit, Qt::QueuedConnection);
    window.RunAll();
    loop.exec();
  }
  if (!screenshot.isEmpty()) {
    return window.SaveScreenshot(screenshot.toStdString()) ? kExitOk : kExitBadInput;
  }
  return QApplication::exec();
}
