// The density stage: mattes of the input views -> out/density.vdb.
#include <cstring>

#include "core/io/vdb_io.h"
#include "core/util/file_util.h"
#include "reconstruct/density/density_reconstruction.h"
#include "ui/pipeline/stage_context.h"

namespace sylva {
namespace {

void AddDensityFigures(const DensitySummary& summary, const std::string& units, StageRun* run) {
  int iterations = 0;
  for (const CglsSummary& solve : summary.solves) iterations += solve.iterations;
  run->AddFigure("views", summary.num_views, "views");
  run->AddFigure("distrusted_views", summary.distrusted_views.size(), "views");
  run->AddFigure("resolution", summary.resolution, "voxels");
  run->AddFigure("voxel_size", summary.voxel_size, units);
  run->AddFigure("carved_voxels", summary.num_carved_voxels, "voxels");
  run->AddFigure("pixel_rays", summary.num_rows, "rays");
  run->AddFigure("unexplained_pixels", summary.num_unexplained_pixels, "pixels");
  run->AddFigure("iterations", iterations, "iterations");
  run->AddFigure("warm_voxels", summary.num_warm_voxels, "voxels");
  run->AddFigure("stored_voxels", summary.num_output_voxels, "voxels");
  run->AddFigure("solve_seconds", summary.seconds_solve, "s");
}

// The reconstruction's own steps as sub-steps.
void AddDensitySteps(const DensitySummary& summary, StageStep* step) {
  step->Add("views_and_bounds", summary.seconds_bounds)
      .Add("init", summary.seconds_init)
      .Add("system", summary.seconds_system)
      .Add("solve", summary.seconds_solve);
}

// cache/density_warm_start.bin: the last solve's state (DensityWarmStart),
// so that the run after a density edit re-solves from it. Binary: the magic
// line, the key line, the count n (uint64), stop_gradient (double), n voxel
// indices (int64), n depths (float), in this machine's byte order. A missing,
// old or damaged file only means a cold start (the cache is safe to delete).
constexpr char kWarmStartMagic[] = "sylva-density-warm-start/1\n";

fs::path WarmStartPath(const Project& project) {
  return project.CacheDir() / "density_warm_start.bin";
}

// What makes two solves comparable beyond the grid (which the reconstruction
// adds): the cameras' contents, the input views and the Density options.
std::string WarmStartContext(const StageContext& context, const ImageSet& views) {
  PipelineOptions comparable = context.options;
  comparable.density.warm_start = false;  // using the state or not does not change it
  std::string text = OptionsText(comparable, {"Density."});
  for (const fs::path& file : context.project.CameraFiles()) {
    text += ";" + HexString(Fnv1a64(ReadFileToString(file)));
  }
  for (const View& view : views.views) text += ";" + view.name;
  return text;
}

void ReadWarmStart(const fs::path& path, DensityWarmStart* warm) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return;
  const std::string bytes = ReadFileToString(path);
  const size_t magic = std::strlen(kWarmStartMagic);
  const size_t key_end = bytes.find('\n', magic);
  if (bytes.compare(0, magic, kWarmStartMagic) != 0 || key_end == std::string::npos) return;
  uint64_t n = 0;
  size_t at = key_end + 1;
  if (bytes.size() < at + sizeof(n) + sizeof(double)) return;
  std::memcpy(&n, bytes.data() + at, sizeof(n));
  std::memcpy(&warm->stop_gradient, bytes.data() + at + sizeof(n), sizeof(double));
  at += sizeof(n) + sizeof(double);
  if (n > bytes.size() || bytes.size() != at + n * (sizeof(int64_t) + sizeof(float))) return;
  warm->voxels.resize(n);
  warm->depths.resize(n);
  std::memcpy(warm->voxels.data(), bytes.data() + at, n * sizeof(int64_t));
  std::memcpy(warm->depths.data(), bytes.data() + at + n * sizeof(int64_t), n * sizeof(float));
  warm->key = bytes.substr(magic, key_end - magic);
}

void WriteWarmStart(const fs::path& path, const DensityWarmStart& warm) {
  const uint64_t n = warm.voxels.size();
  std::string bytes = kWarmStartMagic + warm.key + "\n";
  bytes.append(reinterpret_cast<const char*>(&n), sizeof(n));
  bytes.append(reinterpret_cast<const char*>(&warm.stop_gradient), sizeof(double));
  bytes.append(reinterpret_cast<const char*>(warm.voxels.data()), n * sizeof(int64_t));
  bytes.append(reinterpret_cast<const char*>(warm.depths.data()), n * sizeof(float));
  fs::create_directories(path.parent_path());
  AtomicWriteString(path, bytes);
}

}  // namespace

StageRun RunDensityStage(const StageContext& context) {
  StageRun run;
  StepClock clock(&run.profile);
  const ImageSet views = context.InputViews();
  const std::vector<FloatImage> mattes = context.LoadMattes(views, "density: reading mattes");
  clock.Lap("read_mattes");
  DensityOptions options = context.options.density;
  for (const View& view : views.views) {
    if (!context.project.DensityEditPath(view.name).empty() ||
        !context.project.CrownEditPath(view.name).empty()) {
      options.edited_views.push_back(view.name);
    }
  }
  DensityWarmStart warm;
  warm.context = WarmStartContext(context, views);
  if (!context.cold && options.warm_start) ReadWarmStart(WarmStartPath(context.project), &warm);
  DensitySummary summary;
  DensityGrid grid = ReconstructDensity(views, mattes, options, context.progress, &summary, &warm);
  AddDensitySteps(summary, &clock.Lap("reconstruct"));
  grid.SetMetadata("units", context.Units());
  run.brief = summary.BriefReport();
  AddDensityFigures(summary, context.Units(), &run);
  run.warnings = summary.warnings;
  run.outputs = {context.Out("density.vdb")};
  WriteDensityGrid(run.outputs[0], grid);
  WriteWarmStart(WarmStartPath(context.project), warm);
  clock.Lap("write");
  return run;
}

}  // namespace sylva
