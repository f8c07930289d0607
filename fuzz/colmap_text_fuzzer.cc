// Fuzz target: COLMAP text models (core/io/colmap_model.h): the input is
// cameras.txt, images.txt and points3D.txt separated by kPartSeparator.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/io/colmap_model.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sylva;
  const std::filesystem::path dir = fuzz::WorkDir() / "colmap_text";
  std::filesystem::create_directories(dir);
  const std::vector<std::string_view> parts = fuzz::Parts(data, size, 3);
  fuzz::WriteBytes(dir / "cameras.txt", parts[0]);
  fuzz::WriteBytes(dir / "images.txt", parts[1]);
  fuzz::WriteBytes(dir / "points3D.txt", parts[2]);
  try {
    ReadColmapModelText(dir);
  } catch (const InputError&) {
  }
  return 0;
}
