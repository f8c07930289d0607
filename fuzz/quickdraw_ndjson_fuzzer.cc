// Fuzz target: Quick, Draw! ndjson drawings (sketch/drawing_io.h).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "sketch/drawing_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".ndjson", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadQuickDrawNdjson(path, 0).Check();
  });
}
