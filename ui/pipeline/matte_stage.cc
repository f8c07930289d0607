// The matte stage (projects without given mattes): every photo -> an alpha
// matte (automatic trimap, or the painted one in edits/trimaps/, refined by
// alpha matting), then the whole set is checked (reconstruct/matting/
// matte_set.h): static structure of a fixed-camera rig becomes background,
// and implausible mattes (border-filling, foreground far from the others'
// share, e.g. inverted) are re-matted against the backdrop the other photos
// agree on, or named -> out/mattes/<photo>.png (8-bit, same relative name).
//
// Each photo's own matte is cached: cache/mattes/<photo>.png, with
// cache/mattes.json recording for each photo a key of the photo file, its
// trimap hint and the Matting options, and the trimap source and backdrop
// colour found; a photo whose key is unchanged is not matted again. The set
// checks are quick (small copies) and run whenever the stage runs.
#include <algorithm>
#include <atomic>
#include <sstream>

#include "core/io/image_io.h"
#include "core/io/json_util.h"
#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/logging.h"
#include "core/util/statistics.h"
#include "core/util/threading.h"
#include "reconstruct/matting/matte_set.h"
#include "reconstruct/matting/matte_tools.h"
#include "reconstruct/matting/matting.h"
#include "reconstruct/matting/trimap_io.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

constexpr char kMatteVersion[] = "matte/2";

fs::path MatteRecordsPath(const Project& project) { return project.CacheDir() / "mattes.json"; }

// Where a photo's own matte (before the set checks) is cached.
fs::path OwnMattePath(const Project& project, const std::string& name) {
  return project.CacheDir() / "mattes" / fs::path(name).replace_extension(".png");
}

// What matting one photo found, kept with its cached matte, and the key of
// the final matte made from it (out/mattes/), which is only rewritten when
// that key changes.
struct OwnMatte {
  std::string key;
  std::string trimap_source;
  std::array<double, 3> backdrop_rgb = {0, 0, 0};
  std::string final_key;
  bool repaired = false;  // the final matte was matted again (MatteSet checks)
};

Json OwnMatteJson(const OwnMatte& own) {
  return {{"key", own.key},
          {"trimap_source", own.trimap_source},
          {"backdrop_rgb", {own.backdrop_rgb[0], own.backdrop_rgb[1], own.backdrop_rgb[2]}},
          {"final_key", own.final_key},
          {"repaired", own.repaired}};
}

// cache/mattes.json's records by photo name (none if missing or unreadable:
// the cache is safe to delete).
std::map<std::string, OwnMatte> ReadMatteRecords(const Project& project) {
  std::map<std::string, OwnMatte> records;
  const fs::path path = MatteRecordsPath(project);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return records;
  try {
    const Json json = ReadJsonFile(path);
    if (!json.is_object() || !json.contains("photos") || !json["photos"].is_object())
      return records;
    for (const auto& [name, record] : json["photos"].items()) {
      if (!record.is_object() || !record.contains("backdrop_rgb")) continue;
      OwnMatte own;
      own.key = record.value("key", "");
      own.trimap_source = record.value("trimap_source", "");
      own.final_key = record.value("final_key", "");
      own.repaired = record.value("repaired", false);
      for (int c = 0; c < 3; ++c) own.backdrop_rgb[c] = record["backdrop_rgb"].at(c).get<double>();
      records[name] = own;
    }
  } catch (const std::exception& error) {
    SYLVA_LOG(kWarning) << path.string() << ": " << error.what()
                        << " (ignored; mattes will be recomputed)";
  }
  return records;
}

// The background photo (Matting's difference keying), or empty.
FloatImage ReadBackgroundPhoto(const StageContext& context, std::string* key) {
  const std::string& given = context.options.matte_stage.background_photo;
  if (given.empty()) return FloatImage();
  const fs::path path =
      fs::path(given).is_absolute() ? fs::path(given) : context.project.root() / given;
  *key = FileKey(context.project, path);
  return ReadImage(path);
}

// A photo, its painted trimap hint (may be empty), checked against each other
// and the background photo.
struct PhotoInputs {
  FloatImage photo, hint;
};

PhotoInputs ReadPhotoInputs(const StageContext& context, const std::string& name,
                            const FloatImage& background) {
  const Project& project = context.project;
  PhotoInputs inputs;
  const fs::path photo_path = project.PhotoPath(name);
  inputs.photo = ReadImage(photo_path);
  SYLVA_CHECK_INPUT(inputs.photo.channels() >= 3, photo_path.string())
      << "photo has " << inputs.photo.channels() << " channel(s); matting needs colour photos";
  const fs::path hint_path = project.TrimapHintPath(name);
  if (!hint_path.empty()) {
    inputs.hint = ReadHintTrimap(hint_path);
    SYLVA_CHECK_INPUT(inputs.hint.width() == inputs.photo.width() &&
                          inputs.hint.height() == inputs.photo.height(),
                      hint_path.string())
        << "trimap is " << inputs.hint.width() << "x" << inputs.hint.height()
        << " but the photo is " << inputs.photo.width() << "x" << inputs.photo.height();
  }
  if (!background.empty()) {
    SYLVA_CHECK_INPUT(
        background.width() == inputs.photo.width() && background.height() == inputs.photo.height(),
        context.options.matte_stage.background_photo)
        << "background photo is " << background.width() << "x" << background.height()
        << " but photo '" << name << "' is " << inputs.photo.width() << "x"
        << inputs.photo.height();
  }
  return inputs;
}

// Mattes every photo listed in `to_compute` into cache/mattes/ (through a
// staging folder, so a failed or cancelled stage leaves the cache as it was)
// and fills their records.
void ComputeOwnMattes(const StageContext& context, const std::vector<int>& to_compute,
                      const FloatImage& background, std::vector<OwnMatte>* records) {
  const Project& project = context.project;
  const std::vector<std::string>& names = project.photo_names();
  const fs::path staging = TempPathBeside(project.CacheDir() / "matte-staging");
  std::error_code ec;
  fs::remove_all(staging, ec);
  const auto staged = [&](const std::string& name) {
    return staging / fs::path(name).replace_extension(".png");
  };
  ProgressTask progress(context.progress, "matte: computing mattes");
  progress.Update(0.0);
  std::atomic<int> done{0};
  try {
    ParallelForFirstError(static_cast<int>(to_compute.size()), [&](int t) {
      progress.CheckCancelled();
      const int i = to_compute[t];
      const PhotoInputs inputs = ReadPhotoInputs(context, names[i], background);
      MattingSummary summary;
      const FloatImage matte = ComputeMatte(inputs.photo, inputs.hint, background,
                                            context.options.matting, nullptr, &summary);
      (*records)[i].trimap_source = summary.trimap_source;
      (*records)[i].backdrop_rgb = summary.backdrop_rgb;
      fs::create_directories(staged(names[i]).parent_path());
      WriteImage(staged(names[i]), matte, PixelFormat::kUint8);
      progress.Update(static_cast<double>(++done) / to_compute.size());
    });
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  for (int i : to_compute) {
    const fs::path target = OwnMattePath(project, names[i]);
    fs::create_directories(target.parent_path());
    fs::rename(staged(names[i]), target);
  }
  fs::remove_all(staging, ec);
  progress.Update(1.0);
}

// The photo set at analysis size, with its own mattes.
struct SmallSet {
  std::vector<FloatImage> photos, mattes;
  std::vector<int> factors;
};

SmallSet ReadSmallSet(const StageContext& context, const MatteSetOptions& options) {
  const std::vector<std::string>& names = context.project.photo_names();
  SmallSet set;
  set.photos.resize(names.size());
  set.mattes.resize(names.size());
  set.factors.resize(names.size());
  ProgressTask progress(context.progress, "matte: checking the set");
  ParallelForFirstError(static_cast<int>(names.size()), [&](int i) {
    progress.CheckCancelled();
    const FloatImage photo = ReadImage(context.project.PhotoPath(names[i]));
    set.factors[i] = MatteSetFactor(photo.width(), photo.height(), options);
    set.photos[i] = DownsampleChannels(photo, set.factors[i]);
    set.mattes[i] = SmallMatte(ReadMatte(OwnMattePath(context.project, names[i])), set.factors[i]);
  });
  return set;
}

// `matte` with the static structure (an analysis-size mask, may be empty)
// made background.
FloatImage WithoutStructure(FloatImage matte, const FloatImage& structure, int factor) {
  if (structure.empty()) return matte;
  for (int y = 0; y < matte.height(); ++y) {
    for (int x = 0; x < matte.width(); ++x) {
      if (structure.at(x / factor, y / factor) > 0.5f) matte.at(x, y) = 0.0f;
    }
  }
  return matte;
}

// A key of an image's size and values (empty images: "none").
std::string ImageKey(const FloatImage& image) {
  if (image.empty()) return "none";
  return std::to_string(image.width()) + "x" + std::to_string(image.height()) + ":" +
         HexString(Fnv1a64(image.data(), image.values().size() * sizeof(float)));
}

double MedianForegroundShare(const std::vector<MatteShape>& shapes) {
  if (shapes.size() < 3) return 0.0;  // too few photos to compare
  std::vector<double> shares;
  for (const MatteShape& shape : shapes) shares.push_back(shape.foreground_share);
  return Median(shares);
}

// The backdrop colour most photos were keyed against (per-channel median of
// the plausible photos keyed by "backdrop"); false if none.
bool ConsensusBackdrop(const std::vector<OwnMatte>& records,
                       const std::vector<std::string>& reasons, std::array<double, 3>* rgb) {
  std::array<std::vector<double>, 3> channels;
  for (size_t i = 0; i < records.size(); ++i) {
    if (records[i].trimap_source != "backdrop" || !reasons[i].empty()) continue;
    for (int c = 0; c < 3; ++c) channels[c].push_back(records[i].backdrop_rgb[c]);
  }
  if (channels[0].empty()) return false;
  for (int c = 0; c < 3; ++c) {
    std::nth_element(channels[c].begin(), channels[c].begin() + channels[c].size() / 2,
                     channels[c].end());
    (*rgb)[c] = channels[c][channels[c].size() / 2];
  }
  return true;
}

std::string RgbText(const std::array<double, 3>& rgb) {
  std::ostringstream out;
  out << std::lround(255 * rgb[0]) << "," << std::lround(255 * rgb[1]) << ","
      << std::lround(255 * rgb[2]);
  return out.str();
}

// Photo i's matte repaired against `backdrop` (RepairMatte), the static
// structure removed; empty if that is no more plausible.
FloatImage RepairedMatte(const StageContext& context, int i, const std::array<double, 3>& backdrop,
                         const FloatImage& structure, const MatteSetOptions& options,
                         double median_share, const FloatImage& background) {
  const std::string& name = context.project.photo_names()[i];
  const PhotoInputs inputs = ReadPhotoInputs(context, name, background);
  const int factor = MatteSetFactor(inputs.photo.width(), inputs.photo.height(), options);
  const FloatImage matte = WithoutStructure(
      RepairMatte(inputs.photo, inputs.hint, ReadMatte(OwnMattePath(context.project, name)),
                  backdrop, context.options.matting),
      structure, factor);
  const MatteShape shape = MeasureMatte(SmallMatte(matte, factor));
  if (!ImplausibleMatteReason(shape, median_share, options).empty()) return FloatImage();
  return matte;
}

// Step 1: the photos whose own matte must be made again (its inputs
// changed), with every photo's record (kept from cache/mattes.json where
// still valid).
std::vector<int> StaleOwnMattes(const StageContext& context, const std::string& background_key,
                                std::vector<OwnMatte>* records) {
  const Project& project = context.project;
  const std::vector<std::string>& names = project.photo_names();
  const std::string options_text = OptionsText(context.options, {"Matting."});
  const std::map<std::string, OwnMatte> previous = ReadMatteRecords(project);
  records->assign(names.size(), OwnMatte());
  std::vector<int> stale;
  for (size_t i = 0; i < names.size(); ++i) {
    const fs::path hint = project.TrimapHintPath(names[i]);
    const std::string key = HexString(Fnv1a64(std::string(kMatteVersion) + ";" +
                                              FileKey(project, project.PhotoPath(names[i])) + ";" +
                                              (hint.empty() ? "no hint" : FileKey(project, hint)) +
                                              ";" + background_key + ";" + options_text));
    const auto found = previous.find(names[i]);
    std::error_code exists_ec;
    if (found != previous.end() && found->second.key == key &&
        fs::is_regular_file(OwnMattePath(project, names[i]), exists_ec)) {
      (*records)[i] = found->second;
    } else {
      (*records)[i].key = key;
      stale.push_back(static_cast<int>(i));
    }
  }
  return stale;
}

void WriteMatteRecords(const Project& project, const std::vector<OwnMatte>& records) {
  Json json = Json::object();
  for (size_t i = 0; i < records.size(); ++i) {
    json[project.photo_names()[i]] = OwnMatteJson(records[i]);
  }
  WriteJsonFile(MatteRecordsPath(project), Json{{"photos", json}});
}

// Step 2: what the set checks found.
struct SetVerdict {
  SmallSet small;
  std::vector<FloatImage> structure;  // per photo, analysis size (empty: none)
  std::vector<MatteShape> shapes;     // without the structure
  double median_share = 0.0;
  std::vector<std::string> reasons;  // per photo: why implausible ("" if not)
  bool has_backdrop = false;         // the set agrees on a backdrop colour
  std::array<double, 3> backdrop{};
};

SetVerdict CheckSet(const StageContext& context, const std::vector<OwnMatte>& records,
                    std::vector<Warning>* warnings) {
  const MatteSetOptions& options = context.options.matte_set;
  SetVerdict verdict;
  verdict.small = ReadSmallSet(context, options);
  verdict.structure =
      FindStaticStructure(verdict.small.photos, verdict.small.mattes, options, warnings);
  for (size_t i = 0; i < records.size(); ++i) {
    verdict.shapes.push_back(
        MeasureMatte(WithoutStructure(verdict.small.mattes[i], verdict.structure[i], 1)));
  }
  verdict.median_share = MedianForegroundShare(verdict.shapes);
  for (const MatteShape& shape : verdict.shapes) {
    verdict.reasons.push_back(ImplausibleMatteReason(shape, verdict.median_share, options));
  }
  verdict.has_backdrop = ConsensusBackdrop(records, verdict.reasons, &verdict.backdrop);
  return verdict;
}

// Step 3: the photos whose final matte must be written again: each final
// key covers the photo's own matte, the structure removed from it, its repair
// and the MatteSet options.
std::vector<int> StaleFinalMattes(const StageContext& context, const SetVerdict& verdict,
                                  std::vector<OwnMatte>* records) {
  const Project& project = context.project;
  const std::string options_text = OptionsText(context.options, {"MatteSet."});
  std::vector<int> stale;
  for (size_t i = 0; i < records->size(); ++i) {
    OwnMatte& record = (*records)[i];
    const std::string repair = verdict.reasons[i].empty() || !verdict.has_backdrop
                                   ? "none"
                                   : "backdrop " + RgbText(verdict.backdrop);
    const std::string key = HexString(Fnv1a64(record.key + ";" + ImageKey(verdict.structure[i]) +
                                              ";" + repair + ";" + options_text));
    std::error_code exists_ec;
    if (key != record.final_key ||
        !fs::is_regular_file(project.ComputedMattePath(project.photo_names()[i]), exists_ec)) {
      stale.push_back(static_cast<int>(i));
    }
    record.final_key = key;
  }
  return stale;
}

// Writes the final mattes of the photos in `stale` to out/mattes/ together
// (staging folder, then renamed): repaired where implausible and repairable,
// else the own matte, static structure removed. Sets records' `repaired`.
void WriteFinalMattes(const StageContext& context, const SetVerdict& verdict,
                      const std::vector<int>& stale, const FloatImage& background,
                      std::vector<OwnMatte>* records) {
  const Project& project = context.project;
  const std::vector<std::string>& names = project.photo_names();
  const fs::path staging = TempPathBeside(project.CacheDir() / "matte-final");
  const auto staged = [&](int i) { return staging / fs::path(names[i]).replace_extension(".png"); };
  std::error_code ec;
  fs::remove_all(staging, ec);
  std::vector<char> repaired(names.size(), 0);
  try {
    ParallelForFirstError(static_cast<int>(stale.size()), [&](int t) {
      const int i = stale[t];
      FloatImage matte;
      if (!verdict.reasons[i].empty() && verdict.has_backdrop) {
        matte = RepairedMatte(context, i, verdict.backdrop, verdict.structure[i],
                              context.options.matte_set, verdict.median_share, background);
        repaired[i] = !matte.empty();
      }
      if (matte.empty()) {
        matte = WithoutStructure(ReadMatte(OwnMattePath(project, names[i])), verdict.structure[i],
                                 verdict.small.factors[i]);
      }
      fs::create_directories(staged(i).parent_path());
      WriteImage(staged(i), matte, PixelFormat::kUint8);
    });
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  for (int i : stale) {
    const fs::path target = project.ComputedMattePath(names[i]);
    fs::create_directories(target.parent_path());
    fs::rename(staged(i), target);
    (*records)[i].repaired = repaired[i];
  }
  fs::remove_all(staging, ec);
}

// The warnings about implausible mattes, repaired or kept.
void AddMatteWarnings(const std::vector<std::string>& names, const SetVerdict& verdict,
                      const std::vector<OwnMatte>& records, std::vector<Warning>* warnings) {
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string& reason = verdict.reasons[i];
    if (reason.empty()) continue;
    if (records[i].repaired) {
      warnings->push_back({"repaired-matte",
                           names[i] + ": " + reason +
                               "; matted again against the backdrop the "
                               "other photos agree on (RGB " +
                               RgbText(verdict.backdrop) + ")",
                           names[i]});
    } else {
      warnings->push_back({"implausible-matte",
                           names[i] + ": " + reason +
                               "; kept (the density stage tests it "
                               "against the other views; paint a trimap in edits/trimaps/ to "
                               "fix it)",
                           names[i]});
    }
  }
}

// The summary's figures: mattes computed and kept, implausible and repaired,
// and the mean foreground share.
void AddMatteFigures(size_t num_photos, size_t num_computed, const SetVerdict& verdict,
                     const std::vector<OwnMatte>& records, StageRun* run) {
  int implausible = 0, repaired = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    implausible += !verdict.reasons[i].empty();
    repaired += records[i].repaired;
  }
  run->AddFigure("photos", num_photos, "photos");
  run->AddFigure("computed", num_computed, "mattes");
  run->AddFigure("unchanged", num_photos - num_computed, "mattes");
  run->AddFigure("implausible", implausible, "mattes");
  run->AddFigure("repaired", repaired, "mattes");
  if (verdict.shapes.empty()) return;
  double share = 0.0;
  for (const MatteShape& shape : verdict.shapes) share += shape.foreground_share;
  run->AddFigure("mean_foreground", 100.0 * share / verdict.shapes.size(), "% of pixels");
}

}  // namespace

StageRun RunMatteStage(const StageContext& context) {
  const Project& project = context.project;
  const std::vector<std::string>& names = project.photo_names();
  context.options.matte_set.Check();
  std::string background_key;
  const FloatImage background = ReadBackgroundPhoto(context, &background_key);

  // 1. Each photo's own matte, matted again only when its inputs changed.
  std::vector<OwnMatte> records;
  const std::vector<int> computed = StaleOwnMattes(context, background_key, &records);
  ComputeOwnMattes(context, computed, background, &records);
  WriteMatteRecords(project, records);

  // 2. The set: static structure, implausible mattes. 3. The final mattes.
  StageRun run;
  const SetVerdict verdict = CheckSet(context, records, &run.warnings);
  const std::vector<int> written = StaleFinalMattes(context, verdict, &records);
  WriteFinalMattes(context, verdict, written, background, &records);
  WriteMatteRecords(project, records);
  AddMatteWarnings(names, verdict, records, &run.warnings);

  std::ostringstream brief;
  brief << names.size() << " mattes in out/mattes/ (" << computed.size() << " computed, "
        << names.size() - computed.size() << " unchanged)";
  double mean_share = 0.0;
  for (const MatteShape& shape : verdict.shapes) mean_share += shape.foreground_share;
  if (!verdict.shapes.empty()) {
    brief << "; mean foreground " << 100.0 * mean_share / verdict.shapes.size()
          << " % of the pixels";
  }
  run.brief = brief.str();
  AddMatteFigures(names.size(), computed.size(), verdict, records, &run);
  for (const std::string& name : names) run.outputs.push_back(project.ComputedMattePath(name));
  return run;
}

}  // namespace sylva
