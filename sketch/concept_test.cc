// Concept sketches (Anastacio et al. 2006): construction lines told apart,
// organs placed in the five phyllotactic patterns with the paper's
// divergence angles, sized within the boundary lines, and degenerate
// drawings refused naming the file. Drawings: datasets/concept/ (made for
// sylva, CC0) and small ones written here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "sketch/concept_plant.h"
#include "sketch/concept_sketch.h"
#include "sketch/drawing_io.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

const fs::path kDrawings = fs::path(SYLVA_SOURCE_DIR) / "datasets" / "concept";

// The divergence as measured looking down the stem: folded into [0, 180].
double FoldedDeg(double degrees) {
  double d = std::fmod(std::abs(degrees), 360.0);
  return d > 180 ? 360 - d : d;
}

ConceptPlant PlantOf(const fs::path& path, const ConceptPlantOptions& options = {}) {
  return BuildConceptPlant(InterpretConceptDrawing(ReadSketchSvg(path)), options);
}

// Largest |measured - expected| over successive organs.
double MaxDivergenceError(const ConceptPlant& plant, double expected_deg) {
  double worst = 0;
  for (size_t k = 1; k < plant.organs.size(); ++k) {
    worst = std::max(worst, std::abs(MeasuredDivergenceDeg(plant.organs[k - 1], plant.organs[k]) -
                                     FoldedDeg(expected_deg)));
  }
  return worst;
}

// How far any blade vertex or organ centre point lies outside the envelope.
double MaxExcess(const ConceptPlant& plant) {
  double worst = -INFINITY;
  for (const Eigen::Vector3f& v : plant.blades.vertices) {
    worst = std::max(worst, plant.EnvelopeExcess(v.cast<double>()));
  }
  for (const ConceptOrgan& organ : plant.organs) {
    for (const Eigen::Vector3d& p : organ.centre) worst = std::max(worst, plant.EnvelopeExcess(p));
  }
  return worst;
}

// An independent check in the drawing itself: every blade vertex seen from
// the front lies on the stem's side of the drawn boundary lines (the segment
// from the stem at its height to it crosses no boundary).
int VerticesOutsideDrawnBoundaries(const ConceptStructure& structure, const ConceptPlant& plant) {
  int outside = 0;
  for (const Eigen::Vector3f& v : plant.blades.vertices) {
    const Eigen::Vector2d canvas(plant.base_px.x() + v.x() / plant.world_per_pixel,
                                 plant.base_px.y() - v.z() / plant.world_per_pixel);
    // The stem point at that height (the stems here are nearly vertical).
    Eigen::Vector2d foot = structure.stem.front();
    for (double s = 0; s <= PolylineLengthPx(structure.stem); s += 0.25) {
      const Eigen::Vector2d p = PointAtArc(structure.stem, s);
      if (std::abs(p.y() - canvas.y()) < std::abs(foot.y() - canvas.y())) foot = p;
    }
    const Eigen::Vector2d to = canvas - foot;
    if (to.norm() < 1e-6) continue;
    const double hit = CastRay2d(structure.envelope, foot, to.normalized());
    if (hit < to.norm() - 0.05) ++outside;  // 0.05 px: the front view's rounding
  }
  return outside;
}

struct PatternCase {
  const char* file;
  ConceptPattern pattern;
  double divergence_deg;
};

const PatternCase kCases[] = {
    {"spiral.svg", ConceptPattern::kSpiral, 137.5},
    {"monostichous.svg", ConceptPattern::kMonostichous, 30.0},
    {"distichous.svg", ConceptPattern::kDistichous, 180.0},
    {"tristichous.svg", ConceptPattern::kTristichous, 120.0},
    {"tetrastichous.svg", ConceptPattern::kTetrastichous, 90.0},
};

TEST(ConceptSketchTest, FivePatternsMatchTheirDivergenceAndFitTheBoundaries) {
  for (const PatternCase& c : kCases) {
    SCOPED_TRACE(c.file);
    const ConceptStructure structure = InterpretConceptDrawing(ReadSketchSvg(kDrawings / c.file));
    ASSERT_TRUE(structure.drawn_pattern.has_value());
    EXPECT_EQ(*structure.drawn_pattern, c.pattern);
    EXPECT_EQ(structure.num_boundaries, 2);
    EXPECT_GE(structure.inclinations.size(), 2u);
    const ConceptPlant plant = BuildConceptPlant(structure, ConceptPlantOptions());
    EXPECT_EQ(plant.pattern, c.pattern);
    EXPECT_DOUBLE_EQ(plant.divergence_deg, c.divergence_deg);
    ASSERT_GE(plant.organs.size(), 8u);
    const double error = MaxDivergenceError(plant, c.divergence_deg);
    const double excess = MaxExcess(plant);
    const int outside = VerticesOutsideDrawnBoundaries(structure, plant);
    double fit = 0;
    for (const ConceptOrgan& organ : plant.organs) fit += organ.fit / plant.organs.size();
    std::printf(
        "%-18s %3zu organs, max divergence error %.4f deg, max envelope excess %.2e m, "
        "%d of %d blade vertices outside the drawn boundaries, %d shortened (mean length / "
        "reach %.3f)\n",
        c.file, plant.organs.size(), error, excess, outside, plant.blades.NumVertices(),
        plant.shrunk_organs, fit);
    EXPECT_LE(error, 2.0);
    EXPECT_LE(excess, 1e-6 * 0.3);
    EXPECT_EQ(outside, 0);
    EXPECT_GT(plant.blades.NumTriangles(), 0);
    plant.skeleton.Check();
  }
}

TEST(ConceptSketchTest, LineOrgansBecomeBranches) {
  // needles.svg: two open organ strokes (a curved and a straight needle).
  ConceptPlantOptions options;
  options.organs_per_layer = 20;
  const ConceptPlant plant = PlantOf(kDrawings / "needles.svg", options);
  ASSERT_EQ(plant.organs.size(), 20u);
  EXPECT_EQ(plant.blades.NumTriangles(), 0);
  EXPECT_TRUE(plant.veins.empty());
  EXPECT_LE(MaxDivergenceError(plant, 137.5), 2.0);
  EXPECT_LE(MaxExcess(plant), 1e-6 * options.stem_length);
  // Each needle is an order-1 axis of the wood's skeleton, from the stem.
  int tips = 0;
  for (int tip : plant.wood_skeleton.Tips()) tips += plant.wood_skeleton.nodes[tip].order == 1;
  EXPECT_EQ(tips, 20);
  EXPECT_EQ(plant.skeleton.NumNodes(), plant.wood_skeleton.NumNodes());
}

TEST(ConceptSketchTest, OrgansFollowTheInclinationLines) {
  // distichous.svg is symmetric about its straight stem, so organs in the
  // drawing plane (azimuth 0 and 180) point along the paper's branching
  // rays: at the interpolated angle phi from the stem's downward direction.
  const ConceptPlant plant = PlantOf(kDrawings / "distichous.svg");
  double worst = 0;
  for (const ConceptOrgan& organ : plant.organs) {
    const Eigen::Vector3d direction = (organ.tip - organ.base).normalized();
    const double from_down = std::acos(-direction.z()) * 180.0 / M_PI;
    worst = std::max(worst, std::abs(from_down - organ.branching_deg));
    EXPECT_GT(organ.branching_deg, 90.0);  // the drawn V lines rise outwards
  }
  std::printf("distichous: max |organ angle - inclination angle| %.4f deg\n", worst);
  EXPECT_LE(worst, 0.5);
}

TEST(ConceptSketchTest, OrganTipsReachTheEnvelope) {
  // The organs are sized by the boundary: a typical one reaches it.
  const ConceptPlant plant = PlantOf(kDrawings / "spiral.svg");
  int reaching = 0;
  for (const ConceptOrgan& organ : plant.organs) {
    EXPECT_NEAR(plant.EnvelopeExcess(organ.reference_tip), 0.0, 1e-6);
    reaching += organ.fit > 0.8 ? 1 : 0;
  }
  EXPECT_GE(reaching, static_cast<int>(plant.organs.size()) / 2);
}

TEST(ConceptSketchTest, OptionOverridesTheDrawnPatternAndDecussatePairs) {
  ConceptPlantOptions options;
  options.phyllotaxis = "distichous";
  const ConceptPlant distichous = PlantOf(kDrawings / "spiral.svg", options);
  EXPECT_EQ(distichous.pattern, ConceptPattern::kDistichous);
  EXPECT_LE(MaxDivergenceError(distichous, 180.0), 2.0);
  // Tetrastichous with two organs per node: opposite pairs, successive pairs
  // crossed (decussate).
  options.phyllotaxis = "tetrastichous";
  options.organs_per_node = 2;
  const ConceptPlant decussate = PlantOf(kDrawings / "tetrastichous.svg", options);
  ASSERT_GE(decussate.organs.size(), 8u);
  for (size_t k = 1; k < decussate.organs.size(); ++k) {
    const ConceptOrgan &a = decussate.organs[k - 1], &b = decussate.organs[k];
    const double expected = a.node == b.node ? 180.0 : 90.0;
    EXPECT_NEAR(MeasuredDivergenceDeg(a, b), expected, 2.0) << "organ " << k;
  }
  options = ConceptPlantOptions();
  options.divergence_deg = 0;  // strictly one-sided
  const ConceptPlant one_side = PlantOf(kDrawings / "monostichous.svg", options);
  EXPECT_LE(MaxDivergenceError(one_side, 0.0), 2.0);
}

TEST(ConceptSketchTest, GeometryTellsTheLinesApartAsTheirNamesDo) {
  // spiral.svg names its lines (the element's own words first, then its
  // layer's) and writes its pattern as a <text>.
  const SketchDrawing drawing = ReadSketchSvg(kDrawings / "spiral.svg");
  ASSERT_EQ(drawing.texts.size(), 1u);
  EXPECT_EQ(drawing.texts[0], "spiral");
  EXPECT_EQ(drawing.strokes[0].name, "stem construction");
  EXPECT_EQ(drawing.strokes[0].role, StrokeRole::kConstruction);
  // The same drawing without ids is read the same.
  const std::string text = ReadFileToString(kDrawings / "spiral.svg");
  std::string stripped = text;
  for (const char* id :
       {" id=\"stem\"", " id=\"boundary-left\"", " id=\"boundary-right\"", " id=\"inclination-0\"",
        " id=\"inclination-1\"", " id=\"inclination-2\""}) {
    stripped.replace(stripped.find(id), std::string(id).size(), "");
  }
  const fs::path copy = fs::temp_directory_path() / "sylva_concept_unnamed.svg";
  AtomicWriteString(copy, stripped);
  const ConceptStructure named = InterpretConceptDrawing(ReadSketchSvg(kDrawings / "spiral.svg"));
  const ConceptStructure unnamed = InterpretConceptDrawing(ReadSketchSvg(copy));
  fs::remove(copy);
  EXPECT_EQ(unnamed.num_boundaries, named.num_boundaries);
  ASSERT_EQ(unnamed.inclinations.size(), named.inclinations.size());
  ASSERT_EQ(unnamed.stem.size(), named.stem.size());
  for (size_t i = 0; i < named.stem.size(); ++i) EXPECT_EQ(unnamed.stem[i], named.stem[i]);
  // Base first: the lower end.
  EXPECT_GT(named.stem.front().y(), named.stem.back().y());
  // The inclination lines rise outwards: angles from the downward stem > 90.
  for (const auto& line : named.inclinations) {
    EXPECT_GT(line.left_deg, 90.0);
    EXPECT_GT(line.right_deg, 90.0);
  }
  EXPECT_EQ(named.organs.size(), 2u);
  EXPECT_TRUE(named.organs.front().blade);
}

TEST(ConceptSketchTest, SameDrawingAndSeedGiveTheSamePlant) {
  const ConceptPlant a = PlantOf(kDrawings / "tristichous.svg");
  const ConceptPlant b = PlantOf(kDrawings / "tristichous.svg");
  ASSERT_EQ(a.organs.size(), b.organs.size());
  for (size_t k = 0; k < a.organs.size(); ++k) {
    EXPECT_EQ(a.organs[k].tip, b.organs[k].tip);
    EXPECT_EQ(a.organs[k].template_t, b.organs[k].template_t);
  }
  ASSERT_EQ(a.blades.vertices.size(), b.blades.vertices.size());
  for (size_t i = 0; i < a.blades.vertices.size(); ++i) {
    EXPECT_EQ(a.blades.vertices[i], b.blades.vertices[i]);
  }
  ConceptPlantOptions other;
  other.seed = 7;
  const ConceptPlant c = PlantOf(kDrawings / "tristichous.svg", other);
  bool differs = false;
  for (size_t k = 0; k < a.organs.size(); ++k)
    differs |= a.organs[k].template_t != c.organs[k].template_t;
  EXPECT_TRUE(differs) << "two templates: the seed chooses the in-betweens";
}

// Writes `body` as an SVG in the temp folder and returns its path.
fs::path WriteSvg(const std::string& name, const std::string& body) {
  const fs::path path = fs::temp_directory_path() / name;
  AtomicWriteString(path,
                    "<svg xmlns=\"http://www.w3.org/2000/svg\" "
                    "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" "
                    "viewBox=\"0 0 200 300\">" +
                        body + "</svg>");
  return path;
}

// The error's message names the file.
void ExpectRefusedNaming(const fs::path& path, const std::string& words) {
  try {
    InterpretConceptDrawing(ReadSketchSvg(path));
    ADD_FAILURE() << path << " was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
  fs::remove(path);
}

TEST(ConceptSketchTest, DegenerateDrawingsAreRefusedNamingTheFile) {
  // Only organs: no construction lines.
  ExpectRefusedNaming(WriteSvg("sylva_concept_organs_only.svg",
                               "<g inkscape:label=\"organs\"><path d=\"M 10 10 L 20 30 L 5 25 Z\"/>"
                               "</g>"),
                      "no construction lines");
  // Only transverse construction lines: no stem.
  ExpectRefusedNaming(WriteSvg("sylva_concept_no_stem.svg",
                               "<g inkscape:label=\"construction\"><path d=\"M 10 100 L 190 110\"/>"
                               "</g>"),
                      "no stem");
  // A stem without boundaries.
  ExpectRefusedNaming(WriteSvg("sylva_concept_no_boundary.svg",
                               "<g inkscape:label=\"construction\"><path d=\"M 100 290 L 100 20\"/>"
                               "</g>"),
                      "no boundary");
  // A stroke of one point.
  ExpectRefusedNaming(WriteSvg("sylva_concept_one_point.svg",
                               "<g inkscape:label=\"construction\"><path d=\"M 100 100\"/></g>"),
                      "fewer than two");
  // An inclination line named so that misses the stem.
  ExpectRefusedNaming(
      WriteSvg("sylva_concept_bad_inclination.svg",
               "<g inkscape:label=\"construction\"><path id=\"stem\" d=\"M 100 290 L 100 20\"/>"
               "<path d=\"M 60 290 L 60 20\"/><path d=\"M 140 290 L 140 20\"/>"
               "<path id=\"inclination\" d=\"M 10 100 L 40 80\"/></g>"),
      "does not cross the stem");
}

TEST(ConceptSketchTest, PatternNamesRoundTrip) {
  for (const PatternCase& c : kCases) {
    EXPECT_EQ(ConceptPatternFromName(ConceptPatternName(c.pattern)), c.pattern);
    EXPECT_DOUBLE_EQ(ConceptDivergenceDeg(c.pattern), c.divergence_deg);
  }
  EXPECT_EQ(ConceptPatternFromName("Spiral"), ConceptPattern::kSpiral);
  EXPECT_FALSE(ConceptPatternFromName("whorled").has_value());
  ConceptPlantOptions bad;
  bad.phyllotaxis = "whorled";
  EXPECT_THROW(bad.Check(), InputError);
}

}  // namespace
}  // namespace sylva
