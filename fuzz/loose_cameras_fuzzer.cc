// Fuzz target: loose-camera files, the points a person clicked in 2-4
// loosely placed photos (reconstruct/registration/loose_setup_io.h).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "reconstruct/registration/loose_setup_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(
      data, size, ".json", [](const std::filesystem::path& path) { sylva::ReadLooseSetup(path); });
}
