// The interface of libsylva_oiio.so, the module through which image_io.cc
// reads and writes every image that is not a PNG (JPEG, TIFF, OpenEXR,
// BMP) with OpenImageIO. The module is loaded (dlopen) the first time such
// an image is met: linking OpenImageIO into every binary cost each process
// 0.2 s at start (png_codec.h says why).
//
// Plain C types only, and no exception crosses it: each function returns 1
// on success, or 0 with a one-line reason in `error` (at most error_size
// bytes, NUL-terminated), phrased to follow "cannot read image: ".
#ifndef SYLVA_CORE_IO_OIIO_PLUGIN_H_
#define SYLVA_CORE_IO_OIIO_PLUGIN_H_

#include <cstddef>

extern "C" {

// Bumped whenever a signature below changes; a module of another version is
// refused.
#define SYLVA_OIIO_PLUGIN_VERSION 1

struct SylvaOiioHeader {
  int width;
  int height;
  int channels;
  int alpha_channel;  // index, or -1
};

// Sample types for writing.
enum SylvaOiioSample { kSylvaOiioUint8 = 0, kSylvaOiioUint16 = 1, kSylvaOiioFloat = 2 };

// Returns storage for header->width * height * channels floats (or null).
typedef float* (*SylvaOiioAllocate)(void* context, const SylvaOiioHeader* header);

struct SylvaOiioPlugin {
  int version;
  // `format` is OpenImageIO's reader name ("jpeg", "tiff", ...); only that
  // reader is tried. read_header fills `header`; read also decodes the
  // pixels into allocate(context, header).
  int (*read_header)(const char* path, const char* format, SylvaOiioHeader* header, char* error,
                     size_t error_size);
  int (*read)(const char* path, const char* format, SylvaOiioAllocate allocate, void* context,
              SylvaOiioHeader* header, char* error, size_t error_size);
  // Writes pixels (straight alpha in the last channel of 2 or 4) in the
  // format `path`'s extension names.
  int (*write)(const char* path, const float* pixels, int width, int height, int channels,
               int sample, char* error, size_t error_size);
};

// The module's one exported symbol.
const SylvaOiioPlugin* sylva_oiio_plugin(void);
typedef const SylvaOiioPlugin* (*SylvaOiioPluginEntry)(void);

}  // extern "C"

#endif  // SYLVA_CORE_IO_OIIO_PLUGIN_H_
