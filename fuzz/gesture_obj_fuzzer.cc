// Fuzz target: 3D gesture files, .obj (sketch/gesture_io.h).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "sketch/gesture_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".obj", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadGestureObj(path).Check();
  });
}
