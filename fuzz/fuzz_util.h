// What every fuzz target shares: the input written to a file the reader
// under test opens by path, as a user's file would be.
//
// The readers' contract (CONVENTIONS.md): bad input gives an InputError
// naming the file. A fuzz target therefore catches InputError and nothing
// else: any other exception, a crash or a sanitizer report is a finding.
#ifndef SYLVA_FUZZ_FUZZ_UTIL_H_
#define SYLVA_FUZZ_FUZZ_UTIL_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/util/check.h"

namespace sylva::fuzz {

// A folder of this process's own under the temporary folder.
inline std::filesystem::path WorkDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("sylva_fuzz_" + std::to_string(getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return dir;
}

inline void WriteBytes(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), bytes.size());
}

// Writes the input to WorkDir()/input<extension> and calls read(path).
template <typename Read>
int FuzzFile(const uint8_t* data, size_t size, const std::string& extension, Read read) {
  const std::filesystem::path path = WorkDir() / ("input" + extension);
  WriteBytes(path, std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    read(path);
  } catch (const InputError&) {
  }
  return 0;
}

// The input cut into `count` parts at kPartSeparator (missing parts empty),
// for readers of several files (a COLMAP model).
constexpr std::string_view kPartSeparator = "\n@@sylva-fuzz-part@@\n";
inline std::vector<std::string_view> Parts(const uint8_t* data, size_t size, int count) {
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  std::vector<std::string_view> parts;
  for (int k = 0; k + 1 < count; ++k) {
    const size_t at = rest.find(kPartSeparator);
    parts.push_back(rest.substr(0, at));
    rest =
        at == std::string_view::npos ? std::string_view() : rest.substr(at + kPartSeparator.size());
  }
  parts.push_back(rest);
  return parts;
}

}  // namespace sylva::fuzz

#endif  // SYLVA_FUZZ_FUZZ_UTIL_H_
