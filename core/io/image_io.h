// Photos and mattes: PNG through libpng (png_codec.h), JPEG, TIFF, OpenEXR
// and BMP through OpenImageIO, loaded when first needed (oiio_plugin.h); 8/16-
// bit integer or float. Pixel values are converted to float in [0, 1]. Pixels
// are read as stored: EXIF orientation is not applied (COLMAP does not apply
// it either, so cameras and pixels stay consistent).
// Alpha is straight (unassociated) both ways: colour is never premultiplied
// by alpha on reading, nor divided by it on writing.
#ifndef SYLVA_CORE_IO_IMAGE_IO_H_
#define SYLVA_CORE_IO_IMAGE_IO_H_

#include <filesystem>
#include <string>
#include <vector>

#include "core/types/float_image.h"

namespace sylva {

struct ImageHeader {
  int width = 0;
  int height = 0;
  int channels = 0;
  int alpha_channel = -1;  // index of the alpha channel, or -1
};

// Reads only the header (fast). Throws InputError naming the file.
ImageHeader ReadImageHeader(const std::filesystem::path& path);

// Reads all channels. Throws InputError naming the file if it is missing,
// unreadable, truncated, larger than 2^28 pixels (refused before decoding)
// or contains non-finite values.
FloatImage ReadImage(const std::filesystem::path& path);

// Reads a matte as one channel of alpha in [0, 1]:
//   1 channel (grayscale)      -> that channel;
//   2 or 4 channels            -> the alpha channel, unless it is opaque
//                                 everywhere (a grey silhouette saved with a
//                                 constant alpha): then the grey values, as
//                                 for 1 or 3 channels;
//   3 channels                 -> accepted only if R = G = B (a grayscale
//                                 image saved as RGB), otherwise InputError.
FloatImage ReadMatte(const std::filesystem::path& path);

enum class PixelFormat { kUint8, kUint16, kFloat };

// Writes atomically; the format follows the extension. Values are clamped to
// [0, 1] for integer formats.
void WriteImage(const std::filesystem::path& path, const FloatImage& image,
                PixelFormat format = PixelFormat::kUint8);

// The file in `folder` holding the matte of photo `photo_name` (which may have
// sub-folders): the same relative path, with the photo's own extension or any
// of .png .tif .tiff .exr .jpg; empty path if none exists.
std::filesystem::path FindMatteFile(const std::filesystem::path& folder,
                                    const std::string& photo_name);

// The image files under `folder` (recursively; .jpg .jpeg .png .tif .tiff
// .exr .bmp in any letter case; hidden files and folders skipped), as names
// relative to it with '/' separators, sorted. InputError naming the folder if
// it cannot be read.
std::vector<std::string> ListImageFiles(const std::filesystem::path& folder);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_IMAGE_IO_H_
