#include "core/io/qsm_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "core/util/check.h"
#include "core/util/file_util.h"

namespace sylva {
namespace {

const fs::path kItsmeDir = fs::path(SYLVA_SOURCE_DIR) / "datasets" / "itsme-qsm";

fs::path TestDir() {
  const fs::path dir = fs::temp_directory_path() / "sylva_qsm_io_test";
  fs::create_directories(dir);
  return dir;
}

double RelativeError(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() / std::max(a.norm(), 1e-300);
}
double RelativeError(double a, double b) { return std::abs(a - b) / std::abs(a); }

// Largest relative error of start, axis, length and radius over matching ids;
// fails if ids, parents, branches or orders differ.
double MaxRelativeError(const QsmModel& expected, const QsmModel& actual) {
  EXPECT_EQ(expected.cylinders.size(), actual.cylinders.size());
  double error = 0.0;
  for (size_t i = 0; i < std::min(expected.cylinders.size(), actual.cylinders.size()); ++i) {
    const QsmCylinder& e = expected.cylinders[i];
    const QsmCylinder& a = actual.cylinders[i];
    EXPECT_EQ(e.id, a.id);
    EXPECT_EQ(e.parent_id, a.parent_id) << "cylinder " << e.id;
    EXPECT_EQ(e.branch, a.branch) << "cylinder " << e.id;
    EXPECT_EQ(e.branch_order, a.branch_order) << "cylinder " << e.id;
    error = std::max({error, RelativeError(e.start, a.start), RelativeError(e.axis, a.axis),
                      RelativeError(e.length, a.length), RelativeError(e.radius, a.radius)});
  }
  return error;
}

QsmModel RoundTrip(const QsmModel& qsm, const std::string& name) {
  const fs::path path = TestDir() / name;
  WriteQsmCsv(path, QsmFromSkeletons(SkeletonsFromQsm(qsm), qsm.units));
  return ReadQsmCsv(path);
}

TEST(QsmIoTest, ItsmeTree1SurvivesTheSkeletonRoundTrip) {
  const QsmModel original = ReadQsmCsv(kItsmeDir / "tree_1_qsm.csv");
  ASSERT_EQ(original.cylinders.size(), 66u);
  EXPECT_EQ(original.units, "m");
  const std::vector<QsmSkeleton> parts = SkeletonsFromQsm(original);
  ASSERT_EQ(parts.size(), 1u);
  parts[0].skeleton.Check();
  // Every TreeQSM child starts a few mm off its parent's end: the root and a
  // connector per child have no cylinder id.
  const std::vector<int64_t>& ids = parts[0].cylinder_ids;
  EXPECT_EQ(std::count(ids.begin(), ids.end(), 0), 1 + 65);
  EXPECT_GE(parts[0].skeleton.NumNodes(), 1 + 66 + 65);
  EXPECT_LT(MaxRelativeError(original, RoundTrip(original, "tree_1.csv")), 1e-10);
}

// Total length of the cylinders of `qsm` lying on cylinder `c` (same axis and
// radius, start on c's segment).
double LengthOnCylinder(const QsmCylinder& c, const QsmModel& qsm) {
  double length = 0.0;
  for (const QsmCylinder& b : qsm.cylinders) {
    const Eigen::Vector3d offset = b.start - c.start;
    const double along = offset.dot(c.axis);
    if (RelativeError(c.axis, b.axis) < 1e-6 && RelativeError(c.radius, b.radius) < 1e-9 &&
        (offset - along * c.axis).norm() < 1e-9 * c.start.norm() && along > -1e-9 &&
        along < c.length) {
      length += b.length;
    }
  }
  return length;
}

TEST(QsmIoTest, ItsmeTree1KeepsItsGeometryThroughAPlainSkeleton) {
  // Through the skeleton alone (no cylinder ids) every original cylinder is a
  // chain of collinear cylinders (split where branches leave) of its length;
  // connectors become extra short cylinders.
  const QsmModel original = ReadQsmCsv(kItsmeDir / "tree_1_qsm.csv");
  const SkeletonGraph skeleton = SkeletonsFromQsm(original)[0].skeleton;
  const fs::path path = TestDir() / "tree_1_plain.csv";
  WriteQsmCsv(path, QsmFromSkeleton(skeleton, "m"));
  const QsmModel back = ReadQsmCsv(path);
  EXPECT_EQ(static_cast<int>(back.cylinders.size()), skeleton.NumNodes() - 1);
  double worst = 0.0;
  for (const QsmCylinder& c : original.cylinders) {
    worst = std::max(worst, RelativeError(c.length, LengthOnCylinder(c, back)));
  }
  EXPECT_LT(worst, 1e-6);
}

double ShortestEdge(const SkeletonGraph& skeleton) {
  double shortest = 1e300;
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0) continue;
    const Eigen::Vector3d& parent = skeleton.nodes[node.parent_idx].position;
    shortest = std::min(shortest, (node.position - parent).norm());
  }
  return shortest;
}

TEST(QsmIoTest, AllFourItsmeTablesRoundTripWithValidSkeletons) {
  struct Case {
    const char* file;
    size_t cylinders, roots;
  };
  const Case cases[] = {{"tree_1_qsm.csv", 66, 1},
                        {"tree_2_qsm.csv", 106, 2},
                        {"buttressed_tree_1_qsm_1.csv", 211, 1},
                        {"buttressed_tree_2_qsm_1.csv", 169, 1}};
  for (const Case& test : cases) {
    const QsmModel original = ReadQsmCsv(kItsmeDir / test.file);
    EXPECT_EQ(original.cylinders.size(), test.cylinders) << test.file;
    const std::vector<QsmSkeleton> parts = SkeletonsFromQsm(original);
    EXPECT_EQ(parts.size(), test.roots) << test.file;
    for (const QsmSkeleton& part : parts) EXPECT_NO_THROW(part.skeleton.Check());
    const double error = MaxRelativeError(original, RoundTrip(original, test.file));
    EXPECT_LT(error, 1e-10) << test.file;
    int nodes = 0;
    double shortest_edge = 1e300;
    for (const QsmSkeleton& part : parts) {
      nodes += part.skeleton.NumNodes();
      shortest_edge = std::min(shortest_edge, ShortestEdge(part.skeleton));
    }
    EXPECT_GT(shortest_edge, 0.0) << test.file;
    // Merging connectors shorter than a tenth of the child's radius leaves no
    // edge shorter than 1 mm; exact skeletons keep micro-connectors (float32).
    QsmToSkeletonOptions merge;
    merge.merge_fraction = 0.1;
    const std::vector<QsmSkeleton> merged = SkeletonsFromQsm(original, merge);
    double shortest_merged = 1e300;
    for (const QsmSkeleton& part : merged) {
      EXPECT_NO_THROW(part.skeleton.Check());
      shortest_merged = std::min(shortest_merged, ShortestEdge(part.skeleton));
    }
    EXPECT_GT(shortest_merged, 1e-3) << test.file;
    const QsmModel merged_back = QsmFromSkeletons(merged, "m");
    EXPECT_EQ(merged_back.cylinders.size(), original.cylinders.size());
    std::printf(
        "%s: %zu cylinders, %zu roots, %d skeleton nodes, shortest edge %.2e m (merged "
        "%.2e m), round-trip max relative error %.2e\n",
        test.file, original.cylinders.size(), parts.size(), nodes, shortest_edge, shortest_merged,
        error);
  }
}

// A TreeQSM-like pair: a trunk cylinder and a branch starting inside it
// (0.05 from its axis), and the trunk's next cylinder starting 0.02 back
// inside it. By default both get connector nodes; merge_inside_parent drops
// them: the branch hangs from a split node on the axis, the next cylinder
// from the end node. A branch starting outside keeps its connector.
TEST(QsmIoTest, MergeInsideParentDropsConnectorsWithinTheParent) {
  QsmModel qsm;
  auto add = [&](int64_t id, int64_t parent, const Eigen::Vector3d& start,
                 const Eigen::Vector3d& axis, double length, double radius, int64_t branch) {
    QsmCylinder c;
    c.id = id;
    c.parent_id = parent;
    c.start = start;
    c.axis = axis.normalized();
    c.length = length;
    c.radius = radius;
    c.branch = branch;
    c.branch_order = branch == 1 ? 0 : 1;
    qsm.cylinders.push_back(c);
  };
  add(1, 0, {0, 0, 0}, {0, 0, 1}, 1.0, 0.1, 1);
  add(2, 1, {0, 0, 0.98}, {0, 0, 1}, 1.0, 0.09, 1);
  add(3, 1, {0.05, 0, 0.5}, {1, 0, 1}, 0.5, 0.03, 2);
  add(4, 1, {0.3, 0, 0.3}, {1, 0, 0}, 0.5, 0.03, 3);
  const std::vector<QsmSkeleton> exact = SkeletonsFromQsm(qsm);
  QsmToSkeletonOptions options;
  options.merge_inside_parent = true;
  const std::vector<QsmSkeleton> merged = SkeletonsFromQsm(qsm, options);
  ASSERT_EQ(exact.size(), 1u);
  ASSERT_EQ(merged.size(), 1u);
  auto connectors = [](const QsmSkeleton& part) {
    int n = 0;
    for (size_t i = 1; i < part.cylinder_ids.size(); ++i) n += part.cylinder_ids[i] == 0 ? 1 : 0;
    return n;
  };
  EXPECT_EQ(connectors(exact[0]), 3);
  EXPECT_EQ(connectors(merged[0]), 1);  // the branch starting outside, 0.3 off the axis
  EXPECT_EQ(merged[0].skeleton.NumNodes(), exact[0].skeleton.NumNodes() - 2);
  EXPECT_NO_THROW(merged[0].skeleton.Check());
}

// The union of two coaxial cylinders overlapping by a quarter of one, and a
// third one apart: exact 0.07 pi + 0.5 pi 0.01 (Monte Carlo, 0.5 %).
TEST(QsmIoTest, UnionVolumeCountsOverlapsOnce) {
  QsmModel qsm;
  for (int k = 0; k < 3; ++k) {
    QsmCylinder c;
    c.id = k + 1;
    c.start = k < 2 ? Eigen::Vector3d(0, 0, 0.75 * k) : Eigen::Vector3d(5, 0, 0);
    c.length = k < 2 ? 1.0 : 0.5;
    c.radius = k < 2 ? 0.1 : 0.1;
    qsm.cylinders.push_back(c);
  }
  const double sum = QsmCylinderVolumeSum(qsm);
  EXPECT_NEAR(sum, M_PI * 0.01 * 2.5, 1e-12);
  const double exact = M_PI * 0.01 * (1.75 + 0.5);
  EXPECT_NEAR(QsmUnionVolume(qsm, 20000, 1) / exact, 1.0, 0.005);
  EXPECT_EQ(QsmUnionVolume(qsm, 1000, 7), QsmUnionVolume(qsm, 1000, 7));
}

TEST(QsmIoTest, SkeletonToQsmAndBackSharesJunctionNodes) {
  // A Y: trunk 0 -> 1 -> 2 straight up, a branch 1 -> 3 at 45 degrees.
  SkeletonGraph y;
  y.radius_source = "ground truth";
  const int base = y.AddNode({0, 0, 0}, 0.2, -1, 0);
  const int fork = y.AddNode({0, 0, 1}, 0.15, base, 0);
  y.AddNode({0, 0, 2}, 0.1, fork, 0);
  y.AddNode({0.5, 0, 1.5}, 0.05, fork, 1);
  const QsmModel qsm = QsmFromSkeleton(y, "m");
  ASSERT_EQ(qsm.cylinders.size(), 3u);
  EXPECT_EQ(qsm.radius_source, "ground truth");
  const QsmCylinder& branch = qsm.cylinders[2];
  EXPECT_EQ(branch.id, 3);
  EXPECT_EQ(branch.parent_id, 1);  // the trunk cylinder ending at the fork
  EXPECT_EQ(branch.branch, 2);
  EXPECT_EQ(branch.branch_order, 1);
  EXPECT_NEAR(branch.length, std::sqrt(0.5), 1e-15);
  EXPECT_TRUE(branch.axis.isApprox(Eigen::Vector3d(1, 0, 1).normalized(), 1e-15));
  EXPECT_EQ(branch.radius, 0.05);
  EXPECT_EQ(qsm.cylinders[1].parent_id, 1);

  const std::vector<QsmSkeleton> back = SkeletonsFromQsm(qsm);
  ASSERT_EQ(back.size(), 1u);
  const SkeletonGraph& skeleton = back[0].skeleton;
  ASSERT_EQ(skeleton.NumNodes(), 4);  // no connectors: children start at their parent's end
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT((skeleton.nodes[i].position - y.nodes[i].position).norm(), 1e-15);
    EXPECT_EQ(skeleton.nodes[i].parent_idx, y.nodes[i].parent_idx);
    EXPECT_EQ(skeleton.nodes[i].order, y.nodes[i].order);
  }
  EXPECT_EQ(skeleton.nodes[0].radius, 0.15);  // the root takes its cylinder's radius
  EXPECT_EQ(skeleton.nodes[3].radius, 0.05);
}

TEST(QsmIoTest, CsvRoundTripIsExact) {
  QsmModel qsm;
  qsm.radius_source = "allometric prior";
  qsm.position_source = "measured";
  qsm.branching_source = "prior";
  qsm.units = "arbitrary";
  QsmCylinder a;
  a.id = 7;
  a.start = {1.0 / 3.0, -2e-17, 123456.789012345678};
  a.axis = Eigen::Vector3d(0.1, -0.7, 1.0 / 7.0).normalized();
  a.length = 0.1 + 0.2;
  a.radius = 1e-5 / 3.0;
  a.branch = 4;
  a.branch_order = 2;
  QsmCylinder b = a;
  b.id = 3;
  b.parent_id = 7;
  b.start = a.End();
  qsm.cylinders = {a, b};
  const fs::path path = TestDir() / "exact.csv";
  WriteQsmCsv(path, qsm);
  const QsmModel back = ReadQsmCsv(path);
  EXPECT_EQ(back.radius_source, "allometric prior");
  EXPECT_EQ(back.position_source, "measured");
  EXPECT_EQ(back.branching_source, "prior");
  EXPECT_EQ(back.units, "arbitrary");
  ASSERT_EQ(back.cylinders.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(back.cylinders[i].start, qsm.cylinders[i].start);
    EXPECT_EQ(back.cylinders[i].length, qsm.cylinders[i].length);
    EXPECT_EQ(back.cylinders[i].radius, qsm.cylinders[i].radius);
    EXPECT_LT((back.cylinders[i].axis - qsm.cylinders[i].axis).norm(), 1e-15);
    EXPECT_EQ(back.cylinders[i].parent_id, qsm.cylinders[i].parent_id);
  }
}

TEST(QsmIoTest, ReadsColumnsByNameInAnyOrderWithQuotesCrLfAndBom) {
  const fs::path path = TestDir() / "reordered.csv";
  AtomicWriteString(
      path,
      "\xEF\xBB\xBF\"radius\",\"id\",\"note\",\"parent_id\",start_z,start_y,start_x,axis_x,"
      "axis_y,axis_z,length,branch,branch_order,radius_source\r\n"
      "0.5,1,\"a, b\",0,3,2,1,0,0,1.0000001,1.5,1,0,measured\r\n"
      "\r\n"
      "0.25,2,x,1,6,2,1,0.6,0,0.8,1,2,1,measured\r\n");
  const QsmModel qsm = ReadQsmCsv(path);
  ASSERT_EQ(qsm.cylinders.size(), 2u);
  EXPECT_EQ(qsm.radius_source, "measured");
  EXPECT_EQ(qsm.position_source, "unknown");  // no such column
  EXPECT_EQ(qsm.branching_source, "unknown");
  EXPECT_EQ(qsm.units, "m");
  EXPECT_EQ(qsm.cylinders[0].start, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(qsm.cylinders[0].axis, Eigen::Vector3d(0, 0, 1));  // normalised
  EXPECT_EQ(qsm.cylinders[1].parent_id, 1);
  EXPECT_EQ(qsm.cylinders[1].branch_order, 1);
}

// The message of the InputError ReadQsmCsv throws for `text`.
std::string ReadError(const std::string& text) {
  const fs::path path = TestDir() / "bad.csv";
  AtomicWriteString(path, text);
  try {
    ReadQsmCsv(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(QsmIoTest, RejectsBadTablesNamingFileAndLine) {
  const std::string header =
      "id,parent_id,start_x,start_y,start_z,axis_x,axis_y,axis_z,length,radius,branch,"
      "branch_order\n";
  const std::string good = "1,0,0,0,0,0,0,1,1,0.1,1,0\n";
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {"", "empty file"},
      {"id,parent_id,start_x\n", "bad.csv:1: missing column 'start_y'"},
      {header + good + "2,1,0,0,x,0,0,1,1,0.1,1,0\n", "bad.csv:3: start_z 'x' is not a number"},
      {header + good + "2,1,0,0,1e999,0,0,1,1,0.1,1,0\n", "bad.csv:3: start_z"},
      {header + good + "2,1,0,0,nan,0,0,1,1,0.1,1,0\n", "bad.csv:3: start_z is not finite"},
      {header + good + "2,1,0,0,1,0,0,1,-1,0.1,1,0\n", "bad.csv:3: length must be > 0"},
      {header + good + "2,1,0,0,1,0,0,1,1,0,1,0\n", "bad.csv:3: radius must be > 0"},
      {header + good + "2,1,0,0,1,0,0.1,1,1,0.1,1,0\n", "bad.csv:3: axis has length"},
      {header + good + "1,0,0,0,1,0,0,1,1,0.1,1,0\n", "bad.csv:3: id 1 also on line 2"},
      {header + good + "2,5,0,0,1,0,0,1,1,0.1,1,0\n", "bad.csv:3: parent_id 5 is no cylinder"},
      {header + good + "2,3,0,0,1,0,0,1,1,0.1,1,0\n3,2,0,0,1,0,0,1,1,0.1,1,0\n",
       "bad.csv:3: cylinder 2 is on a cycle"},
      {header + good + "2,2,0,0,1,0,0,1,1,0.1,1,0\n", "its own parent"},
      {header + "0,0,0,0,0,0,0,1,1,0.1,1,0\n", "bad.csv:2: id must be > 0"},
      {header + good + "2,1,0,0,1,0,0,1\n", "bad.csv:3: row has 8 fields"},
      {"id,parent_id,start_x,start_y,start_z,axis_x,axis_y,axis_z,length,radius,branch,"
       "branch_order,radius_source\n1,0,0,0,0,0,0,1,1,0.1,1,0,a\n2,1,0,0,1,0,0,1,1,0.1,1,0,b\n",
       "bad.csv:3: radius_source 'b' differs"},
  };
  for (const Case& test : cases) {
    const std::string message = ReadError(test.text);
    EXPECT_NE(message.find(test.expected), std::string::npos)
        << "got: " << message << "\nexpected: " << test.expected;
  }
}

TEST(QsmIoTest, WriterRejectsAnInvalidModel) {
  QsmModel qsm;
  QsmCylinder c;
  c.id = 1;
  c.parent_id = 2;  // missing
  c.length = 1;
  c.radius = 0.1;
  qsm.cylinders = {c};
  EXPECT_THROW(WriteQsmCsv(TestDir() / "invalid.csv", qsm), Error);
  EXPECT_FALSE(fs::exists(TestDir() / "invalid.csv"));
}

}  // namespace
}  // namespace sylva
