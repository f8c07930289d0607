// Benchmark of the tree previews (mesh/tree_preview.h): a tree with 10^5
// leaves rendered with the leaves as Embree instances of one leaf geometry,
// beside the simple way of doing it run in the same process: every leaf
// baked into the triangle mesh (LeafInstances::Bake) and the whole mesh in
// one BVH. Prints scene build time and the process' resident memory growth
// for each (the renderer's copies of the geometry + Embree's BVH), render
// time (best of 3) and camera rays per second (4 views, shadow rays not
// counted), and the mean absolute difference between the two pictures
// (they must agree).
//
// The tree: the synthetic generator's default tree (seed 1), its watertight
// bark (mesh/bark_mesh.h), and leaves of the "ovate" shape spread evenly
// over ellipsoidal clusters around its tips, random orientations, lengths
// 5-10 cm.
//
// usage: sylva_preview_benchmark [--quick] [--keep=DIR] [--qsm=QSM.csv]
//   --quick: smoke test, 10^4 leaves and 160 x 160 pictures
//   --keep=DIR: also write the previews DIR/synthetic_preview_<k>.png
//   --qsm=QSM.csv (with --keep): a close-up of the thickest junction of that
//     QSM's watertight bark, DIR/qsm_junction.png (the close-up's image
//     plane cuts away what is nearer than 5 junction radii)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/io/image_io.h"
#include "core/io/qsm_io.h"
#include "core/util/random.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/bark_mesh.h"
#include "mesh/leaves.h"
#include "mesh/tree_preview.h"
#include "tests/bench/agreement.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

constexpr double kDegrees = M_PI / 180.0;

// Resident memory of this process, MiB (Linux /proc).
double ResidentMiB() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

// `count` ovate leaves spread over ellipsoids around the tips of `skeleton`.
LeafInstances ClusterLeaves(const SkeletonGraph& skeleton, const SyntheticTreeOptions& tree,
                            int count, uint64_t seed) {
  const std::vector<std::vector<int>> children = skeleton.Children();
  std::vector<int> tips;
  for (int n = 0; n < skeleton.NumNodes(); ++n) {
    if (children[n].empty()) tips.push_back(n);
  }
  LeafInstances leaves;
  leaves.shape = BuiltinLeafShape("ovate", tree.leaf_aspect);
  leaves.material = {"leaves", tree.leaf_color, true};
  RandomEngine random(seed);
  auto uniform = [&](double lo, double hi) { return static_cast<float>(random.Uniform(lo, hi)); };
  for (int k = 0; k < count; ++k) {
    const SkeletonNode& tip = skeleton.nodes[tips[k % tips.size()]];
    Eigen::Vector3f offset;
    do {
      offset = Eigen::Vector3f(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    } while (offset.norm() > 1.0f);
    LeafInstance leaf;
    leaf.translation =
        tip.position.cast<float>() + static_cast<float>(tree.cluster_radius) *
                                         Eigen::Vector3f(offset.x(), offset.y(), 1.3f * offset.z());
    leaf.rotation =
        Eigen::Quaternionf(static_cast<float>(random.Normal()), static_cast<float>(random.Normal()),
                           static_cast<float>(random.Normal()), static_cast<float>(random.Normal()))
            .normalized();
    leaf.scale = uniform(tree.leaf_length_min, tree.leaf_length_max);
    leaves.instances.push_back(leaf);
  }
  return leaves;
}

struct Timed {
  std::vector<FloatImage> pictures;
  double build_seconds = 0, render_seconds = 0, memory_mib = 0;
  TreePreviewStats stats;
};

Timed RenderTimed(const TriangleMesh& mesh, const LeafInstances* leaves,
                  const TreePreviewOptions& options, int repetitions) {
  Timed timed;
  const double memory_before = ResidentMiB();
  const BenchClock::time_point start = BenchClock::now();
  const TreePreviewRenderer renderer(mesh, leaves);
  timed.build_seconds = Seconds(start);
  timed.memory_mib = ResidentMiB() - memory_before;
  timed.stats = renderer.Stats();
  const std::vector<PreviewView> views = renderer.FramedViews(options);
  timed.render_seconds = BestSeconds(repetitions, [&] {
    timed.pictures.clear();
    for (const PreviewView& view : views) timed.pictures.push_back(renderer.Render(view, options));
  });
  return timed;
}

double MeanAbsDifference(const std::vector<FloatImage>& a, const std::vector<FloatImage>& b) {
  double sum = 0;
  size_t count = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    for (size_t i = 0; i < a[k].values().size(); ++i) {
      sum += std::abs(a[k].values()[i] - b[k].values()[i]);
      ++count;
    }
  }
  return sum / count;
}

// The junction (node with 2+ children) whose second-thickest child is the
// thickest, and the azimuth that sees that child's edge from the side (of
// the two, the one on the sun's side).
int ThickestJunction(const SkeletonGraph& skeleton, const Eigen::Vector3d& sun,
                     double* azimuth_deg) {
  const std::vector<std::vector<int>> children = skeleton.Children();
  int best = -1;
  double best_radius = -1;
  for (int n = 0; n < skeleton.NumNodes(); ++n) {
    if (children[n].size() < 2) continue;
    std::vector<int> sorted = children[n];
    std::sort(sorted.begin(), sorted.end(),
              [&](int a, int b) { return skeleton.nodes[a].radius > skeleton.nodes[b].radius; });
    if (skeleton.nodes[sorted[1]].radius <= best_radius) continue;
    best_radius = skeleton.nodes[sorted[1]].radius;
    best = n;
    const Eigen::Vector3d d = skeleton.nodes[sorted[1]].position - skeleton.nodes[n].position;
    *azimuth_deg = std::atan2(d.y(), d.x()) / kDegrees;
  }
  // The camera of azimuth a sits towards (sin a, -cos a) (tree_preview.h).
  const double a = *azimuth_deg * kDegrees;
  if (std::sin(a) * sun.x() - std::cos(a) * sun.y() < 0) *azimuth_deg += 180.0;
  return best;
}

void WriteJunctionCloseUp(const SkeletonGraph& skeleton, const TriangleMesh& bark,
                          const std::filesystem::path& path) {
  const TreePreviewOptions options;
  double azimuth = 0;
  const int junction = ThickestJunction(skeleton, options.sun_direction, &azimuth);
  if (junction < 0) return;
  const SkeletonNode& node = skeleton.nodes[junction];
  WriteImage(
      path, RenderCloseUp(bark, nullptr, node.position, 5.0 * node.radius, azimuth, 20.0, options));
  std::printf("wrote %s (junction node %d, radius %.3f)\n", path.string().c_str(), junction,
              node.radius);
}

int Run(bool quick, const std::string& keep, const std::string& qsm_path) {
  const SyntheticTreeOptions tree_options;
  const SkeletonGraph skeleton = GenerateSyntheticSkeleton(tree_options, 1);
  BarkMeshOptions bark_options;
  bark_options.tube.bark.diffuse_color = tree_options.bark_color;
  BarkMeshSummary summary;
  const TriangleMesh bark = MeshBarkWatertight(skeleton, bark_options, &summary);
  const int num_leaves = quick ? 10000 : 100000;
  const LeafInstances leaves = ClusterLeaves(skeleton, tree_options, num_leaves, 2);
  TreePreviewOptions options;
  if (quick) options.width = options.height = 160;
  const int repetitions = quick ? 1 : 3;  // render time: the best of these

  // The small scene first: the large one may reuse the pages it freed, which
  // understates the baked scene's growth by at most the instanced one's.
  const Timed instanced = RenderTimed(bark, &leaves, options, repetitions);
  const BenchClock::time_point bake_start = BenchClock::now();
  TriangleMesh baked = bark;
  baked.Append(leaves.Bake());
  const double bake_seconds = Seconds(bake_start);
  const Timed reference = RenderTimed(baked, nullptr, options, repetitions);

  const double rays = static_cast<double>(options.width) * options.height *
                      options.samples_per_axis * options.samples_per_axis *
                      instanced.pictures.size();
  std::printf(
      "tree: %d bark triangles, %d leaves x %d triangles; %d views of %d x %d, %d x %d rays "
      "per pixel\n",
      bark.NumTriangles(), num_leaves, instanced.stats.leaf_triangles,
      static_cast<int>(instanced.pictures.size()), options.width, options.height,
      options.samples_per_axis, options.samples_per_axis);
  std::printf("%-10s %12s %12s %12s %14s\n", "leaves", "build s", "memory MiB", "render s",
              "camera rays/s");
  std::printf("%-10s %12.3f %12.1f %12.3f %14.3g   (+ %.3f s baking %d triangles)\n", "baked",
              reference.build_seconds, reference.memory_mib, reference.render_seconds,
              rays / reference.render_seconds, bake_seconds, baked.NumTriangles());
  std::printf("%-10s %12.3f %12.1f %12.3f %14.3g\n", "instanced", instanced.build_seconds,
              instanced.memory_mib, instanced.render_seconds, rays / instanced.render_seconds);
  // The pictures' own choice (RenderTreePreviews): triangles when there are
  // 5 or more camera rays per baked leaf triangle.
  const bool bake = ChoosePreviewLeafGeometry(&leaves, rays) == PreviewLeafGeometry::kTriangles;
  std::printf("RenderTreePreviews holds these leaves as %s (%.1f camera rays per baked triangle)\n",
              bake ? "triangles" : "instances",
              rays / (static_cast<double>(num_leaves) * instanced.stats.leaf_triangles));
  const double difference = MeanAbsDifference(instanced.pictures, reference.pictures);
  std::printf("mean |instanced - baked| per channel: %.2e\n", difference);
  if (!keep.empty()) {
    std::filesystem::create_directories(keep);
    for (size_t k = 0; k < instanced.pictures.size(); ++k) {
      WriteImage(std::filesystem::path(keep) / ("synthetic_preview_" + std::to_string(k) + ".png"),
                 instanced.pictures[k]);
    }
    if (!qsm_path.empty()) {
      QsmToSkeletonOptions convert;
      convert.merge_fraction = 0.1;
      const QsmSkeleton part = SkeletonsFromQsm(ReadQsmCsv(qsm_path), convert).front();
      const TriangleMesh qsm_bark = MeshBarkWatertight(part.skeleton, BarkMeshOptions(), nullptr);
      WriteJunctionCloseUp(part.skeleton, qsm_bark,
                           std::filesystem::path(keep) / "qsm_junction.png");
    }
  }
  // The two ways must draw the same tree: the same triangles, transformed
  // once at bake time or per ray by Embree's instance transform, which
  // rounds differently and moves a few leaf-edge and shadow-ray hits.
  // Measured 2.6e-7 (quick) and 1.2e-6 (full); TOLERANCE 1e-4, about 80x
  // that (one pixel in ~100 of a 160 x 160 picture entirely wrong fails).
  constexpr double kMaxMeanDifference = 1e-4;
  Agreement agreement;
  agreement.AtMost("mean |instanced - baked| per channel", difference, kMaxMeanDifference);
  return agreement.ExitCode();
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  bool quick = false;
  std::string keep, qsm;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strncmp(argv[i], "--keep=", 7) == 0) {
      keep = argv[i] + 7;
    } else if (std::strncmp(argv[i], "--qsm=", 6) == 0) {
      qsm = argv[i] + 6;
    } else {
      std::fprintf(stderr, "usage: %s [--quick] [--keep=DIR] [--qsm=QSM.csv]\n", argv[0]);
      return 2;
    }
  }
  return sylva::GuardedMain([&] { return sylva::Run(quick, keep, qsm); });
}
