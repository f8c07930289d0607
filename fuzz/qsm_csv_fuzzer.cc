// Fuzz target: QSM cylinder tables and their skeletons (core/io/qsm_io.h, sylva mesh-qsm).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "core/io/qsm_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sylva::fuzz::FuzzFile(data, size, ".csv", [](const std::filesystem::path& path) {
    using namespace sylva;
    SkeletonsFromQsm(ReadQsmCsv(path));
  });
}
