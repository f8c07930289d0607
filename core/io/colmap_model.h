// COLMAP sparse models: cameras, images and (optionally) points3D, in text
// (cameras.txt, images.txt, points3D.txt) or binary (*.bin) form, with
// COLMAP's conventions (see camera.h and image_set.h).
#ifndef SYLVA_CORE_IO_COLMAP_MODEL_H_
#define SYLVA_CORE_IO_COLMAP_MODEL_H_

#include <filesystem>

#include "core/types/image_set.h"

namespace sylva {

// Reads the model in `model_dir`: binary if cameras.bin exists (as COLMAP
// does), otherwise text. points3D is optional. Throws InputError naming the
// file (and line, for text) of any problem.
ImageSet ReadColmapModel(const std::filesystem::path& model_dir);
ImageSet ReadColmapModelText(const std::filesystem::path& model_dir);
ImageSet ReadColmapModelBinary(const std::filesystem::path& model_dir);

// True if `model_dir` holds cameras.txt or cameras.bin.
bool IsColmapModelDir(const std::filesystem::path& model_dir);

// Write the model (each file atomically); creates `model_dir`. Views' 2D
// observations are not kept by sylva, so POINTS2D lines are empty. Throws
// InputError for cameras COLMAP cannot represent (ORTHOGRAPHIC).
void WriteColmapModelText(const ImageSet& image_set, const std::filesystem::path& model_dir);
void WriteColmapModelBinary(const ImageSet& image_set, const std::filesystem::path& model_dir);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_COLMAP_MODEL_H_
