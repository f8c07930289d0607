#include "sketch/drawing_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/random.h"

namespace sylva {
namespace {

fs::path WriteTestFile(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "sylva_drawing_io_test";
  fs::create_directories(dir);
  AtomicWriteString(dir / name, text);
  return dir / name;
}

fs::path SketchData(const std::string& relative) {
  return fs::path(SYLVA_SOURCE_DIR) / "datasets" / "sketches" / relative;
}

void ExpectPoint(const Eigen::Vector2d& actual, double x, double y) {
  EXPECT_NEAR(actual.x(), x, 1e-9) << actual.transpose();
  EXPECT_NEAR(actual.y(), y, 1e-9) << actual.transpose();
}

// The message of the InputError reading `path` throws, checked to name the file.
std::string ReadError(const fs::path& path, int index = 0) {
  try {
    ReadSketch(path, index);
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), path.string()) << error.what();
    return error.message();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return "";
}

std::string ReadError(const std::string& name, const std::string& text, int index = 0) {
  return ReadError(WriteTestFile(name, text), index);
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// ---------------------------------------------------------------- SVG

// An Inkscape-like drawing: roles from layer labels, classes and colours,
// widths under transforms, closed shapes as crowns, a root circle. The
// viewBox starts at (10, 20), so canvas = user - (10, 20).
constexpr char kLayeredSvg[] = R"svg(<?xml version="1.0"?>
<svg xmlns="http://www.w3.org/2000/svg"
     xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
     width="200mm" height="300mm" viewBox="10 20 200 300">
  <g inkscape:groupmode="layer" inkscape:label="Crown">
    <path d="M 20 30 L 60 40"/>
  </g>
  <g inkscape:groupmode="layer" inkscape:label="Branches" transform="scale(2)"
     style="stroke:#00aa00;stroke-width:1.5">
    <path d="M 10 20 L 30 40"/>
    <rect class="crown" x="20" y="20" width="10" height="5"/>
    <rect x="40" y="20" width="10" height="5"/>
  </g>
  <g class="organ leaves"><polyline points="50,50 60,60 70,50"/></g>
  <g inkscape:label="Construction lines"><line x1="100" y1="30" x2="100" y2="300"/></g>
  <path d="M 100 100 L 110 100" stroke="ForestGreen" stroke-width="2"
        transform="rotate(30) scale(3)"/>
  <path d="M 100 200 L 100 300" style="stroke: #7b5517; stroke-width: 4px"/>
  <path d="M 120 200 L 130 300" style="fill:#028700;stroke:none;stroke-width:5"/>
  <line x1="150" y1="50" x2="160" y2="60" stroke="rgb(20, 200, 40)"/>
  <path d="M 120 100 L 100 100" stroke="black"/>
  <ellipse cx="110" cy="120" rx="40" ry="20" stroke="#6b4226"/>
  <circle cx="150" cy="150" r="10"/>
  <path d="M 160 160 h 20 v 20 z m 30 0 l 5 5"/>
  <circle id="root" cx="110" cy="318" r="2"/>
  <circle class="ignored" r="0"/>
</svg>
)svg";

TEST(ReadSketchSvgTest, RolesWidthsAndClosedShapes) {
  const SketchDrawing drawing = ReadSketch(WriteTestFile("layers.svg", kLayeredSvg));
  EXPECT_EQ(drawing.width, 200);
  EXPECT_EQ(drawing.height, 300);
  ASSERT_TRUE(drawing.root);
  ExpectPoint(*drawing.root, 100, 298);
  ASSERT_EQ(drawing.strokes.size(), 15u);
  const auto expect = [&](size_t k, StrokeRole role, bool closed, double width) {
    SCOPED_TRACE("stroke " + std::to_string(k));
    EXPECT_EQ(StrokeRoleName(drawing.strokes[k].role), std::string(StrokeRoleName(role)));
    EXPECT_EQ(drawing.strokes[k].closed, closed);
    EXPECT_NEAR(drawing.strokes[k].width, width, 1e-9);
  };
  expect(0, StrokeRole::kCrown, false, 0);         // the "Crown" layer, open
  expect(1, StrokeRole::kBranch, false, 3);        // "Branches" beats green; 1.5 x scale 2
  expect(2, StrokeRole::kCrown, true, 3);          // class="crown"
  expect(3, StrokeRole::kBranch, true, 3);         // closed, but the layer says branch
  expect(4, StrokeRole::kOrgan, false, 0);         // class "organ leaves"
  expect(5, StrokeRole::kConstruction, false, 0);  // "Construction lines"
  expect(6, StrokeRole::kCrown, false, 6);         // forestgreen; 2 x scale 3 (rotation kept)
  expect(7, StrokeRole::kBranch, false, 4);        // brown
  expect(8, StrokeRole::kCrown, false, 0);         // no stroke: the green fill; no width
  expect(9, StrokeRole::kCrown, false, 0);         // rgb() green
  expect(10, StrokeRole::kBranch, false, 0);       // black
  expect(11, StrokeRole::kCrown, true, 0);         // ellipse, although brown
  expect(12, StrokeRole::kCrown, true, 0);         // circle that is not the root
  expect(13, StrokeRole::kCrown, true, 0);         // subpath closed by z
  expect(14, StrokeRole::kBranch, false, 0);       // the open subpath after it
  EXPECT_EQ(drawing.CountRole(StrokeRole::kCrown), 8);

  // Geometry in canvas pixels: the viewBox origin and the transforms applied.
  ExpectPoint(drawing.strokes[0].points.front(), 10, 10);
  ExpectPoint(drawing.strokes[1].points.back(), 50, 60);
  // A rect under scale(2): 4 corners, the first not repeated.
  ASSERT_EQ(drawing.strokes[2].points.size(), 4u);
  ExpectPoint(drawing.strokes[2].points[2], 50, 30);
  // rotate(30) scale(3) of (110, 100).
  const double angle = M_PI / 6;
  ExpectPoint(drawing.strokes[6].points.back(),
              3 * (110 * std::cos(angle) - 100 * std::sin(angle)) - 10,
              3 * (110 * std::sin(angle) + 100 * std::cos(angle)) - 20);
  // The ellipse is flattened within a quarter pixel of the exact curve.
  for (const Eigen::Vector2d& p : drawing.strokes[11].points) {
    const Eigen::Vector2d q = p - Eigen::Vector2d(100, 100);
    EXPECT_NEAR(std::hypot(q.x() / 40, q.y() / 20), 1.0, 0.25 / 20);
  }
  EXPECT_GT(drawing.strokes[11].points.size(), 16u);
  EXPECT_EQ(drawing.strokes[13].points.size(), 3u);
}

// What the app's sketch canvas saves is read back with the same strokes.
TEST(WriteSketchSvgTest, ReadSketchSvgReadsBackTheSameDrawing) {
  SketchDrawing drawing;
  drawing.width = 400;
  drawing.height = 600.5;
  RandomEngine random(7);
  const auto stroke = [&](StrokeRole role, bool closed, int n, double width) {
    SketchStroke s;
    s.role = role;
    s.closed = closed;
    s.width = width;
    for (int i = 0; i < n; ++i) {
      s.points.emplace_back(random.Uniform(0, 400), random.Uniform(0, 600) + 1.0 / 3);
    }
    drawing.strokes.push_back(s);
  };
  stroke(StrokeRole::kBranch, false, 12, 4.5);
  stroke(StrokeRole::kCrown, true, 30, 2);
  stroke(StrokeRole::kBranch, false, 2, 0);
  stroke(StrokeRole::kCrown, false, 5, 1);  // an open crown stroke keeps its role by its layer
  drawing.root = Eigen::Vector2d(200.25, 590);
  const fs::path path = WriteTestFile("written.svg", "");
  WriteSketchSvg(path, drawing);
  const SketchDrawing read = ReadSketchSvg(path);
  EXPECT_DOUBLE_EQ(read.width, 400);
  EXPECT_DOUBLE_EQ(read.height, 600.5);
  ASSERT_TRUE(read.root);
  EXPECT_NEAR((*read.root - *drawing.root).norm(), 0, 1e-6);
  ASSERT_EQ(read.strokes.size(), drawing.strokes.size());
  // Written layer by layer: crowns first, then branches, each in order.
  std::vector<const SketchStroke*> expected;
  for (StrokeRole role : {StrokeRole::kCrown, StrokeRole::kBranch}) {
    for (const SketchStroke& s : drawing.strokes) {
      if (s.role == role) expected.push_back(&s);
    }
  }
  for (size_t i = 0; i < read.strokes.size(); ++i) {
    const SketchStroke& a = read.strokes[i];
    const SketchStroke& b = *expected[i];
    EXPECT_EQ(a.role, b.role) << i;
    EXPECT_EQ(a.closed, b.closed) << i;
    EXPECT_NEAR(a.width, b.width, 1e-6) << i;
    ASSERT_EQ(a.points.size(), b.points.size()) << i;
    for (size_t k = 0; k < a.points.size(); ++k) {
      EXPECT_NEAR((a.points[k] - b.points[k]).norm(), 0, 1e-5) << i << " " << k;
    }
  }
}

TEST(ReadSketchSvgTest, CanvasFromWidthAndHeightWithoutViewBox) {
  const SketchDrawing drawing = ReadSketch(WriteTestFile(
      "pt.svg", "<svg width='90pt' height='1in'><polygon points='1,1 50,1 20,40'/></svg>"));
  EXPECT_EQ(drawing.width, 120);
  EXPECT_EQ(drawing.height, 96);
  ASSERT_EQ(drawing.strokes.size(), 1u);
  EXPECT_TRUE(drawing.strokes[0].closed);
  EXPECT_EQ(drawing.strokes[0].role, StrokeRole::kCrown);
  EXPECT_EQ(drawing.strokes[0].points.size(), 3u);
}

TEST(ReadSketchSvgTest, TheHeadersExample) {
  const SketchDrawing drawing = ReadSketch(WriteTestFile("example.svg", R"svg(
<svg xmlns="http://www.w3.org/2000/svg"
     xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
     width="200mm" height="300mm" viewBox="0 0 200 300">
  <g inkscape:groupmode="layer" inkscape:label="Crown">
    <ellipse cx="100" cy="90" rx="80" ry="70"/>
  </g>
  <g inkscape:label="branches" style="stroke:#6b4226;stroke-width:4">
    <path d="M 100 290 C 102 200 98 150 100 120"/>
  </g>
  <path d="M 40 60 q 20 -30 50 -20" stroke="green"/>
  <circle id="root" cx="100" cy="292" r="3"/>
</svg>)svg"));
  ASSERT_EQ(drawing.strokes.size(), 3u);
  EXPECT_EQ(drawing.strokes[0].role, StrokeRole::kCrown);
  EXPECT_TRUE(drawing.strokes[0].closed);
  EXPECT_EQ(drawing.strokes[1].role, StrokeRole::kBranch);
  EXPECT_EQ(drawing.strokes[1].width, 4);
  EXPECT_EQ(drawing.strokes[2].role, StrokeRole::kCrown);
  EXPECT_FALSE(drawing.strokes[2].closed);
  ASSERT_TRUE(drawing.root);
  ExpectPoint(*drawing.root, 100, 292);
}

TEST(ReadSketchSvgTest, TheRootElementsStyleAndClassApply) {
  const SketchDrawing drawing =
      ReadSketch(WriteTestFile("root_style.svg",
                               "<svg viewBox='0 0 10 10' class='Crowns' style='stroke-width:0.5'>"
                               "<line x1='1' x2='9' y1='5' y2='5'/></svg>"));
  ASSERT_EQ(drawing.strokes.size(), 1u);
  EXPECT_EQ(drawing.strokes[0].role, StrokeRole::kCrown);
  EXPECT_EQ(drawing.strokes[0].width, 0.5);
}

TEST(ReadSketchSvgTest, RealOpenclipartDrawings) {
  // Crown and trunk drawn as solid black areas: 13 closed filled subpaths,
  // all crown outlines by the closed-shape rule (no layers, no colour cue
  // needed). width/height in pt: 180 x 250 pt = 240 x 333.3 px.
  const SketchDrawing bw = ReadSketch(SketchData("openclipart/arbre_modern_bw_jean-vic_01.svg"));
  EXPECT_NEAR(bw.width, 240, 1e-9);
  EXPECT_NEAR(bw.height, 1000.0 / 3, 1e-9);
  EXPECT_EQ(bw.strokes.size(), 13u);
  EXPECT_EQ(bw.CountRole(StrokeRole::kCrown), 13);

  // Outside <defs>: the leafy crown (an open path filled #028700, no
  // stroke), a green ground line (stroke #33b73e, width 2.5), 10 grass
  // <rect>s and the trunk with roots (a closed path filled brown).
  const SketchDrawing roots = ReadSketch(SketchData("openclipart/tree_branches_and_roots_01.svg"));
  EXPECT_NEAR(roots.width, 400 * 4.0 / 3, 1e-9);
  ASSERT_EQ(roots.strokes.size(), 13u);
  EXPECT_EQ(roots.strokes[0].role, StrokeRole::kCrown);  // by its green fill
  EXPECT_FALSE(roots.strokes[0].closed);
  EXPECT_GT(roots.strokes[0].points.size(), 100u);
  EXPECT_EQ(roots.strokes[1].role, StrokeRole::kCrown);  // by its green stroke
  EXPECT_NEAR(roots.strokes[1].width, 2.5, 1e-9);
  for (size_t k = 2; k < 12; ++k) {
    EXPECT_TRUE(roots.strokes[k].closed);
    EXPECT_EQ(roots.strokes[k].points.size(), 4u);
  }
  // The closed-shape rule makes the brown trunk silhouette a "crown" too: a
  // drawing made as clip art needs layers or classes to say otherwise.
  EXPECT_TRUE(roots.strokes[12].closed);
  EXPECT_EQ(roots.strokes[12].role, StrokeRole::kCrown);
}

TEST(ReadSketchSvgTest, BadInputNamesTheFileAndElement) {
  EXPECT_TRUE(Contains(ReadError("empty.svg", ""), "not valid XML"));
  EXPECT_TRUE(Contains(ReadError("a.svg", "<html/>"), "not <svg>"));
  EXPECT_TRUE(
      Contains(ReadError("a.svg", "<svg><path d='M 0 0 L 1 1'/></svg>"), "canvas size is unknown"));
  EXPECT_TRUE(Contains(ReadError("a.svg", "<svg viewBox='0 0 10 10'/>"), "no strokes"));
  EXPECT_TRUE(Contains(ReadError("a.svg",
                                 "<svg viewBox='0 0 10 10'><defs><path d='M0 0 L1 1'/></defs>"
                                 "<text>tree</text></svg>"),
                       "no strokes"));
  const std::string huge = ReadError(
      "a.svg", "<svg viewBox='0 0 10 10'>\n<g>\n<path id='p3' d='M 0 0 L 1e300 5'/></g></svg>");
  EXPECT_TRUE(Contains(huge, "<path id=\"p3\"> on line 3")) << huge;
  EXPECT_TRUE(Contains(huge, "far outside")) << huge;
  const std::string scaled = ReadError(
      "a.svg", "<svg viewBox='0 0 10 10'><g transform='scale(1e200)'><line x2='1'/></g></svg>");
  EXPECT_TRUE(Contains(scaled, "<line> on line 1")) << scaled;
  EXPECT_TRUE(Contains(ReadError("a.svg",
                                 "<svg viewBox='0 0 10 10'><path stroke-width='thick' d='M0 0 "
                                 "L1 1'/></svg>"),
                       "stroke-width"));
  EXPECT_TRUE(Contains(ReadError("a.svg",
                                 "<svg viewBox='0 0 10 10'><g style='stroke-width:-2'><path "
                                 "d='M0 0 L1 1'/></g></svg>"),
                       "<g> on line 1: stroke-width is negative"));
  EXPECT_TRUE(Contains(ReadError("a.svg",
                                 "<svg viewBox='0 0 10 10'><line y2='1' "
                                 "stroke-width='1e300' transform='matrix(1e20 0 0 1 0 "
                                 "0)'/></svg>"),
                       "width overflows"));
  EXPECT_TRUE(Contains(ReadError("a.svg",
                                 "<svg viewBox='0 0 10 10'><path d='M0 0 L1 1'/>"
                                 "<circle id='root'/><circle class='root'/></svg>"),
                       "second root"));
  EXPECT_TRUE(Contains(ReadError("a.svg", "<svg viewBox='0 0 10 10'><path d='M 5 5 L 5 5'/></svg>"),
                       "fewer than two distinct points"));
  EXPECT_TRUE(Contains(ReadError("a.svg", "<svg viewBox='0 0 10 10'><path d='M 5 5 L'/></svg>"),
                       "attribute d"));
}

TEST(ReadSketchTest, UnknownExtensionNamesTheAcceptedOnes) {
  const std::string message = ReadError("tree.txt", "not read");
  EXPECT_TRUE(Contains(message, "'.txt'")) << message;
  EXPECT_TRUE(Contains(message, ".svg")) << message;
  EXPECT_TRUE(Contains(message, ".ndjson")) << message;
  EXPECT_TRUE(Contains(message, ".png")) << message;
  // A corrupt scan is the tracer's InputError naming the file.
  EXPECT_FALSE(ReadError("tree.png", "not a picture").empty());
}

// Random edits of a valid file: each damaged file is read into a drawing
// that passes Check or rejected with an InputError naming it; nothing else.
void ExpectDamagedFilesRejectedCleanly(const std::string& name, const std::string& valid,
                                       const std::string& alphabet, uint64_t seed) {
  RandomEngine random(seed);
  const fs::path path = WriteTestFile(name, valid);
  int read = 0, rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string text = valid;
    for (int edits = 1 + random.UniformInt(2); edits > 0 && !text.empty(); --edits) {
      const size_t at = random.UniformInt(static_cast<uint32_t>(text.size()));
      const uint32_t kind = random.UniformInt(4);
      if (kind < 2) {
        text[at] = alphabet[random.UniformInt(static_cast<uint32_t>(alphabet.size()))];
      } else if (kind < 3) {
        text.erase(at, 1 + random.UniformInt(8));
      } else {
        text.resize(at);
      }
    }
    std::ofstream(path, std::ios::binary) << text;  // faster than an atomic write
    SketchDrawing drawing;
    try {
      drawing = ReadSketch(path);
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), path.string());
      ++rejected;
      continue;
    }
    EXPECT_NO_THROW(drawing.Check()) << text;
    ++read;
  }
  // Both outcomes occur, so the edits neither always break nor never matter.
  EXPECT_GT(read, 10);
  EXPECT_GT(rejected, 10);
}

TEST(ReadSketchSvgTest, DamagedFilesNeverCrash) {
  ExpectDamagedFilesRejectedCleanly("damaged.svg", kLayeredSvg,
                                    "<>/=\"' -+.,e0123456789MmLlHhCcAaZz():;#", 20261202);
}

// ---------------------------------------------------------------- Quick, Draw!

constexpr int kQuickDrawTrees = 15;

TEST(ReadQuickDrawTest, ReadsAStrokeListInCanvasPixels) {
  const fs::path path = WriteTestFile(
      "two.ndjson",
      R"({"word":"tree","drawing":[[[10,10,20],[250,100,100]],[[5],[5]]]})"
      "\n"
      R"({"word":"tree","drawing":[[[0,255,255,0,0],[0,0,120,120,1]],[[120,120],[120,255]]]})"
      "\n");
  const SketchDrawing first = ReadSketch(path, 0);
  EXPECT_EQ(first.source, path.string());
  EXPECT_EQ(first.width, 256);
  EXPECT_EQ(first.height, 256);
  ASSERT_EQ(first.strokes.size(), 1u);  // the dot is skipped
  ExpectPoint(first.strokes[0].points[1], 10, 100);
  EXPECT_EQ(first.strokes[0].role, StrokeRole::kBranch);

  // A closed box on top of a trunk line: the crown outline.
  const SketchDrawing second = ReadSketch(path, 1);
  ASSERT_EQ(second.strokes.size(), 2u);
  EXPECT_EQ(second.strokes[0].role, StrokeRole::kCrown);
  EXPECT_TRUE(second.strokes[0].closed);
  EXPECT_EQ(second.strokes[0].points.size(), 5u);  // (0, 1) is 1 px from the start, not repeated
  EXPECT_EQ(second.strokes[1].role, StrokeRole::kBranch);
}

// The roles the crown rule gives the strokes of each of the 15 real
// doodles: C a closed crown outline, c an open one, b a branch. Checked by eye
// on a rendering of the strokes. Doodle 12 is the tree's silhouette drawn in
// four open strokes (the left side from the ground, two short strokes on
// top, the right side with the crown's lobes down to the ground; no stroke
// encloses 10 % of the drawing): they are joined into one closed outline, in
// that order. Doodle 5 is the whole tree
// in one closed stroke, doodle 6's crown stroke also draws a trunk line: both
// whole strokes become crown outlines.
constexpr const char* kDoodleRoles[kQuickDrawTrees] = {
    "Cbb", "bC", "bc",    "bbbbbbbbbbbC", "bbc", "C",   "bc",  "bbc",
    "bbC", "bc", "bbbCb", "bbbbbbbbbc",   "C",   "bbC", "bbcb"};

TEST(ReadQuickDrawTest, RealTreeDoodles) {
  const fs::path path = SketchData("quickdraw/tree.ndjson");
  int with_crown = 0;
  for (int index = 0; index < kQuickDrawTrees; ++index) {
    const SketchDrawing drawing = ReadSketch(path, index);
    drawing.Check();
    std::string roles;
    for (const SketchStroke& s : drawing.strokes) {
      roles += s.role == StrokeRole::kCrown ? (s.closed ? 'C' : 'c') : 'b';
    }
    EXPECT_EQ(roles, kDoodleRoles[index]) << "doodle " << index;
    with_crown += drawing.CountRole(StrokeRole::kCrown) > 0;
  }
  EXPECT_EQ(with_crown, 15);
}

// An outline drawn in pieces (drawing_io.h): a conifer's two sides, open at
// the apex and along the ground, become one closed crown outline; two trunk
// lines, or pieces too far apart, stay branches.
TEST(ReadQuickDrawTest, AnOutlineInPiecesBecomesOneCrown) {
  const fs::path path = WriteTestFile(
      "pieces.ndjson",
      R"({"word":"tree","drawing":[[[20,120],[250,20]],[[135,220],[25,250]],[[125,126],[3,0]]]})"
      "\n"
      R"({"word":"tree","drawing":[[[100,100],[250,40]],[[112,112],[40,250]]]})"
      "\n"
      R"({"word":"tree","drawing":[[[0,40],[250,10]],[[255,215],[250,10]]]})"
      "\n");
  const SketchDrawing conifer = ReadSketch(path, 0);
  ASSERT_EQ(conifer.strokes.size(), 2u);
  EXPECT_EQ(conifer.strokes[0].role, StrokeRole::kCrown);
  EXPECT_TRUE(conifer.strokes[0].closed);
  // From the lowest end (20, 250) up the left side, then the right side down.
  ASSERT_EQ(conifer.strokes[0].points.size(), 4u);
  ExpectPoint(conifer.strokes[0].points[0], 20, 250);
  ExpectPoint(conifer.strokes[0].points[1], 120, 20);
  ExpectPoint(conifer.strokes[0].points[2], 135, 25);
  ExpectPoint(conifer.strokes[0].points[3], 220, 250);
  EXPECT_EQ(conifer.strokes[1].role, StrokeRole::kBranch);  // the tip, left out of the chain
  ASSERT_EQ(conifer.notes.size(), 1u);
  EXPECT_TRUE(Contains(conifer.notes[0], "2 open strokes")) << conifer.notes[0];
  for (int index : {1, 2}) {  // a trunk's two lines; two sides 175 px apart at the top
    const SketchDrawing drawing = ReadSketch(path, index);
    EXPECT_EQ(drawing.CountRole(StrokeRole::kCrown), 0) << index;
    EXPECT_EQ(drawing.strokes.size(), 2u) << index;
    EXPECT_TRUE(drawing.notes.empty()) << index;
  }
}

TEST(ReadQuickDrawTest, DamagedFilesNeverCrash) {
  const std::string doodle = ReadFileToString(SketchData("quickdraw/tree.ndjson"));
  ExpectDamagedFilesRejectedCleanly("damaged.ndjson", doodle.substr(0, doodle.find('\n') + 1),
                                    "[]{}\":,-.e0123456789 ", 20261203);
}

TEST(ReadQuickDrawTest, BadInputNamesTheFileAndLine) {
  const std::string good = R"({"drawing":[[[10,20],[30,40]]]})";
  EXPECT_TRUE(Contains(ReadError("a.ndjson", good + "\n" + good + "\n", 2), "no drawing 2"));
  EXPECT_TRUE(Contains(ReadError("a.ndjson", good + "\n", -1), "no drawing -1"));
  EXPECT_TRUE(Contains(ReadError("a.ndjson", "", 0), "the file has 0 lines"));
  const std::string truncated =
      ReadError("a.ndjson", good + "\n" + R"({"word":"tree","drawing":[[[10,20],[30)", 1);
  EXPECT_TRUE(Contains(truncated, "line 2: not valid JSON")) << truncated;
  EXPECT_TRUE(Contains(ReadError("a.ndjson", "[1, 2]\n"), "line 1"));
  EXPECT_TRUE(Contains(ReadError("a.ndjson", R"({"word":"tree"})"), "line 1"));
  EXPECT_TRUE(
      Contains(ReadError("a.ndjson", R"({"drawing":[[[10,20,30],[30,40]]]})"), "3 x but 2 y"));
  EXPECT_TRUE(Contains(ReadError("a.ndjson", R"({"drawing":[[[10,20],[30,"40"]]]})"), "line 1"));
  const std::string huge = ReadError("a.ndjson", R"({"drawing":[[[10,1e300],[30,40]]]})");
  EXPECT_TRUE(Contains(huge, "outside 0-255")) << huge;
  EXPECT_TRUE(Contains(ReadError("a.ndjson", R"({"drawing":[[[10,1e999],[30,40]]]})"), "line 1"));
  EXPECT_TRUE(
      Contains(ReadError("a.ndjson", R"({"drawing":[[[5],[5]], [[7,7],[8,8]]]})"), "no strokes"));
  EXPECT_TRUE(Contains(ReadError("a.ndjson", R"({"drawing":[]})"), "no strokes"));
  EXPECT_TRUE(Contains(ReadError(SketchData("quickdraw/tree.ndjson"), kQuickDrawTrees),
                       "the file has 15 lines"));
}

}  // namespace
}  // namespace sylva

namespace sylva {
namespace {

// ReadSketch traces a scanned drawing.
TEST(ReadSketchTest, ScansAreTraced) {
  const SketchDrawing maple = ReadSketch(SketchData("treesketchnet/2_camera_right.png"));
  EXPECT_NO_THROW(maple.Check());
  EXPECT_GE(maple.CountRole(StrokeRole::kCrown), 1);
  EXPECT_GE(maple.CountRole(StrokeRole::kBranch), 20);
}

}  // namespace
}  // namespace sylva
