// Benchmark of Loop subdivision (mesh/subdivision.h) on watertight bark, in
// output triangles per second, beside a straightforward reference run in the
// same process, so the ratio holds on a noisy machine.
//
// The reference does what a first implementation would: an std::map from
// each undirected edge to its odd vertex and its opposite corners, and an
// std::set of neighbours per vertex, instead of the fast code's half-edge
// table grouped by origin (arrays only, no sorting or hashing). It emits
// the same child triangles in the same order, so both results are compared
// triangle by triangle (corner positions within 1e-6 of the tree size).
//
// Part 2, figures for the report (full mode only): the volume ratio and the
// crossing triangle pairs (CheckMesh) before / after one level, on the
// 8-sided watertight bark of synthetic trees with seeds 1-10, and on the
// bark `sylva mesh-qsm --subdivide 1` makes of ITSMe tree_1 (8 sides and
// the default 4-24).
//
// usage: sylva_subdivision_benchmark [--quick]   (--quick: smoke test)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/io/qsm_io.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/bark_mesh.h"
#include "mesh/mesh_checks.h"
#include "mesh/subdivision.h"
#include "tests/bench/agreement.h"
#include "tests/bench/probe_main.h"
#include "ui/pipeline/qsm_meshing.h"

namespace sylva {
namespace {

// ---- The straightforward reference -------------------------------------------

using Edge = std::pair<int, int>;

Edge Undirected(int a, int b) { return a < b ? Edge(a, b) : Edge(b, a); }

TriangleMesh ReferenceLoopOnce(const TriangleMesh& mesh) {
  std::map<Edge, std::vector<int>> opposite;  // edge -> the corners facing it
  std::vector<std::set<int>> neighbours(mesh.NumVertices());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      opposite[Undirected(t[k], t[(k + 1) % 3])].push_back(t[(k + 2) % 3]);
      neighbours[t[k]].insert(t[(k + 1) % 3]);
      neighbours[t[k]].insert(t[(k + 2) % 3]);
    }
  }
  TriangleMesh fine;
  fine.materials = mesh.materials;
  for (int v = 0; v < mesh.NumVertices(); ++v) {
    const double n = neighbours[v].size();
    const double beta = n == 3 ? 3.0 / 16 : 3.0 / (8 * n);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int u : neighbours[v]) sum += mesh.vertices[u].cast<double>();
    fine.AddVertex(((1 - n * beta) * mesh.vertices[v].cast<double>() + beta * sum).cast<float>());
  }
  std::map<Edge, int> odd;
  for (const auto& [edge, corners] : opposite) {
    const Eigen::Vector3d p =
        3.0 / 8 *
            (mesh.vertices[edge.first].cast<double>() + mesh.vertices[edge.second].cast<double>()) +
        1.0 / 8 *
            (mesh.vertices[corners[0]].cast<double>() + mesh.vertices[corners[1]].cast<double>());
    odd[edge] = fine.AddVertex(p.cast<float>());
  }
  for (int t = 0; t < mesh.NumTriangles(); ++t) {
    const Eigen::Vector3i& v = mesh.triangles[t];
    const int m01 = odd[Undirected(v[0], v[1])], m12 = odd[Undirected(v[1], v[2])],
              m20 = odd[Undirected(v[2], v[0])];
    const int material = mesh.triangle_materials[t];
    fine.AddTriangle(v[0], m01, m20, material);
    fine.AddTriangle(v[1], m12, m01, material);
    fine.AddTriangle(v[2], m20, m12, material);
    fine.AddTriangle(m01, m12, m20, material);
  }
  return fine;
}

TriangleMesh ReferenceLoop(const TriangleMesh& mesh, int levels) {
  TriangleMesh result = mesh;
  for (int level = 0; level < levels; ++level) result = ReferenceLoopOnce(result);
  return result;
}

// Largest distance between the same corner of the same triangle; -1 if the
// triangle counts differ.
double MaxCornerDistance(const TriangleMesh& a, const TriangleMesh& b) {
  if (a.NumTriangles() != b.NumTriangles()) return -1;
  double worst = 0;
  for (int t = 0; t < a.NumTriangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const float d = (a.vertices[a.triangles[t][k]] - b.vertices[b.triangles[t][k]]).norm();
      worst = std::max(worst, static_cast<double>(d));
    }
  }
  return worst;
}

BarkMeshOptions Sides(int min_sides, int max_sides) {
  BarkMeshOptions options;
  options.tube.min_sides = min_sides;
  options.tube.max_sides = max_sides;
  return options;
}

// ---- Part 1: speed -----------------------------------------------------------

// Both emit the same child triangles in the same order from the same
// formulas (the reference sums neighbours in another order, in double), so
// corners agree to float rounding: measured 0. TOLERANCE: float rounding.
constexpr double kMaxCornerDeviationFraction = 1e-6;

void TimeLevels(const TriangleMesh& bark, bool quick, Agreement* agreement) {
  const int repetitions = quick ? 1 : 5;
  const double size = bark.Bounds().diagonal().norm();
  for (int levels = 1; levels <= (quick ? 1 : 2); ++levels) {
    TriangleMesh fast, slow;
    const double fast_s = BestSeconds(repetitions, [&] { fast = SubdivideLoop(bark, levels); });
    const double slow_s = BestSeconds(quick ? 1 : 3, [&] { slow = ReferenceLoop(bark, levels); });
    const double deviation = MaxCornerDistance(fast, slow);
    std::printf("%d level(s): %d -> %d triangles\n", levels, bark.NumTriangles(),
                fast.NumTriangles());
    std::printf("  SubdivideLoop (best of %d)  %9.2f ms  %6.2f M triangles/s\n", repetitions,
                1e3 * fast_s, fast.NumTriangles() / fast_s / 1e6);
    std::printf("  reference (std::map)       %9.2f ms  %6.2f M triangles/s   ratio %.1fx\n",
                1e3 * slow_s, slow.NumTriangles() / slow_s / 1e6, slow_s / fast_s);
    std::printf("  max corner deviation from the reference: %.2e (tree size %.2f)\n", deviation,
                size);
    const std::string level = ", " + std::to_string(levels) + " level(s)";
    agreement->AtMost("|triangle count difference| from the reference" + level,
                      std::abs(fast.NumTriangles() - slow.NumTriangles()), 0);
    // -1 (counts differ) is reported above; NaN fails.
    agreement->AtMost("max corner deviation / tree size" + level,
                      deviation < 0 ? std::nan("") : deviation / size, kMaxCornerDeviationFraction);
  }
}

// ---- Part 2: figures -----------------------------------------------------------

void PrintBeforeAfter(const char* what, const TriangleMesh& bark) {
  const TriangleMesh fine = SubdivideLoop(bark, 1);
  const MeshCheck before = CheckMesh(bark), after = CheckMesh(fine);
  std::printf("%-28s volume x%.4f  crossing pairs %5ld -> %5ld  triangles %7d -> %7d  %s\n", what,
              after.volume / before.volume, static_cast<long>(before.self_intersections),
              static_cast<long>(after.self_intersections), before.triangles, after.triangles,
              after.boundary_edges + after.nonmanifold_edges + after.misoriented_edges == 0
                  ? "closed"
                  : "NOT CLOSED");
}

void PrintFigures() {
  std::printf("\nOne level on watertight bark (CheckMesh before -> after):\n");
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const SkeletonGraph g = GenerateSyntheticSkeleton(SyntheticTreeOptions(), seed);
    const std::string what = "synthetic seed " + std::to_string(seed) + ", 8 sides";
    PrintBeforeAfter(what.c_str(), MeshBarkWatertight(g, Sides(8, 8), nullptr));
  }
  const QsmModel qsm =
      ReadQsmCsv(std::string(SYLVA_SOURCE_DIR) + "/datasets/itsme-qsm/tree_1_qsm.csv");
  for (const auto& [lo, hi] : {std::pair<int, int>(8, 8), std::pair<int, int>(4, 24)}) {
    PipelineOptions options;
    options.branch_mesh.min_sides = lo;
    options.branch_mesh.max_sides = hi;
    const std::string what =
        "ITSMe tree_1, " + std::to_string(lo) + "-" + std::to_string(hi) + " sides";
    PrintBeforeAfter(what.c_str(), MeshQsm(qsm, options, 0.1).bark);
  }
}

int Main(bool quick) {
  std::printf("Loop subdivision benchmark: watertight bark of the synthetic tree (seed 1), %s\n",
              quick ? "quick mode" : "full mode");
  const SkeletonGraph g = GenerateSyntheticSkeleton(SyntheticTreeOptions(), 1);
  const TriangleMesh bark = MeshBarkWatertight(g, BarkMeshOptions(), nullptr);
  Agreement agreement;
  TimeLevels(bark, quick, &agreement);
  if (!quick) PrintFigures();
  return agreement.ExitCode();
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  return sylva::GuardedMain([&] { return sylva::Main(quick); });
}
