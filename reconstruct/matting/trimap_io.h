// Reading painted hint trimaps and writing trimaps (PNG or any format
// OpenImageIO reads).
#ifndef SYLVA_RECONSTRUCT_MATTING_TRIMAP_IO_H_
#define SYLVA_RECONSTRUCT_MATTING_TRIMAP_IO_H_

#include <filesystem>

#include "core/types/float_image.h"

namespace sylva {

// Reads a hint trimap painted by a person (PROJECT/edits/<photo>.png):
//   grey values: black (<= 0.2, i.e. <= 51 of 255) paints background, white
//   (>= 0.8, >= 204) paints foreground, anything between (128 by convention)
//   is unpainted;
//   an alpha channel, if present, marks unpainted pixels by alpha < 0.5 (a
//   transparent paint layer), whatever their grey value.
// RGB(A) files must be grey (R, G, B within 2/255 of each other). Returns one
// channel of 0 / 0.5 / 1 for CombineHintTrimap. Throws InputError naming the
// file if it is unreadable, has another channel count, is coloured or holds
// values outside [0, 1].
FloatImage ReadHintTrimap(const std::filesystem::path& path);

// Writes a trimap as 8-bit grey with 0 / 128 / 255 (values classified with the
// thresholds of matting.h), atomically.
void WriteTrimap(const std::filesystem::path& path, const FloatImage& trimap);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_MATTING_TRIMAP_IO_H_
