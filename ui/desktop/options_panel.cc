#include "ui/desktop/options_panel.h"

#include <QCheckBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QScrollArea>
#include <QToolBox>
#include <QVBoxLayout>
#include <exception>

#include "ui/pipeline/project.h"

namespace sylva {
namespace {

std::string SectionOf(const std::string& key) { return key.substr(0, key.find('.')); }

QString Tooltip(const OptionRegistry::Entry& entry) {
  QString tip = QString::fromStdString(entry.key + " (" + entry.type +
                                       (entry.unit.empty() ? "" : ", " + entry.unit) + ")\n" +
                                       entry.help + "\ndefault: " + entry.default_text);
  return tip;
}

}  // namespace

OptionsPanel::OptionsPanel(QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  toolbox_ = new QToolBox(this);
  layout->addWidget(toolbox_);
  options_ = std::make_unique<PipelineOptions>();
  registry_ = std::make_unique<OptionRegistry>();
  RegisterPipelineOptions(options_.get(), registry_.get());
}

void OptionsPanel::SetProject(Project* project) {
  project_ = project;
  options_ = std::make_unique<PipelineOptions>();
  registry_ = std::make_unique<OptionRegistry>();
  RegisterPipelineOptions(options_.get(), registry_.get());
  if (project_ != nullptr) project_->ApplySavedOptions(registry_.get());
  Rebuild();
}

void OptionsPanel::Rebuild() {
  while (toolbox_->count() > 0) {
    QWidget* page = toolbox_->widget(0);
    toolbox_->removeItem(0);
    page->deleteLater();
  }
  fields_.clear();
  // One page per section, in the order sections first appear (a section's
  // fields need not be registered together).
  std::map<std::string, QFormLayout*> forms;
  for (const OptionRegistry::Entry& entry : registry_->entries()) {
    const std::string section = SectionOf(entry.key);
    QFormLayout*& form = forms[section];
    if (form == nullptr) {
      auto* scroll = new QScrollArea;
      auto* page = new QWidget;
      form = new QFormLayout(page);
      form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
      scroll->setWidget(page);
      scroll->setWidgetResizable(true);
      toolbox_->addItem(scroll, QString::fromStdString(section));
    }
    const std::string key = entry.key;
    QWidget* field = nullptr;
    if (entry.type == "bool") {
      auto* box = new QCheckBox;
      box->setChecked(registry_->Get(key) == "true");
      connect(box, &QCheckBox::toggled,
              [this, key](bool on) { Commit(key, on ? "true" : "false"); });
      field = box;
    } else {
      auto* edit = new QLineEdit(QString::fromStdString(registry_->Get(key)));
      connect(edit, &QLineEdit::editingFinished, [this, key, edit] {
        const bool ok = Commit(key, edit->text().toStdString());
        edit->setStyleSheet(ok ? "" : "background: #f4b4b4");
        if (ok) edit->setText(QString::fromStdString(registry_->Get(key)));
      });
      field = edit;
    }
    field->setToolTip(Tooltip(entry));
    field->setObjectName(QString::fromStdString(key));
    auto* label = new QLabel(QString::fromStdString(key.substr(section.size() + 1)));
    label->setToolTip(Tooltip(entry));
    form->addRow(label, field);
    fields_[key] = field;
  }
}

QWidget* OptionsPanel::Field(const std::string& key) const {
  const auto it = fields_.find(key);
  return it == fields_.end() ? nullptr : it->second;
}

bool OptionsPanel::SetText(const std::string& key, const std::string& text) {
  QWidget* field = Field(key);
  if (auto* box = qobject_cast<QCheckBox*>(field)) {
    if (text != "true" && text != "false") return false;
    box->setChecked(text == "true");
    return registry_->Get(key) == text;
  }
  auto* edit = qobject_cast<QLineEdit*>(field);
  if (edit == nullptr) return false;
  edit->setText(QString::fromStdString(text));
  emit edit->editingFinished();
  return edit->styleSheet().isEmpty();
}

bool OptionsPanel::Commit(const std::string& key, const std::string& text) {
  try {
    registry_->Set(key, text, "the options panel");
  } catch (const std::exception&) {
    return false;
  }
  if (project_ != nullptr) {
    try {
      project_->SaveOptions(*registry_);
    } catch (const std::exception& error) {
      emit SaveFailed(QString::fromStdString(error.what()));
    }
  }
  emit OptionsChanged();
  return true;
}

}  // namespace sylva
