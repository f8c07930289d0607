// Fuzz target: 3D gesture files, .json (sketch/gesture_io.h).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "sketch/gesture_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".json", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadGestureJson(path).Check();
  });
}
