// A main() for the fuzz targets in the ordinary build (no libFuzzer): runs
// the target on every file given (or in a folder given), then on
// deterministic damage of each - truncations at 16 lengths and 32 single
// bytes overwritten - the damage a killed write or a bad disk does. CTest
// runs it on the seed corpora (fuzz/seeds.txt); scripts/fuzz.sh does the
// real fuzzing. Exits non-zero only through a crash or an escaped exception.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

std::vector<uint8_t> ReadAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

int Replay(const std::filesystem::path& path) {
  const std::vector<uint8_t> bytes = ReadAll(path);
  LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  constexpr int kCuts = 16, kFlips = 32;
  for (int k = 0; k < kCuts; ++k) {
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size() * k / kCuts);
  }
  uint64_t state = 0x9e3779b97f4a7c15ULL;  // fixed: the same damage every run
  for (int k = 0; k < kFlips && !bytes.empty(); ++k) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    std::vector<uint8_t> damaged = bytes;
    const uint8_t values[] = {0x00, 0xff, '"', '-', '9', '<', static_cast<uint8_t>(state >> 56)};
    damaged[(state >> 17) % damaged.size()] = values[(state >> 40) % std::size(values)];
    LLVMFuzzerTestOneInput(damaged.data(), damaged.size());
  }
  return 1 + kCuts + kFlips;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 0, files = 0;
  for (int i = 1; i < argc; ++i) {
    const std::filesystem::path arg = argv[i];
    if (std::filesystem::is_directory(arg)) {
      for (const auto& entry : std::filesystem::directory_iterator(arg)) {
        runs += Replay(entry.path());
        ++files;
      }
    } else {
      runs += Replay(arg);
      ++files;
    }
  }
  std::printf("%d inputs from %d files, no crash\n", runs, files);
  return files > 0 ? 0 : 2;
}
