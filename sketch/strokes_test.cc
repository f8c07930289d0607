#include "sketch/strokes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "core/util/check.h"
#include "core/util/file_util.h"
#include "core/util/random.h"
#include "sketch/stroke_graph.h"

namespace sylva {
namespace {

fs::path WriteTestFile(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "sylva_strokes_test";
  fs::create_directories(dir);
  AtomicWriteString(dir / name, text);
  return dir / name;
}

void ExpectPoint(const Eigen::Vector2d& actual, double x, double y) {
  EXPECT_NEAR(actual.x(), x, 1e-9) << actual.transpose();
  EXPECT_NEAR(actual.y(), y, 1e-9) << actual.transpose();
}

// The error of reading `text` as `name`, checked to name the file.
std::string ReadError(const std::string& name, const std::string& text) {
  const fs::path path = WriteTestFile(name, text);
  try {
    ReadStrokes(path, 1440, 1080);
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), path.string()) << error.what();
    return error.message();
  }
  ADD_FAILURE() << "no InputError for " << text;
  return "";
}

TEST(StrokesSvgTest, ViewBoxTransformsAndSkippedElements) {
  // A 144 x 108 viewBox on a 1440 x 1080 photo: x10.
  const fs::path path = WriteTestFile("IMG_0001.jpg.strokes.svg", R"svg(<?xml version="1.0"?>
<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
     xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
     width="144mm" height="108mm" viewBox="0 0 144 108">
  <defs><path id="ignored" d="M 0 0 L 1 1"/></defs>
  <image xlink:href="IMG_0001.jpg" width="144" height="108"/>
  <text x="3" y="3">trunk</text>
  <g inkscape:groupmode="layer" id="layer1" transform="translate(1, 2)">
    <path d="M 70 100 L 70 60"/>
    <g transform="scale(2)"><polyline points="35,30 25,20 20,10"/></g>
    <circle class="marker root" cx="69" cy="101" r="1"/>
    <circle cx="5" cy="5" r="1"/>
  </g>
  <g style="display: none"><path d="M 0 0 L 100 100"/></g>
  <path display="none" d="M 0 0 L 100 100"/>
  <line x1="10" y1="10" x2="20" y2="15" transform="rotate(90)"/>
  <polygon points="0,0 10,0 10,10"/>
</svg>
)svg");
  const StrokeSet set = ReadStrokes(path, 1440, 1080);
  EXPECT_EQ(set.width, 1440);
  EXPECT_EQ(set.height, 1080);
  ASSERT_EQ(set.strokes.size(), 4u);
  ASSERT_EQ(set.strokes[0].points.size(), 2u);
  ExpectPoint(set.strokes[0].points[0], 710, 1020);
  ExpectPoint(set.strokes[0].points[1], 710, 620);
  ASSERT_EQ(set.strokes[1].points.size(), 3u);
  ExpectPoint(set.strokes[1].points[0], 710, 620);  // (1 + 2*35, 2 + 2*30) * 10
  ExpectPoint(set.strokes[1].points[2], 410, 220);
  ExpectPoint(set.strokes[2].points[0], -100, 100);  // rotate(90): (x, y) -> (-y, x)
  ExpectPoint(set.strokes[2].points[1], -150, 200);
  ASSERT_EQ(set.strokes[3].points.size(), 4u);  // the polygon closes
  ExpectPoint(set.strokes[3].points[3], 0, 0);
  ASSERT_TRUE(set.root.has_value());
  ExpectPoint(*set.root, 700, 1030);
}

TEST(StrokesSvgTest, SizeWithoutViewBoxAndNeither) {
  // 381 mm = 1440 px of user space mapped onto a 720 px photo: x0.5.
  const fs::path mm = WriteTestFile("mm.svg", R"(<svg width="381mm" height="285.75mm">
    <path id="root" d="M 100 200 l 40 0"/></svg>)");
  const StrokeSet half = ReadStrokesSvg(mm, 720, 540);
  ExpectPoint(half.strokes[0].points[0], 50, 100);
  ExpectPoint(half.strokes[0].points[1], 70, 100);
  EXPECT_FALSE(half.root.has_value());  // only a <circle> gives the root
  const fs::path plain = WriteTestFile("plain.svg", R"(<svg width="100%" height="100%">
    <path d="M 100 200 h 40"/><circle id="root" cx="1" cy="2" r="3"/></svg>)");
  const StrokeSet same = ReadStrokesSvg(plain, 720, 540);
  ExpectPoint(same.strokes[0].points[1], 140, 200);
  ExpectPoint(*same.root, 1, 2);
}

TEST(StrokesSvgTest, CurvesAreFlattenedInPhotoPixels) {
  // A quarter circle of radius 10 user units, x20: every point within a
  // quarter pixel of the radius-200 circle in photo pixels.
  const fs::path path = WriteTestFile("arc.svg", R"(<svg viewBox="0 0 72 54">
    <path d="M 10 0 A 10 10 0 0 1 0 10"/></svg>)");
  const StrokeSet set = ReadStrokesSvg(path, 1440, 1080);
  const std::vector<Eigen::Vector2d>& points = set.strokes[0].points;
  double worst = 0;  // the largest gap between a chord and the circle
  for (size_t k = 0; k < points.size(); ++k) {
    EXPECT_NEAR(points[k].norm(), 200, 1e-9);
    if (k > 0) worst = std::max(worst, 200 - ((points[k] + points[k - 1]) / 2).norm());
  }
  EXPECT_LE(worst, 0.25);
  EXPECT_GE(worst, 0.15) << "more points than the tolerance needs: " << points.size();
}

TEST(StrokesJsonTest, ScalesOntoThePhoto) {
  const fs::path path = WriteTestFile("IMG_0002.jpg.strokes.json", R"({
    "format": "sylva-strokes", "version": 1, "width": 720, "height": 540,
    "strokes": [[[360, 530], [360, 300]], [[360, 300], [360, 300], [250, 100.5]]],
    "root": [360, 535]})");
  const StrokeSet set = ReadStrokes(path, 1440, 1080);
  ASSERT_EQ(set.strokes.size(), 2u);
  ExpectPoint(set.strokes[0].points[0], 720, 1060);
  ASSERT_EQ(set.strokes[1].points.size(), 2u);  // the repeated point is merged
  ExpectPoint(set.strokes[1].points[1], 500, 201);
  ExpectPoint(*set.root, 720, 1070);
}

TEST(StrokesTest, MalformedSvgFilesNameTheFileAndTheProblem) {
  EXPECT_NE(ReadError("a.svg", "<svg><path d='M 0 0 L 1 1'></svg>").find("not valid XML"),
            std::string::npos);
  EXPECT_NE(ReadError("a.svg", "plain text").find("not valid XML"), std::string::npos);
  EXPECT_NE(ReadError("a.svg", "<html><path d='M 0 0 L 1 1'/></html>").find("not <svg>"),
            std::string::npos);
  const std::string bad_path =
      ReadError("a.svg", "<svg>\n<g>\n<path id='p7' d='M 0 0 L 1'/></g></svg>");
  EXPECT_NE(bad_path.find("<path id=\"p7\"> on line 3: attribute d: expected a number"),
            std::string::npos)
      << bad_path;
  EXPECT_NE(ReadError("a.svg", "<svg><path d='M 0 0 L 1 1e999'/></svg>").find("out of range"),
            std::string::npos);
  EXPECT_NE(ReadError("a.svg", "<svg><g transform='scale(x)'><path d='M0 0 L1 1'/></g></svg>")
                .find("<g> on line 1: attribute transform"),
            std::string::npos);
  EXPECT_NE(ReadError("a.svg", "<svg><polyline points='1 2 3'/></svg>").find("odd number"),
            std::string::npos);
  EXPECT_NE(ReadError("a.svg", "<svg><line x1='1em' x2='3'/></svg>").find("attribute x1"),
            std::string::npos);
  EXPECT_NE(ReadError("a.svg", "<svg><path d='M 5 5 L 5 5'/></svg>")
                .find("subpath 1 has fewer than two distinct points"),
            std::string::npos);
  EXPECT_NE(
      ReadError("a.svg", "<svg><defs><path d='M 5 5 L 6 6'/></defs></svg>").find("no strokes"),
      std::string::npos);
  EXPECT_NE(ReadError("a.svg", "<svg><path id='far' d='M 0 0 L 3000 0'/></svg>")
                .find("<path id=\"far\"> on line 1: subpath 1 reaches (3000.000000, 0.000000), "
                      "far outside the photo"),
            std::string::npos);
  EXPECT_NE(
      ReadError("a.svg", "<svg viewBox='0 0 0 10'><path d='M0 0 L1 1'/></svg>").find("viewBox"),
      std::string::npos);
  EXPECT_NE(ReadError("a.svg",
                      "<svg><path d='M0 0 L1 1'/><circle id='root'/><circle class='root'/></svg>")
                .find("a second root circle"),
            std::string::npos);
}

TEST(StrokesTest, MalformedJsonFilesNameTheFileAndTheLocation) {
  const std::string head =
      R"({"format": "sylva-strokes", "version": 1, "width": 10, "height": 10, )";
  EXPECT_NE(ReadError("a.json", R"({"format": "sylva-strokes",)").find("invalid JSON"),
            std::string::npos);
  EXPECT_NE(ReadError("a.json", R"({"format": "sylva-attractor-graph", "version": 1})")
                .find("at /format"),
            std::string::npos);
  EXPECT_NE(ReadError("a.json", R"({"format": "sylva-strokes", "version": 3})")
                .find("unsupported version 3"),
            std::string::npos);
  EXPECT_NE(ReadError("a.json", R"({"format": "sylva-strokes", "version": 1, "height": 10})")
                .find("missing key 'width'"),
            std::string::npos);
  EXPECT_NE(ReadError("a.json", head + R"("strokes": []})").find("at /strokes: no strokes"),
            std::string::npos);
  EXPECT_NE(ReadError("a.json", head + R"("strokes": [[[1, 2], [3, 4]], [[1, 1], [1, 1]]]})")
                .find("at /strokes/1: a stroke needs at least two distinct points"),
            std::string::npos);
  EXPECT_NE(ReadError("a.json", head + R"("strokes": [[[1, 2], [3, "4"]]]})")
                .find("at /strokes/0/1/1: expected a number"),
            std::string::npos);
  EXPECT_NE(
      ReadError("a.json", head + R"("strokes": [[[1, 2], [3, 1e400]]]})").find("number overflow"),
      std::string::npos);
  EXPECT_NE(ReadError("a.json", head + R"("strokes": [[[1, 2], [21, 4]]]})")
                .find("stroke 0 point 1 (3024, 432) is not finite or lies far outside"),
            std::string::npos);
  EXPECT_NE(ReadError("a.json", head + R"("strokes": [[[1, 2], [3, 4]]], "root": [1]})")
                .find("at /root: expected 2 numbers"),
            std::string::npos);
  EXPECT_NE(ReadError("a.json", R"({"format": "sylva-strokes", "version": 1, "width": -5})")
                .find("at /width: must be positive"),
            std::string::npos);
}

TEST(StrokesTest, ChoosesTheReaderByExtension) {
  const fs::path upper = WriteTestFile("b.SVG", "<svg><line x2='5'/></svg>");
  EXPECT_EQ(ReadStrokes(upper, 10, 10).strokes.size(), 1u);
  EXPECT_NE(ReadError("b.txt", "M 0 0 L 1 1").find("unknown stroke file type '.txt'"),
            std::string::npos);
  EXPECT_THROW(ReadStrokes(fs::temp_directory_path() / "sylva_no_such.svg", 10, 10), InputError);
}

TEST(StrokesTest, CheckRejectsBadSetsBuiltInCode) {
  StrokeSet set;
  set.width = 10;
  set.height = 10;
  EXPECT_THROW(set.Check("test"), InputError);  // no strokes
  set.strokes.push_back({{{0, 0}, {1, 1}}});
  set.Check("test");
  set.strokes.push_back({{{0, 0}}});
  EXPECT_THROW(set.Check("test"), InputError);
  set.strokes.back().points.push_back({0, std::nan("")});
  EXPECT_THROW(set.Check("test"), InputError);
}

// Randomly damaged files (fixed seed): every read either succeeds or throws
// InputError, and every set that reads becomes a valid graph.
TEST(StrokesTest, DamagedFilesNeverCrash) {
  const std::string svg =
      R"svg(<svg viewBox="0 0 144 108"><g transform="rotate(5 70 50) scale(1.5)">
<path d="M 70 100 C 72 90 68 70 70 60 s 10 -5 20 -20 Q 60 40 50 30 t -10 -10 A 5 8 30 1 0 40 20 Z"/>
<polyline points="70,60 60,50 55,40"/><line x1="70" y1="60" x2="80" y2="45"/>
<circle id="root" cx="70" cy="100" r="2"/></g></svg>)svg";
  const std::string json = R"({"format": "sylva-strokes", "version": 1, "width": 144,
"height": 108, "strokes": [[[70, 100], [70, 60]], [[70, 60], [50, 30], [45, 20]]], "root": [70, 101]})";
  const std::string alphabet = "<>/=\"' -+.,e0123456789MmLlHhCcSsQqTtAaZz()[]{}:";
  RandomEngine random(20240611);
  const fs::path dir = WriteTestFile("damaged.svg", svg).parent_path();
  int read = 0, rejected = 0;
  for (int trial = 0; trial < 600; ++trial) {
    std::string text = trial % 2 == 0 ? svg : json;
    for (int edits = 1 + random.UniformInt(2); edits > 0 && !text.empty(); --edits) {
      const size_t at = random.UniformInt(static_cast<uint32_t>(text.size()));
      const uint32_t kind = random.UniformInt(8);
      if (kind < 4) {
        text[at] = alphabet[random.UniformInt(static_cast<uint32_t>(alphabet.size()))];
      } else if (kind < 6) {
        text.erase(at, 1 + random.UniformInt(8));
      } else if (kind < 7) {
        text.insert(at, text.substr(random.UniformInt(static_cast<uint32_t>(text.size())), 6));
      } else {
        text.resize(at);
      }
    }
    const fs::path path = fs::path(dir) / (trial % 2 == 0 ? "damaged.svg" : "damaged.json");
    std::ofstream(path, std::ios::binary) << text;  // faster than an atomic write
    StrokeSet set;
    try {
      set = ReadStrokes(path, 1440, 1080);
    } catch (const InputError& error) {
      EXPECT_EQ(error.source(), path.string());
      ++rejected;
      continue;
    }
    ++read;
    const AttractorGraph2D graph = GraphFromStrokes(set, StrokeGraphOptions());
    EXPECT_NO_THROW(graph.Check("damaged")) << text;
  }
  EXPECT_GT(read, 30);      // the damage leaves many files readable...
  EXPECT_GT(rejected, 50);  // ...and breaks many
}

}  // namespace
}  // namespace sylva
