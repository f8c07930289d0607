// Fuzz target: batch manifests (ui/batch/manifest.h). The manifest's folder
// holds a tree folder `t` with every input a row can name (photos, mattes,
// colmap, cameras.json, loose.json, held_out.txt), so rows that name them
// get past the existence checks to the rest of the reader.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_util.h"
#include "ui/batch/manifest.h"

namespace {

std::filesystem::path ManifestDir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path root = sylva::fuzz::WorkDir() / "manifest";
    for (const char* folder : {"t/photos", "t/mattes", "t/colmap"})
      std::filesystem::create_directories(root / folder);
    for (const char* file : {"t/cameras.json", "t/loose.json", "t/held_out.txt"})
      sylva::fuzz::WriteBytes(root / file, "");
    return root;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = ManifestDir() / "manifest.csv";
  sylva::fuzz::WriteBytes(path, std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    sylva::ReadManifest(path);
  } catch (const sylva::InputError&) {
  }
  return 0;
}
