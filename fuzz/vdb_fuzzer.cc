// Fuzz target: Density grids (.vdb, core/io/vdb_io.h, OpenVDB).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "core/io/vdb_io.h"
#include "fuzz/fuzz_util.h"
#include "fuzz/throwing_new.h"  // a damaged block size throws, as in the program

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".vdb", [](const std::filesystem::path& path) {
    using namespace sylva;
    ReadDensityGrid(path);
  });
}
