// Every option of the pipeline, as a panel generated from the one option
// registry (ui/pipeline/option_registry.h, COLMAP's OptionManager idea):
// one page per section, one field per Section.field with its unit and help
// as tooltip. An edited value is parsed by the registry (an unparsable one
// is shown in red and not kept) and the project's non-default options are
// saved to sylva.json at once (atomically).
#ifndef SYLVA_UI_DESKTOP_OPTIONS_PANEL_H_
#define SYLVA_UI_DESKTOP_OPTIONS_PANEL_H_

#include <QWidget>
#include <map>
#include <memory>
#include <string>

#include "ui/pipeline/option_registry.h"
#include "ui/pipeline/pipeline_options.h"

class QToolBox;

namespace sylva {

class Project;

class OptionsPanel : public QWidget {
  Q_OBJECT

 public:
  explicit OptionsPanel(QWidget* parent = nullptr);

  // Shows the options of `project` (its saved ones over the defaults); the
  // project must outlive the panel or the next SetProject. Null clears.
  void SetProject(Project* project);
  const PipelineOptions& options() const { return *options_; }
  const OptionRegistry& registry() const { return *registry_; }

  // Sets an option as if typed into its field (for tests and scripts);
  // false if the registry refused the text.
  bool SetText(const std::string& key, const std::string& text);
  // The field of `key` (a QLineEdit or QCheckBox), or null.
  QWidget* Field(const std::string& key) const;

 signals:
  void OptionsChanged();
  void SaveFailed(const QString& message);

 private:
  void Rebuild();
  bool Commit(const std::string& key, const std::string& text);

  Project* project_ = nullptr;
  std::unique_ptr<PipelineOptions> options_;
  std::unique_ptr<OptionRegistry> registry_;
  QToolBox* toolbox_ = nullptr;
  std::map<std::string, QWidget*> fields_;
};

}  // namespace sylva

#endif  // SYLVA_UI_DESKTOP_OPTIONS_PANEL_H_
