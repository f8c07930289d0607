// End-to-end test of `sylva concept` (issue 17): a concept sketch of
// datasets/concept/ becomes a plant whose outputs exist and read back; a
// degenerate drawing is refused with exit code 2, naming the file, and
// leaves no output folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/io/image_io.h"
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
const fs::path kDrawings = fs::path(SYLVA_SOURCE_DIR) / "datasets" / "concept";

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sylva_concept_e2e_" + name);
  fs::remove_all(dir);
  return dir;
}

TEST(ConceptE2eTest, MakesAPlantWithEveryOutput) {
  const fs::path out = FreshDir("spiral");
  const SubprocessResult result =
      RunSubprocess({kSylva, "concept", (kDrawings / "spiral.svg").string(), out.string(),
                     "--PenAndInk.image_size=400", "--Report.preview_size=128"});
  ASSERT_EQ(result.exit_code, 0) << result.Describe();
  EXPECT_NE(result.out.find("spiral phyllotaxis"), std::string::npos) << result.out;
  for (const char* name :
       {"tree.glb",      "tree.obj",      "tree.mtl",        "bark.obj",        "skeleton.json",
        "qsm.csv",       "tree.lpy",      "tree_turtle.lpy", "tree.mtg",        "organs.json",
        "pen_front.svg", "pen_front.png", "pen_oblique.svg", "pen_oblique.png", "pen_top.svg",
        "pen_top.png",   "preview_0.png", "metrics.json",    "report.json",     "report.html"}) {
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
  }
  EXPECT_NE(ReadFileToString(out / "report.html").find("made without photos"), std::string::npos);
  // The meshes read back: bark and leaves.
  const TriangleMesh glb = ReadGlb(out / "tree.glb");
  const TriangleMesh obj = ReadObj(out / "tree.obj");
  EXPECT_EQ(glb.NumTriangles(), obj.NumTriangles());
  bool leaves = false;
  for (const Material& m : obj.materials) leaves |= m.name == "leaves";
  EXPECT_TRUE(leaves);
  // The skeleton in its three exports.
  const SkeletonGraph skeleton = ReadSkeletonJson(out / "skeleton.json");
  const LpyTree lpy = ReadLpy(out / "tree.lpy");
  ASSERT_EQ(lpy.parts.size(), 1u);
  EXPECT_EQ(lpy.parts[0].NumNodes(), skeleton.NumNodes());
  const MtgSkeletons mtg = SkeletonsFromMtg(ReadMtg(out / "tree.mtg"), "tree.mtg");
  ASSERT_EQ(mtg.parts.size(), 1u);
  EXPECT_EQ(mtg.parts[0].NumNodes(), skeleton.NumNodes());
  // Organs with their divergence; the pen-and-ink drawings with layers.
  const Json organs = Json::parse(ReadFileToString(out / "organs.json"));
  EXPECT_EQ(organs["phyllotaxis"], "spiral");
  ASSERT_GE(organs["organs"].size(), 10u);
  for (size_t k = 1; k < organs["organs"].size(); ++k) {
    EXPECT_NEAR(organs["organs"][k]["divergence_deg"].get<double>(), 137.5, 2.0);
  }
  const std::string svg = ReadFileToString(out / "pen_front.svg");
  EXPECT_NE(svg.find("inkscape:label=\"outline\""), std::string::npos);
  EXPECT_NE(svg.find("inkscape:label=\"hatching\""), std::string::npos);
  const FloatImage png = ReadImage(out / "pen_front.png");
  EXPECT_GT(png.width(), 100);
  fs::remove_all(out);
}

TEST(ConceptE2eTest, PatternOptionAndDegenerateDrawings) {
  const fs::path out = FreshDir("distichous");
  const SubprocessResult result =
      RunSubprocess({kSylva, "concept", (kDrawings / "spiral.svg").string(), out.string(),
                     "--Concept.phyllotaxis=distichous", "--PenAndInk.image_size=200",
                     "--Report.previews=false"});
  ASSERT_EQ(result.exit_code, 0) << result.Describe();
  const Json organs = Json::parse(ReadFileToString(out / "organs.json"));
  EXPECT_EQ(organs["phyllotaxis"], "distichous");
  EXPECT_FALSE(fs::exists(out / "preview_0.png"));
  // The same drawing and options again: the same organs.
  const fs::path again = FreshDir("distichous_again");
  ASSERT_EQ(RunSubprocess({kSylva, "concept", (kDrawings / "spiral.svg").string(), again.string(),
                           "--Concept.phyllotaxis=distichous", "--PenAndInk.image_size=200",
                           "--Report.previews=false"})
                .exit_code,
            0);
  const Json repeated = Json::parse(ReadFileToString(again / "organs.json"));
  ASSERT_EQ(repeated["organs"].size(), organs["organs"].size());
  for (size_t k = 0; k < organs["organs"].size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(repeated["organs"][k]["tip"][c].get<double>(),
                  organs["organs"][k]["tip"][c].get<double>(), 1e-12);
    }
  }
  fs::remove_all(out);
  fs::remove_all(again);

  // A stem without boundary lines, and a one-point stroke.
  const fs::path bad_dir = FreshDir("bad_inputs");
  fs::create_directories(bad_dir);
  const std::string head =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" "
      "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" viewBox=\"0 0 200 300\">"
      "<g inkscape:label=\"construction\">";
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"stem_only.svg", "<path d=\"M 100 290 L 100 20\"/>"},
      {"one_point.svg", "<path d=\"M 100 100\"/>"},
      {"no_stem.svg", "<path d=\"M 10 100 L 190 110\"/>"}};
  for (const auto& [name, body] : bad) {
    const fs::path drawing = bad_dir / name;
    AtomicWriteString(drawing, head + body + "</g></svg>");
    const fs::path bad_out = bad_dir / ("out_" + name);
    const SubprocessResult refused =
        RunSubprocess({kSylva, "concept", drawing.string(), bad_out.string()});
    EXPECT_EQ(refused.exit_code, 2) << refused.Describe();
    EXPECT_NE(refused.err.find(drawing.string()), std::string::npos) << refused.err;
    EXPECT_FALSE(fs::exists(bad_out)) << name;
  }
  // A non-empty OUT_DIR is refused before any work.
  const SubprocessResult occupied =
      RunSubprocess({kSylva, "concept", (kDrawings / "spiral.svg").string(), bad_dir.string()});
  EXPECT_EQ(occupied.exit_code, 2) << occupied.Describe();
  fs::remove_all(bad_dir);
  const SubprocessResult help = RunSubprocess({kSylva, "concept", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("Concept.phyllotaxis"), std::string::npos);
}

}  // namespace
}  // namespace sylva
