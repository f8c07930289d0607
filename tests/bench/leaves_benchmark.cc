// Benchmark of twigs and leaves (thesis 5.4) and of their glTF export.
//
// 1. Leaf generation in leaves per second: GenerateLeafInstances (free
//    draws near thin branches, and phyllotaxis along twigs) beside a
//    straightforward reference run in the same process, so the ratio holds
//    on a noisy machine. The reference does what a first implementation
//    would: the density voxel drawn by a linear scan of the cumulative
//    opacities, the nearest thin-branch point by a linear scan of all of
//    them, and each leaf's quad appended to a TriangleMesh as it is made.
//    It draws from its own random stream, so it is checked by statistics
//    (same leaf count, mean leaf position within 2 % of the tree height),
//    not leaf by leaf.
// 2. .glb size and write time with the leaves instanced
//    (EXT_mesh_gpu_instancing) and baked, for 10^4 and 10^5 leaves, quad and
//    ovate shapes (written to the system's temp folder).
//
// The tree: the synthetic generator's default tree, twigs grown on it
// (GrowTwigs), and a density grid made of the voxels around its thin
// branches (opacity 0.4).
//
// usage: sylva_leaves_benchmark [--quick] [--keep=DIR]
//   --quick: smoke test, 10^4 leaves only
//   --keep=DIR: also write DIR/tree_instanced.glb, DIR/tree_baked.glb (bark
//   with twigs + 10^4 ovate leaves) and DIR/tree_image_leaves.glb (leaves
//   from a drawn RGBA leaf image), e.g. for the Khronos glTF validator.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>

#include "core/util/random.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/branch_mesh.h"
#include "mesh/gltf_export.h"
#include "mesh/leaves.h"
#include "mesh/phyllotaxis.h"
#include "mesh/twigs.h"
#include "tests/bench/agreement.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

using Clock = BenchClock;

// Voxels within one voxel of the thin branches' sample points, opacity 0.4.
DensityGrid ThinBranchDensity(const SkeletonGraph& skeleton, double thin_radius, double voxel) {
  DensityGrid grid(voxel, Eigen::Vector3d::Zero());
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0 || node.radius > thin_radius) continue;
    const Eigen::Vector3d& from = skeleton.nodes[node.parent_idx].position;
    const int steps = std::max(1, static_cast<int>((node.position - from).norm() / voxel));
    for (int s = 0; s <= steps; ++s) {
      const Eigen::Vector3i c =
          grid.IndexFromWorld(from + (node.position - from) * (double(s) / steps))
              .array()
              .round()
              .cast<int>();
      for (int k = -1; k <= 1; ++k)
        for (int j = -1; j <= 1; ++j)
          for (int i = -1; i <= 1; ++i) grid.SetValue(c + Eigen::Vector3i(i, j, k), 0.4f);
    }
  }
  return grid;
}

// ---- The straightforward reference -----------------------------------------

TriangleMesh ReferenceLeaves(const SkeletonGraph& skeleton, const DensityGrid& density,
                             const LeafOptions& options) {
  const double length = options.leaf_length;
  const double thin =
      options.thin_branch_radius_fraction * skeleton.nodes[skeleton.RootIdx()].radius;
  std::vector<Eigen::Vector3d> points;
  for (const SkeletonNode& node : skeleton.nodes) {
    if (node.parent_idx < 0 || node.radius > thin) continue;
    const Eigen::Vector3d& from = skeleton.nodes[node.parent_idx].position;
    const int steps =
        std::max(1, static_cast<int>(std::ceil((node.position - from).norm() / (0.5 * length))));
    for (int s = 0; s <= steps; ++s)
      points.push_back(from + (node.position - from) * (double(s) / steps));
  }
  std::vector<Eigen::Vector3i> voxels;
  std::vector<double> cumulative;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double total = 0.0;
  density.ForEachActive([&](const Eigen::Vector3i& ijk, float alpha) {
    voxels.push_back(ijk);
    total += alpha;
    cumulative.push_back(total);
    centroid += alpha * density.WorldFromIndex(ijk.cast<double>());
  });
  centroid /= total;
  TriangleMesh mesh;
  const int material = mesh.AddMaterial({"leaves", Eigen::Vector3f(0.22f, 0.46f, 0.13f), true});
  RandomEngine rng(options.seed, 99);
  int kept = 0;
  for (int draw = 0; kept < options.num_leaves && draw < 3 * options.num_leaves; ++draw) {
    const double u = rng.Uniform() * total;
    size_t v = 0;
    while (v + 1 < voxels.size() && cumulative[v] <= u) ++v;
    const Eigen::Vector3d center = density.WorldFromIndex(
        voxels[v].cast<double>() +
        Eigen::Vector3d(rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5)));
    double best = options.twig_reach * length;
    int nearest = -1;
    for (size_t p = 0; p < points.size(); ++p) {
      if ((points[p] - center).norm() < best) {
        best = (points[p] - center).norm();
        nearest = static_cast<int>(p);
      }
    }
    if (nearest < 0) continue;
    const Eigen::Vector3d axis = (center - points[nearest]).normalized();
    const Eigen::Vector3d outward = (center - centroid).normalized();
    Eigen::Vector3d random(rng.Normal(), rng.Normal(), rng.Normal());
    random = (random - random.dot(axis) * axis).normalized();
    const Eigen::Vector3d normal =
        (options.phototropism * (outward - outward.dot(axis) * axis).normalized() +
         (1 - options.phototropism) * random)
            .normalized();
    const Eigen::Vector3d side = normal.cross(axis);
    const double width = options.leaf_aspect * length;
    const int first = mesh.AddVertex((center - 0.5 * length * axis).cast<float>());
    mesh.AddVertex((center + 0.5 * width * side).cast<float>());
    mesh.AddVertex((center + 0.5 * length * axis).cast<float>());
    mesh.AddVertex((center - 0.5 * width * side).cast<float>());
    mesh.AddTriangle(first, first + 2, first + 1, material);
    mesh.AddTriangle(first, first + 3, first + 2, material);
    ++kept;
  }
  return mesh;
}

// The reference draws from its own random stream, so its leaves are other
// leaves from the same distribution: it must keep as many, and the mean
// position and the spread (RMS distance from the mean) of the leaf vertices
// agree within the sampling noise. Measured: mean offset 0.24 % (10^4
// leaves) and 0.12 % (10^5) of the height; spread difference 0.44 % and
// 0.02 %. TOLERANCES: about 4x the larger.
constexpr double kMaxMeanOffsetPercent = 1.0;
constexpr double kMaxSpreadDifferencePercent = 2.0;

Eigen::Vector3d MeanVertex(const TriangleMesh& mesh) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& v : mesh.vertices) sum += v.cast<double>();
  return sum / std::max(1, mesh.NumVertices());
}

// RMS distance of the vertices from their mean.
double VertexSpread(const TriangleMesh& mesh) {
  const Eigen::Vector3d mean = MeanVertex(mesh);
  double sum = 0.0;
  for (const Eigen::Vector3f& v : mesh.vertices) sum += (v.cast<double>() - mean).squaredNorm();
  return std::sqrt(sum / std::max(1, mesh.NumVertices()));
}

// ---- Figures ----------------------------------------------------------------

void PrintGlbSizes(const TriangleMesh& bark, const LeafInstances& leaves, int repetitions) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path();
  for (const bool instanced : {true, false}) {
    GltfExportOptions options;
    options.instance_leaves = instanced;
    const std::filesystem::path path = folder / "sylva_leaves_benchmark.glb";
    const double seconds = BestSeconds(repetitions, [&] { WriteGlb(path, bark, leaves, options); });
    const double leaves_bytes = static_cast<double>(std::filesystem::file_size(path));
    WriteGlb(path, bark, LeafInstances(), options);
    const double bark_bytes = static_cast<double>(std::filesystem::file_size(path));
    std::printf(
        "  %-10s %-8s %7zu leaves: %8.2f MB .glb (leaves %6.1f bytes each), write %8.2f ms\n",
        leaves.shape.name.c_str(), instanced ? "instanced" : "baked", leaves.instances.size(),
        leaves_bytes / 1e6, (leaves_bytes - bark_bytes) / leaves.instances.size(), 1e3 * seconds);
    std::filesystem::remove(path);
  }
}

// Divergence angles measured on every branch axis of the tree (curved
// polylines), between successive nodes' first leaves, per pattern. The
// projection on the plane normal to the first leaf's axis tangent is only a
// divergence where the axis is locally straight: pairs whose tangents differ
// by more than kStraightDeg (at a kink of the polyline) are counted apart.
void PrintDivergences(const SkeletonGraph& tree, double internode) {
  std::printf("Phyllotaxis on the %zu branch axes of the tree with twigs (internode %.3f):\n",
              tree.BranchAxes().size(), internode);
  for (const char* name : {"spiral", "alternate", "opposite_decussate", "whorled"}) {
    PhyllotaxisOptions options;
    options.pattern = ParsePhyllotaxisPattern(name, "benchmark");
    options.internode = internode;
    const int per_node = options.LeavesPerNode();
    constexpr double kStraightDeg = 5.0;
    double sum = 0.0, worst = 0.0;
    int64_t count = 0, kinked = 0;
    for (const BranchAxis& axis : tree.BranchAxes()) {
      std::vector<Eigen::Vector3d> points;
      for (int node : axis) points.push_back(tree.nodes[node].position);
      const std::vector<LeafAttachment> leaves = PlaceLeavesAlongAxis(points, options);
      for (size_t i = 0; i + per_node < leaves.size(); i += per_node) {
        if (leaves[i].axis_tangent.dot(leaves[i + per_node].axis_tangent) <
            std::cos(kStraightDeg * M_PI / 180)) {
          ++kinked;
          continue;
        }
        ++count;
        const double angle = DivergenceAngleDeg(leaves[i], leaves[i + per_node]);
        sum += angle;
        worst = std::max(worst, std::abs(angle - options.DivergenceDeg()));
      }
    }
    std::printf(
        "  %-19s expected %7.2f deg, measured mean %8.3f deg over %lld node pairs, "
        "max deviation %.3f deg (%lld pairs across kinks left out)\n",
        name, options.DivergenceDeg(), sum / count, static_cast<long long>(count), worst,
        static_cast<long long>(kinked));
  }
  std::printf("\n");
}

// A 64 x 128 RGBA leaf: an ellipse with alpha 1 inside, green, a pale midrib.
FloatImage DrawnLeafImage() {
  FloatImage image(64, 128, 4, 0.0f);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const double u = (x + 0.5) / 32.0 - 1.0, v = (y + 0.5) / 64.0 - 1.0;
      if (u * u + v * v > 1.0) continue;
      const bool midrib = std::abs(u) < 0.04;
      image.at(x, y, 0) = midrib ? 0.6f : 0.15f;
      image.at(x, y, 1) = midrib ? 0.8f : 0.45f;
      image.at(x, y, 2) = midrib ? 0.4f : 0.1f;
      image.at(x, y, 3) = 1.0f;
    }
  }
  return image;
}

void KeepFiles(const std::filesystem::path& folder, const SkeletonGraph& with_twigs,
               const DensityGrid& density, LeafOptions options) {
  std::filesystem::create_directories(folder);
  const TriangleMesh bark = MeshBranches(with_twigs, BranchMeshOptions(), nullptr);
  options.num_leaves = 10000;
  options.shape = "ovate";
  const LeafInstances leaves =
      GenerateLeafInstances(with_twigs, density, ImageSet(), {}, options, nullptr);
  GltfExportOptions gltf;
  WriteGlb(folder / "tree_instanced.glb", bark, leaves, gltf);
  gltf.instance_leaves = false;
  WriteGlb(folder / "tree_baked.glb", bark, leaves, gltf);
  const LeafShape image = LeafShapeFromImage(DrawnLeafImage(), "drawn leaf");
  const LeafInstances image_leaves =
      GenerateLeafInstances(with_twigs, density, ImageSet(), {}, options, nullptr, &image);
  WriteGlb(folder / "tree_image_leaves.glb", bark, image_leaves);
  std::printf("\nWrote tree_instanced.glb, tree_baked.glb, tree_image_leaves.glb to %s\n",
              folder.string().c_str());
}

int Main(bool quick, const std::string& keep) {
  SkeletonGraph skeleton = GenerateSyntheticSkeleton(SyntheticTreeOptions(), 1);
  const double height = skeleton.Height();
  const double thin = 0.35 * skeleton.nodes[skeleton.RootIdx()].radius;
  const DensityGrid density = ThinBranchDensity(skeleton, thin, 0.02 * height);
  TwigOptions twig_options;
  twig_options.twigs_per_length = 3.0;
  TwigSummary twig_summary;
  SkeletonGraph with_twigs;
  const int repetitions = quick ? 1 : 3;
  const double twig_seconds = BestSeconds(
      repetitions, [&] { with_twigs = GrowTwigs(skeleton, density, twig_options, &twig_summary); });
  std::printf("Tree: %d nodes, height %.2f; %zu active voxels\n%s\n  %.2f ms, %.0f twigs/s\n\n",
              skeleton.NumNodes(), height, static_cast<size_t>(density.NumActiveVoxels()),
              twig_summary.BriefReport().c_str(), 1e3 * twig_seconds,
              twig_summary.twigs / twig_seconds);

  PrintDivergences(with_twigs, 0.6 * 0.01 * height);
  // What twigs cost the bark mesh (they are swept like any branch).
  for (const SkeletonGraph* tree : {&skeleton, &with_twigs}) {
    TriangleMesh bark;
    const double seconds =
        BestSeconds(repetitions, [&] { bark = MeshBranches(*tree, BranchMeshOptions(), nullptr); });
    std::printf("  MeshBranches %-13s %8d triangles in %8.2f ms\n",
                tree == &skeleton ? "without twigs" : "with twigs", bark.NumTriangles(),
                1e3 * seconds);
  }
  std::printf("\n");

  Agreement agreement;
  std::vector<int> counts = {10000};
  if (!quick) counts.push_back(100000);
  LeafOptions options;
  options.leaf_length = 0.01 * height;
  for (const int count : counts) {
    options.num_leaves = count;
    options.phyllotaxis = "none";
    LeafSummary summary;
    LeafInstances leaves;
    const double fast = BestSeconds(repetitions, [&] {
      leaves = GenerateLeafInstances(with_twigs, density, ImageSet(), {}, options, &summary);
    });
    TriangleMesh baked;
    const double bake = BestSeconds(repetitions, [&] { baked = leaves.Bake(); });
    std::printf("%d leaves wanted\n  %s\n", count, summary.BriefReport().c_str());
    std::printf("  GenerateLeafInstances (free)   %8.2f ms  %8.2f k leaves/s; Bake %.2f ms\n",
                1e3 * fast, summary.kept / fast / 1e3, 1e3 * bake);
    options.phyllotaxis = "spiral";
    LeafSummary phyllo_summary;
    const double phyllo = BestSeconds(repetitions, [&] {
      GenerateLeafInstances(with_twigs, density, ImageSet(), {}, options, &phyllo_summary);
    });
    std::printf(
        "  GenerateLeafInstances (spiral) %8.2f ms  %8.2f k leaves/s (%lld kept of %lld sites)\n",
        1e3 * phyllo, phyllo_summary.kept / phyllo / 1e3,
        static_cast<long long>(phyllo_summary.kept),
        static_cast<long long>(phyllo_summary.phyllotaxis_sites));
    if (count <= 10000 || !quick) {
      options.phyllotaxis = "none";
      TriangleMesh reference;
      const Clock::time_point start = Clock::now();
      reference = ReferenceLeaves(with_twigs, density, options);
      const double slow = Seconds(start);
      const int reference_kept = reference.NumTriangles() / 2;
      const double offset = (MeanVertex(reference) - MeanVertex(baked)).norm();
      const double spread = VertexSpread(reference);
      const double spread_difference = std::abs(VertexSpread(baked) - spread) / spread;
      std::printf(
          "  reference (linear scans)       %8.2f ms  %8.2f k leaves/s   speed-up %.1fx; "
          "mean leaf offset %.3f (%.2f %% of height), spread difference %.2f %%\n",
          1e3 * slow, reference_kept / slow / 1e3, (summary.kept / fast) / (reference_kept / slow),
          offset, 100 * offset / height, 100 * spread_difference);
      const std::string at = ", " + std::to_string(count) + " leaves";
      agreement.AtMost("|leaf count difference| from the reference" + at,
                       std::abs(reference_kept - summary.kept), 0);
      agreement.AtMost("mean leaf offset from the reference, % of the height" + at,
                       100 * offset / height, kMaxMeanOffsetPercent);
      agreement.AtMost("leaf spread difference from the reference, %" + at, 100 * spread_difference,
                       kMaxSpreadDifferencePercent);
      std::printf("\n");
    }
  }

  std::printf("glTF export (leaves only, best of %d):\n", repetitions);
  for (const int count : counts) {
    options.num_leaves = count;
    options.phyllotaxis = "none";
    for (const char* shape : {"quad", "ovate"}) {
      options.shape = shape;
      const LeafInstances leaves =
          GenerateLeafInstances(with_twigs, density, ImageSet(), {}, options, nullptr);
      PrintGlbSizes(TriangleMesh(), leaves, repetitions);
    }
  }
  if (!keep.empty()) KeepFiles(keep, with_twigs, density, options);
  return agreement.ExitCode();
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  bool quick = false;
  std::string keep;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strncmp(argv[i], "--keep=", 7) == 0) {
      keep = argv[i] + 7;
    } else {
      std::fprintf(stderr, "usage: sylva_leaves_benchmark [--quick] [--keep=DIR]\n");
      return 2;
    }
  }
  return sylva::Main(quick, keep);
}
