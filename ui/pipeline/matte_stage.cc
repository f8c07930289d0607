// The matte stage (projects without given mattes): every photo -> an alpha
// matte (automatic trimap, or the painted one in edits/trimaps/, refined by
// alpha matting) -> out/mattes/<photo>.png (8-bit, same relative name).
//
// Mattes are cached per photo: cache/mattes.json records, for each photo,
// a key of the photo file, its trimap hint and the Matting options; a photo
// whose key is unchanged and whose matte exists is not recomputed.
#include <atomic>
#include <mutex>
#include <sstream>

#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/logging.h"
#include "core/util/threading.h"
#include "reconstruct/matting/matting.h"
#include "reconstruct/matting/trimap_io.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

constexpr char kMatteVersion[] = "matte/1";

fs::path MatteRecordsPath(const Project& project) { return project.CacheDir() / "mattes.json"; }

// cache/mattes.json's "photos" object (empty if missing or unreadable: the
// cache is safe to delete).
Json ReadMatteRecords(const Project& project) {
  const fs::path path = MatteRecordsPath(project);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Json::object();
  try {
    const Json json = ReadJsonFile(path);
    if (json.is_object() && json.contains("photos") && json["photos"].is_object()) {
      return json["photos"];
    }
  } catch (const InputError& error) {
    SYLVA_LOG(kWarning) << error.what() << " (ignored; mattes will be recomputed)";
  }
  return Json::object();
}

}  // namespace

StageRun RunMatteStage(const StageContext& context) {
  const Project& project = context.project;
  const std::vector<std::string>& names = project.photo_names();
  const std::string options_text = OptionsText(context.options, {"Matting."});
  const fs::path background_path = context.options.matte_stage.background_photo.empty()
                                       ? fs::path()
                                       : fs::path(context.options.matte_stage.background_photo);
  FloatImage background;
  std::string background_key;
  if (!background_path.empty()) {
    const fs::path resolved =
        background_path.is_absolute() ? background_path : project.root() / background_path;
    background = ReadImage(resolved);
    background_key = FileKey(project, resolved);
  }

  // Which photos need a new matte.
  const Json previous = ReadMatteRecords(project);
  std::vector<std::string> keys(names.size());
  std::vector<int> to_compute;
  for (size_t i = 0; i < names.size(); ++i) {
    const fs::path hint = project.TrimapHintPath(names[i]);
    keys[i] = HexString(Fnv1a64(std::string(kMatteVersion) + ";" +
                                FileKey(project, project.PhotoPath(names[i])) + ";" +
                                (hint.empty() ? "no hint" : FileKey(project, hint)) + ";" +
                                background_key + ";" + options_text));
    std::error_code exists_ec;
    const bool cached = previous.contains(names[i]) && previous[names[i]].is_string() &&
                        previous[names[i]].get<std::string>() == keys[i] &&
                        fs::is_regular_file(project.ComputedMattePath(names[i]), exists_ec);
    if (!cached) to_compute.push_back(static_cast<int>(i));
  }

  // New mattes are written to a staging folder and moved into out/mattes/
  // only when every one succeeded, so a failed or cancelled stage changes
  // nothing in out/.
  const fs::path staging = TempPathBeside(project.CacheDir() / "matte-staging");
  std::error_code ec;
  fs::remove_all(staging, ec);
  const auto staged = [&](const std::string& name) {
    return staging / fs::path(name).replace_extension(".png");
  };
  ProgressTask progress(context.progress, "matte: computing mattes");
  progress.Update(0.0);
  std::atomic<int> done{0};
  std::vector<double> foreground(names.size(), -1.0);
  try {
    ParallelForFirstError(static_cast<int>(to_compute.size()), [&](int t) {
      progress.CheckCancelled();
      const int i = to_compute[t];
      const fs::path photo_path = project.PhotoPath(names[i]);
      const FloatImage photo = ReadImage(photo_path);
      SYLVA_CHECK_INPUT(photo.channels() >= 3, photo_path.string())
          << "photo has " << photo.channels() << " channel(s); matting needs colour photos";
      FloatImage hint;
      const fs::path hint_path = project.TrimapHintPath(names[i]);
      if (!hint_path.empty()) {
        hint = ReadHintTrimap(hint_path);
        SYLVA_CHECK_INPUT(hint.width() == photo.width() && hint.height() == photo.height(),
                          hint_path.string())
            << "trimap is " << hint.width() << "x" << hint.height() << " but the photo is "
            << photo.width() << "x" << photo.height();
      }
      if (!background.empty()) {
        SYLVA_CHECK_INPUT(
            background.width() == photo.width() && background.height() == photo.height(),
            context.options.matte_stage.background_photo)
            << "background photo is " << background.width() << "x" << background.height()
            << " but photo '" << names[i] << "' is " << photo.width() << "x" << photo.height();
      }
      const FloatImage matte = ComputeMatte(photo, hint, background, context.options.matting);
      double sum = 0.0;
      for (float a : matte.values()) sum += a;
      foreground[i] = sum / static_cast<double>(matte.NumPixels());
      fs::create_directories(staged(names[i]).parent_path());
      WriteImage(staged(names[i]), matte, PixelFormat::kUint8);
      progress.Update(static_cast<double>(++done) / to_compute.size());
    });
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  for (int i : to_compute) {
    const fs::path target = project.ComputedMattePath(names[i]);
    fs::create_directories(target.parent_path());
    fs::rename(staged(names[i]), target);
  }
  fs::remove_all(staging, ec);
  progress.Update(1.0);

  Json records = Json::object();
  for (size_t i = 0; i < names.size(); ++i) records[names[i]] = keys[i];
  WriteJsonFile(MatteRecordsPath(project), Json{{"photos", records}});

  double mean_foreground = 0.0;
  int computed = 0;
  for (double f : foreground) {
    if (f < 0) continue;
    mean_foreground += f;
    ++computed;
  }
  std::ostringstream brief;
  brief << names.size() << " mattes in out/mattes/ (" << to_compute.size() << " computed, "
        << names.size() - to_compute.size() << " unchanged)";
  if (computed > 0) {
    brief << "; mean foreground " << 100.0 * mean_foreground / computed << " % of the pixels";
  }
  StageRun run;
  run.brief = brief.str();
  for (const std::string& name : names) run.outputs.push_back(project.ComputedMattePath(name));
  return run;
}

}  // namespace sylva
