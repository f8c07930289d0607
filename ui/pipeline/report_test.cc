#include "ui/pipeline/report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/util/file_util.h"
#include "datasets/synthetic/synthetic_dataset.h"

namespace sylva {
namespace {

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A small synthetic set (48-pixel views) and a density filling the tree's
// bounding box: the scores are real, their values do not matter here.
struct Fixture {
  SyntheticDataset data;
  DensityGrid grid{0.25, Eigen::Vector3d::Zero()};

  explicit Fixture(int num_held_out) {
    SyntheticDatasetOptions options;
    options.num_views = 3;
    options.num_held_out = num_held_out;
    options.image_size = 48;
    options.samples_per_axis = 1;
    data = MakeSyntheticDataset(options);
    const Box3d bounds = data.tree.mesh.Bounds();
    const Eigen::Vector3i lo = grid.IndexFromWorld(bounds.min()).array().round().cast<int>();
    const Eigen::Vector3i hi = grid.IndexFromWorld(bounds.max()).array().round().cast<int>();
    for (int k = lo.z(); k <= hi.z(); ++k) {
      for (int j = lo.y(); j <= hi.y(); ++j) {
        for (int i = lo.x(); i <= hi.x(); ++i) grid.SetValue({i, j, k}, 0.3f);
      }
    }
  }

  FidelityReport Report() const {
    ReportOptions options;
    FidelityReport report =
        ComputeFidelity(grid, data.image_set, data.mattes, data.HeldOutFlags(), options);
    report.units = "m";
    return report;
  }
};

fs::path TestDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "sylva_report_test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(ReportTest, NoHeldOutViewsMeansNoHeldOutFiguresNotZeros) {
  const Fixture fixture(0);
  const FidelityReport report = fixture.Report();
  EXPECT_EQ(report.input.num_views, 3);
  ASSERT_TRUE(report.input.mean_iou.has_value());
  EXPECT_GT(*report.input.mean_iou, 0.0);
  EXPECT_EQ(report.held_out.num_views, 0);
  EXPECT_FALSE(report.held_out.mean_iou || report.held_out.min_iou ||
               report.held_out.mean_precision || report.held_out.mean_recall);
  const std::string brief = report.BriefReport();
  EXPECT_FALSE(Contains(brief, "held-out views (")) << brief;
  EXPECT_TRUE(Contains(brief, "no held-out views")) << brief;

  const fs::path out = TestDir("no_held_out");
  ReportOptions options;
  WriteFidelityReport(report, {}, options, out);
  const nlohmann::json json = nlohmann::json::parse(ReadFileToString(out / "report.json"));
  EXPECT_EQ(json["held_out_views"]["num_views"], 0);
  for (const char* key : {"mean_iou", "min_iou", "mean_precision", "mean_recall"}) {
    EXPECT_TRUE(json["held_out_views"][key].is_null()) << key;
    EXPECT_TRUE(json["input_views"][key].is_number()) << key;
  }
  const std::string html = ReadFileToString(out / "report.html");
  EXPECT_FALSE(Contains(html, "held-out views (0)")) << html;
}

FidelityGroup Group(int views, double iou, double precision, double recall) {
  FidelityGroup group;
  group.num_views = views;
  group.mean_iou = group.min_iou = iou;
  group.mean_precision = precision;
  group.mean_recall = recall;
  return group;
}

TEST(ReportTest, PoorFitsAreNamedWithWhatTheSilhouettesDoWrong) {
  FidelityReport report;
  const ReportOptions options;
  EXPECT_TRUE(FidelityWarnings(report, options).empty());  // no views (a tree made without photos)
  // ROMI's figures: the density misses most of the thin siliques.
  report.input = Group(22, 0.422, 0.909, 0.441);
  report.mesh_input = Group(22, 0.85, 0.9, 0.9);
  std::vector<Warning> warnings = FidelityWarnings(report, options);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].code, "poor-density-fit");
  EXPECT_TRUE(warnings[0].subject.empty());
  EXPECT_TRUE(Contains(warnings[0].message,
                       "mean IoU 0.422 over 22 input views (precision 0.909, "
                       "recall 0.441): it lacks structure"))
      << warnings[0].message;
  // A tree larger than the mattes, and a density just above the threshold.
  report.input = Group(8, options.poor_fit_iou + 0.01, 0.9, 0.9);
  report.mesh_input = Group(8, 0.3, 0.31, 0.95);
  warnings = FidelityWarnings(report, options);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].code, "poor-mesh-fit");
  EXPECT_TRUE(Contains(warnings[0].message, "the tree is larger than the mattes show"))
      << warnings[0].message;
  // From real scores: a density filling the tree's bounding box covers far
  // more than the mattes.
  const FidelityReport box = Fixture(0).Report();
  ASSERT_LT(*box.input.mean_iou, options.poor_fit_iou);
  warnings = FidelityWarnings(box, options);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(Contains(warnings[0].message, "it covers more than the mattes show"))
      << warnings[0].message;
  // Report.poor_fit_iou = 0 turns them off.
  ReportOptions never;
  never.poor_fit_iou = 0.0;
  EXPECT_TRUE(FidelityWarnings(box, never).empty());
}

TEST(ReportTest, PriorViewsAreShownButNotInTheFigures) {
  const Fixture fixture(0);
  FidelityReport report = fixture.Report();
  const std::string prior = report.views[1].name;
  MarkPriorViews({prior}, &report);
  ASSERT_TRUE(report.views[1].prior);
  EXPECT_EQ(report.NumPriorViews(), 1);
  EXPECT_EQ(report.input.num_views, 2);
  EXPECT_NEAR(*report.input.mean_iou, (report.views[0].scores.iou + report.views[2].scores.iou) / 2,
              1e-12);
  EXPECT_TRUE(Contains(report.BriefReport(), "1 prior view(s)")) << report.BriefReport();

  const fs::path out = TestDir("prior");
  WriteFidelityReport(report, {}, ReportOptions(), out);
  const nlohmann::json json = nlohmann::json::parse(ReadFileToString(out / "report.json"));
  EXPECT_EQ(json["prior_views"], 1);
  EXPECT_EQ(json["input_views"]["num_views"], 2);
  EXPECT_EQ(json["views"][1]["prior"], true);
  EXPECT_FALSE(json["views"][0].contains("prior"));
  EXPECT_TRUE(Contains(ReadFileToString(out / "report.html"), "prior (not a photo)"));
}

TEST(ReportTest, HeldOutFiguresAreTheHeldOutViewsOwn) {
  const Fixture fixture(1);
  const FidelityReport report = fixture.Report();
  ASSERT_EQ(report.held_out.num_views, 1);
  const ViewFidelity& held_out = report.views.back();
  ASSERT_TRUE(held_out.held_out);
  ASSERT_TRUE(report.held_out.mean_iou && report.held_out.min_iou);
  EXPECT_EQ(*report.held_out.mean_iou, held_out.scores.iou);
  EXPECT_EQ(*report.held_out.min_iou, held_out.scores.iou);
  double mean = 0.0, lowest = 1.0;
  for (int v = 0; v < 3; ++v) {
    mean += report.views[v].scores.iou / 3;
    lowest = std::min(lowest, report.views[v].scores.iou);
  }
  EXPECT_NEAR(*report.input.mean_iou, mean, 1e-12);
  EXPECT_EQ(*report.input.min_iou, lowest);
  EXPECT_TRUE(Contains(report.BriefReport(), "density, held-out views (1)"));
  // No mesh compared: no mesh groups.
  EXPECT_EQ(report.mesh_input.num_views, 0);
  EXPECT_FALSE(report.mesh_input.mean_iou.has_value());
}

TEST(ReportTest, TreeFiguresAreMetricsJsonsWithTheirSources) {
  // The mesh stage's metrics.json, read back as the report stage does.
  const Fixture fixture(0);
  const fs::path out = TestDir("tree");
  SkeletonGraph skeleton = fixture.data.tree.skeleton;
  skeleton.radius_source = "allometric prior";
  WriteTreeMetricsJson(out / "metrics.json",
                       ComputeTreeMetrics(skeleton, &fixture.grid, "m", TreeMetricsOptions(),
                                          SkeletonSources::Reconstruction()));
  FidelityReport report = fixture.Report();
  report.metrics = ReadTreeMetricsJson(out / "metrics.json");
  report.has_metrics = true;
  const std::string brief = report.BriefReport();
  EXPECT_TRUE(Contains(brief, "(measured); DBH")) << brief;
  EXPECT_TRUE(Contains(brief, "(allometric prior)")) << brief;
  EXPECT_TRUE(Contains(brief, "(prior).")) << brief;

  ReportOptions options;
  options.write_images = true;
  WriteFidelityReport(report, {}, options, out);
  const nlohmann::json json = nlohmann::json::parse(ReadFileToString(out / "report.json"));
  const nlohmann::json metrics = nlohmann::json::parse(ReadFileToString(out / "metrics.json"));
  EXPECT_EQ(json["version"], 3);
  EXPECT_EQ(json["tree"], metrics);  // the same figures, not a second definition
  const std::string html = ReadFileToString(out / "report.html");
  EXPECT_TRUE(Contains(
      html, "<td>height</td><td>" +
                [&] {
                  std::ostringstream text;
                  text << std::setprecision(4) << report.metrics.height << " m";
                  return text.str();
                }() +
                "</td><td>measured</td>"))
      << html;
  EXPECT_TRUE(Contains(html, "<td>allometric prior</td>")) << html;
  EXPECT_TRUE(Contains(html, "<td>order 1</td>")) << html;
  // One table of tree figures: no second height from the mesh.
  EXPECT_EQ(html.find("<td>height</td>"), html.rfind("<td>height</td>"));
}

TEST(ReportTest, StagesFiguresAreWrittenAsGiven) {
  const Fixture fixture(0);
  FidelityReport report = fixture.Report();
  report.stage_figures = {{"register", {{"registered", 3, "photos"}}},
                          {"density", {{"views", 3, "views"}, {"voxel_size", 0.25, "m"}}}};
  const fs::path out = TestDir("stage_figures");
  ReportOptions options;
  WriteFidelityReport(report, {}, options, out);
  const nlohmann::json json = nlohmann::json::parse(ReadFileToString(out / "report.json"));
  const nlohmann::json& density = json.at("stage_figures").at("density");
  ASSERT_EQ(density.size(), 2u);
  EXPECT_EQ(density[1]["key"], "voxel_size");
  EXPECT_EQ(density[1]["value"], 0.25);
  EXPECT_EQ(density[1]["unit"], "m");
  EXPECT_EQ(json["stage_figures"]["register"][0]["value"], 3);
  const std::string html = ReadFileToString(out / "report.html");
  EXPECT_TRUE(Contains(html, "<tr><td>density</td><td>views=3 views, voxel_size=0.25 m</td></tr>"))
      << html;
}

}  // namespace
}  // namespace sylva
