// PNG through libpng, for image_io.cc: the format of every image sylva writes
// (mattes, edits, overlays, report pictures) and of most it reads.
//
// Why not OpenImageIO, which reads everything else: Debian's OpenImageIO
// links 262 shared libraries (ffmpeg, GDAL, DCMTK, ...), and binding their
// symbols took 0.2 s at every start of a process that linked it: most of a
// `sylva run` with nothing to do, a tenth of a run after an edit. libpng
// is one small library; OpenImageIO is now loaded only when a photo in
// another format is read or written (oiio_plugin.h).
//
// Pixels are the same as OpenImageIO's, bit for bit (png_codec_test.cc
// checks every colour type and bit depth against it): palettes, grey below
// 8 bits and tRNS transparency are expanded (to RGB, 8 bits and an alpha
// channel), 16-bit samples are scaled by 1/65535 and 8-bit by 1/255; no
// gamma is applied; alpha stays straight. Written samples are
// round(clamp(v) * 255) (or 65535), as OpenImageIO rounds them.
#ifndef SYLVA_CORE_IO_PNG_CODEC_H_
#define SYLVA_CORE_IO_PNG_CODEC_H_

#include <cstdint>
#include <filesystem>

#include "core/io/image_io.h"
#include "core/types/float_image.h"

namespace sylva {

// The header of a PNG whose chunk structure has been checked. Throws
// InputError naming the file if libpng refuses it.
ImageHeader ReadPngHeader(const std::filesystem::path& path);

// All channels, converted to float, and the header in *header; an image of
// more than `max_pixels` pixels is not decoded (an empty image is returned).
// Throws InputError naming the file.
FloatImage ReadPng(const std::filesystem::path& path, int64_t max_pixels, ImageHeader* header);

// Writes `image` (1 to 4 channels) with 8 or 16 bits per sample to `path`
// (not atomically: the caller writes a temporary file), with zlib's fastest
// level: about 3x faster than its default, and masks and renders compress
// nearly as well. Throws Error on failure.
void WritePng(const std::filesystem::path& path, const FloatImage& image, PixelFormat format);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_PNG_CODEC_H_
