// Fuzz target: OpenAlea MTG files and their skeletons (core/io/mtg_io.h, sylva mesh-mtg).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "core/io/mtg_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".mtg", [](const std::filesystem::path& path) {
    using namespace sylva;
    const Mtg mtg = ReadMtg(path);
    SkeletonsFromMtg(mtg, path.string());
  });
}
