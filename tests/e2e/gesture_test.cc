// End-to-end test of `sylva gesture` (issue 17, Murakami et al.): a gesture
// file of datasets/gesture/ becomes a meshed tree with leaves whose outputs
// exist and read back; a bad grammar and a bad gesture file are refused with exit
// code 2, naming the file and place, and leave no output folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/io/json_util.h"
#include "core/io/lpy_io.h"
#include "core/io/mesh_io.h"
#include "core/io/mtg_io.h"
#include "core/io/skeleton_io.h"
#include "core/util/file_util.h"
#include "mesh/gltf_export.h"
#include "tests/e2e/subprocess.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

const char kSylva[] = SYLVA_BINARY_DIR "/bin/sylva";
const fs::path kGestures = fs::path(SYLVA_SOURCE_DIR) / "datasets" / "gesture";

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sylva_gesture_e2e_" + name);
  fs::remove_all(dir);
  return dir;
}

TEST(GestureE2eTest, GrowsAndMeshesATree) {
  const fs::path out = FreshDir("obj");
  const SubprocessResult result = RunSubprocess(
      {kSylva, "gesture", (kGestures / "two_trunks.obj").string(), out.string(),
       "--Gesture.iterations=5", "--Gesture.defines=ANGLE=35,LR=0.75", "--Report.preview_size=96"});
  ASSERT_EQ(result.exit_code, 0) << result.Describe();
  EXPECT_LT(result.seconds, 20.0);
  EXPECT_NE(result.out.find("2 trunk stroke(s)"), std::string::npos) << result.out;
  // Leaves at the spiral phyllotaxis nodes of the thin branches (the
  // command's default), in tree.obj as their own material.
  EXPECT_NE(result.out.find("spiral phyllotaxis"), std::string::npos) << result.out;
  for (const char* name :
       {"tree.glb", "tree.obj", "bark.obj", "skeleton.json", "qsm.csv", "metrics.json", "tree.lpy",
        "tree_turtle.lpy", "tree.mtg", "lstring.txt", "roi.json", "options.json", "preview_0.png",
        "report.json", "report.html"}) {
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
  }
  // The report of a tree made without photos: its figures, previews beside
  // it and the summary; no comparison with photos.
  const std::string html = ReadFileToString(out / "report.html");
  EXPECT_NE(html.find("made without photos"), std::string::npos);
  EXPECT_NE(html.find("src=\"preview_0.png\""), std::string::npos);
  EXPECT_NE(html.find("total branch length"), std::string::npos);
  EXPECT_NE(html.find("spiral phyllotaxis"), std::string::npos);
  EXPECT_EQ(html.find("Comparisons"), std::string::npos);
  const Json report = Json::parse(ReadFileToString(out / "report.json"));
  EXPECT_EQ(report.at("previews").at(0), "preview_0.png");
  const Json metrics = Json::parse(ReadFileToString(out / "metrics.json"));
  EXPECT_EQ(metrics.at("sources").at("height"), "gestures (trunks) and L-system (branches)");
  EXPECT_GT(ReadGlb(out / "tree.glb").NumTriangles(), 1000);
  EXPECT_NE(ReadFileToString(out / "tree.obj").find("usemtl leaves"), std::string::npos);
  const SkeletonGraph skeleton = ReadSkeletonJson(out / "skeleton.json");
  EXPECT_GT(skeleton.NumNodes(), 100);
  const LpyTree lpy = ReadLpy(out / "tree.lpy");
  ASSERT_EQ(lpy.parts.size(), 1u);
  EXPECT_EQ(lpy.parts[0].NumNodes(), skeleton.NumNodes());
  const MtgSkeletons mtg = SkeletonsFromMtg(ReadMtg(out / "tree.mtg"), "tree.mtg");
  ASSERT_EQ(mtg.parts.size(), 1u);
  EXPECT_EQ(mtg.parts[0].NumNodes(), skeleton.NumNodes());
  const Json roi = Json::parse(ReadFileToString(out / "roi.json"));
  EXPECT_EQ(roi["fitted_to"], "roi strokes");
  const Json options = Json::parse(ReadFileToString(out / "options.json"));
  EXPECT_EQ(options["Gesture"]["iterations"], 5);
  EXPECT_EQ(options["Gesture"]["defines"], "ANGLE=35,LR=0.75");
  EXPECT_NE(ReadFileToString(out / "lstring.txt").find("T("), std::string::npos);
  fs::remove_all(out);
}

TEST(GestureE2eTest, BadGrammarAndGestureFiles) {
  const fs::path dir = FreshDir("bad");
  fs::create_directories(dir);
  const fs::path grammar = dir / "bad.lsys";
  AtomicWriteString(grammar, "#define A 1\nB(x) : x > -> F(x)\n");
  const fs::path out = dir / "out";
  const SubprocessResult bad_grammar =
      RunSubprocess({kSylva, "gesture", (kGestures / "s_trunk.json").string(), out.string(),
                     "--Gesture.grammar=" + grammar.string()});
  EXPECT_EQ(bad_grammar.exit_code, 2) << bad_grammar.Describe();
  EXPECT_NE(bad_grammar.err.find(grammar.string() + ": line 2, column 12"), std::string::npos)
      << bad_grammar.err;
  EXPECT_FALSE(fs::exists(out));
  const fs::path gesture = dir / "bad.obj";
  AtomicWriteString(gesture, "v 0 0 0\nv 0 0 1\nv 0 x 2\nl 1 2 3\n");
  const SubprocessResult bad_gesture =
      RunSubprocess({kSylva, "gesture", gesture.string(), out.string()});
  EXPECT_EQ(bad_gesture.exit_code, 2) << bad_gesture.Describe();
  EXPECT_NE(bad_gesture.err.find(gesture.string() + ": line 3: expected x y z"), std::string::npos)
      << bad_gesture.err;
  EXPECT_FALSE(fs::exists(out));
  const SubprocessResult bad_option =
      RunSubprocess({kSylva, "gesture", (kGestures / "s_trunk.json").string(), out.string(),
                     "--Gesture.growth_spacing=0"});
  EXPECT_EQ(bad_option.exit_code, 2);
  EXPECT_NE(bad_option.err.find("Gesture.growth_spacing"), std::string::npos);
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(dir);
  const SubprocessResult help = RunSubprocess({kSylva, "gesture", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("Gesture.grammar"), std::string::npos);
}

}  // namespace
}  // namespace sylva
