#include "ui/desktop/new_project_wizard.h"

#include <QButtonGroup>
#include <QCheckBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QRadioButton>
#include <QVBoxLayout>
#include <exception>
#include <vector>

#include "ui/desktop/loose_cameras_page.h"

namespace sylva {
namespace {

struct SourceInfo {
  CameraSource source;
  const char* label;
  const char* path_hint;  // what camera_path holds; empty: nothing
};

const std::vector<SourceInfo>& Sources() {
  static const std::vector<SourceInfo> sources = {
      {CameraSource::kColmapModel,
       "Given COLMAP sparse model (folder of cameras/images .txt or .bin)", "COLMAP model folder"},
      {CameraSource::kCameraFile,
       "Given sylva camera file (.json, orthographic or hand-placed views)", "camera file"},
      {CameraSource::kRegisterColmap, "Register with COLMAP (structure from motion on the photos)",
       ""},
      {CameraSource::kRegisterManual,
       "Manual: 2-4 loose cameras (azimuths and clicked points: a loose cameras file, or "
       "leave it empty to click them on the next page)",
       "loose cameras file"},
  };
  return sources;
}

}  // namespace

NewProjectWizard::NewProjectWizard(QWidget* parent) : QWizard(parent) {
  setWindowTitle("New sylva project");
  setOption(QWizard::NoBackButtonOnStartPage);
  setPage(kPhotosPage, BuildPhotosPage());
  setPage(kCamerasPage, BuildCamerasPage());
  loose_page_ = new LooseCamerasPage(
      [this] { return std::filesystem::path(photos_->text().trimmed().toStdString()); });
  setPage(kLoosePage, loose_page_);
  setPage(kProjectPage, BuildProjectPage());
}

QWidget* NewProjectWizard::PathRow(QLineEdit* edit, bool file, const QString& title) {
  auto* row = new QWidget;
  auto* layout = new QHBoxLayout(row);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(edit, 1);
  auto* browse = new QPushButton("Browse…");
  layout->addWidget(browse);
  connect(browse, &QPushButton::clicked, this, [this, edit, file, title] {
    const QString path = file ? QFileDialog::getOpenFileName(this, title, edit->text())
                              : QFileDialog::getExistingDirectory(this, title, edit->text());
    if (!path.isEmpty()) edit->setText(path);
  });
  return row;
}

QWizardPage* NewProjectWizard::BuildPhotosPage() {
  auto* page = new QWizardPage;
  page->setTitle("Photos");
  page->setSubTitle("The photos of one tree, and optionally their mattes.");
  auto* form = new QFormLayout(page);
  photos_ = new QLineEdit;
  mattes_ = new QLineEdit;
  mattes_->setPlaceholderText("optional: else the photos' alpha, else computed");
  held_out_ = new QLineEdit;
  held_out_->setPlaceholderText("optional: a.png, b.png  or  @FILE (one name per line)");
  copy_ = new QCheckBox("Copy the photos and mattes into the project");
  form->addRow("Photos folder", PathRow(photos_, false, "Photos folder"));
  form->addRow("Mattes folder", PathRow(mattes_, false, "Mattes folder"));
  form->addRow("Held-out views", held_out_);
  form->addRow(copy_);
  return page;
}

QWizardPage* NewProjectWizard::BuildCamerasPage() {
  auto* page = new QWizardPage;
  page->setTitle("Cameras");
  page->setSubTitle("Where the photos were taken from.");
  auto* layout = new QVBoxLayout(page);
  sources_ = new QButtonGroup(this);
  for (const SourceInfo& info : Sources()) {
    auto* button = new QRadioButton(info.label);
    sources_->addButton(button, static_cast<int>(info.source));
    layout->addWidget(button);
  }
  camera_path_ = new QLineEdit;
  units_ = new QLineEdit;
  units_->setPlaceholderText("optional: from the camera file, else 'arbitrary'");
  auto* form = new QFormLayout;
  auto* path_label = new QLabel;
  form->addRow(path_label, PathRow(camera_path_, true, "Cameras"));
  form->addRow("World units", units_);
  layout->addLayout(form);
  connect(sources_, &QButtonGroup::idToggled, this, [path_label, this](int id, bool on) {
    if (!on) return;
    const SourceInfo& info = Sources()[id];
    path_label->setText(info.path_hint[0] ? QString(info.path_hint) : QString("(none)"));
    camera_path_->setEnabled(info.path_hint[0] != '\0');
  });
  SetCameraSource(CameraSource::kColmapModel);
  return page;
}

QWizardPage* NewProjectWizard::BuildProjectPage() {
  auto* page = new QWizardPage;
  page->setTitle("Project folder");
  page->setSubTitle("A new (or empty) folder for the project: settings, edits and outputs.");
  auto* layout = new QVBoxLayout(page);
  project_ = new QLineEdit;
  layout->addWidget(PathRow(project_, false, "Project folder"));
  error_label_ = new QLabel;
  error_label_->setWordWrap(true);
  error_label_->setStyleSheet("color: #c03030");
  layout->addWidget(error_label_);
  layout->addStretch(1);
  page->setFinalPage(true);
  return page;
}

QLineEdit* NewProjectWizard::Field(const QString& name) const {
  const std::vector<std::pair<const char*, QLineEdit*>> fields = {
      {"photos", photos_},           {"mattes", mattes_}, {"held_out", held_out_},
      {"camera_path", camera_path_}, {"units", units_},   {"project", project_}};
  for (const auto& [key, edit] : fields) {
    if (name == key) return edit;
  }
  return nullptr;
}

void NewProjectWizard::SetCameraSource(CameraSource source) {
  sources_->button(static_cast<int>(source))->setChecked(true);
}

void NewProjectWizard::SetCopyInputs(bool copy) { copy_->setChecked(copy); }

ProjectSetup NewProjectWizard::Setup() const {
  const auto path = [](const QLineEdit* edit) {
    return std::filesystem::path(edit->text().trimmed().toStdString());
  };
  ProjectSetup setup;
  setup.root = path(project_);
  setup.photos_dir = path(photos_);
  setup.mattes_dir = path(mattes_);
  setup.held_out = ParseViewNames(held_out_->text().trimmed().toStdString());
  setup.copy_inputs = copy_->isChecked();
  setup.units = units_->text().trimmed().toStdString();
  switch (static_cast<CameraSource>(sources_->checkedId())) {
    case CameraSource::kColmapModel:
      setup.colmap_model_dir = path(camera_path_);
      break;
    case CameraSource::kCameraFile:
      setup.camera_file = path(camera_path_);
      break;
    case CameraSource::kRegisterColmap:
      setup.register_method = "colmap";
      break;
    case CameraSource::kRegisterManual:
      setup.register_method = "manual";
      setup.loose_cameras_file = path(camera_path_);
      if (setup.loose_cameras_file.empty()) setup.loose_cameras_file = loose_page_->written_file();
      break;
  }
  return setup;
}

bool NewProjectWizard::CreateProject() {
  try {
    const Project project = Project::Create(Setup());
    created_root_ = project.root();
    last_error_.clear();
    error_label_->clear();
    return true;
  } catch (const std::exception& error) {
    last_error_ = QString::fromStdString(error.what());
    error_label_->setText(last_error_);
    return false;
  }
}

int NewProjectWizard::nextId() const {
  switch (currentId()) {
    case kPhotosPage:
      return kCamerasPage;
    case kCamerasPage:
      return sources_->checkedId() == static_cast<int>(CameraSource::kRegisterManual) &&
                     camera_path_->text().trimmed().isEmpty()
                 ? kLoosePage
                 : kProjectPage;
    case kLoosePage:
      return kProjectPage;
    default:
      return -1;
  }
}

bool NewProjectWizard::validateCurrentPage() {
  if (!QWizard::validateCurrentPage()) return false;
  return currentPage() != page(pageIds().back()) || CreateProject();
}

}  // namespace sylva
