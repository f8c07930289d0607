// sylva-app end to end on the bundled demo (datasets/demo, initialised as
// scripts/demo.sh does; a coarse grid so it stays quick): density painted
// with the app's brush into a region outside the tree in every input view
// makes the tree (its density and its mesh) cover it there after a re-run from the app, painting it
// out empties it again, and the same edit files run through the `sylva run` binary give the same
// tree.
#include <QElapsedTimer>
#include <QProcess>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QtTest>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/mesh_io.h"
#include "core/io/vdb_io.h"
#include "core/types/density_grid.h"
#include "core/types/triangle_mesh.h"
#include "core/util/file_util.h"
#include "ui/desktop/app_test_util.h"
#include "ui/desktop/edit_document.h"
#include "ui/desktop/main_window.h"
#include "ui/desktop/photo_view.h"
#include "ui/desktop/run_controller.h"
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/project.h"

namespace sylva {
namespace fs = std::filesystem;

// Options that keep the demo quick; saved in sylva.json, so the app and the
// CLI both read them.
const std::vector<std::pair<std::string, std::string>> kQuickOptions = {
    {"Density.resolution", "32"},
    {"Density.max_iterations", "15"},
    {"Report.previews", "false"},
    {"Report.mesh_samples_per_axis", "1"}};

// A disc on one input photo: the projection of a ball.
struct Disc {
  int photo_index;  // in Project::photo_names()
  std::string name;
  QPointF center;  // photo pixels
  double radius;
};

// The share of the disc's pixels that the tree's report silhouette `kind`
// covers (ReportCovers' test, on the picture's own pixels: the report draws
// at a fraction of the photo's size). A share, not the centre alone: a crown
// of leaves is speckled at that scale.
double DiscCoverage(const fs::path& root, const std::string& kind, const Disc& disc,
                    int photo_width) {
  const fs::path path =
      root / "out" / "report" / kind / fs::path(disc.name).replace_extension(".png");
  const QImage picture(QString::fromStdString(path.string()));
  if (picture.isNull()) return 0.0;
  const double scale = double(picture.width()) / photo_width;
  const QPointF centre = disc.center * scale;
  const double radius = disc.radius * scale;
  int inside = 0, covered = 0;
  for (int y = int(centre.y() - radius); y <= int(centre.y() + radius) + 1; ++y) {
    for (int x = int(centre.x() - radius); x <= int(centre.x() + radius) + 1; ++x) {
      if (std::hypot(x + 0.5 - centre.x(), y + 0.5 - centre.y()) > radius) continue;
      ++inside;
      covered += picture.valid(x, y) && qRed(picture.pixel(x, y)) >= 200;
    }
  }
  return inside > 0 ? double(covered) / inside : 0.0;
}

// The fraction of the discs of which the tree's report silhouette `kind`
// covers at least half.
double CoveredShare(const fs::path& root, const std::string& kind, const std::vector<Disc>& discs,
                    int photo_width) {
  int covered = 0;
  for (const Disc& disc : discs) {
    const double share = DiscCoverage(root, kind, disc, photo_width);
    qInfo("  %s: %s silhouette covers %.0f %% of the disc", disc.name.c_str(), kind.c_str(),
          100 * share);
    covered += share >= 0.5;
  }
  return double(covered) / discs.size();
}

class AppDemoTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase();
  void paintedDensityInAndOutOfEveryViewAndCliGivesSameTree();

 private:
  // A ball low beside the trunk that no input view's silhouette covers, as
  // discs on the input photos.
  std::vector<Disc> FindEmptyRegion(const Project& project);
  void Paint(MainWindow* window, const std::vector<Disc>& discs, Tool tool);
  void RunFromApp(MainWindow* window);
  void RunCliOnCopy(const fs::path& copy);

  QTemporaryDir temp_;
  fs::path project_;
  int photo_width_ = 0;
};

void AppDemoTest::initTestCase() {
  QVERIFY(temp_.isValid());
  qputenv("XDG_CONFIG_HOME", (temp_.path() + "/config").toUtf8());
  const fs::path demo = fs::path(SYLVA_SOURCE_DIR) / "datasets" / "demo";
  ProjectSetup setup;  // as scripts/demo.sh's `sylva init`
  setup.root = fs::path(temp_.path().toStdString()) / "demo-project";
  setup.photos_dir = demo / "photos";
  setup.mattes_dir = demo / "mattes";
  setup.colmap_model_dir = demo / "colmap";
  setup.held_out = {"heldout_00.png", "heldout_01.png"};
  setup.units = "m";
  Project project = Project::Create(setup);
  project_ = setup.root;
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  for (const auto& [key, value] : kQuickOptions) registry.Set(key, value, "test");
  project.SaveOptions(registry);
  QElapsedTimer timer;
  timer.start();
  Pipeline(project, options, nullptr).Run(Stage::kReport, false);
  qInfo("demo pipeline: %.2f s", timer.elapsed() / 1000.0);
  photo_width_ = QImage(QString::fromStdString(project.PhotoPath("view_00.png").string())).width();
  QCOMPARE(photo_width_, 512);
}

std::vector<Disc> AppDemoTest::FindEmptyRegion(const Project& project) {
  const ImageSet cameras = project.LoadCameras();
  const Box3d box = ReadDensityGrid(project.OutDir() / "density.vdb").ActiveWorldBounds();
  const Eigen::Vector3d size = box.sizes();
  const double radius = 0.05 * size.z();
  // Candidates on a ring around the trunk at a tenth of the tree's height
  // (below the crown: above its top the demo's photos are cut off).
  for (int k = 0; k < 24; ++k) {
    const double angle = 2 * M_PI * k / 24;
    const Eigen::Vector3d ball(box.center().x() + 0.25 * size.x() * std::cos(angle),
                               box.center().y() + 0.25 * size.y() * std::sin(angle),
                               box.min().z() + 0.1 * size.z());
    std::vector<Disc> discs;
    bool empty = true;
    for (int v = 0; v < cameras.NumViews() && empty; ++v) {
      const std::string& name = cameras.views[v].name;
      if (project.IsHeldOut(name)) continue;
      Eigen::Vector2d middle, top;
      if (!cameras.Project(v, ball, &middle) ||
          !cameras.Project(v, ball + radius * Eigen::Vector3d::UnitZ(), &top)) {
        empty = false;
        break;
      }
      const auto& names = project.photo_names();
      const Disc disc{int(std::find(names.begin(), names.end(), name) - names.begin()), name,
                      QPointF(middle.x(), middle.y()), std::max(4.0, (top - middle).norm())};
      // Empty in and around the disc, for both silhouettes.
      for (const QPointF& d : {QPointF(0, 0), QPointF(disc.radius, 0), QPointF(-disc.radius, 0),
                               QPointF(0, disc.radius), QPointF(0, -disc.radius)}) {
        for (const char* kind : {"density", "mesh"}) {
          empty = empty && !ReportCovers(project.root(), kind, name, disc.center + d, photo_width_);
        }
      }
      discs.push_back(disc);
    }
    if (empty) return discs;
  }
  return {};
}

void AppDemoTest::Paint(MainWindow* window, const std::vector<Disc>& discs, Tool tool) {
  for (const Disc& disc : discs) {
    window->SelectPhoto(disc.photo_index);
    QCOMPARE(window->photo_view()->photo_name(), disc.name);
    window->SetTool(tool);
    window->photo_view()->brush() = BrushShape{disc.radius, 1.0, 1.0};
    PhotoView* view = window->photo_view();
    QWidget* viewport = view->viewport();
    const QPoint from = view->mapFromScene(disc.center - QPointF(0.5, 0));
    const QPoint to = view->mapFromScene(disc.center + QPointF(0.5, 0));
    QTest::mousePress(viewport, Qt::LeftButton, {}, from);
    QMouseEvent move(QEvent::MouseMove, to, viewport->mapToGlobal(to), Qt::NoButton, Qt::LeftButton,
                     Qt::NoModifier);
    QApplication::sendEvent(viewport, &move);
    QTest::mouseRelease(viewport, Qt::LeftButton, {}, to);
  }
}

void AppDemoTest::RunFromApp(MainWindow* window) {
  QSignalSpy finished(window->run_controller(), &RunController::Finished);
  QElapsedTimer timer;
  timer.start();
  window->RunAll();
  QVERIFY(finished.wait(120000));
  QVERIFY2(finished.last().at(0).toBool(), qPrintable(finished.last().at(2).toString()));
  qInfo("re-run from the app: %.2f s", timer.elapsed() / 1000.0);
}

void AppDemoTest::RunCliOnCopy(const fs::path& copy) {
  // The project as a user would copy it: settings, cameras and edits, no
  // outputs or cache.
  fs::create_directories(copy);
  for (const auto& entry : fs::directory_iterator(project_)) {
    const std::string name = entry.path().filename().string();
    if (name == "out" || name == "cache") continue;
    fs::copy(entry.path(), copy / name, fs::copy_options::recursive);
  }
  QProcess cli;
  QElapsedTimer timer;
  timer.start();
  cli.start(SYLVA_BINARY_DIR "/bin/sylva", {"run", QString::fromStdString(copy.string())});
  QVERIFY(cli.waitForFinished(180000));
  QVERIFY2(cli.exitCode() == 0, cli.readAllStandardError().constData());
  qInfo("sylva run on the copy: %.2f s", timer.elapsed() / 1000.0);
}

void AppDemoTest::paintedDensityInAndOutOfEveryViewAndCliGivesSameTree() {
  MainWindow window(false);
  QVERIFY(ShowWithProject(&window, project_));
  const std::vector<Disc> discs = FindEmptyRegion(*window.project());
  QCOMPARE(discs.size(), size_t(8));  // every input view
  qInfo("region: disc radius %.1f px in view %s", discs[0].radius, discs[0].name.c_str());

  // Painted in: the tree's density and its mesh (the wood that carries the
  // painted density is kept, simulate/painted_density.h, and grows leaves
  // there) cover the region in every input view.
  Paint(&window, discs, Tool::kDensityAdd);
  QCOMPARE(window.document()->undo_stack()->count(), 8);
  RunFromApp(&window);
  const double density_in = CoveredShare(project_, "density", discs, photo_width_);
  const double mesh_in = CoveredShare(project_, "mesh", discs, photo_width_);
  qInfo("painted in: density projection covers %.0f %%, mesh silhouette %.0f %% of the views",
        100 * density_in, 100 * mesh_in);
  QCOMPARE(density_in, 1.0);
  QCOMPARE(mesh_in, 1.0);
  // Only the density and what follows re-ran.
  for (const StageRun& stage : window.run_controller()->last_summary().stages) {
    QCOMPARE(stage.up_to_date, stage.stage == Stage::kMatte || stage.stage == Stage::kRegister);
  }

  // The same edit files through the CLI, from scratch on a copy: the same
  // tree. Compared by the mesh's counts and bounding box (to 1e-6: the
  // pipeline is deterministic for a seed, so any difference means a
  // different input or option) and the skeleton file, byte for byte.
  const fs::path copy = fs::path(temp_.path().toStdString()) / "cli-copy";
  RunCliOnCopy(copy);
  const TriangleMesh app_tree = ReadObj(project_ / "out" / "tree.obj");
  const TriangleMesh cli_tree = ReadObj(copy / "out" / "tree.obj");
  qInfo("app tree: %d vertices, %d triangles; CLI tree: %d vertices, %d triangles",
        app_tree.NumVertices(), app_tree.NumTriangles(), cli_tree.NumVertices(),
        cli_tree.NumTriangles());
  QCOMPARE(cli_tree.NumVertices(), app_tree.NumVertices());
  QCOMPARE(cli_tree.NumTriangles(), app_tree.NumTriangles());
  QVERIFY((cli_tree.Bounds().min() - app_tree.Bounds().min()).norm() < 1e-6);
  QVERIFY((cli_tree.Bounds().max() - app_tree.Bounds().max()).norm() < 1e-6);
  QVERIFY(ReadFileToString(copy / "out" / "skeleton.json") ==
          ReadFileToString(project_ / "out" / "skeleton.json"));
  QCOMPARE(CoveredShare(copy, "density", discs, photo_width_), 1.0);
  QCOMPARE(CoveredShare(copy, "mesh", discs, photo_width_), 1.0);

  // Painted out: the region empties again.
  Paint(&window, discs, Tool::kDensityRemove);
  RunFromApp(&window);
  const double density_out = CoveredShare(project_, "density", discs, photo_width_);
  const double mesh_out = CoveredShare(project_, "mesh", discs, photo_width_);
  qInfo("painted out: density projection covers %.0f %%, mesh silhouette %.0f %% of the views",
        100 * density_out, 100 * mesh_out);
  QCOMPARE(density_out, 0.0);
  QCOMPARE(mesh_out, 0.0);
  // Leave the project without edits.
  while (window.document()->undo_stack()->canUndo()) window.document()->undo_stack()->undo();
  for (const Disc& disc : discs) {
    QVERIFY(!fs::exists(project_ / "edits" / "density" / disc.name));
  }
}

}  // namespace sylva

QTEST_MAIN(sylva::AppDemoTest)
#include "app_demo_test.moc"
