#include "core/util/file_util.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/util/check.h"

namespace sylva {

std::string ReadFileToString(const fs::path& path) {
  std::error_code ec;
  SYLVA_CHECK_INPUT(fs::is_regular_file(path, ec), path.string()) << "no such file";
  std::ifstream in(path, std::ios::binary);
  SYLVA_CHECK_INPUT(in.good(), path.string()) << "cannot open: " << std::strerror(errno);
  std::ostringstream contents;
  contents << in.rdbuf();
  SYLVA_CHECK_INPUT(!in.bad(), path.string()) << "read error";
  return contents.str();
}

fs::path TempPathBeside(const fs::path& path) {
  static std::atomic<int> counter{0};
  std::ostringstream name;
  name << "." << path.stem().string() << ".tmp-" << getpid() << "-" << counter++
       << path.extension().string();
  return path.parent_path() / name.str();
}

void AtomicWriteWith(const fs::path& path, const std::function<void(const fs::path&)>& write) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  const fs::path temp = TempPathBeside(path);
  try {
    write(temp);
    fs::rename(temp, path);
  } catch (...) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw;
  }
}

void AtomicWriteString(const fs::path& path, const std::string& contents) {
  AtomicWriteWith(path, [&](const fs::path& temp) {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    SYLVA_CHECK(out.good()) << "cannot write " << temp << ": " << std::strerror(errno);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.close();
    SYLVA_CHECK(out.good()) << "write failed for " << temp;
  });
}

uint64_t FileStamp(const fs::path& path) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) return 0;
  const auto mtime = fs::last_write_time(path, ec).time_since_epoch().count();
  if (ec) return 0;
  uint64_t hash = Fnv1a64(&size, sizeof(size));
  return Fnv1a64(&mtime, sizeof(mtime), hash);
}

uint64_t Fnv1a64(const void* data, size_t size, uint64_t hash) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

uint64_t Fnv1a64(const std::string& text, uint64_t hash) {
  return Fnv1a64(text.data(), text.size(), hash);
}

std::string HexString(uint64_t value) {
  std::ostringstream out;
  out << std::hex << std::setw(16) << std::setfill('0') << value;
  return out.str();
}

}  // namespace sylva
