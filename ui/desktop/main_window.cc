#include "ui/desktop/main_window.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCheckBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QGridLayout>
#include <QLabel>
#include <QListWidget>
#include <QMenuBar>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSignalBlocker>
#include <QSplitter>
#include <QStackedWidget>
#include <QStatusBar>
#include <QTabWidget>
#include <QToolBar>
#include <QToolButton>
#include <QVBoxLayout>
#include <exception>
#include <iostream>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "ui/desktop/edit_document.h"
#include "ui/desktop/new_project_wizard.h"
#include "ui/desktop/options_panel.h"
#include "ui/desktop/overlays.h"
#include "ui/desktop/photo_view.h"
#include "ui/desktop/run_controller.h"
#include "ui/desktop/sketch_canvas.h"
#include "ui/desktop/view_3d.h"
#ifdef SYLVA_HAVE_GL_VIEW
#include "ui/desktop/view_3d_gl.h"
#endif
#include "ui/pipeline/pipeline.h"
#include "ui/pipeline/project.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

constexpr int kMaxRecent = 8;
constexpr int kSettleMilliseconds = 150;
const char* const kRecentKey = "recent_projects";

// Overlay tints: density projection cyan, mesh silhouette magenta.
constexpr QRgb kDensityTint = qRgb(0, 230, 230);
constexpr QRgb kMeshTint = qRgb(255, 40, 200);

struct ToolInfo {
  Tool tool;
  const char* name;
  const char* shortcut;
  const char* help;
};

const std::vector<ToolInfo>& Tools() {
  static const std::vector<ToolInfo> tools = {
      {Tool::kNavigate, "Navigate", "N", "Pan with the left button; wheel zooms"},
      {Tool::kDensityAdd, "Density +", "A", "Paint density in (edits/density, grey 255)"},
      {Tool::kDensityRemove, "Density −", "R", "Paint density out (edits/density, grey 0)"},
      {Tool::kTrimapForeground, "Trimap FG", "F", "Matting hint: foreground (edits/trimaps)"},
      {Tool::kTrimapBackground, "Trimap BG", "B", "Matting hint: background (edits/trimaps)"},
      {Tool::kTrimapUnknown, "Trimap ?", "U",
       "Matting hint: unknown = unpainted (the automatic trimap decides)"},
      {Tool::kStrokes, "Branch", "S",
       "Draw a branch stroke (edits/<photo>.strokes.json); Shift+click marks the tree base"},
      {Tool::kPolyline, "Polyline", "P",
       "Click a branch stroke point by point; double-click or Enter finishes, Backspace "
       "removes the last point, Escape drops it"},
      {Tool::kCrown, "Crown", "C", "Draw a crown outline (edits/<photo>.crown.svg)"},
      {Tool::kEraser, "Eraser", "E", "Erase painted density and hints; removes strokes it touches"},
  };
  return tools;
}

// Whether the OpenGL 3D view can be shown (asked once: it makes a context).
bool GlViewAvailable() {
#ifdef SYLVA_HAVE_GL_VIEW
  static const bool available = View3dGl::Available();
  return available;
#else
  return false;
#endif
}

QString IouText(const std::optional<double>& iou) {
  return iou ? QString::number(*iou, 'f', 3) : QString("–");
}

}  // namespace

MainWindow::MainWindow(bool interactive, QWidget* parent)
    : QMainWindow(parent), interactive_(interactive) {
  setWindowTitle("sylva");
  run_controller_ = new RunController(this);

  photo_view_ = new PhotoView;
  view_3d_ = new View3d;
  photo_label_ = new QLabel("Open a project (File > Open)");
  auto* photo_pane = new QWidget;
  auto* photo_layout = new QVBoxLayout(photo_pane);
  photo_layout->setContentsMargins(0, 0, 0, 0);
  photo_layout->addWidget(photo_label_);
  photo_layout->addWidget(photo_view_, 1);
  auto* splitter = new QSplitter;
  splitter->addWidget(photo_pane);
  view_3d_stack_ = new QStackedWidget;
  view_3d_stack_->addWidget(view_3d_);
  splitter->addWidget(view_3d_stack_);
  splitter->setStretchFactor(0, 1);
  splitter->setStretchFactor(1, 1);
  splitter->setSizes({1000, 1000});  // halves of whatever width it gets
  pages_ = new QTabWidget;
  pages_->addTab(splitter, "Photos");
  pages_->addTab(BuildSketchPage(), "Sketch");
  setCentralWidget(pages_);

  photo_list_ = new QListWidget;
  auto* photos_dock = new QDockWidget("Photos", this);
  photos_dock->setObjectName("photos");
  photos_dock->setWidget(photo_list_);
  addDockWidget(Qt::LeftDockWidgetArea, photos_dock);
  connect(photo_list_, &QListWidget::currentRowChanged, this, &MainWindow::SelectPhoto);

  options_panel_ = new OptionsPanel;
  auto* tabs = panels_ = new QTabWidget;
  tabs->addTab(BuildLayersPanel(), "Layers");
  tabs->addTab(BuildRunPanel(), "Run");
  tabs->addTab(options_panel_, "Options");
  auto* panel_dock = new QDockWidget("Panels", this);
  panel_dock->setObjectName("panels");
  panel_dock->setWidget(tabs);
  addDockWidget(Qt::RightDockWidgetArea, panel_dock);
  connect(options_panel_, &OptionsPanel::OptionsChanged, this, &MainWindow::RefreshStageStates);
  connect(options_panel_, &OptionsPanel::SaveFailed, this, &MainWindow::ShowError);

  BuildMenus();
  BuildToolBar();
  connect(run_controller_, &RunController::StageStarted, this, [this](int stage) {
    ++stages_started_;
    StageRow& row = stage_rows_[static_cast<Stage>(stage)];
    row.state->setText("running");
    row.bar->setValue(0);
  });
  connect(run_controller_, &RunController::Progress, this,
          [this](int stage, const QString& task, double fraction) {
            if (stage < 0) {  // before the first stage (checks of the inputs)
              statusBar()->showMessage(task);
              return;
            }
            StageRow& row = stage_rows_[static_cast<Stage>(stage)];
            row.bar->setValue(static_cast<int>(fraction * 1000));
            row.bar->setFormat(task + "  %p%");
          });
  connect(run_controller_, &RunController::StageFinished, this,
          [this](int stage, const QString& brief, bool up_to_date) {
            StageRow& row = stage_rows_[static_cast<Stage>(stage)];
            row.bar->setValue(1000);
            row.bar->setFormat(up_to_date ? "up to date" : "done");
            summary_text_->appendPlainText(
                QString::fromUtf8(GetStageInfo(static_cast<Stage>(stage)).name) +
                (up_to_date ? " (up to date): " : ": ") + brief);
          });
  connect(run_controller_, &RunController::Finished, this, &MainWindow::OnRunFinished);
  statusBar()->showMessage("Ready");
  resize(1500, 900);
}

MainWindow::~MainWindow() = default;

void MainWindow::BuildMenus() {
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("&New project…", QKeySequence::New, this, &MainWindow::NewProject);
  file->addAction("&Open project…", QKeySequence::Open, [this] {
    const QString dir = QFileDialog::getExistingDirectory(this, "Open a sylva project");
    if (!dir.isEmpty()) OpenProject(dir.toStdString());
  });
  recent_menu_ = file->addMenu("Open &recent");
  UpdateRecentMenu();
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, this, &QWidget::close);

  QMenu* edit = menuBar()->addMenu("&Edit");
  undo_action_ = edit->addAction("&Undo");
  undo_action_->setShortcut(QKeySequence::Undo);
  undo_action_->setEnabled(false);
  redo_action_ = edit->addAction("&Redo");
  redo_action_->setShortcut(QKeySequence::Redo);
  redo_action_->setEnabled(false);
  connect(undo_action_, &QAction::triggered, this, [this] {
    if (document_) document_->undo_stack()->undo();
  });
  connect(redo_action_, &QAction::triggered, this, [this] {
    if (document_) document_->undo_stack()->redo();
  });

  QMenu* view = menuBar()->addMenu("&View");
  view->addAction("&Fit photo", [this] { photo_view_->FitPhoto(); });
  view->addAction("Frame &3D view", [this] {
    view_3d_->FrameAll();
    if (view_3d_gl_ != nullptr) view_3d_gl_->FrameAll();
  });
  opengl_action_ = view->addAction("&OpenGL 3D view");
  opengl_action_->setCheckable(true);
  opengl_action_->setEnabled(GlViewAvailable());
  opengl_action_->setToolTip(GlViewAvailable()
                                 ? "Draw the 3D view with OpenGL (off: Embree on the CPU)"
                                 : "No OpenGL context can be made here; the 3D view uses Embree");
  connect(opengl_action_, &QAction::toggled, this, [this](bool on) { UseOpenGlView(on); });
}

bool MainWindow::UseOpenGlView(bool on) {
  if (on && !GlViewAvailable()) return false;
#ifdef SYLVA_HAVE_GL_VIEW
  if (on && view_3d_gl_ == nullptr) {
    view_3d_gl_ = new View3dGl;
    view_3d_stack_->addWidget(view_3d_gl_);
    view_3d_gl_->SetScene(view_3d_->scene());
    ApplyShown3d();
  }
  if (on) {
    view_3d_gl_->SetCamera(view_3d_->camera());
    view_3d_stack_->setCurrentWidget(view_3d_gl_);
  } else if (view_3d_gl_ != nullptr) {
    view_3d_->SetCamera(view_3d_gl_->camera());
    view_3d_stack_->setCurrentWidget(view_3d_);
  }
#endif
  const QSignalBlocker blocker(opengl_action_);
  opengl_action_->setChecked(on);
  return true;
}

bool MainWindow::opengl_view_shown() const {
  return view_3d_gl_ != nullptr && view_3d_stack_->currentIndex() != 0;
}

void MainWindow::ApplyShown3d() {
  const bool mesh = mesh_box_->isChecked(), points = points_box_->isChecked(),
             skeleton = skeleton_box_->isChecked();
  view_3d_->SetShown(mesh, points, skeleton);
#ifdef SYLVA_HAVE_GL_VIEW
  if (view_3d_gl_ != nullptr) view_3d_gl_->SetShown(mesh, points, skeleton);
#endif
}

void MainWindow::BuildToolBar() {
  QToolBar* bar = addToolBar("Tools");
  bar->setObjectName("tools");
  auto* group = new QActionGroup(this);
  for (const ToolInfo& info : Tools()) {
    QAction* action = bar->addAction(info.name);
    action->setCheckable(true);
    action->setShortcut(QKeySequence(info.shortcut));
    action->setToolTip(QString("%1 (%2)").arg(info.help, info.shortcut));
    action->setChecked(info.tool == Tool::kNavigate);
    group->addAction(action);
    const Tool tool = info.tool;
    connect(action, &QAction::triggered, this, [this, tool] { SetTool(tool); });
  }
  bar->addSeparator();
  const auto add_box = [&](const QString& label, double low, double high, double value,
                           double step) {
    bar->addWidget(new QLabel(" " + label + " "));
    auto* box = new QDoubleSpinBox;
    box->setRange(low, high);
    box->setSingleStep(step);
    box->setValue(value);
    bar->addWidget(box);
    return box;
  };
  size_box_ = add_box("Size", 1, 500, 2 * photo_view_->brush().radius, 1);
  size_box_->setToolTip("Brush diameter, photo pixels");
  hardness_box_ = add_box("Hardness", 0, 1, photo_view_->brush().hardness, 0.05);
  strength_box_ = add_box("Strength", 0, 1, photo_view_->brush().strength, 0.05);
  connect(size_box_, &QDoubleSpinBox::valueChanged, this,
          [this](double v) { photo_view_->brush().radius = v / 2; });
  connect(hardness_box_, &QDoubleSpinBox::valueChanged, this,
          [this](double v) { photo_view_->brush().hardness = v; });
  connect(strength_box_, &QDoubleSpinBox::valueChanged, this,
          [this](double v) { photo_view_->brush().strength = v; });
}

QWidget* MainWindow::BuildLayersPanel() {
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);
  layout->addWidget(new QLabel("<b>Photo overlays</b>"));
  const std::vector<std::pair<Overlay, QString>> overlays = {
      {Overlay::kMatte, "Matte (blue)"},
      {Overlay::kDensityProjection, "Density projection (cyan, report)"},
      {Overlay::kMeshSilhouette, "Mesh silhouette (magenta, report)"},
      {Overlay::kAttractors, "Attractor graph (yellow)"}};
  for (const auto& [overlay, label] : overlays) {
    auto* box = new QCheckBox(label);
    box->setChecked(overlay != Overlay::kDensityProjection && overlay != Overlay::kMatte);
    const Overlay which = overlay;
    connect(box, &QCheckBox::toggled, this,
            [this, which](bool on) { photo_view_->SetOverlayVisible(which, on); });
    photo_view_->SetOverlayVisible(overlay, box->isChecked());
    overlay_boxes_.push_back(box);
    layout->addWidget(box);
  }
  edits_box_ = new QCheckBox("Edits (density, trimap, strokes, crowns)");
  edits_box_->setChecked(true);
  connect(edits_box_, &QCheckBox::toggled, photo_view_, &PhotoView::SetEditsVisible);
  layout->addWidget(edits_box_);
  layout->addSpacing(12);
  layout->addWidget(new QLabel("<b>3D view</b>"));
  mesh_box_ = new QCheckBox("Mesh (out/tree.obj)");
  points_box_ = new QCheckBox("Density voxels (out/density.vdb)");
  skeleton_box_ = new QCheckBox("Skeleton (out/skeleton.json)");
  for (QCheckBox* box : {mesh_box_, points_box_, skeleton_box_}) {
    box->setChecked(box == mesh_box_);
    layout->addWidget(box);
    connect(box, &QCheckBox::toggled, this, &MainWindow::ApplyShown3d);
  }
  ApplyShown3d();
  layout->addStretch(1);
  return panel;
}

QWidget* MainWindow::BuildRunPanel() {
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);
  auto* buttons = new QHBoxLayout;
  run_button_ = new QPushButton("Run all");
  run_button_->setToolTip("Runs every stage that is out of date");
  cancel_button_ = new QPushButton("Cancel");
  cancel_button_->setEnabled(false);
  buttons->addWidget(run_button_);
  buttons->addWidget(cancel_button_);
  layout->addLayout(buttons);
  connect(run_button_, &QPushButton::clicked, this, &MainWindow::RunAll);
  connect(cancel_button_, &QPushButton::clicked, this, &MainWindow::CancelRun);
  auto* grid = new QGridLayout;
  int row = 0;
  for (const StageInfo& info : AllStages()) {
    StageRow stage_row;
    auto* name = new QLabel(info.name);
    name->setToolTip(info.description);
    stage_row.state = new QLabel("–");
    stage_row.bar = new QProgressBar;
    stage_row.bar->setRange(0, 1000);
    stage_row.bar->setValue(0);
    stage_row.bar->setTextVisible(true);
    stage_row.bar->setFormat("");
    stage_row.run = new QToolButton;
    stage_row.run->setText("▶");
    stage_row.run->setToolTip(QString("Run the %1 stage alone").arg(info.name));
    const Stage stage = info.stage;
    connect(stage_row.run, &QToolButton::clicked, this, [this, stage] { RunOneStage(stage); });
    grid->addWidget(name, row, 0);
    grid->addWidget(stage_row.state, row, 1);
    grid->addWidget(stage_row.bar, row, 2);
    grid->addWidget(stage_row.run, row, 3);
    stage_rows_[stage] = stage_row;
    ++row;
  }
  grid->setColumnStretch(2, 1);
  layout->addLayout(grid);
  layout->addWidget(new QLabel("Stage summaries"));
  summary_text_ = new QPlainTextEdit;
  summary_text_->setObjectName("stage_summaries");
  summary_text_->setReadOnly(true);
  summary_text_->setLineWrapMode(QPlainTextEdit::WidgetWidth);
  layout->addWidget(summary_text_, 1);
  return panel;
}

QWidget* MainWindow::BuildSketchPage() {
  auto* page = new QWidget;
  auto* layout = new QVBoxLayout(page);
  auto* bar = new QToolBar;
  sketch_canvas_ = new SketchCanvas;
  auto* roles = new QActionGroup(page);
  for (const auto& [role, name] :
       {std::pair{StrokeRole::kBranch, "Branch"}, std::pair{StrokeRole::kCrown, "Crown"}}) {
    QAction* action = bar->addAction(name, [this, role = role] { sketch_canvas_->SetRole(role); });
    action->setCheckable(true);
    action->setChecked(role == StrokeRole::kBranch);
    roles->addAction(action);
  }
  bar->addSeparator();
  bar->addAction("Undo stroke", [this] { sketch_canvas_->UndoLastStroke(); });
  bar->addAction("Clear", [this] { sketch_canvas_->Clear(); });
  bar->addAction("Open SVG…", [this] {
    const QString path = QFileDialog::getOpenFileName(this, "Open a drawing", {}, "SVG (*.svg)");
    if (path.isEmpty()) return;
    try {
      sketch_canvas_->OpenSvg(path.toStdString());
    } catch (const std::exception& error) {
      ShowError(QString::fromStdString(error.what()));
    }
  });
  bar->addAction("Save SVG…", [this] {
    const QString path = QFileDialog::getSaveFileName(this, "Save the drawing", {}, "SVG (*.svg)");
    if (path.isEmpty()) return;
    try {
      sketch_canvas_->SaveSvg(path.toStdString());
    } catch (const std::exception& error) {
      ShowError(QString::fromStdString(error.what()));
    }
  });
  bar->addSeparator();
  bar->addAction("Make tree…", [this] {
    const QString dir = QFileDialog::getExistingDirectory(this, "An empty folder for the tree");
    if (!dir.isEmpty()) MakeTreeFromSketch(dir.toStdString());
  });
  layout->addWidget(bar);
  layout->addWidget(new QLabel(
      "Draw the tree: branch strokes from the base up, crown outlines (a crown stroke ending "
      "near its start closes); Shift+click marks the base. Make tree runs sylva sketch."));
  layout->addWidget(sketch_canvas_, 1);
  return page;
}

bool MainWindow::MakeTreeFromSketch(const fs::path& out_dir) {
  if (run_controller_->IsRunning()) {
    ShowError("A run is in progress; cancel it before making a tree from the drawing.");
    return false;
  }
  SketchSetup setup;
  setup.root = out_dir / "project";
  setup.drawings = {out_dir / "drawing.svg"};
  try {
    std::error_code ec;
    SYLVA_CHECK_INPUT(!fs::exists(out_dir, ec) || fs::is_empty(out_dir, ec), out_dir.string())
        << "already exists and is not empty";
    fs::create_directories(out_dir);
    sketch_canvas_->SaveSvg(setup.drawings[0]);
  } catch (const std::exception& error) {
    ShowError(QString::fromStdString(error.what()));
    return false;
  }
  BeginRun();
  pending_sketch_root_ = setup.root;
  statusBar()->showMessage("Making the tree of the drawing in " +
                           QString::fromStdString(out_dir.string()));
  run_controller_->StartSketch(setup);
  return true;
}

void MainWindow::ShowError(const QString& message) {
  last_error_ = message;
  statusBar()->showMessage(message);
  if (interactive_) {
    QMessageBox::warning(this, "sylva", message);
  } else {
    std::cerr << "sylva-app: " << message.toStdString() << "\n";
  }
}

void MainWindow::NewProject() {
  NewProjectWizard wizard(this);
  if (wizard.exec() == QDialog::Accepted) OpenProject(wizard.created_root());
}

bool MainWindow::OpenProject(const std::filesystem::path& root) {
  if (run_controller_->IsRunning()) {
    ShowError("A run is in progress; cancel it before opening another project.");
    return false;
  }
  std::unique_ptr<Project> project;
  try {
    project = std::make_unique<Project>(Project::Open(root));
  } catch (const std::exception& error) {
    ShowError(QString::fromStdString(error.what()));
    return false;
  }
  photo_view_->SetPhoto(nullptr, "", QImage());
  document_.reset();
  project_ = std::move(project);
  document_ = std::make_unique<EditDocument>(project_.get());
  connect(document_.get(), &EditDocument::SaveFailed, this, &MainWindow::ShowError);
  connect(document_.get(), &EditDocument::Changed, this, [this](const QString& photo) {
    if (photo.toStdString() == photo_view_->photo_name()) photo_view_->RefreshEdits();
    RefreshStageStates();
  });
  QUndoStack* stack = document_->undo_stack();
  undo_action_->setEnabled(false);
  redo_action_->setEnabled(false);
  connect(stack, &QUndoStack::canUndoChanged, undo_action_, &QAction::setEnabled);
  connect(stack, &QUndoStack::canRedoChanged, redo_action_, &QAction::setEnabled);
  options_panel_->SetProject(project_.get());
  setWindowTitle("sylva — " + QString::fromStdString(project_->root().filename().string()));
  AddRecent(QString::fromStdString(fs::absolute(project_->root()).string()));
  ReloadOutputs();
  RefreshPhotoList();
  RefreshStageStates();
  ShowRecordedSummaries();
  // The first input view (held-out views judge, they are not edited).
  const auto& names = project_->photo_names();
  for (size_t i = 0; i < names.size(); ++i) {
    if (!project_->IsHeldOut(names[i]) || i + 1 == names.size()) {
      SelectPhoto(static_cast<int>(i));
      break;
    }
  }
  return true;
}

void MainWindow::RefreshPhotoList() {
  const int current = photo_list_->currentRow();
  const QSignalBlocker block(photo_list_);
  photo_list_->clear();
  if (!project_) return;
  std::map<std::string, ViewScores> scores;
  try {
    scores = ReadViewScores(*project_);
  } catch (const std::exception& error) {
    statusBar()->showMessage(QString::fromStdString(error.what()));
  }
  photo_titles_.clear();
  for (const std::string& name : project_->photo_names()) {
    QString text = QString::fromStdString(name);
    if (project_->IsHeldOut(name)) text += "  (held out)";
    const auto it = scores.find(name);
    if (it != scores.end()) {
      text += QString("\n  IoU density %1 · mesh %2")
                  .arg(IouText(it->second.density_iou), IouText(it->second.mesh_iou));
    }
    photo_titles_[QString::fromStdString(name)] = text;
    photo_list_->addItem(text);
  }
  if (current >= 0 && current < photo_list_->count()) {
    photo_list_->setCurrentRow(current);
    photo_label_->setText(photo_list_->item(current)->text().replace('\n', ' '));
  }
}

void MainWindow::SelectPhoto(int index) {
  if (!project_ || index < 0 || index >= static_cast<int>(project_->photo_names().size())) return;
  if (photo_list_->currentRow() != index) {
    photo_list_->setCurrentRow(index);  // calls back
    return;
  }
  const std::string& name = project_->photo_names()[index];
  try {
    const QImage photo = LoadPhoto(*project_, name);
    document_->Edits(name, photo.width(), photo.height());  // validates the edit files
    photo_view_->SetPhoto(document_.get(), name, photo);
    ShowPhotoOverlays();
    photo_label_->setText(photo_titles_[QString::fromStdString(name)].replace('\n', ' '));
  } catch (const std::exception& error) {
    ShowError(QString::fromStdString(error.what()));
  }
}

void MainWindow::ShowPhotoOverlays() {
  const std::string& name = photo_view_->photo_name();
  if (!project_ || name.empty()) return;
  try {
    photo_view_->SetOverlayImage(Overlay::kMatte, MatteOverlay(*project_, name));
    photo_view_->SetOverlayImage(Overlay::kDensityProjection,
                                 ReportSilhouetteOverlay(*project_, "density", name, kDensityTint));
    photo_view_->SetOverlayImage(Overlay::kMeshSilhouette,
                                 ReportSilhouetteOverlay(*project_, "mesh", name, kMeshTint));
    photo_view_->SetAttractorPath(AttractorPath(*project_, name));
  } catch (const std::exception& error) {
    statusBar()->showMessage(QString::fromStdString(error.what()));
  }
}

void MainWindow::ReloadOutputs() {
  if (!project_) return;
  view_3d_->LoadProject(*project_);
#ifdef SYLVA_HAVE_GL_VIEW
  if (view_3d_gl_ != nullptr) {
    view_3d_gl_->SetScene(view_3d_->scene());
    view_3d_gl_->SetCamera(view_3d_->camera());
  }
#endif
  statusBar()->showMessage(view_3d_->status());
  ShowPhotoOverlays();
  RefreshPhotoList();
}

void MainWindow::ShowRecordedSummaries() {
  summary_text_->clear();
  for (const StageInfo& info : AllStages()) {
    const std::string brief = ReadRecordedBrief(*project_, info.name);
    if (brief.empty()) continue;
    summary_text_->appendPlainText(QString::fromUtf8(info.name) +
                                   " (last run): " + QString::fromStdString(brief));
  }
}

void MainWindow::RefreshStageStates() {
  if (!project_) return;
  try {
    const Pipeline pipeline(*project_, options_panel_->options(), nullptr);
    for (const StageInfo& info : AllStages()) {
      StageRow& row = stage_rows_[info.stage];
      if (run_controller_->IsRunning() && row.state->text() == "running") continue;
      const bool needed = pipeline.StageKey(info.stage) != "not needed";
      row.state->setText(!needed                           ? "not needed"
                         : pipeline.IsUpToDate(info.stage) ? "up to date"
                                                           : "out of date");
    }
  } catch (const std::exception& error) {
    for (auto& [stage, row] : stage_rows_) row.state->setText("–");
    statusBar()->showMessage(QString::fromStdString(error.what()));
  }
}

bool MainWindow::ShowPanel(const QString& name) {
  for (QTabWidget* tabs : {panels_, pages_}) {
    for (int i = 0; i < tabs->count(); ++i) {
      if (tabs->tabText(i).compare(name, Qt::CaseInsensitive) == 0) {
        tabs->setCurrentIndex(i);
        return true;
      }
    }
  }
  return false;
}

void MainWindow::SetTool(Tool tool) { photo_view_->SetTool(tool); }

void MainWindow::BeginRun() {
  summary_text_->clear();
  for (auto& [stage, row] : stage_rows_) row.bar->setValue(0), row.bar->setFormat("");
  run_button_->setEnabled(false);
  cancel_button_->setEnabled(true);
  stages_started_ = 0;
}

void MainWindow::RunAll() {
  if (!project_ || run_controller_->IsRunning()) return;
  BeginRun();
  run_controller_->Start(project_->root(), options_panel_->options(), AllStages().back().stage);
}

void MainWindow::RunOneStage(Stage stage) {
  if (!project_ || run_controller_->IsRunning()) return;
  BeginRun();
  run_controller_->Start(project_->root(), options_panel_->options(), stage, stage);
}

void MainWindow::CancelRun() {
  run_controller_->Cancel();
  statusBar()->showMessage("Cancelling…");
}

void MainWindow::OnRunFinished(bool ok, bool cancelled, const QString& message) {
  run_button_->setEnabled(true);
  cancel_button_->setEnabled(false);
  for (auto& [stage, row] : stage_rows_) {
    if (!ok && row.state->text() == "running") {
      row.bar->setFormat(cancelled ? "cancelled" : "failed");
    }
  }
  if (ok) {
    summary_text_->appendPlainText(
        QString::fromStdString(run_controller_->last_summary().BriefReport()));
    statusBar()->showMessage("Run finished");
  } else if (cancelled) {
    statusBar()->showMessage("Run cancelled; the project is as it was before the stage started");
  } else {
    ShowError(message);
  }
  // A cancelled or failed stage wrote nothing; stages before it in the run did.
  if (ok || stages_started_ > 1) ReloadOutputs();
  RefreshStageStates();
  const fs::path sketch_root = pending_sketch_root_;
  pending_sketch_root_.clear();
  if (!sketch_root.empty() && fs::is_regular_file(sketch_root / "sylva.json")) {
    OpenProject(sketch_root);  // the drawing's project, with what the run made
    pages_->setCurrentIndex(0);
  }
}

bool MainWindow::SaveScreenshot(const std::filesystem::path& path) {
  // Let pending layout and resize events settle (the photo view refits).
  QElapsedTimer settle;
  settle.start();
  while (settle.elapsed() < kSettleMilliseconds) {
    QApplication::processEvents(QEventLoop::AllEvents, kSettleMilliseconds);
  }
  const QPixmap shot = grab();
  try {
    AtomicWriteWith(path, [&](const fs::path& temp) {
      SYLVA_CHECK(shot.save(QString::fromStdString(temp.string()), "PNG"))
          << "cannot write " << temp.string();
    });
  } catch (const std::exception& error) {
    ShowError(QString::fromStdString(error.what()));
    return false;
  }
  return true;
}

void MainWindow::UpdateRecentMenu() {
  recent_menu_->clear();
  const QStringList recent = QSettings("sylva", "sylva-app").value(kRecentKey).toStringList();
  for (const QString& root : recent) {
    recent_menu_->addAction(root, [this, root] { OpenProject(root.toStdString()); });
  }
  recent_menu_->setEnabled(!recent.isEmpty());
}

void MainWindow::AddRecent(const QString& root) {
  QSettings settings("sylva", "sylva-app");
  QStringList recent = settings.value(kRecentKey).toStringList();
  recent.removeAll(root);
  recent.prepend(root);
  while (recent.size() > kMaxRecent) recent.removeLast();
  settings.setValue(kRecentKey, recent);
  UpdateRecentMenu();
}

}  // namespace sylva
