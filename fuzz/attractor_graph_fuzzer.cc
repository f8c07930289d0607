// Fuzz target: Attractor graph files (core/io/attractor_io.h).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "core/io/attractor_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".json", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadAttractorGraphJson(path);
  });
}
