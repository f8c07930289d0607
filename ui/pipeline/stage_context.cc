#include "ui/pipeline/stage_context.h"

#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/logging.h"
#include "core/util/threading.h"

namespace sylva {

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

std::vector<FloatImage> StageContext::LoadMattes(const ImageSet& image_set,
                                                 const std::string& task) const {
  ProgressTask progress_task(progress, task);
  std::vector<FloatImage> mattes(image_set.NumViews());
  progress_task.Update(0.0);
  ParallelForFirstError(image_set.NumViews(), [&](int v) {
    progress_task.CheckCancelled();
    mattes[v] = project.LoadMatte(image_set, v);
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
  const Json records = ParseJson(ReadStageRecordsText(project), "stage records");
  if (!records.contains(stage_name)) return "";
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
