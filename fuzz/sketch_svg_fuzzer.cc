// Fuzz target: Drawings in SVG (sketch/drawing_io.h, sylva sketch).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "sketch/drawing_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".svg", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadSketchSvg(path).Check();
  });
}
