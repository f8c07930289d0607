// Fuzz target: COLMAP binary models (core/io/colmap_model.h): the input is
// cameras.bin, images.bin and points3D.bin separated by kPartSeparator.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/io/colmap_model.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sylva;
  const std::filesystem::path dir = fuzz::WorkDir() / "colmap_binary";
  std::filesystem::create_directories(dir);
  const std::vector<std::string_view> parts = fuzz::Parts(data, size, 3);
  fuzz::WriteBytes(dir / "cameras.bin", parts[0]);
  fuzz::WriteBytes(dir / "images.bin", parts[1]);
  fuzz::WriteBytes(dir / "points3D.bin", parts[2]);
  try {
    ReadColmapModelBinary(dir);
  } catch (const InputError&) {
  }
  return 0;
}
