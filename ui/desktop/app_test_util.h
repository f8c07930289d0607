// What the app's QTest suites share (app_test.cc, app_demo_test.cc).
#ifndef SYLVA_UI_DESKTOP_APP_TEST_UTIL_H_
#define SYLVA_UI_DESKTOP_APP_TEST_UTIL_H_

#include <QImage>
#include <QPointF>
#include <QtTest>
#include <filesystem>
#include <string>

#include "ui/desktop/main_window.h"
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/pipeline_test_util.h"
#include "ui/pipeline/project.h"

namespace sylva {

// The project `root` of the synthetic set in `data` (WriteTinySyntheticSet), as `sylva init` makes
// it.
inline void CreateSmallProject(const std::filesystem::path& data,
                               const std::filesystem::path& root) {
  ProjectSetup setup;
  setup.root = root;
  setup.photos_dir = data / "photos";
  setup.colmap_model_dir = data / "colmap";
  setup.mattes_dir = data / "mattes";
  setup.held_out = {"heldout_00.png"};
  Project::Create(setup);
}

// Every stage of the project at `root`, small (a 32 grid, no previews;
// saved in its sylva.json, so the app and the CLI read them too).
inline void RunSmallPipeline(const std::filesystem::path& root) {
  Project project = Project::Open(root);
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  registry.Set("Density.resolution", "32", "test");
  registry.Set("Report.previews", "false", "test");
  project.SaveOptions(registry);
  Pipeline(project, options, nullptr).Run(Stage::kReport, false);
}

// Shows `window` at `width` x `height`, waits until it is on screen and
// opens `project`; false if either fails (for QVERIFY).
inline bool ShowWithProject(MainWindow* window, const std::filesystem::path& project,
                            int width = 1200, int height = 800) {
  window->resize(width, height);
  window->show();
  return QTest::qWaitForWindowExposed(window) && window->OpenProject(project);
}

// Whether the report's comparison picture `kind` ("density" or "mesh") of
// `view_name` (out/report/<kind>/<view>.png, at its own scale) predicts
// photo pixel `point`: predicted pixels have a high red channel.
// `photo_width` is the photo's width in pixels.
inline bool ReportCovers(const std::filesystem::path& root, const std::string& kind,
                         const std::string& view_name, const QPointF& point, int photo_width) {
  const std::filesystem::path path =
      root / "out" / "report" / kind / std::filesystem::path(view_name).replace_extension(".png");
  const QImage picture(QString::fromStdString(path.string()));
  if (picture.isNull()) return false;
  const double scale = double(picture.width()) / photo_width;
  const QPoint pixel(int(point.x() * scale), int(point.y() * scale));
  return picture.valid(pixel) && qRed(picture.pixel(pixel)) >= 200;
}

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_APP_TEST_UTIL_H_
