// Fuzz target: 3D gesture files, .inkml (sketch/gesture_io.h).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "sketch/gesture_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".inkml", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadGestureInkml(path).Check();
  });
}
