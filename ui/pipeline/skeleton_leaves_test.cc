// Leaves of the trees made without photos (issue 17 item 4): a tree grown
// from the bundled gestures (datasets/gesture) and one drawn by MRF from a
// bundled drawing (datasets/sketches) get leaves on their thin branches with
// the spiral phyllotaxis of their defaults (UseSkeletonTreeDefaults): near
// the thin branches, 137.5 degrees between successive leaves along a branch,
// the same for the same seed, none for Leaves.num_leaves=-1, and the written
// tree.obj / tree.glb hold them.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "core/geometry/polyline.h"
#include "core/io/mesh_io.h"
#include "core/util/file_util.h"
#include "mesh/gltf_export.h"
#include "mesh/phyllotaxis.h"
#include "sketch/drawing_io.h"
#include "sketch/gesture_io.h"
#include "ui/pipeline/gesture_meshing.h"
#include "ui/pipeline/qsm_meshing.h"
#include "ui/pipeline/sketch_mrf.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(SYLVA_SOURCE_DIR) / "datasets";

PipelineOptions SkeletonTreeOptions() {
  PipelineOptions options;
  UseSkeletonTreeDefaults(&options);
  options.gesture.iterations = 5;
  options.sketch_mrf.mrf.max_segments = 400;
  options.report.previews = false;
  return options;
}

struct Segment {
  Eigen::Vector3d a, b;
};

// The edges that carry leaves: radius at most Leaves.thin_branch_radius_fraction
// of the largest part's trunk (AddSkeletonLeaves).
std::vector<Segment> ThinSegments(const QsmMeshing& meshing, const LeafOptions& options) {
  double trunk = 0.0;
  for (const QsmSkeleton& part : meshing.parts) {
    trunk = std::max(trunk, part.skeleton.nodes[part.skeleton.RootIdx()].radius);
  }
  std::vector<Segment> segments;
  for (const QsmSkeleton& part : meshing.parts) {
    for (const SkeletonNode& node : part.skeleton.nodes) {
      if (node.parent_idx < 0 || node.radius > options.thin_branch_radius_fraction * trunk) {
        continue;
      }
      segments.push_back({part.skeleton.nodes[node.parent_idx].position, node.position});
    }
  }
  return segments;
}

// The largest distance from a leaf's centre to the nearest thin segment.
double FarthestLeafFromThinBranches(const LeafInstances& leaves,
                                    const std::vector<Segment>& segments) {
  double farthest = 0.0;
  for (const LeafInstance& leaf : leaves.instances) {
    const Eigen::Vector3d center =
        (leaf.translation + 0.5f * leaf.scale * (leaf.rotation * Eigen::Vector3f::UnitX()))
            .cast<double>();
    double nearest2 = INFINITY;
    for (const Segment& s : segments) {
      nearest2 = std::min(nearest2, SegmentDistance2(center, s.a, s.b));
    }
    farthest = std::max(farthest, std::sqrt(nearest2));
  }
  return farthest;
}

// The thin segment nearest p.
const Segment& NearestSegment(const Eigen::Vector3d& p, const std::vector<Segment>& segments) {
  size_t best = 0;
  double best2 = INFINITY;
  for (size_t k = 0; k < segments.size(); ++k) {
    const double d2 = SegmentDistance2(p, segments[k].a, segments[k].b);
    if (d2 < best2) best2 = d2, best = k;
  }
  return segments[best];
}

// Divergence angles between successive leaves along a branch: consecutive
// instances (sites are made axis by axis, node by node) one internode apart
// along the thin segment nearest the first one's base (the bases sit on
// the bark, a radius off the axis), looking down that segment.
std::vector<double> SuccessiveDivergences(const LeafInstances& leaves,
                                          const std::vector<Segment>& thin, double internode) {
  std::vector<double> angles;
  for (size_t i = 0; i + 1 < leaves.instances.size(); ++i) {
    const LeafInstance& p = leaves.instances[i];
    const LeafInstance& q = leaves.instances[i + 1];
    const Segment& segment = NearestSegment(p.translation.cast<double>(), thin);
    const Eigen::Vector3d tangent = (segment.b - segment.a).normalized();
    const double along = (q.translation - p.translation).cast<double>().dot(tangent);
    if (std::abs(along - internode) > 0.1 * internode) continue;
    LeafAttachment a, b;
    a.axis_tangent = tangent;
    a.petiole_direction = (p.rotation * Eigen::Vector3f::UnitX()).cast<double>();
    b.petiole_direction = (q.rotation * Eigen::Vector3f::UnitX()).cast<double>();
    angles.push_back(DivergenceAngleDeg(a, b));
  }
  return angles;
}

double Median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

double FractionNear(const std::vector<double>& values, double target, double tolerance) {
  const auto near = std::count_if(values.begin(), values.end(),
                                  [&](double v) { return std::abs(v - target) <= tolerance; });
  return static_cast<double>(near) / values.size();
}

// What every skeleton tree's leaves must show.
void ExpectPhyllotacticLeaves(const QsmMeshing& meshing, const PipelineOptions& options) {
  SCOPED_TRACE(meshing.leaf_summary.BriefReport());
  const LeafInstances& leaves = meshing.leaves;
  ASSERT_GT(leaves.instances.size(), 300u);
  EXPECT_EQ(static_cast<int64_t>(leaves.instances.size()), meshing.leaf_summary.kept);
  EXPECT_EQ(leaves.material.name, "leaves");
  EXPECT_NE(meshing.brief.find("Leaves: " + std::to_string(leaves.instances.size())),
            std::string::npos);
  const double length = meshing.leaf_summary.leaf_length;
  ASSERT_GT(length, 0.0);
  const std::vector<Segment> thin = ThinSegments(meshing, options.leaves);
  const double farthest = FarthestLeafFromThinBranches(leaves, thin);
  EXPECT_LT(farthest, 2.0 * length);
  const std::vector<double> divergences =
      SuccessiveDivergences(leaves, thin, options.leaves.internode * length);
  ASSERT_GT(divergences.size(), leaves.instances.size() / 2);
  const double median = Median(divergences), within = FractionNear(divergences, 137.5, 3.0);
  EXPECT_NEAR(median, 137.5, 1.0);
  EXPECT_GT(within, 0.9);
  std::cout << leaves.instances.size() << " leaves, farthest " << farthest / length
            << " leaf lengths from a thin branch; " << divergences.size()
            << " successive pairs, median divergence " << median << " degrees, " << 100 * within
            << " % within 3 degrees of 137.5\n";
}

TEST(SkeletonLeavesTest, GestureTreeGrowsPhyllotacticLeaves) {
  const PipelineOptions options = SkeletonTreeOptions();
  const GestureSet gestures = ReadGesture(kData / "gesture" / "two_trunks.obj");
  const GestureMeshing meshing = MeshGestures(gestures, options);
  ExpectPhyllotacticLeaves(meshing.meshing, options);

  // Same seed, same leaves.
  const GestureMeshing again = MeshGestures(gestures, options);
  ASSERT_EQ(again.meshing.leaves.instances.size(), meshing.meshing.leaves.instances.size());
  for (size_t i = 0; i < meshing.meshing.leaves.instances.size(); ++i) {
    EXPECT_EQ(again.meshing.leaves.instances[i].translation,
              meshing.meshing.leaves.instances[i].translation);
    EXPECT_EQ(again.meshing.leaves.instances[i].rotation.coeffs(),
              meshing.meshing.leaves.instances[i].rotation.coeffs());
  }

  // The written tree holds them: a "leaves" material in tree.obj, instanced
  // leaves in tree.glb.
  const fs::path out = fs::temp_directory_path() / "sylva_skeleton_leaves_test";
  fs::remove_all(out);
  WriteGestureMeshing(meshing, out, options);
  EXPECT_NE(ReadFileToString(out / "tree.obj").find("usemtl leaves"), std::string::npos);
  LeafInstances read;
  ReadGlbKeepingLeafInstances(out / "tree.glb", &read);
  EXPECT_EQ(read.instances.size(), meshing.meshing.leaves.instances.size());
  fs::remove_all(out);

  // Leafless on request, and by default for laser-scanned QSMs.
  PipelineOptions leafless = options;
  leafless.leaves.num_leaves = -1;
  QsmMeshing bare = meshing.meshing;
  AddSkeletonLeaves(leafless, &bare);
  EXPECT_TRUE(bare.leaves.instances.empty());
  EXPECT_NE(bare.brief.find("No leaves"), std::string::npos);
  PipelineOptions qsm_defaults;
  UseQsmMeshingDefaults(&qsm_defaults);
  AddSkeletonLeaves(qsm_defaults, &bare);
  EXPECT_TRUE(bare.leaves.instances.empty());
}

TEST(SkeletonLeavesTest, MrfSketchTreeGrowsPhyllotacticLeaves) {
  const PipelineOptions options = SkeletonTreeOptions();
  const SketchDrawing drawing =
      ReadSketch(kData / "sketches" / "openclipart" / "arbre_modern_bw_jean-vic_01.svg");
  const MrfSketchTree tree = MakeMrfSketchTree({drawing}, options, BuiltinExemplars());
  QsmModel qsm;
  const QsmMeshing meshing = MeshSketchTree(tree, options, &qsm);
  ExpectPhyllotacticLeaves(meshing, options);

  PipelineOptions leafless = options;
  leafless.leaves.num_leaves = -1;
  QsmMeshing bare = meshing;
  AddSkeletonLeaves(leafless, &bare);
  EXPECT_TRUE(bare.leaves.instances.empty());
}

}  // namespace
}  // namespace sylva
