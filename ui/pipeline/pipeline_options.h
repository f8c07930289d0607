// All options of a sylva run, one struct per stage, and their registration
// in the option registry (the single place that names them for users).
#ifndef SYLVA_UI_PIPELINE_PIPELINE_OPTIONS_H_
#define SYLVA_UI_PIPELINE_PIPELINE_OPTIONS_H_

#include <cstdint>
#include <string>

#include "reconstruct/density/density_options.h"
#include "ui/pipeline/option_registry.h"

namespace sylva {

struct GeneralOptions {
  // Seed of every random choice of the run; same inputs and seed give the
  // same tree.
  uint64_t seed = 1;
  // Worker threads; 0 uses every core.
  int num_threads = 0;
  void Check() const;
};

struct ReportOptions {
  // A pixel of the projected density is foreground at this opacity or more.
  double opacity_threshold = 0.5;
  // A matte pixel is foreground at this alpha or more.
  double matte_threshold = 0.5;
  // Mattes and projections are compared after downsampling so that a voxel
  // covers about this many pixels across (independent of the density stage's
  // own sampling, so that solver settings are compared on equal terms).
  double pixels_per_voxel = 1.0;
  // Write per-view comparison pictures and report.html under out/.
  bool write_images = true;
  void Check() const;
};

struct PipelineOptions {
  GeneralOptions general;
  DensityOptions density;
  ReportOptions report;

  // Throws InputError naming the first invalid option.
  void Check() const;
};

// Registers every field of `options` (which must outlive the registry).
void RegisterPipelineOptions(PipelineOptions* options, OptionRegistry* registry);

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_PIPELINE_OPTIONS_H_
