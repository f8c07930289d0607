#include "core/io/image_io.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string_view>

#include "core/io/oiio_plugin.h"
#include "core/io/png_codec.h"
#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

using std::string_view_literals::operator""sv;

// The largest image sylva decodes: 2^28 pixels (268 megapixels; 3 GB of
// floats in RGB), beyond any camera's photo.
constexpr int64_t kMaxImagePixels = int64_t{1} << 28;

// Two 8-bit levels: tolerance for "R = G = B" in mattes saved as RGB.
constexpr float kGrayTolerance = 2.0f / 255.0f;

uint32_t BigEndian32(const unsigned char* bytes) {
  return (uint32_t{bytes[0]} << 24) | (uint32_t{bytes[1]} << 16) | (uint32_t{bytes[2]} << 8) |
         uint32_t{bytes[3]};
}

// A PNG's chunk structure (the signature, then chunks of length, type, data
// and CRC from IHDR to IEND, each within the file), checked before
// libpng decodes it: a truncated or damaged PNG gets one clear error naming
// where it breaks.
void CheckPngChunks(std::ifstream& file, const fs::path& path, uint64_t size) {
  std::array<unsigned char, 8> bytes{};
  uint64_t at = 8;  // after the signature
  for (bool first = true;; first = false) {
    file.seekg(static_cast<std::streamoff>(at));
    SYLVA_CHECK_INPUT(file.read(reinterpret_cast<char*>(bytes.data()), 8), path.string())
        << "damaged PNG: the file ends at byte " << at << " before its IEND chunk (truncated)";
    const uint32_t length = BigEndian32(bytes.data());
    const std::string type(bytes.begin() + 4, bytes.end());
    SYLVA_CHECK_INPUT(std::all_of(type.begin(), type.end(),
                                  [](unsigned char c) { return std::isalpha(c) != 0; }) &&
                          length <= 0x7fffffffu,
                      path.string())
        << "damaged PNG: no valid chunk at byte " << at;
    SYLVA_CHECK_INPUT(!first || (type == "IHDR" && length == 13), path.string())
        << "damaged PNG: it does not start with its IHDR chunk";
    const uint64_t end = at + 12 + uint64_t{length};  // length, type, data, CRC
    SYLVA_CHECK_INPUT(end <= size, path.string())
        << "damaged PNG: chunk " << type << " at byte " << at << " needs " << end - at
        << " bytes, the file ends at byte " << size << " (truncated)";
    if (type == "IEND") return;
    at = end;
  }
}

// The formats sylva reads, told by the file's first bytes (an extension
// may lie), as OpenImageIO's reader names. Only these readers are tried: a
// file that is not an image is refused at once instead of being offered to
// every decoder OpenImageIO has (RAW, DICOM, video, ...).
// (sv literals: the TIFF signatures hold zero bytes.)
struct Signature {
  std::string_view bytes;
  const char* format;
};
constexpr Signature kSignatures[] = {{"\x89PNG\r\n\x1a\n"sv, "png"},
                                     {"\xff\xd8\xff"sv, "jpeg"},
                                     {"II*\0"sv, "tiff"},
                                     {"MM\0*"sv, "tiff"},
                                     {"II+\0"sv, "tiff"},
                                     {"MM\0+"sv, "tiff"},  // BigTIFF
                                     {"v/1\x01"sv, "openexr"},
                                     {"BM"sv, "bmp"}};

// The OpenImageIO format of the file; InputError if it is none sylva reads
// (or a damaged PNG).
const char* ImageFormat(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  SYLVA_CHECK_INPUT(file.is_open(), path.string()) << "cannot open image file";
  char head[8] = {};
  file.read(head, sizeof(head));
  const std::string_view start(head, static_cast<size_t>(file.gcount()));
  const Signature* match = std::find_if(
      std::begin(kSignatures), std::end(kSignatures),
      [&](const Signature& known) { return start.substr(0, known.bytes.size()) == known.bytes; });
  SYLVA_CHECK_INPUT(match != std::end(kSignatures), path.string())
      << "not an image sylva reads: its first bytes are those of no PNG, JPEG, TIFF, OpenEXR "
         "or BMP file";
  if (std::string_view(match->format) == "png") {
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    SYLVA_CHECK_INPUT(!ec, path.string()) << "cannot read image: " << ec.message();
    file.clear();
    CheckPngChunks(file, path, size);
  }
  return match->format;
}

// The module that reads and writes images other than PNG (oiio_plugin.h),
// loaded on first use: $SYLVA_OIIO_PLUGIN if set, else where the build put
// it, else beside the running program. Error if none loads.
const SylvaOiioPlugin* LoadOiioPlugin() {
  std::vector<fs::path> candidates;
  std::error_code ec;
  if (const char* chosen = std::getenv("SYLVA_OIIO_PLUGIN")) {
    candidates.emplace_back(chosen);
  } else {
    candidates.emplace_back(SYLVA_OIIO_PLUGIN_PATH);
    const fs::path program = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) candidates.push_back(program.parent_path() / "libsylva_oiio.so");
  }
  std::string looked;
  const SylvaOiioPlugin* plugin = nullptr;
  for (const fs::path& candidate : candidates) {
    looked += (looked.empty() ? "" : ", ") + candidate.string();
    if (!fs::is_regular_file(candidate, ec)) continue;
    void* module = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    SYLVA_CHECK(module != nullptr) << "cannot load " << candidate << ": " << dlerror();
    const auto entry = reinterpret_cast<SylvaOiioPluginEntry>(dlsym(module, "sylva_oiio_plugin"));
    SYLVA_CHECK(entry != nullptr) << candidate << " is not sylva's OpenImageIO module";
    plugin = entry();
    SYLVA_CHECK(plugin != nullptr && plugin->version == SYLVA_OIIO_PLUGIN_VERSION)
        << candidate << " is another version of sylva's OpenImageIO module";
    break;
  }
  SYLVA_CHECK(plugin != nullptr)
      << "sylva's OpenImageIO module (libsylva_oiio.so) is missing (looked for " << looked
      << "): images other than PNG cannot be read or written";
  return plugin;
}

const SylvaOiioPlugin& OiioPlugin() {
  static const SylvaOiioPlugin* const plugin = LoadOiioPlugin();
  return *plugin;
}

ImageHeader HeaderOf(const SylvaOiioHeader& header) {
  return {header.width, header.height, header.channels, header.alpha_channel};
}

void CheckHasPixels(const ImageHeader& header, const fs::path& path) {
  SYLVA_CHECK_INPUT(header.width > 0 && header.height > 0 && header.channels > 0, path.string())
      << "image has no pixels";
}

// The format of the image at `path` (InputError if it is missing or none
// sylva reads).
const char* CheckedImageFormat(const fs::path& path) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(path, ec), path.string()) << "image file not found";
  return ImageFormat(path);
}

bool IsPng(const char* format) { return std::string_view(format) == "png"; }

// An image of more pixels than kMaxImagePixels is refused before its pixels
// are allocated: a few megabytes of compressed PNG or JPEG can state
// 30,000 x 30,000 pixels, whose floats (11 GB) took a machine down.
void CheckDecodable(const ImageHeader& header, const fs::path& path) {
  SYLVA_CHECK_INPUT(int64_t{header.width} * header.height <= kMaxImagePixels, path.string())
      << "image of " << header.width << " x " << header.height
      << " pixels is larger than sylva decodes (" << kMaxImagePixels / 1000000
      << " megapixels); downscale it";
}

}  // namespace

ImageHeader ReadImageHeader(const fs::path& path) {
  const char* format = CheckedImageFormat(path);
  if (IsPng(format)) return ReadPngHeader(path);
  SylvaOiioHeader header{};
  char error[512] = {};
  SYLVA_CHECK_INPUT(
      OiioPlugin().read_header(path.c_str(), format, &header, error, sizeof(error)) != 0,
      path.string())
      << error;
  const ImageHeader result = HeaderOf(header);
  CheckHasPixels(result, path);
  return result;
}

FloatImage ReadImage(const fs::path& path) {
  const char* format = CheckedImageFormat(path);
  FloatImage image;
  if (IsPng(format)) {
    ImageHeader header;
    image = ReadPng(path, kMaxImagePixels, &header);
    CheckDecodable(header, path);
  } else {
    struct Target {
      FloatImage* image;
      bool too_large = false;
    } target{&image};
    const SylvaOiioAllocate allocate = [](void* context, const SylvaOiioHeader* header) {
      auto* into = static_cast<Target*>(context);
      if (int64_t{header->width} * header->height > kMaxImagePixels) {
        into->too_large = true;
        return static_cast<float*>(nullptr);
      }
      *into->image = FloatImage(header->width, header->height, header->channels);
      return into->image->data();
    };
    SylvaOiioHeader header{};
    char error[512] = {};
    const bool ok = OiioPlugin().read(path.c_str(), format, allocate, &target, &header, error,
                                      sizeof(error)) != 0;
    if (target.too_large) CheckDecodable(HeaderOf(header), path);
    SYLVA_CHECK_INPUT(ok, path.string()) << error;
  }
  for (float& value : image.values()) {
    SYLVA_CHECK_INPUT(std::isfinite(value), path.string()) << "image contains NaN or infinity";
  }
  return image;
}

namespace {

// The first channel of an image whose first `color_channels` channels are
// equal (a grey image saved as RGB); InputError otherwise.
FloatImage GrayChannel(const FloatImage& image, int color_channels, const fs::path& path) {
  const int stride = image.channels();
  for (size_t i = 0; i < image.NumPixels(); ++i) {
    const float* pixel = image.data() + stride * i;
    for (int c = 1; c < color_channels; ++c) {
      SYLVA_CHECK_INPUT(std::abs(pixel[c] - pixel[0]) <= kGrayTolerance, path.string())
          << "matte is a colour image without a usable alpha channel; a matte must be "
             "grayscale or carry its values in the alpha channel";
    }
  }
  return image.Channel(0);
}

bool IsOpaqueEverywhere(const FloatImage& alpha) {
  return std::all_of(alpha.values().begin(), alpha.values().end(),
                     [](float a) { return a >= 1.0f; });
}

}  // namespace

FloatImage ReadMatte(const fs::path& path) {
  const FloatImage image = ReadImage(path);
  const int channels = image.channels();
  SYLVA_CHECK_INPUT(channels >= 1 && channels <= 4, path.string())
      << "matte has " << channels << " channels; expected 1 (gray), 2, 3 or 4";
  FloatImage matte;
  if (channels == 1) {
    matte = image;
  } else if (channels == 3) {
    matte = GrayChannel(image, 3, path);
  } else {
    matte = image.Channel(channels - 1);
    // An alpha channel that is opaque everywhere carries no matte (e.g. a
    // grey silhouette saved as grey+alpha): the grey values are the matte.
    if (IsOpaqueEverywhere(matte)) matte = GrayChannel(image, channels - 1, path);
  }
  for (float& value : matte.values()) value = std::clamp(value, 0.0f, 1.0f);
  return matte;
}

void WriteImage(const fs::path& path, const FloatImage& image, PixelFormat format) {
  SYLVA_CHECK(!image.empty()) << "writing an empty image to " << path;
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  AtomicWriteWith(path, [&](const fs::path& temp) {
    if (extension == ".png" && format != PixelFormat::kFloat) {
      WritePng(temp, image, format);
      return;
    }
    const int sample = format == PixelFormat::kUint16  ? kSylvaOiioUint16
                       : format == PixelFormat::kFloat ? kSylvaOiioFloat
                                                       : kSylvaOiioUint8;
    char error[512] = {};
    SYLVA_CHECK(OiioPlugin().write(temp.c_str(), image.data(), image.width(), image.height(),
                                   image.channels(), sample, error, sizeof(error)) != 0)
        << "cannot write " << path << ": " << error;
  });
}

fs::path FindMatteFile(const fs::path& folder, const std::string& photo_name) {
  const fs::path relative(photo_name);
  std::vector<fs::path> candidates = {folder / relative};
  for (const char* extension : {".png", ".tif", ".tiff", ".exr", ".jpg"}) {
    candidates.push_back(folder / fs::path(relative).replace_extension(extension));
  }
  std::error_code ec;
  for (const fs::path& candidate : candidates) {
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  return {};
}

std::vector<std::string> ListImageFiles(const fs::path& folder) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_directory(folder, ec), folder.string()) << "not a folder";
  std::vector<std::string> names;
  const auto options = fs::directory_options::skip_permission_denied;
  fs::recursive_directory_iterator it(folder, options, ec);
  SYLVA_CHECK_INPUT(!ec, folder.string()) << "cannot read the folder: " << ec.message();
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    SYLVA_CHECK_INPUT(!ec, folder.string()) << "cannot read the folder: " << ec.message();
    const fs::path& path = it->path();
    if (path.filename().string().rfind('.', 0) == 0) {
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file(ec)) continue;
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    static const char* const kExtensions[] = {".jpg",  ".jpeg", ".png", ".tif",
                                              ".tiff", ".exr",  ".bmp"};
    if (std::none_of(std::begin(kExtensions), std::end(kExtensions),
                     [&](const char* e) { return extension == e; })) {
      continue;
    }
    names.push_back(path.lexically_relative(folder).generic_string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace sylva
