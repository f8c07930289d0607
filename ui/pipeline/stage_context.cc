#include "ui/pipeline/stage_context.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/logging.h"
#include "core/util/threading.h"

namespace sylva {

void StageRun::AddFigure(const std::string& key, double value, const std::string& unit) {
  figures.push_back({key, value, unit});
}

std::optional<double> StageRun::Figure(const std::string& key) const {
  for (const StageFigure& figure : figures) {
    if (figure.key == key) return figure.value;
  }
  return std::nullopt;
}

std::string FiguresText(const std::vector<StageFigure>& figures) {
  std::ostringstream text;
  for (size_t i = 0; i < figures.size(); ++i) {
    const StageFigure& figure = figures[i];
    text << (i > 0 ? ", " : "") << figure.key << "=";
    // Counts up to 2^53 are exact in a double: print them whole.
    if (figure.value == std::round(figure.value) && std::abs(figure.value) < 9.0e15) {
      text << static_cast<int64_t>(figure.value);
    } else {
      text << std::setprecision(4) << figure.value;
    }
    if (!figure.unit.empty()) text << " " << figure.unit;
  }
  return text.str();
}

StageStep& StageStep::Add(const std::string& step_name, double step_seconds) {
  steps.push_back({step_name, step_seconds, {}});
  return *this;
}

std::string ProfileText(const std::vector<StageStep>& steps) {
  std::ostringstream text;
  text << std::setprecision(3);
  for (size_t i = 0; i < steps.size(); ++i) {
    text << (i > 0 ? ", " : "") << steps[i].name << " " << steps[i].seconds << " s";
    if (steps[i].steps.empty()) continue;
    text << " (";
    for (size_t k = 0; k < steps[i].steps.size(); ++k) {
      text << (k > 0 ? ", " : "") << steps[i].steps[k].name << " " << steps[i].steps[k].seconds;
    }
    text << ")";
  }
  return text.str();
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

StepClock::StepClock(std::vector<StageStep>* steps)
    : steps_(steps), start_(std::chrono::steady_clock::now()) {}

StageStep& StepClock::Lap(const std::string& name) {
  const auto now = std::chrono::steady_clock::now();
  steps_->push_back({name, std::chrono::duration<double>(now - start_).count(), {}});
  start_ = now;
  return steps_->back();
}

fs::path StageContext::RequireOutput(const std::string& name, const char* stage) const {
  const fs::path path = Out(name);
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(path, ec), path.string())
      << "not made yet; run the " << stage << " stage first ('sylva run')";
  return path;
}

ImageSet StageContext::InputViews() const {
  ImageSet inputs = project.LoadCameras();
  std::vector<View> kept;
  for (const View& view : inputs.views) {
    if (!project.IsHeldOut(view.name)) kept.push_back(view);
  }
  inputs.views = std::move(kept);
  return inputs;
}

std::vector<FloatImage> StageContext::LoadMattes(const ImageSet& image_set, const std::string& task,
                                                 bool edited) const {
  ProgressTask progress_task(progress, task);
  std::vector<FloatImage> mattes(image_set.NumViews());
  progress_task.Update(0.0);
  ParallelForFirstError(image_set.NumViews(), [&](int v) {
    progress_task.CheckCancelled();
    mattes[v] = edited ? project.LoadEditedMatte(image_set, v) : project.LoadMatte(image_set, v);
  });
  progress_task.Update(1.0);
  return mattes;
}

std::string StageContext::Units() const {
  const fs::path path = project.RegisteredCamerasDir() / "registration.json";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return project.units();
  const Json json = ReadJsonFile(path);
  return json.is_object() && json.contains("units") && json["units"].is_string()
             ? json["units"].get<std::string>()
             : project.units();
}

std::string StageContext::RecordedBrief(const std::string& stage_name) const {
  return ReadRecordedBrief(project, stage_name);
}

std::string ReadRecordedBrief(const Project& project, const std::string& stage_name) {
  const Json records = ParseJson(ReadStageRecordsText(project), "stage records");
  if (!records.contains(stage_name) || !records[stage_name].is_object()) return "";
  return records[stage_name].value("summary", "");
}

std::vector<Warning> ReadRecordedWarnings(const Project& project, const std::string& stage_name) {
  const Json records = ParseJson(ReadStageRecordsText(project), "stage records");
  std::vector<Warning> warnings;
  if (!records.contains(stage_name)) return warnings;
  for (const Json& warning : records[stage_name].value("warnings", Json::array())) {
    if (warning.is_object()) {
      warnings.push_back(
          {warning.value("code", ""), warning.value("message", ""), warning.value("subject", "")});
    }
  }
  return warnings;
}

std::vector<Warning> StageContext::RecordedWarnings(const std::string& stage_name) const {
  return ReadRecordedWarnings(project, stage_name);
}

std::vector<StageFigure> ReadRecordedFigures(const Project& project,
                                             const std::string& stage_name) {
  const Json records = ParseJson(ReadStageRecordsText(project), "stage records");
  std::vector<StageFigure> figures;
  if (!records.contains(stage_name)) return figures;
  for (const Json& figure : records[stage_name].value("figures", Json::array())) {
    if (figure.is_object() && figure.contains("value") && figure["value"].is_number()) {
      figures.push_back(
          {figure.value("key", ""), figure["value"].get<double>(), figure.value("unit", "")});
    }
  }
  return figures;
}

std::vector<StageFigure> StageContext::RecordedFigures(const std::string& stage_name) const {
  return ReadRecordedFigures(project, stage_name);
}

std::string OptionsText(const PipelineOptions& options, const std::vector<std::string>& prefixes) {
  PipelineOptions copy = options;
  OptionRegistry registry;
  RegisterPipelineOptions(&copy, &registry);
  std::string text;
  for (const auto& entry : registry.entries()) {
    for (const std::string& prefix : prefixes) {
      if (entry.key.rfind(prefix, 0) == 0) text += entry.key + "=" + entry.get() + ";";
    }
  }
  return text;
}

std::string FileKey(const Project& project, const fs::path& file) {
  const fs::path relative = file.lexically_relative(project.root());
  const bool inside = !relative.empty() && *relative.begin() != "..";
  return (inside ? relative : file).generic_string() + ":" + HexString(FileStamp(file));
}

std::string ReadStageRecordsText(const Project& project) {
  const fs::path path = project.CacheDir() / "stages.json";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return "{}";
  try {
    const Json json = ReadJsonFile(path);
    return json.is_object() ? json.dump() : "{}";
  } catch (const InputError& error) {
    SYLVA_LOG(kWarning) << error.what() << " (ignored; stages will re-run)";
    return "{}";
  }
}

}  // namespace sylva
