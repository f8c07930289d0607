// Fuzz target: Strokes drawn over a photo, JSON (sketch/strokes.h).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "sketch/strokes.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".json", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadStrokes(path, 640, 480);
  });
}
