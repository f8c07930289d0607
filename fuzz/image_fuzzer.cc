// Fuzz target: Photos and mattes through the image reader (core/io/image_io.h, OpenImageIO); PNG by
// extension, any format by content.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "core/io/image_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".png", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadImage(path);
  });
}
