#include "core/util/file_util.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

fs::path TestDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sylva_file_util_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(FileUtilTest, AtomicWriteReplacesAndLeavesNoTemp) {
  const fs::path dir = TestDir("atomic");
  const fs::path path = dir / "sub" / "out.txt";
  AtomicWriteString(path, "first");
  AtomicWriteString(path, "second");
  EXPECT_EQ(ReadFileToString(path), "second");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) files += entry.is_regular_file();
  EXPECT_EQ(files, 1);
}

TEST(FileUtilTest, FailedWriteKeepsOldFile) {
  const fs::path dir = TestDir("failed");
  const fs::path path = dir / "keep.txt";
  AtomicWriteString(path, "precious");
  EXPECT_THROW(AtomicWriteWith(path,
                               [](const fs::path& temp) {
                                 AtomicWriteString(temp, "partial");
                                 throw Error("killed half way");
                               }),
               Error);
  EXPECT_EQ(ReadFileToString(path), "precious");
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) files += entry.is_regular_file();
  EXPECT_EQ(files, 1);
}

TEST(FileUtilTest, ReadMissingFileNamesIt) {
  try {
    ReadFileToString("/nonexistent/sylva.json");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "/nonexistent/sylva.json");
  }
}

TEST(FileUtilTest, HashAndStamp) {
  EXPECT_EQ(Fnv1a64(std::string("abc")), Fnv1a64(std::string("abc")));
  EXPECT_NE(Fnv1a64(std::string("abc")), Fnv1a64(std::string("abd")));
  EXPECT_EQ(HexString(255), "00000000000000ff");
  const fs::path dir = TestDir("stamp");
  EXPECT_EQ(FileStamp(dir / "missing"), 0u);
  AtomicWriteString(dir / "a", "1");
  const uint64_t stamp = FileStamp(dir / "a");
  EXPECT_NE(stamp, 0u);
  AtomicWriteString(dir / "a", "22");
  EXPECT_NE(FileStamp(dir / "a"), stamp);
}

}  // namespace
}  // namespace sylva
