// Shared by the pipeline's tests: a tiny written synthetic dataset.
#ifndef SYLVA_UI_PIPELINE_PIPELINE_TEST_UTIL_H_
#define SYLVA_UI_PIPELINE_PIPELINE_TEST_UTIL_H_

#include <filesystem>

#include "datasets/synthetic/synthetic_dataset.h"

namespace sylva {

// Writes a synthetic dataset of 3 input views and one held out
// ("heldout_00.png"), `image_size` px square, with photos, mattes and a
// COLMAP model, into `dir` (WriteSyntheticDataset's layout).
inline void WriteTinySyntheticSet(const std::filesystem::path& dir, int image_size = 48) {
  SyntheticDatasetOptions options;
  options.num_views = 3;
  options.num_held_out = 1;
  options.image_size = image_size;
  options.samples_per_axis = 1;
  WriteSyntheticDataset(MakeSyntheticDataset(options), options, dir);
}

}  // namespace sylva

#endif  // SYLVA_UI_PIPELINE_PIPELINE_TEST_UTIL_H_
