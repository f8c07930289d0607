// The new-project wizard's page for manual ("loose") cameras when no loose
// cameras file is given: the person picks 2-4 photos, gives each its
// azimuth around the tree and projection, and clicks the tree's base, its
// top and any other named point on each photo that shows it. The page
// writes the loose cameras file (reconstruct/registration/loose_setup_io.h)
// that `sylva init --register manual --loose-cameras FILE` takes, and the
// wizard creates the project from it.
#ifndef SYLVA_UI_DESKTOP_LOOSE_CAMERAS_PAGE_H_
#define SYLVA_UI_DESKTOP_LOOSE_CAMERAS_PAGE_H_

#include <QPointF>
#include <QString>
#include <QTemporaryDir>
#include <QWizardPage>
#include <filesystem>
#include <functional>
#include <map>
#include <utility>

#include "reconstruct/registration/loose_setup.h"

class QComboBox;
class QDoubleSpinBox;
class QGraphicsScene;
class QGraphicsView;
class QLabel;
class QLineEdit;
class QTableWidget;

namespace sylva {

class LooseCamerasPage : public QWizardPage {
  Q_OBJECT

 public:
  // `photos_dir` gives the photos folder the wizard's first page names.
  explicit LooseCamerasPage(std::function<std::filesystem::path()> photos_dir,
                            QWidget* parent = nullptr);

  // Lists the photos of the folder (called when the page is shown).
  void initializePage() override;
  // Checks the set-up and writes the loose cameras file; false (with the
  // error shown) if it is incomplete.
  bool validatePage() override;

  // For tests and scripting: use photo `row` (0-based, in name order) with
  // an azimuth; show it; name the point that clicks place.
  void UsePhoto(int row, double azimuth_deg, bool orthographic = false);
  void ShowPhoto(int row);
  void SetCurrentPoint(const QString& name);
  QGraphicsView* photo_view() const { return view_; }

  // What the page holds now, and the file written by validatePage().
  LooseSetup Setup() const;
  const std::filesystem::path& written_file() const { return written_file_; }

 protected:
  bool eventFilter(QObject* object, QEvent* event) override;

 private:
  void DrawMarks();

  std::function<std::filesystem::path()> photos_dir_;
  QTableWidget* photos_ = nullptr;  // use, name, azimuth, projection
  QComboBox* points_ = nullptr;     // editable: the point clicks place
  QDoubleSpinBox* tree_height_ = nullptr;
  QLineEdit* units_ = nullptr;
  QGraphicsView* view_ = nullptr;
  QGraphicsScene* scene_ = nullptr;
  QLabel* error_ = nullptr;
  int shown_row_ = -1;
  // (point name, photo name) -> clicked pixel (COLMAP convention).
  std::map<std::pair<QString, QString>, QPointF> clicks_;
  QTemporaryDir temp_;
  std::filesystem::path written_file_;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_LOOSE_CAMERAS_PAGE_H_
