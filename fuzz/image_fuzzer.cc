// Fuzz target: Photos and mattes through the image reader (core/io/image_io.h:
// PNG through libpng, the rest through OpenImageIO); PNG by extension, any
// format by content.
//
// The header is read and checked for every input; the pixels only for images
// of at most kMaxPixels. A 21-byte input can claim to be a WebP of
// 9573 x 13786 pixels: the reader then allocates 1.6 GB of floats before
// the decoder gives up, about 10 s per input under ASan, which leaves the
// fuzzer no time for anything else. (A photo of that size is legitimate;
// only the fuzzer's inputs, at most 64 KB, cannot be one.)
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "core/io/image_io.h"
#include "fuzz/fuzz_util.h"

namespace {
constexpr int64_t kMaxPixels = int64_t{1} << 18;  // 512 x 512
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".png", [](const std::filesystem::path& path) {
    using namespace sylva;
    const ImageHeader header = ReadImageHeader(path);
    if (int64_t{header.width} * header.height > kMaxPixels) return;
    ReadImage(path);
  });
}
