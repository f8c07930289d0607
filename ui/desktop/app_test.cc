// Headless tests of sylva-app (QTest, QT_QPA_PLATFORM=offscreen): brushes
// write the edit files the pipeline reads, undo/redo restore them, Cancel
// stops a running stage promptly leaving the project as it was, the options
// panel round-trips every option through sylva.json, and --screenshot
// renders the photo and the 3D view.
#include <QCheckBox>
#include <QElapsedTimer>
#include <QLineEdit>
#include <QPlainTextEdit>
#include <QProcess>
#include <QProgressBar>
#include <QPushButton>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QtTest>
#include <chrono>
#include <filesystem>
#include <map>
#include <string>

#include "core/io/image_io.h"
#include "core/io/vdb_io.h"
#include "core/types/density_grid.h"
#include "core/util/file_util.h"
#include "datasets/synthetic/synthetic_dataset.h"
#include "reconstruct/matting/trimap_io.h"
#include "reconstruct/registration/loose_setup_io.h"
#include "sketch/drawing_io.h"
#include "sketch/strokes.h"
#include "ui/desktop/app_test_util.h"
#include "ui/desktop/edit_document.h"
#include "ui/desktop/loose_cameras_page.h"
#include "ui/desktop/main_window.h"
#include "ui/desktop/new_project_wizard.h"
#include "ui/desktop/options_panel.h"
#include "ui/desktop/photo_view.h"
#include "ui/desktop/run_controller.h"
#include "ui/desktop/sketch_canvas.h"
#include "ui/desktop/view_3d.h"
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/project.h"

namespace sylva {
namespace fs = std::filesystem;

// Every file under `dir` with its size and modification time.
std::map<std::string, std::pair<uintmax_t, fs::file_time_type>> Snapshot(const fs::path& dir) {
  std::map<std::string, std::pair<uintmax_t, fs::file_time_type>> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) {
      files[entry.path().string()] = {entry.file_size(), entry.last_write_time()};
    }
  }
  return files;
}

class AppTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase();
  void densityBrushWritesEditAndUndoRedoRestoreIt();
  void trimapStrokesCrownAndEraserWriteTheirFiles();
  void polylineStrokesAreOneUndoStepEach();
  void newProjectWizardMakesWhatSylvaInitMakes();
  void wizardManualCamerasPageWritesTheLooseCamerasFile();
  void sketchCanvasSavesTheSvgSylvaSketchReads();
  void optionsPanelRoundTripsEveryOption();
  void screenshotShowsPhotoAndTree();
  void screenshotCommandWritesPng();
  void paintedDensityGrowsAndEmptiesTheTreeAfterRerun();
  void cancelStopsRunningStageAndLeavesProject();

 private:
  fs::path CreateProject(const std::string& name);
  // Drags the left button along photo-pixel points on the photo view.
  void Drag(MainWindow* window, const std::vector<QPointF>& points);

  QTemporaryDir temp_;
  fs::path data_, project_;
};

fs::path AppTest::CreateProject(const std::string& name) {
  const fs::path root = data_.parent_path() / name;
  CreateSmallProject(data_, root);
  return root;
}

void AppTest::initTestCase() {
  QVERIFY(temp_.isValid());
  qputenv("XDG_CONFIG_HOME", (temp_.path() + "/config").toUtf8());  // recent projects
  data_ = fs::path(temp_.path().toStdString()) / "data";
  WriteTinySyntheticSet(data_, 96);
  project_ = CreateProject("project");
  // The whole pipeline once, small, so the outputs exist.
  QElapsedTimer timer;
  timer.start();
  RunSmallPipeline(project_);
  qInfo("pipeline on the test project: %.2f s", timer.elapsed() / 1000.0);
  QVERIFY(fs::is_regular_file(Project::Open(project_).OutDir() / "tree.obj"));
}

void AppTest::Drag(MainWindow* window, const std::vector<QPointF>& points) {
  PhotoView* view = window->photo_view();
  QWidget* viewport = view->viewport();
  const auto at = [&](const QPointF& p) { return view->mapFromScene(p); };
  QTest::mousePress(viewport, Qt::LeftButton, {}, at(points.front()));
  for (size_t i = 1; i < points.size(); ++i) {
    QMouseEvent move(QEvent::MouseMove, at(points[i]), viewport->mapToGlobal(at(points[i])),
                     Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(viewport, &move);
  }
  QTest::mouseRelease(viewport, Qt::LeftButton, {}, at(points.back()));
}

void AppTest::densityBrushWritesEditAndUndoRedoRestoreIt() {
  MainWindow window(false);
  QVERIFY(ShowWithProject(&window, project_));
  const std::string photo = window.photo_view()->photo_name();
  QCOMPARE(QString::fromStdString(photo), QString("view_00.png"));
  const fs::path file = project_ / "edits" / "density" / "view_00.png";
  QVERIFY(!fs::exists(file));
  Project project = Project::Open(project_);
  const Pipeline pipeline(project, window.options_panel()->options(), nullptr);
  const std::string density_key = pipeline.StageKey(Stage::kDensity);
  const std::string register_key = pipeline.StageKey(Stage::kRegister);
  QVERIFY(pipeline.IsUpToDate(Stage::kDensity));

  // A hard brush of radius 5 along y = 30 from x = 20 to x = 70: in.
  window.SetTool(Tool::kDensityAdd);
  window.photo_view()->brush() = BrushShape{5.0, 1.0, 1.0};
  Drag(&window, {{20, 30}, {45, 30}, {70, 30}});
  QVERIFY(fs::is_regular_file(file));
  QImage added(QString::fromStdString(file.string()));
  added = added.convertToFormat(QImage::Format_RGBA8888);
  QCOMPARE(added.size(), QSize(96, 96));
  QCOMPARE(added.pixelColor(45, 30), QColor(255, 255, 255, 255));
  QCOMPARE(added.pixelColor(20, 32), QColor(255, 255, 255, 255));
  QCOMPARE(added.pixelColor(45, 37).alpha(), 0);  // 7.5 px from the line
  QCOMPARE(added.pixelColor(5, 80).alpha(), 0);
  // The pipeline reads it: the density is out of date, registration not.
  QVERIFY(pipeline.StageKey(Stage::kDensity) != density_key);
  QCOMPARE(pipeline.StageKey(Stage::kRegister), register_key);
  // Through the pipeline's own reader: mix(matte, 1, 1) = 1 under the stroke.
  const FloatImage edited = project.LoadEditedMatte(project.LoadCameras(), 0);
  QCOMPARE(edited.at(45, 30), 1.0f);

  // A soft half-strength brush out, across it at x = 45.
  window.SetTool(Tool::kDensityRemove);
  window.photo_view()->brush() = BrushShape{4.0, 1.0, 0.5};
  Drag(&window, {{45, 20}, {45, 40}});
  QImage both =
      QImage(QString::fromStdString(file.string())).convertToFormat(QImage::Format_RGBA8888);
  // Over: alpha 0.5 + 1 * 0.5 = 1, grey (0 * 0.5 + 1 * 1 * 0.5) / 1 = 0.5.
  QCOMPARE(both.pixelColor(45, 30).alpha(), 255);
  QVERIFY(std::abs(both.pixelColor(45, 30).red() - 128) <= 1);
  // Where only the remove brush went: alpha 0.5, grey 0.
  QVERIFY(std::abs(both.pixelColor(45, 22).alpha() - 128) <= 1);
  QCOMPARE(both.pixelColor(45, 22).red(), 0);

  // Undo, undo, redo, redo.
  QUndoStack* stack = window.document()->undo_stack();
  QCOMPARE(stack->count(), 2);
  stack->undo();
  QCOMPARE(QImage(QString::fromStdString(file.string())).convertToFormat(QImage::Format_RGBA8888),
           added);
  stack->undo();
  QVERIFY(!fs::exists(file));
  QCOMPARE(pipeline.StageKey(Stage::kDensity), density_key);  // as before any edit
  stack->redo();
  QCOMPARE(QImage(QString::fromStdString(file.string())).convertToFormat(QImage::Format_RGBA8888),
           added);
  stack->redo();
  QCOMPARE(QImage(QString::fromStdString(file.string())).convertToFormat(QImage::Format_RGBA8888),
           both);
  // Clean up for the other tests.
  stack->undo();
  stack->undo();
  QVERIFY(!fs::exists(file));
}

void AppTest::trimapStrokesCrownAndEraserWriteTheirFiles() {
  MainWindow window(false);
  QVERIFY(ShowWithProject(&window, project_));
  const Project project = Project::Open(project_);

  // Trimap: a foreground stroke, read back by the matte stage's reader.
  window.SetTool(Tool::kTrimapForeground);
  window.photo_view()->brush() = BrushShape{4.0, 1.0, 1.0};
  Drag(&window, {{30, 60}, {60, 60}});
  const fs::path trimap_file = project_ / "edits" / "trimaps" / "view_00.png";
  QCOMPARE(project.TrimapHintPath("view_00.png"), trimap_file);
  const FloatImage hint = ReadHintTrimap(trimap_file);
  QCOMPARE(hint.at(45, 60), 1.0f);
  QCOMPARE(hint.at(45, 70), 0.5f);  // unpainted
  window.SetTool(Tool::kTrimapBackground);
  Drag(&window, {{10, 10}, {12, 10}});
  QCOMPARE(ReadHintTrimap(trimap_file).at(11, 10), 0.0f);

  // A branch stroke and the tree base.
  window.SetTool(Tool::kStrokes);
  Drag(&window, {{48, 90}, {48, 70}, {50, 50}, {60, 35}});
  const fs::path strokes_file = project_ / "edits" / "view_00.strokes.json";
  QCOMPARE(project.StrokesPath("view_00.png"), strokes_file);
  StrokeSet strokes = ReadStrokes(strokes_file, 96, 96);
  QCOMPARE(strokes.strokes.size(), size_t(1));
  QCOMPARE(strokes.strokes[0].points.size(), size_t(4));
  QVERIFY((strokes.strokes[0].points.back() - Eigen::Vector2d(60, 35)).norm() < 1.0);
  QTest::mouseClick(window.photo_view()->viewport(), Qt::LeftButton, Qt::ShiftModifier,
                    window.photo_view()->mapFromScene(QPointF(48, 92)));
  strokes = ReadStrokes(strokes_file, 96, 96);
  QVERIFY(strokes.root && (*strokes.root - Eigen::Vector2d(48, 92)).norm() < 1.0);

  // A crown outline raises the edited matte inside it.
  window.SetTool(Tool::kCrown);
  Drag(&window, {{5, 5}, {25, 5}, {25, 25}, {5, 25}});
  QVERIFY(fs::is_regular_file(project.CrownEditPath("view_00.png")));
  const FloatImage matte = project.LoadEditedMatte(project.LoadCameras(), 0);
  QVERIFY(matte.at(15, 15) >= kCrownOutlineOpacity - 1e-6);

  // The eraser over the branch stroke removes it (and the file).
  window.SetTool(Tool::kEraser);
  window.photo_view()->brush() = BrushShape{3.0, 1.0, 1.0};
  Drag(&window, {{46, 80}, {50, 80}});
  QVERIFY(!fs::exists(strokes_file) || ReadStrokes(strokes_file, 96, 96).strokes.empty());

  // Undo everything: no edit file is left.
  QUndoStack* stack = window.document()->undo_stack();
  QCOMPARE(stack->count(), 6);
  while (stack->canUndo()) stack->undo();
  QVERIFY(!fs::exists(trimap_file));
  QVERIFY(!fs::exists(strokes_file));
  QVERIFY(project.CrownEditPath("view_00.png").empty());
}

void AppTest::polylineStrokesAreOneUndoStepEach() {
  MainWindow window(false);
  QVERIFY(ShowWithProject(&window, project_));
  window.SetTool(Tool::kPolyline);
  PhotoView* view = window.photo_view();
  QWidget* viewport = view->viewport();
  const auto at = [&](double x, double y) { return view->mapFromScene(QPointF(x, y)); };
  const fs::path strokes_file = project_ / "edits" / "view_00.strokes.json";
  QUndoStack* stack = window.document()->undo_stack();
  // Three clicks and Enter: one stroke of three points, one undo step.
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(48, 90));
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(50, 60));
  QVERIFY(!fs::exists(strokes_file));  // nothing saved while drawing
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(65, 40));
  const QString shots = qEnvironmentVariable("SYLVA_APP_SHOT_DIR");  // for the notes
  if (!shots.isEmpty()) window.grab().save(shots + "/polyline-in-progress.png");
  QVERIFY(view->hasFocus());  // the clicks gave it the keyboard (Enter, Backspace, Escape)
  QTest::keyClick(view, Qt::Key_Return);
  QCOMPARE(stack->count(), 1);
  StrokeSet strokes = ReadStrokes(strokes_file, 96, 96);
  QCOMPARE(strokes.strokes.size(), size_t(1));
  QCOMPARE(strokes.strokes[0].points.size(), size_t(3));
  QVERIFY((strokes.strokes[0].points[1] - Eigen::Vector2d(50, 60)).norm() < 1.0);
  // Two clicks, the second a double click: a second stroke of two points.
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(50, 60));
  QTest::mouseDClick(viewport, Qt::LeftButton, {}, at(30, 45));
  QCOMPARE(stack->count(), 2);
  strokes = ReadStrokes(strokes_file, 96, 96);
  QCOMPARE(strokes.strokes.size(), size_t(2));
  QCOMPARE(strokes.strokes[1].points.size(), size_t(2));
  QVERIFY((strokes.strokes[1].points[1] - Eigen::Vector2d(30, 45)).norm() < 1.0);
  // Backspace removes the last point; Escape drops a stroke unsaved.
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(20, 20));
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(25, 30));
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(90, 90));
  QTest::keyClick(view, Qt::Key_Backspace);
  QTest::keyClick(view, Qt::Key_Enter);
  QCOMPARE(stack->count(), 3);
  strokes = ReadStrokes(strokes_file, 96, 96);
  QCOMPARE(strokes.strokes.size(), size_t(3));
  QVERIFY((strokes.strokes[2].points.back() - Eigen::Vector2d(25, 30)).norm() < 1.0);
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(10, 10));
  QTest::mouseClick(viewport, Qt::LeftButton, {}, at(20, 10));
  QTest::keyClick(view, Qt::Key_Escape);
  QCOMPARE(stack->count(), 3);
  QCOMPARE(ReadStrokes(strokes_file, 96, 96).strokes.size(), size_t(3));
  // Freehand and polyline strokes share the file and the undo stack.
  window.SetTool(Tool::kStrokes);
  Drag(&window, {{70, 90}, {70, 70}, {75, 55}});
  QCOMPARE(ReadStrokes(strokes_file, 96, 96).strokes.size(), size_t(4));
  stack->undo();
  stack->undo();
  QCOMPARE(ReadStrokes(strokes_file, 96, 96).strokes.size(), size_t(2));
  stack->redo();
  QCOMPARE(ReadStrokes(strokes_file, 96, 96).strokes.size(), size_t(3));
  while (stack->canUndo()) stack->undo();
  QVERIFY(!fs::exists(strokes_file));
}

// Drives the wizard through its pages with `fields` typed in and compares
// the project's sylva.json with `sylva init`'s for the same choices.
void CompareWizardWithInit(const std::map<QString, QString>& fields, CameraSource source, bool copy,
                           const QStringList& init_args, const fs::path& cli_root) {
  NewProjectWizard wizard;
  wizard.show();
  QVERIFY(QTest::qWaitForWindowExposed(&wizard));
  for (const auto& [name, text] : fields) {
    QVERIFY(wizard.Field(name) != nullptr);
    QTest::keyClicks(wizard.Field(name), text);
  }
  wizard.SetCameraSource(source);
  wizard.SetCopyInputs(copy);
  // SYLVA_APP_SHOT_DIR=DIR saves each page's picture there (for the notes).
  const QString shots = qEnvironmentVariable("SYLVA_APP_SHOT_DIR");
  for (int page = 0; page < 3; ++page) {
    if (!shots.isEmpty()) wizard.grab().save(shots + QString("/wizard-%1.png").arg(page));
    QTest::mouseClick(wizard.button(page < 2 ? QWizard::NextButton : QWizard::FinishButton),
                      Qt::LeftButton);
  }
  QVERIFY2(wizard.last_error().isEmpty(), qPrintable(wizard.last_error()));
  QCOMPARE(wizard.result(), int(QDialog::Accepted));
  const fs::path wizard_root = fields.at("project").toStdString();
  QCOMPARE(wizard.created_root(), wizard_root);

  QProcess init;
  init.start(SYLVA_BINARY_DIR "/bin/sylva",
             QStringList{"init", QString::fromStdString(cli_root.string())} + init_args);
  QVERIFY(init.waitForFinished(60000));
  QVERIFY2(init.exitCode() == 0, init.readAllStandardError().constData());
  const std::string wizard_json = ReadFileToString(wizard_root / "sylva.json");
  QCOMPARE(wizard_json, ReadFileToString(cli_root / "sylva.json"));
  QVERIFY(wizard_json.size() > 100);
}

void AppTest::newProjectWizardMakesWhatSylvaInitMakes() {
  const QString data = QString::fromStdString(data_.string());
  const QString temp = temp_.path();
  // A COLMAP model with mattes, a held-out view and units.
  CompareWizardWithInit({{"photos", data + "/photos"},
                         {"mattes", data + "/mattes"},
                         {"held_out", "heldout_00.png"},
                         {"camera_path", data + "/colmap"},
                         {"units", "m"},
                         {"project", temp + "/wizard-colmap"}},
                        CameraSource::kColmapModel, false,
                        {"--photos", data + "/photos", "--mattes", data + "/mattes", "--held-out",
                         "heldout_00.png", "--colmap", data + "/colmap", "--units", "m"},
                        fs::path(temp.toStdString()) / "init-colmap");
  // A sylva camera file, the inputs copied.
  CompareWizardWithInit({{"photos", data + "/photos"},
                         {"mattes", data + "/mattes"},
                         {"camera_path", data + "/cameras.json"},
                         {"project", temp + "/wizard-file"}},
                        CameraSource::kCameraFile, true,
                        {"--photos", data + "/photos", "--mattes", data + "/mattes", "--cameras",
                         data + "/cameras.json", "--copy"},
                        fs::path(temp.toStdString()) / "init-file");
  // A bad choice: the error shows on the last page and nothing is written.
  NewProjectWizard wizard;
  wizard.show();
  QTest::keyClicks(wizard.Field("photos"), data + "/no-such-folder");
  QTest::keyClicks(wizard.Field("camera_path"), data + "/colmap");
  QTest::keyClicks(wizard.Field("project"), temp + "/wizard-bad");
  QTest::mouseClick(wizard.button(QWizard::NextButton), Qt::LeftButton);
  QTest::mouseClick(wizard.button(QWizard::NextButton), Qt::LeftButton);
  QTest::mouseClick(wizard.button(QWizard::FinishButton), Qt::LeftButton);
  QVERIFY(wizard.isVisible());
  QVERIFY2(wizard.last_error().contains("no-such-folder"), qPrintable(wizard.last_error()));
  QVERIFY(!fs::exists(temp.toStdString() + "/wizard-bad"));
}

void AppTest::wizardManualCamerasPageWritesTheLooseCamerasFile() {
  const QString data = QString::fromStdString(data_.string());
  const fs::path root = fs::path(temp_.path().toStdString()) / "wizard-manual";
  NewProjectWizard wizard;
  wizard.show();
  QVERIFY(QTest::qWaitForWindowExposed(&wizard));
  QTest::keyClicks(wizard.Field("photos"), data + "/photos");
  QTest::keyClicks(wizard.Field("mattes"), data + "/mattes");
  QTest::keyClicks(wizard.Field("project"), QString::fromStdString(root.string()));
  wizard.SetCameraSource(CameraSource::kRegisterManual);  // no file: the page makes it
  QTest::mouseClick(wizard.button(QWizard::NextButton), Qt::LeftButton);
  QTest::mouseClick(wizard.button(QWizard::NextButton), Qt::LeftButton);
  QCOMPARE(wizard.currentId(), int(NewProjectWizard::kLoosePage));
  LooseCamerasPage* page = wizard.loose_page();
  // Photos in name order: heldout_00, view_00, view_01, view_02.
  page->UsePhoto(1, 90);
  page->UsePhoto(2, 200, true);
  const std::map<std::string, std::vector<QPointF>> clicks = {
      {"base", {{48.5, 90.5}, {47.5, 91.5}, {50.5, 89.5}}},
      {"top", {{48.5, 10.5}, {46.5, 12.5}, {49.5, 9.5}}}};
  for (int row = 0; row < 3; ++row) {
    page->ShowPhoto(row);
    for (const auto& [name, points] : clicks) {
      page->SetCurrentPoint(QString::fromStdString(name));
      QTest::mouseClick(page->photo_view()->viewport(), Qt::LeftButton, {},
                        page->photo_view()->mapFromScene(points[row]));
    }
  }
  const QString shots = qEnvironmentVariable("SYLVA_APP_SHOT_DIR");  // for the notes
  if (!shots.isEmpty()) wizard.grab().save(shots + "/wizard-manual-cameras.png");
  QTest::mouseClick(wizard.button(QWizard::NextButton), Qt::LeftButton);
  QCOMPARE(wizard.currentId(), int(NewProjectWizard::kProjectPage));
  QTest::mouseClick(wizard.button(QWizard::FinishButton), Qt::LeftButton);
  QVERIFY2(wizard.last_error().isEmpty(), qPrintable(wizard.last_error()));
  QCOMPARE(wizard.result(), int(QDialog::Accepted));

  // The file the project keeps: three photos, base and top clicked on each.
  const fs::path loose_file = root / "cameras" / "loose.json";
  const LooseSetup loose = ReadLooseSetup(loose_file);
  QCOMPARE(loose.photos.size(), size_t(3));
  QCOMPARE(loose.photos[1].azimuth_deg, 90.0);
  QCOMPARE(loose.photos[2].projection, LooseProjection::kOrthographic);
  for (const auto& [name, points] : clicks) {
    const int point = loose.FindPoint(name);
    QVERIFY(point >= 0);
    QCOMPARE(loose.points[point].observations.size(), size_t(3));
    for (const LooseObservation& seen : loose.points[point].observations) {
      const QPointF& clicked = points[seen.photo_idx];
      // A click lands on a view pixel: within one view pixel of the aim.
      const double view_pixel = 1.0 / page->photo_view()->transform().m11();
      QVERIFY((seen.point_in_image - Eigen::Vector2d(clicked.x(), clicked.y())).norm() <=
              1.5 * view_pixel);
    }
  }
  // `sylva init` with that file makes the same sylva.json.
  const fs::path cli_root = fs::path(temp_.path().toStdString()) / "init-manual";
  QProcess init;
  init.start(SYLVA_BINARY_DIR "/bin/sylva",
             {"init", QString::fromStdString(cli_root.string()), "--photos", data + "/photos",
              "--mattes", data + "/mattes", "--register", "manual", "--loose-cameras",
              QString::fromStdString(loose_file.string())});
  QVERIFY(init.waitForFinished(60000));
  QVERIFY2(init.exitCode() == 0, init.readAllStandardError().constData());
  QCOMPARE(ReadFileToString(root / "sylva.json"), ReadFileToString(cli_root / "sylva.json"));
  QCOMPARE(ReadFileToString(root / "cameras" / "loose.json"),
           ReadFileToString(cli_root / "cameras" / "loose.json"));
}

// Drags the left button along canvas points on the sketch canvas.
void DrawOnCanvas(SketchCanvas* canvas, const std::vector<QPointF>& points,
                  Qt::KeyboardModifiers modifiers = {}) {
  const auto at = [&](const QPointF& p) { return canvas->ToWidget(p).toPoint(); };
  QTest::mousePress(canvas, Qt::LeftButton, modifiers, at(points.front()));
  for (size_t i = 1; i < points.size(); ++i) {
    QMouseEvent move(QEvent::MouseMove, at(points[i]), canvas->mapToGlobal(at(points[i])),
                     Qt::NoButton, Qt::LeftButton, modifiers);
    QApplication::sendEvent(canvas, &move);
  }
  QTest::mouseRelease(canvas, Qt::LeftButton, modifiers, at(points.back()));
}

void AppTest::sketchCanvasSavesTheSvgSylvaSketchReads() {
  MainWindow window(false);
  window.resize(1200, 800);
  window.show();
  QVERIFY(QTest::qWaitForWindowExposed(&window));
  QVERIFY(window.ShowPanel("sketch"));
  SketchCanvas* canvas = window.sketch_canvas();
  QTest::qWait(50);
  // A trunk and two branches, a closed crown outline, an open crown stroke,
  // the base.
  canvas->SetRole(StrokeRole::kBranch);
  DrawOnCanvas(canvas, {{200, 590}, {200, 450}, {202, 300}});
  DrawOnCanvas(canvas, {{201, 400}, {150, 330}, {120, 280}});
  DrawOnCanvas(canvas, {{201, 380}, {260, 320}, {290, 260}});
  canvas->SetRole(StrokeRole::kCrown);
  std::vector<QPointF> outline;
  for (int k = 0; k <= 24; ++k) {
    const double a = 2 * M_PI * k / 24;
    outline.emplace_back(200 + 150 * std::cos(a), 250 + 130 * std::sin(a));
  }
  DrawOnCanvas(canvas, outline);
  DrawOnCanvas(canvas, {{100, 150}, {140, 110}, {190, 100}});
  DrawOnCanvas(canvas, {{200, 590}}, Qt::ShiftModifier);
  const SketchDrawing& drawn = canvas->drawing();
  QCOMPARE(drawn.strokes.size(), size_t(5));
  QVERIFY(drawn.strokes[3].closed && !drawn.strokes[4].closed);
  QVERIFY(drawn.root && (*drawn.root - Eigen::Vector2d(200, 590)).norm() < 2.0);
  QVERIFY(std::abs(drawn.strokes[0].points.front().y() - 590) < 2.0);
  // Saved and read back by sylva sketch's reader: the same strokes.
  const fs::path svg = fs::path(temp_.path().toStdString()) / "canvas.svg";
  canvas->SaveSvg(svg);
  const SketchDrawing read = ReadSketch(svg);
  QCOMPARE(read.width, drawn.width);
  QCOMPARE(read.height, drawn.height);
  QCOMPARE(read.CountRole(StrokeRole::kBranch), 3);
  QCOMPARE(read.CountRole(StrokeRole::kCrown), 2);
  QVERIFY(read.root && (*read.root - *drawn.root).norm() < 1e-6);
  for (const SketchStroke& stroke : read.strokes) {
    // Its twin on the canvas: same role, closure and points.
    const auto twin = std::find_if(drawn.strokes.begin(), drawn.strokes.end(), [&](auto& s) {
      return s.role == stroke.role && s.points.size() == stroke.points.size() &&
             (s.points[0] - stroke.points[0]).norm() < 1e-6;
    });
    QVERIFY(twin != drawn.strokes.end());
    QCOMPARE(twin->closed, stroke.closed);
    for (size_t k = 0; k < stroke.points.size(); ++k) {
      QVERIFY((twin->points[k] - stroke.points[k]).norm() < 1e-6);
    }
  }
  // Undo the last stroke, open the saved drawing back.
  canvas->UndoLastStroke();
  QCOMPARE(canvas->drawing().strokes.size(), size_t(4));
  canvas->OpenSvg(svg);
  QCOMPARE(canvas->drawing().strokes.size(), size_t(5));

  // Make tree: sylva sketch's work in the worker; the project then opens.
  const fs::path out = fs::path(temp_.path().toStdString()) / "sketch-tree";
  QSignalSpy finished(window.run_controller(), &RunController::Finished);
  QElapsedTimer timer;
  timer.start();
  QVERIFY(window.MakeTreeFromSketch(out));
  QVERIFY(window.run_controller()->IsRunning());
  QVERIFY(finished.wait(120000));
  QVERIFY2(finished.last().at(0).toBool(), qPrintable(finished.last().at(2).toString()));
  qInfo("tree from the canvas: %.2f s", timer.elapsed() / 1000.0);
  QVERIFY(fs::is_regular_file(out / "drawing.svg"));
  QVERIFY(fs::is_regular_file(out / "project" / "out" / "tree.obj"));
  QVERIFY(window.project() != nullptr);
  QCOMPARE(window.project()->root(), out / "project");
  QVERIFY(window.view_3d()->HasScene());
  // A second time into the same, now full, folder is refused.
  QVERIFY(!window.MakeTreeFromSketch(out));
  QVERIFY(window.last_error().contains("not empty"));
}

void AppTest::optionsPanelRoundTripsEveryOption() {
  const fs::path root = CreateProject("options");
  Project project = Project::Open(root);
  OptionsPanel panel;
  panel.SetProject(&project);
  std::map<std::string, std::string> expected;
  for (const OptionRegistry::Entry& entry : panel.registry().entries()) {
    const std::string now = panel.registry().Get(entry.key);
    std::string text;
    if (entry.type == "bool") {
      text = now == "true" ? "false" : "true";
    } else if (entry.type == "int" || entry.type == "uint64") {
      text = std::to_string(std::stoll(now) + 1);
    } else if (entry.type == "float") {
      text = FormatDouble(std::stod(now) * 1.5 + 0.25);
    } else if (entry.type == "box") {
      text = now == "auto" ? "-1,-2,-3,1,2,3" : "auto";
    } else if (entry.type == "point") {
      text = now == "auto" ? "0.5,-0.25,2" : "auto";
    } else {
      text = now + "_x";
    }
    QVERIFY2(panel.SetText(entry.key, text), entry.key.c_str());
    expected[entry.key] = panel.registry().Get(entry.key);
    QVERIFY2(expected[entry.key] != entry.default_text, entry.key.c_str());
  }
  QVERIFY(expected.size() > 100);
  // Read back from sylva.json by the pipeline's own code.
  const Project reopened = Project::Open(root);
  PipelineOptions options;
  OptionRegistry registry;
  RegisterPipelineOptions(&options, &registry);
  reopened.ApplySavedOptions(&registry);
  for (const auto& [key, text] : expected) QCOMPARE(registry.Get(key), text);
  // An unparsable value is refused and not saved.
  QVERIFY(!panel.SetText("Density.resolution", "many"));
  QCOMPARE(panel.registry().Get("Density.resolution"), expected["Density.resolution"]);
  // And a fresh panel shows the saved values.
  OptionsPanel again;
  Project for_again = Project::Open(root);
  again.SetProject(&for_again);
  auto* field = qobject_cast<QLineEdit*>(again.Field("Density.resolution"));
  QVERIFY(field != nullptr);
  QCOMPARE(field->text().toStdString(), expected["Density.resolution"]);
}

void AppTest::screenshotShowsPhotoAndTree() {
  MainWindow window(false);
  QVERIFY(ShowWithProject(&window, project_, 1400, 850));
  QVERIFY(window.view_3d()->HasScene());
  // The Run panel shows what each stage recorded at its last run.
  const auto* summaries = window.findChild<QPlainTextEdit*>("stage_summaries");
  QVERIFY(summaries != nullptr);
  for (const char* stage :
       {"density (last run): ", "skeleton (last run): ", "report (last run): "}) {
    QVERIFY2(summaries->toPlainText().contains(stage), stage);
  }
  // Overlays off, so the photo's own pixels show.
  for (QCheckBox* box : window.findChildren<QCheckBox*>()) {
    if (box->text().contains("silhouette") || box->text().contains("Attractor")) {
      box->setChecked(false);
    }
  }
  QTest::qWait(200);  // let the layout settle (the photo view refits on resize)
  const fs::path shot_path = fs::path(temp_.path().toStdString()) / "window.png";
  QVERIFY(window.SaveScreenshot(shot_path));
  const QImage shot =
      QImage(QString::fromStdString(shot_path.string())).convertToFormat(QImage::Format_RGB32);
  QVERIFY(!shot.isNull());
  QCOMPARE(shot.size(), window.size() * window.devicePixelRatio());

  // The photo: opaque photo pixels appear where the view maps them.
  const Project project = Project::Open(project_);
  const QImage photo = QImage(QString::fromStdString(project.PhotoPath("view_00.png").string()))
                           .convertToFormat(QImage::Format_ARGB32);
  PhotoView* view = window.photo_view();
  int compared = 0, matched = 0;
  for (int y = 2; y < photo.height(); y += 7) {
    for (int x = 2; x < photo.width(); x += 7) {
      const QRgb p = photo.pixel(x, y);
      if (qAlpha(p) != 255) continue;
      const QPoint in_view = view->mapFromScene(QPointF(x + 0.5, y + 0.5));
      const QPoint in_window = view->viewport()->mapTo(&window, in_view);
      const QRgb s = shot.pixel(in_window);
      ++compared;
      matched += std::abs(qRed(s) - qRed(p)) + std::abs(qGreen(s) - qGreen(p)) +
                     std::abs(qBlue(s) - qBlue(p)) <=
                 6;
    }
  }
  QVERIFY(compared >= 20);
  QVERIFY2(matched >= 0.9 * compared, qPrintable(QString("%1 of %2").arg(matched).arg(compared)));

  // The 3D view: the tree covers a good part of it.
  const QRect rect(window.view_3d()->mapTo(&window, QPoint(0, 0)), window.view_3d()->size());
  int tree = 0;
  for (int y = rect.top(); y < rect.bottom() - 30; ++y) {  // the help text is at the bottom
    for (int x = rect.left(); x < rect.right(); ++x) tree += shot.pixel(x, y) != kView3dBackground;
  }
  const double fraction = double(tree) / (rect.width() * (rect.height() - 30));
  qInfo("3D view: %.1f %% tree pixels", 100 * fraction);
  QVERIFY(fraction > 0.02);

  // Blender's navigation: middle drag orbits, Shift+middle pans, the wheel zooms.
  View3d* view_3d = window.view_3d();
  const QPoint middle(view_3d->width() / 2, view_3d->height() / 2);
  const auto drag = [&](Qt::KeyboardModifiers modifiers) {
    QTest::mousePress(view_3d, Qt::MiddleButton, modifiers, middle);
    QMouseEvent move(QEvent::MouseMove, middle + QPoint(50, 20),
                     view_3d->mapToGlobal(middle + QPoint(50, 20)), Qt::NoButton, Qt::MiddleButton,
                     modifiers);
    QApplication::sendEvent(view_3d, &move);
    QTest::mouseRelease(view_3d, Qt::MiddleButton, modifiers, middle + QPoint(50, 20));
  };
  const double azimuth = view_3d->azimuth_deg(), elevation = view_3d->elevation_deg();
  drag(Qt::NoModifier);
  QCOMPARE(view_3d->azimuth_deg(), azimuth - 20.0);
  QCOMPARE(view_3d->elevation_deg(), elevation + 8.0);
  const Eigen::Vector3d center = view_3d->center();
  drag(Qt::ShiftModifier);
  QVERIFY((view_3d->center() - center).norm() > 1e-3 * view_3d->radius());
  const double radius = view_3d->radius();
  QWheelEvent wheel(QPointF(middle), QPointF(view_3d->mapToGlobal(middle)), QPoint(),
                    QPoint(0, 120), Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase, false);
  QApplication::sendEvent(view_3d, &wheel);
  QVERIFY(view_3d->radius() < radius);  // zoomed in
  view_3d->repaint();
  QCOMPARE(view_3d->picture().size(), view_3d->size());
}

void AppTest::screenshotCommandWritesPng() {
  const QString out = temp_.path() + "/command.png";
  QProcess app;
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.insert("QT_QPA_PLATFORM", "offscreen");
  env.insert("XDG_CONFIG_HOME", temp_.path() + "/config");
  app.setProcessEnvironment(env);
  app.start(SYLVA_BINARY_DIR "/bin/sylva-app",
            {QString::fromStdString(project_.string()), "--screenshot", out});
  QVERIFY(app.waitForFinished(60000));
  QCOMPARE(app.exitCode(), 0);
  const QImage shot(out);
  QVERIFY(shot.width() >= 800 && shot.height() >= 500);
  // Not blank: many colours (photo, overlays, rendered tree, widgets).
  QSet<QRgb> colors;
  for (int y = 0; y < shot.height(); y += 3) {
    for (int x = 0; x < shot.width(); x += 3) colors.insert(shot.pixel(x, y));
  }
  QVERIFY2(colors.size() > 500, qPrintable(QString::number(colors.size())));
  // A bad project: exit code 2, no file.
  app.start(SYLVA_BINARY_DIR "/bin/sylva-app",
            {temp_.path() + "/no-such-project", "--screenshot", temp_.path() + "/bad.png"});
  QVERIFY(app.waitForFinished(60000));
  QCOMPARE(app.exitCode(), 2);
  QVERIFY(!QFile::exists(temp_.path() + "/bad.png"));
}

void AppTest::paintedDensityGrowsAndEmptiesTheTreeAfterRerun() {
  MainWindow window(false);
  QVERIFY(ShowWithProject(&window, project_));
  const Project project = Project::Open(project_);
  const ImageSet cameras = project.LoadCameras();
  // A ball low beside the trunk, where the tree has no density.
  const DensityGrid before = ReadDensityGrid(project.OutDir() / "density.vdb");
  const Box3d box = before.ActiveWorldBounds();
  const Eigen::Vector3d size = box.sizes();
  const double radius = 0.1 * size.z();
  const Eigen::Vector3d ball(box.min().x() + 0.15 * size.x(), box.center().y(),
                             box.min().z() + 0.15 * size.z());
  // Its projection in every input view: centre and radius in pixels.
  std::vector<std::pair<int, std::pair<Eigen::Vector2d, double>>> discs;
  for (int v = 0; v < cameras.NumViews(); ++v) {
    if (project.IsHeldOut(cameras.views[v].name)) continue;
    Eigen::Vector2d middle, top;
    QVERIFY(cameras.Project(v, ball, &middle));
    QVERIFY(cameras.Project(v, ball + radius * Eigen::Vector3d::UnitZ(), &top));
    discs.push_back({v, {middle, std::max(3.0, (top - middle).norm())}});
    QVERIFY2(!ReportCovers(project_, "density", cameras.views[v].name,
                           QPointF(middle.x(), middle.y()), 96),
             "the tree already covers the region");
  }
  QCOMPARE(discs.size(), size_t(3));
  const auto paint = [&](Tool tool) {
    for (const auto& [v, disc] : discs) {
      const auto& names = project.photo_names();
      window.SelectPhoto(
          int(std::find(names.begin(), names.end(), cameras.views[v].name) - names.begin()));
      window.SetTool(tool);
      window.photo_view()->brush() = BrushShape{disc.second, 1.0, 1.0};
      const QPointF c(disc.first.x(), disc.first.y());
      Drag(&window, {c - QPointF(0.5, 0), c + QPointF(0.5, 0)});
    }
  };
  QSignalSpy finished(window.run_controller(), &RunController::Finished);
  const auto run = [&] {
    window.RunAll();
    QVERIFY(finished.wait(60000));
    QVERIFY2(finished.last().at(0).toBool(), qPrintable(finished.last().at(2).toString()));
  };
  // Painted in: after the re-run the density covers the region in every view.
  paint(Tool::kDensityAdd);
  run();
  for (const auto& [v, disc] : discs) {
    QVERIFY2(ReportCovers(project_, "density", cameras.views[v].name,
                          QPointF(disc.first.x(), disc.first.y()), 96),
             cameras.views[v].name.c_str());
  }
  // Only the density and what follows re-ran.
  const RunSummary& summary = window.run_controller()->last_summary();
  for (const StageRun& stage : summary.stages) {
    QCOMPARE(stage.up_to_date, stage.stage == Stage::kMatte || stage.stage == Stage::kRegister);
  }
  // Painted out: the region empties again.
  paint(Tool::kDensityRemove);
  run();
  for (const auto& [v, disc] : discs) {
    QVERIFY2(!ReportCovers(project_, "density", cameras.views[v].name,
                           QPointF(disc.first.x(), disc.first.y()), 96),
             cameras.views[v].name.c_str());
  }
  // Leave the project without edits for the next test.
  while (window.document()->undo_stack()->canUndo()) window.document()->undo_stack()->undo();
}

void AppTest::cancelStopsRunningStageAndLeavesProject() {
  MainWindow window(false);
  QVERIFY(window.OpenProject(project_));
  // A slow density stage: a fine grid.
  QVERIFY(window.options_panel()->SetText("Density.resolution", "200"));
  const auto before = Snapshot(project_);
  QSignalSpy started(window.run_controller(), &RunController::StageStarted);
  QSignalSpy progress(window.run_controller(), &RunController::Progress);
  QSignalSpy finished(window.run_controller(), &RunController::Finished);
  window.RunAll();
  QVERIFY(window.run_controller()->IsRunning());
  QVERIFY(started.wait(20000));
  QCOMPARE(started.last().at(0).toInt(), static_cast<int>(Stage::kDensity));
  QTest::qWait(700);  // well inside the stage
  QVERIFY2(finished.isEmpty(), "the stage ended before it could be cancelled");
  QElapsedTimer timer;
  timer.start();
  window.CancelRun();
  QVERIFY(finished.wait(5000));
  const double seconds = timer.elapsed() / 1000.0;
  qInfo("cancelled after %.3f s; %d progress updates", seconds, int(progress.size()));
  QVERIFY(seconds < 1.0);
  QCOMPARE(finished.last().at(0).toBool(), false);
  QCOMPARE(finished.last().at(1).toBool(), true);  // cancelled
  QVERIFY(!progress.isEmpty());
  QCOMPARE(window.stage_bar(Stage::kDensity)->format(), QString("cancelled"));
  QVERIFY(Snapshot(project_) == before);
  QVERIFY(window.options_panel()->SetText("Density.resolution", "32"));
}

}  // namespace sylva

QTEST_MAIN(sylva::AppTest)
#include "app_test.moc"
