// sylva-app's main window, a thin layer over ui/pipeline: the project's
// photos (left), the photo with its overlays and brushes and the 3D view
// (centre), layers, run and options panels (right). Errors from the library
// become dialogs (or, when not interactive, status messages and stderr).
#ifndef SYLVA_UI_DESKTOP_MAIN_WINDOW_H_
#define SYLVA_UI_DESKTOP_MAIN_WINDOW_H_

#include <QMainWindow>
#include <QString>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "ui/pipeline/stage_context.h"

class QAction;
class QCheckBox;
class QDoubleSpinBox;
class QLabel;
class QListWidget;
class QMenu;
class QPlainTextEdit;
class QProgressBar;
class QStackedWidget;
class QPushButton;
class QTabWidget;
class QToolButton;

namespace sylva {

class EditDocument;
class OptionsPanel;
class PhotoView;
class Project;
class RunController;
class SketchCanvas;
class View3d;
class View3dGl;
enum class Tool;

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  // `interactive`: errors as dialogs (false for tests and --screenshot).
  explicit MainWindow(bool interactive = true, QWidget* parent = nullptr);
  ~MainWindow() override;

  // Runs the new-project wizard and opens the project it makes.
  void NewProject();
  // Opens a project folder; false (with the error shown) if it is invalid.
  bool OpenProject(const std::filesystem::path& root);
  void SelectPhoto(int index);
  void SetTool(Tool tool);

  // Runs every out-of-date stage, or one stage, in the worker thread.
  void RunAll();
  void RunOneStage(Stage stage);
  void CancelRun();

  // `sylva sketch`'s work on the sketch canvas' drawing, in the worker:
  // saves it as OUT_DIR/drawing.svg, creates the sketch project
  // OUT_DIR/project and runs it; the project opens when the run ends.
  // False (with the error shown) if OUT_DIR is not new or empty, the
  // drawing is invalid, or a run is in progress.
  bool MakeTreeFromSketch(const std::filesystem::path& out_dir);

  // Brings the panel "layers", "run", "options" or the page "photos",
  // "sketch" to the front; false if there is no such panel.
  bool ShowPanel(const QString& name);

  // Shows the OpenGL 3D view (true) or the Embree one (false), keeping the
  // camera; false if OpenGL was asked for and cannot be used here (built
  // without Qt's OpenGL widgets, or View3dGl::Available() is false).
  bool UseOpenGlView(bool on);
  bool opengl_view_shown() const;

  // Renders the whole window into a PNG (atomically); false on failure.
  bool SaveScreenshot(const std::filesystem::path& path);

  PhotoView* photo_view() const { return photo_view_; }
  View3d* view_3d() const { return view_3d_; }
  View3dGl* view_3d_gl() const { return view_3d_gl_; }  // null until UseOpenGlView(true)
  OptionsPanel* options_panel() const { return options_panel_; }
  SketchCanvas* sketch_canvas() const { return sketch_canvas_; }
  RunController* run_controller() const { return run_controller_; }
  EditDocument* document() const { return document_.get(); }
  Project* project() const { return project_.get(); }
  QProgressBar* stage_bar(Stage stage) const { return stage_rows_.at(stage).bar; }
  QString last_error() const { return last_error_; }

 private:
  void BuildMenus();
  void BuildToolBar();
  QWidget* BuildLayersPanel();
  QWidget* BuildRunPanel();
  QWidget* BuildSketchPage();
  // Resets the Run panel for a run that starts now.
  void BeginRun();
  void ShowError(const QString& message);
  void ReloadOutputs();
  // The layer boxes' choice of mesh, points and skeleton, to both 3D views.
  void ApplyShown3d();
  void ShowPhotoOverlays();
  void RefreshPhotoList();
  void RefreshStageStates();
  // The Run panel's summaries as the project's stages last recorded them.
  void ShowRecordedSummaries();
  void UpdateRecentMenu();
  void AddRecent(const QString& root);
  void OnRunFinished(bool ok, bool cancelled, const QString& message);

  bool interactive_;
  std::unique_ptr<Project> project_;
  std::unique_ptr<EditDocument> document_;
  PhotoView* photo_view_ = nullptr;
  View3d* view_3d_ = nullptr;
  View3dGl* view_3d_gl_ = nullptr;
  QStackedWidget* view_3d_stack_ = nullptr;  // view_3d_, and view_3d_gl_ once made
  QAction* opengl_action_ = nullptr;
  OptionsPanel* options_panel_ = nullptr;
  SketchCanvas* sketch_canvas_ = nullptr;
  QTabWidget* pages_ = nullptr;                // photos, sketch
  std::filesystem::path pending_sketch_root_;  // opened when its run ends
  RunController* run_controller_ = nullptr;
  QListWidget* photo_list_ = nullptr;
  QLabel* photo_label_ = nullptr;
  QMenu* recent_menu_ = nullptr;
  QAction *undo_action_ = nullptr, *redo_action_ = nullptr;
  QDoubleSpinBox *size_box_ = nullptr, *hardness_box_ = nullptr, *strength_box_ = nullptr;
  std::vector<QCheckBox*> overlay_boxes_;
  QCheckBox *edits_box_ = nullptr, *mesh_box_ = nullptr, *points_box_ = nullptr,
            *skeleton_box_ = nullptr;
  QPushButton *run_button_ = nullptr, *cancel_button_ = nullptr;
  QPlainTextEdit* summary_text_ = nullptr;
  QTabWidget* panels_ = nullptr;
  struct StageRow {
    QLabel* state = nullptr;
    QProgressBar* bar = nullptr;
    QToolButton* run = nullptr;
  };
  std::map<Stage, StageRow> stage_rows_;
  std::map<QString, QString> photo_titles_;
  QString last_error_;
  int stages_started_ = 0;  // in the current run
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_MAIN_WINDOW_H_
