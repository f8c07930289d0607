// The new-project wizard (File > New project): the choices of `sylva init`
// on three pages (photos; cameras; project folder), made into a project by
// the same library call, Project::Create, so the wizard and the CLI give the
// same sylva.json for the same choices. Errors (a missing photo, a bad
// camera file) are shown on the last page, which stays open; nothing is
// written then.
//
// Cameras: a COLMAP sparse model folder, a sylva camera file, registration
// by COLMAP's structure from motion, or manual registration from a loose
// cameras file (azimuths and clicked correspondences,
// reconstruct/registration/loose_setup_io.h) -- given, or made on the
// manual cameras page (loose_cameras_page.h) when none is given.
#ifndef SYLVA_UI_DESKTOP_NEW_PROJECT_WIZARD_H_
#define SYLVA_UI_DESKTOP_NEW_PROJECT_WIZARD_H_

#include <QString>
#include <QWizard>
#include <filesystem>

#include "ui/pipeline/project.h"

class QButtonGroup;
class QCheckBox;
class QLabel;
class QLineEdit;

namespace sylva {

class LooseCamerasPage;

// How the wizard's project gets its cameras (ProjectSetup's sources).
enum class CameraSource { kColmapModel, kCameraFile, kRegisterColmap, kRegisterManual };

class NewProjectWizard : public QWizard {
  Q_OBJECT

 public:
  explicit NewProjectWizard(QWidget* parent = nullptr);

  // The fields, by name (for tests and scripting): "photos", "mattes",
  // "held_out", "camera_path", "units", "project"; null for another name.
  QLineEdit* Field(const QString& name) const;
  void SetCameraSource(CameraSource source);
  void SetCopyInputs(bool copy);

  // What the choices amount to (as `sylva init` would be given them).
  ProjectSetup Setup() const;
  // The project created when the wizard was accepted; empty before.
  const std::filesystem::path& created_root() const { return created_root_; }
  // The error of the last failed attempt, empty if none.
  const QString& last_error() const { return last_error_; }

  // Creates the project (Project::Create); false, with the error shown on
  // the page, if it cannot be made.
  bool CreateProject();

  // On the last page: CreateProject().
  bool validateCurrentPage() override;
  // The manual cameras page comes after the cameras page only for manual
  // registration without a loose cameras file.
  int nextId() const override;

  LooseCamerasPage* loose_page() const { return loose_page_; }

  enum PageId { kPhotosPage, kCamerasPage, kLoosePage, kProjectPage };

 private:
  QWizardPage* BuildPhotosPage();
  QWizardPage* BuildCamerasPage();
  QWizardPage* BuildProjectPage();
  // A line edit with a Browse button (a folder, or a file if `file`).
  QWidget* PathRow(QLineEdit* edit, bool file, const QString& title);

  QLineEdit *photos_ = nullptr, *mattes_ = nullptr, *held_out_ = nullptr;
  QLineEdit *camera_path_ = nullptr, *units_ = nullptr, *project_ = nullptr;
  QCheckBox* copy_ = nullptr;
  QButtonGroup* sources_ = nullptr;
  LooseCamerasPage* loose_page_ = nullptr;
  QLabel* error_label_ = nullptr;
  std::filesystem::path created_root_;
  QString last_error_;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_NEW_PROJECT_WIZARD_H_
