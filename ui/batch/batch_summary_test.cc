#include "ui/batch/batch_summary.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>

#include "core/io/json_util.h"
#include "core/util/file_util.h"
#include "ui/batch/csv.h"

namespace sylva {
namespace {

// A batch folder written in code: one finished tree with a report and
// metrics, one that failed in its density stage, one never run.
class BatchSummaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (fs::temp_directory_path() / "sylva_summary_XXXXXX").string();
    ASSERT_NE(mkdtemp(templ.data()), nullptr);
    root_ = templ;
    out_ = root_ / "out";
    for (const char* name : {"oak", "elm", "ash"}) fs::create_directories(root_ / name);
    std::ofstream(root_ / "cameras.json") << "{}";
    manifest_ = ParseManifest(
        "name,photos,cameras\noak,oak,cameras.json\nelm,elm,cameras.json\nash,ash,cameras.json\n",
        root_ / "manifest.csv");
    WriteFinishedTree();
    TreeStatus failed;
    failed.name = "elm";
    failed.status = "failed";
    failed.stage = "density";
    failed.error = "elm/mattes/a.png: empty matte";
    failed.exit_code = 2;
    WriteTreeStatus(TreeStatusPath(out_, "elm"), failed);
    WriteJsonFile(out_ / "elm" / "cache" / "stages.json", {{"register", {{"seconds", 0.5}}}});
  }
  void TearDown() override { fs::remove_all(root_); }

  void WriteFinishedTree() {
    TreeStatus ok;
    ok.name = "oak";
    ok.status = "ok";
    ok.exit_code = 0;
    ok.seconds = 12.5;
    WriteTreeStatus(TreeStatusPath(out_, "oak"), ok);
    const fs::path project = out_ / "oak";
    std::ofstream(project / "sylva.json") << "{}";
    WriteJsonFile(project / "cache" / "stages.json",
                  {{"register", {{"seconds", 1.0}}}, {"density", {{"seconds", 4.0}}}});
    const Json group = {{"num_views", 2}, {"mean_iou", 0.9}, {"min_iou", 0.85}};
    const Json empty = {{"num_views", 0}, {"mean_iou", nullptr}, {"min_iou", nullptr}};
    WriteJsonFile(
        project / "out" / "report.json",
        {{"input_views", group},
         {"held_out_views", empty},
         {"views", {{{"iou", 0.95}, {"held_out", false}}, {{"iou", 0.85}, {"held_out", false}}}},
         {"warnings", {{{"code", "thin-structure"}, {"message", "m"}}}},
         {"previews", {"report/preview_0.png"}}});
    WriteJsonFile(project / "out" / "metrics.json", {{"units", "m"},
                                                     {"height", 7.5},
                                                     {"crown_width", 3.25},
                                                     {"crown_volume_hull", 20.0},
                                                     {"crown_volume_density", nullptr},
                                                     {"dbh", 0.25},
                                                     {"num_tips", 40},
                                                     {"orders",
                                                      {{{"order", 0}, {"num_branches", 1}},
                                                       {{"order", 1}, {"num_branches", 6}},
                                                       {{"order", 2}, {"num_branches", 9}}}}});
    fs::create_directories(project / "out" / "report");
    for (const char* file : {"report/preview_0.png", "tree.glb", "report.html"}) {
      std::ofstream(project / "out" / file) << "x";
    }
  }

  // summary.csv as column -> value, per row.
  std::vector<std::map<std::string, std::string>> ReadSummary() {
    const std::vector<CsvRecord> records =
        ParseCsv(ReadFileToString(out_ / "summary.csv"), "summary.csv");
    std::vector<std::map<std::string, std::string>> rows;
    for (size_t r = 1; r < records.size(); ++r) {
      EXPECT_EQ(records[r].fields.size(), records[0].fields.size());
      std::map<std::string, std::string> row;
      for (size_t c = 0; c < records[0].fields.size(); ++c) {
        row[records[0].fields[c]] = records[r].fields[c];
      }
      rows.push_back(row);
    }
    return rows;
  }

  fs::path root_, out_;
  Manifest manifest_;
};

TEST_F(BatchSummaryTest, OneRowPerTreeWithWhatItsRunLeft) {
  WriteBatchSummary(manifest_, out_);
  const auto rows = ReadSummary();
  ASSERT_EQ(rows.size(), 3u);
  const auto& oak = rows[0];
  EXPECT_EQ(oak.at("name"), "oak");
  EXPECT_EQ(oak.at("status"), "ok");
  EXPECT_EQ(oak.at("stage"), "");
  EXPECT_EQ(oak.at("seconds"), "12.5");
  EXPECT_EQ(oak.at("seconds_density"), "4");
  EXPECT_EQ(oak.at("seconds_mesh"), "");
  EXPECT_EQ(oak.at("input_views"), "2");
  EXPECT_EQ(oak.at("input_mean_iou"), "0.9");
  EXPECT_EQ(oak.at("input_min_iou"), "0.85");
  EXPECT_EQ(oak.at("held_out_views"), "0");
  EXPECT_EQ(oak.at("held_out_mean_iou"), "");  // no views, no score
  EXPECT_EQ(oak.at("height"), "7.5");
  EXPECT_EQ(oak.at("crown_width"), "3.25");
  EXPECT_EQ(oak.at("crown_volume_density"), "");
  EXPECT_EQ(oak.at("dbh"), "0.25");
  EXPECT_EQ(oak.at("branches"), "15");
  EXPECT_EQ(oak.at("tips"), "40");
  EXPECT_EQ(oak.at("warnings"), "thin-structure");
  EXPECT_EQ(oak.at("tree_glb"), "oak/out/tree.glb");
  EXPECT_EQ(oak.at("tree_obj"), "");
  EXPECT_EQ(oak.at("preview"), "oak/out/report/preview_0.png");
  EXPECT_EQ(oak.at("log"), "logs/oak.log");

  const auto& elm = rows[1];
  EXPECT_EQ(elm.at("status"), "failed");
  EXPECT_EQ(elm.at("stage"), "density");
  EXPECT_EQ(elm.at("error"), "elm/mattes/a.png: empty matte");
  EXPECT_EQ(elm.at("exit_code"), "2");
  EXPECT_EQ(elm.at("seconds_register"), "0.5");
  EXPECT_EQ(elm.at("input_mean_iou"), "");
  EXPECT_EQ(elm.at("project"), "");

  EXPECT_EQ(rows[2].at("status"), "not-run");

  const std::string html = ReadFileToString(out_ / "summary.html");
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));  // nothing fetched
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("src='oak/out/report/preview_0.png'"), std::string::npos);
  EXPECT_NE(html.find("elm/mattes/a.png: empty matte"), std::string::npos);
  EXPECT_NE(html.find("1 failed"), std::string::npos);
  EXPECT_NE(html.find("1 not-run"), std::string::npos);
}

}  // namespace
}  // namespace sylva
