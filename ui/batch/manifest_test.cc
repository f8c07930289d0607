#include "ui/batch/manifest.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

// A folder of tree folders built in code (files need only exist: the
// manifest reader checks paths, not contents).
class ManifestTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (fs::temp_directory_path() / "sylva_manifest_XXXXXX").string();
    ASSERT_NE(mkdtemp(templ.data()), nullptr);
    root_ = templ;
    for (const char* tree : {"oak", "elm"}) {
      Touch(root_ / tree / "photos" / "a.png");
      Touch(root_ / tree / "mattes" / "a.png");
      Touch(root_ / tree / "cameras.json");
    }
    Touch(root_ / "elm" / "loose.json");
    fs::create_directories(root_ / "elm" / "colmap");
  }
  void TearDown() override { fs::remove_all(root_); }

  static void Touch(const fs::path& path) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << "x";
  }

  Manifest Parse(const std::string& text) { return ParseManifest(text, root_ / "manifest.csv"); }

  // Expects the text to be refused at `line` with a message containing `part`.
  void ExpectRefused(const std::string& text, int line, const std::string& part) {
    try {
      Parse(text);
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const InputError& error) {
      const std::string where =
          (root_ / "manifest.csv").string() + (line > 0 ? ":" + std::to_string(line) : "");
      EXPECT_EQ(error.source(), where) << error.what();
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
    }
  }

  fs::path root_;
};

TEST_F(ManifestTest, ReadsRowsWithPathsRelativeToTheManifest) {
  const Manifest manifest = Parse(
      "name,photos,cameras,register,loose-cameras,mattes,held_out,units,Density.resolution\n"
      "oak,oak/photos,oak/cameras.json,,,oak/mattes,\"a.png,b.png\",m,64\n"
      "elm,elm/photos,,manual,elm/loose.json,,,,\n");
  ASSERT_EQ(manifest.trees.size(), 2u);
  const ManifestTree& oak = manifest.trees[0];
  EXPECT_EQ(oak.line, 2);
  EXPECT_EQ(oak.photos_dir, root_ / "oak" / "photos");
  EXPECT_EQ(oak.camera_file, root_ / "oak" / "cameras.json");
  EXPECT_EQ(oak.mattes_dir, root_ / "oak" / "mattes");
  EXPECT_EQ(oak.held_out, (std::vector<std::string>{"a.png", "b.png"}));
  EXPECT_EQ(oak.units, "m");
  ASSERT_EQ(oak.options.size(), 1u);
  EXPECT_EQ(oak.options[0], (std::pair<std::string, std::string>("Density.resolution", "64")));
  const ManifestTree& elm = *manifest.Find("elm");
  EXPECT_EQ(elm.register_method, "manual");
  EXPECT_EQ(elm.loose_cameras_file, root_ / "elm" / "loose.json");
  EXPECT_TRUE(elm.options.empty());  // an empty cell keeps the batch's value
  EXPECT_NE(oak.InputsKey(), elm.InputsKey());
  EXPECT_EQ(oak.Setup(root_ / "out").root, root_ / "out" / "oak");
}

TEST_F(ManifestTest, RefusesBadManifestsNamingLineAndProblem) {
  const std::string header = "name,photos,cameras\n";
  ExpectRefused("", 0, "empty manifest");
  ExpectRefused(header, 0, "no trees");
  ExpectRefused("name,photos,cameras,colour\n", 1, "unknown column 'colour'");
  ExpectRefused("name,photos,Density.nosuch\n", 1, "unknown option column 'Density.nosuch'");
  ExpectRefused("photos,cameras\n", 1, "no 'name' column");
  ExpectRefused(header + "oak,oak/photos,oak/cameras.json\n,elm/photos,elm/cameras.json\n", 3,
                "no name");
  ExpectRefused(header + "oak,oak/photos,oak/cameras.json\nOak,elm/photos,elm/cameras.json\n", 3,
                "duplicate name 'Oak' (line 2 has 'oak'");
  ExpectRefused(header + "oak tree,oak/photos,oak/cameras.json\n", 2, "letters, digits");
  ExpectRefused(header + "logs,oak/photos,oak/cameras.json\n", 2, "log folder");
  ExpectRefused(header + "oak,oak/fotos,oak/cameras.json\n", 2, "'photos': folder not found");
  ExpectRefused(header + "oak,oak/photos,oak/cams.json\n", 2, "'cameras': file not found");
  ExpectRefused(header + "oak,oak/photos,\n", 2, "no camera source");
  ExpectRefused("name,photos,cameras,colmap\noak,oak/photos,oak/cameras.json,elm/colmap\n", 2,
                "more than one camera source");
  ExpectRefused("name,photos,register\noak,oak/photos,sfm\n", 2, "expected colmap or manual");
  ExpectRefused("name,photos,register\noak,oak/photos,manual\n", 2, "needs 'loose_cameras'");
  ExpectRefused(header + "oak,oak/photos,oak/cameras.json,extra\n", 2, "4 fields");
  ExpectRefused("name,photos,cameras,held_out\noak,oak/photos,oak/cameras.json,@nope.txt\n", 2,
                "'held_out': file not found");
}

TEST_F(ManifestTest, ScanWritesAManifestThatReadsBack) {
  Touch(root_ / "elm" / "held_out.txt");
  std::ofstream(root_ / "elm" / "held_out.txt") << "a.png\n";
  fs::remove(root_ / "elm" / "cameras.json");
  Touch(root_ / "elm" / "colmap" / "cameras.txt");
  Touch(root_ / "ash tree" / "IMG_1.JPG");  // photos in the folder itself, COLMAP registers
  fs::create_directories(root_ / "empty");  // no photos: not a tree
  const std::vector<ManifestTree> trees = ScanTreeFolders(root_);
  ASSERT_EQ(trees.size(), 3u);
  const fs::path manifest_path = root_ / "manifest.csv";
  AtomicWriteString(manifest_path, ManifestText(trees, root_));
  const Manifest manifest = ReadManifest(manifest_path);
  ASSERT_EQ(manifest.trees.size(), 3u);
  const ManifestTree& ash = *manifest.Find("ash_tree");
  EXPECT_EQ(ash.photos_dir, root_ / "ash tree");
  EXPECT_EQ(ash.register_method, "colmap");
  const ManifestTree& elm = *manifest.Find("elm");
  EXPECT_EQ(elm.colmap_model_dir, root_ / "elm" / "colmap");
  EXPECT_EQ(elm.held_out, std::vector<std::string>{"a.png"});
  const ManifestTree& oak = *manifest.Find("oak");
  EXPECT_EQ(oak.camera_file, root_ / "oak" / "cameras.json");
  EXPECT_EQ(oak.mattes_dir, root_ / "oak" / "mattes");
  // Paths are written relative to the manifest.
  EXPECT_NE(ReadFileToString(manifest_path).find("oak,oak/photos,,oak/cameras.json"),
            std::string::npos);
  EXPECT_THROW(ScanTreeFolders(root_ / "empty"), InputError);
}

}  // namespace
}  // namespace sylva
