// File-system helpers: atomic writes, whole-file reads, path handling.
//
// Every output sylva writes goes through AtomicWrite*/AtomicOutputPath: the
// data is written to a temporary file in the destination folder and renamed
// over the destination only when complete, so a killed run never leaves a
// corrupt or half-written output, and an existing file is replaced in one step.
#ifndef SYLVA_CORE_UTIL_FILE_UTIL_H_
#define SYLVA_CORE_UTIL_FILE_UTIL_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

namespace sylva {

namespace fs = std::filesystem;

// Reads a whole file; throws InputError naming the file if it cannot.
std::string ReadFileToString(const fs::path& path);

// Writes `contents` to `path` atomically (temp file + rename). Creates the
// parent folder. Throws Error on failure and removes the temp file.
void AtomicWriteString(const fs::path& path, const std::string& contents);

// For writers that need a file name (OpenImageIO, OpenVDB): calls
// `write(temp_path)`, where temp_path lies beside `path` and keeps its
// extension, then renames temp_path to `path`. If `write` throws, the temp file
// is removed and the exception propagates; `path` is untouched.
void AtomicWriteWith(const fs::path& path, const std::function<void(const fs::path&)>& write);

// A fresh temporary path beside `path` with the same extension.
fs::path TempPathBeside(const fs::path& path);

// A stamp that changes when the file changes: size and modification time.
// Returns 0 for a missing file.
uint64_t FileStamp(const fs::path& path);

// 64-bit FNV-1a hash, for cache keys (not cryptographic).
uint64_t Fnv1a64(const void* data, size_t size, uint64_t hash = 0xcbf29ce484222325ULL);
uint64_t Fnv1a64(const std::string& text, uint64_t hash = 0xcbf29ce484222325ULL);
std::string HexString(uint64_t value);

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_FILE_UTIL_H_
