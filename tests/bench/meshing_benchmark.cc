// Benchmark of branch meshing (thesis 5.1-5.2): MeshBranches on a large
// synthetic skeleton, in triangles per second (goal: >= 10^6 / s), beside a
// straightforward reference sweep run in the same process, so the ratio
// holds on a noisy machine.
//
// Both sweep the same tubes (PlanBranchTubes: same control points, radii,
// rings and sides). The reference does what a first implementation would:
// every spline point and tangent by the recursive Cox-de Boor formula
// (eq. 5.8) instead of the per-segment matrix form (eq. 5.14), frames by an
// explicit axis-angle rotation with acos (eq. 5.19-5.20) instead of the
// change of basis M_{i+1} M_i^T (eq. 5.21-5.23), cos/sin per ring vertex,
// and no reserved storage. Its mesh is checked to match the fast one (same
// counts, vertices within 1e-4 of the tree size; in practice identical
// after rounding to float).
//
// The skeleton: the synthetic generator's tree with more, denser branches
// (about 10,500 nodes, 2,600 axes, 285,000 triangles; --quick: the default
// tree, ~1,150 nodes), its ground-truth radii replaced by pipe-model radii
// from tip counts (the generator stores no strands), which is timed too.
// The .glb export of the result is timed as well (written to the system's
// temp folder).
//
// Part 2, "watertight bark vs overlapping tubes": MeshBarkWatertight (one
// closed manifold, mesh/bark_mesh.h) against MeshBranches (the reference:
// overlapping closed tubes) on the same skeleton and tube options, in
// triangles per second, with CheckMesh's verdict on both (the tubes are
// each closed but cross each other at every junction).
//
// usage: sylva_meshing_benchmark [--quick]   (--quick: smoke test)
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "core/util/memory.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/allometry.h"
#include "mesh/bark_mesh.h"
#include "mesh/branch_mesh.h"
#include "mesh/bspline.h"
#include "mesh/gltf_export.h"
#include "mesh/mesh_checks.h"
#include "tests/bench/agreement.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

using Clock = BenchClock;

SkeletonGraph MakeSkeleton(bool quick) {
  SyntheticTreeOptions options;
  if (!quick) {
    options.num_children = {24, 12, 8};
    options.max_segment_length = 0.1;
  }
  return GenerateSyntheticSkeleton(options, 1);
}

// ---- The straightforward reference -----------------------------------------

// Eq. 5.19-5.20 literally: axis A = T_i x T_{i+1}, angle acos(T_i . T_{i+1}).
Eigen::Vector3d ReferenceTransport(const Eigen::Vector3d& normal, const Eigen::Vector3d& tangent,
                                   const Eigen::Vector3d& next_tangent) {
  const Eigen::Vector3d axis = tangent.cross(next_tangent);
  if (axis.norm() < 1e-12) return normal;
  const double angle = std::acos(std::clamp(tangent.dot(next_tangent), -1.0, 1.0));
  const Eigen::Vector3d rotated = Eigen::AngleAxisd(angle, axis.normalized()) * normal;
  return (rotated - rotated.dot(next_tangent) * next_tangent).normalized();
}

// The sample parameters: rings_per_segment[k] per segment, then the tip.
std::vector<double> ReferenceParameters(const BranchTube& tube) {
  std::vector<double> parameters;
  for (size_t k = 0; k < tube.rings_per_segment.size(); ++k) {
    for (int s = 0; s < tube.rings_per_segment[k]; ++s) {
      parameters.push_back(k + static_cast<double>(s) / tube.rings_per_segment[k]);
    }
  }
  parameters.push_back(tube.rings_per_segment.size());
  return parameters;
}

void ReferenceSweep(const BranchTube& tube, int material, TriangleMesh* mesh) {
  const CubicBSpline spline(tube.control_points);
  const std::vector<double> parameters = ReferenceParameters(tube);
  std::vector<Eigen::Vector3d> tangents;
  for (double u : parameters) tangents.push_back(DerivativeCoxDeBoor(spline, u).normalized());
  Eigen::Vector3d normal = InitialNormal(tangents);
  const int sides = tube.sides, first = mesh->NumVertices();
  for (size_t i = 0; i < parameters.size(); ++i) {
    if (i > 0) normal = ReferenceTransport(normal, tangents[i - 1], tangents[i]);
    const int k = std::min(static_cast<int>(parameters[i]), spline.NumSegments() - 1);
    const double t = parameters[i] - k;
    const double radius = (1 - t) * tube.radii[k] + t * tube.radii[k + 1];
    const Eigen::Vector3d center = EvaluateCoxDeBoor(spline, parameters[i]);
    const Eigen::Vector3d binormal = tangents[i].cross(normal);
    for (int j = 0; j < sides; ++j) {
      const double angle = 2 * M_PI * j / sides;
      mesh->AddVertex((center + radius * (std::cos(angle) * normal + std::sin(angle) * binormal))
                          .cast<float>());
    }
  }
  const int num_rings = static_cast<int>(parameters.size());
  for (int i = 0; i + 1 < num_rings; ++i) {
    for (int j = 0; j < sides; ++j) {
      const int a = first + i * sides + j, b = first + i * sides + (j + 1) % sides;
      mesh->AddTriangle(a, b, b + sides, material);
      mesh->AddTriangle(a, b + sides, a + sides, material);
    }
  }
  const int base = mesh->AddVertex(EvaluateCoxDeBoor(spline, 0).cast<float>());
  const int tip = mesh->AddVertex(EvaluateCoxDeBoor(spline, spline.NumSegments()).cast<float>());
  const int last = first + (num_rings - 1) * sides;
  for (int j = 0; j < sides; ++j) {
    mesh->AddTriangle(base, first + (j + 1) % sides, first + j, material);
    mesh->AddTriangle(tip, last + j, last + (j + 1) % sides, material);
  }
}

TriangleMesh ReferenceMesh(const SkeletonGraph& skeleton, const BranchMeshOptions& options) {
  TriangleMesh mesh;
  const int material = mesh.AddMaterial(options.bark);
  for (const BranchTube& tube : PlanBranchTubes(skeleton, options)) {
    ReferenceSweep(tube, material, &mesh);
  }
  return mesh;
}

// ---- Measurements ------------------------------------------------------------

// Both sweep the same tubes with the same sides, so the vertices differ
// only by rounding of the other formulas (Cox-de Boor vs matrix form, acos
// rotation vs change of basis), in double before the float vertices:
// measured 0 (quick and full). TOLERANCE: float rounding, 1e-6 of the size.
constexpr double kMaxVertexDeviationFraction = 1e-6;

double MaxVertexDistance(const TriangleMesh& a, const TriangleMesh& b) {
  double worst = 0.0;
  for (int i = 0; i < a.NumVertices(); ++i) {
    worst = std::max(worst, static_cast<double>((a.vertices[i] - b.vertices[i]).norm()));
  }
  return worst;
}

int Main(bool quick) {
  std::printf("Meshing benchmark: synthetic tree (seed 1), %s\n",
              quick ? "quick mode" : "full mode");
  SkeletonGraph skeleton = MakeSkeleton(quick);
  const int repetitions = quick ? 2 : 5;
  const double allometry_seconds =
      BestSeconds(repetitions, [&] { AssignPipeModelRadii(AllometryOptions(), &skeleton); });
  std::printf("Skeleton: %d nodes, %zu tips, %zu axes; pipe-model radii in %.2f ms\n",
              skeleton.NumNodes(), skeleton.Tips().size(), skeleton.BranchAxes().size(),
              1e3 * allometry_seconds);

  const BranchMeshOptions options;
  TriangleMesh mesh;
  BranchMeshSummary summary;
  const double fast =
      BestSeconds(repetitions, [&] { mesh = MeshBranches(skeleton, options, &summary); });
  std::printf("  %s\n\n", summary.BriefReport().c_str());
  TriangleMesh reference;
  const double slow =
      BestSeconds(quick ? 1 : 3, [&] { reference = ReferenceMesh(skeleton, options); });
  Agreement agreement;
  if (!agreement.AtMost("|triangle count difference| from the reference",
                        std::abs(reference.NumTriangles() - mesh.NumTriangles()), 0) ||
      !agreement.AtMost("|vertex count difference| from the reference",
                        std::abs(reference.NumVertices() - mesh.NumVertices()), 0)) {
    return agreement.ExitCode();
  }
  const double size = skeleton.NumNodes() > 0 ? mesh.Bounds().diagonal().norm() : 1.0;
  const double deviation = MaxVertexDistance(mesh, reference);
  std::printf("MeshBranches (best of %d)   %9.2f ms  %6.2f M triangles/s  (goal >= 1)\n",
              repetitions, 1e3 * fast, mesh.NumTriangles() / fast / 1e6);
  std::printf("reference sweep            %9.2f ms  %6.2f M triangles/s   ratio %.1fx\n",
              1e3 * slow, mesh.NumTriangles() / slow / 1e6, slow / fast);
  std::printf("max vertex deviation from the reference: %.2e (tree size %.2f)\n", deviation, size);
  agreement.AtMost("max vertex deviation / tree size", deviation / size,
                   kMaxVertexDeviationFraction);
  std::printf("\n");

  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "sylva_meshing_benchmark.glb";
  const double glb = BestSeconds(repetitions, [&] { WriteGlb(path, mesh); });
  std::printf("WriteGlb: %.2f ms for %.1f MB (%d vertices, %d triangles)\n", 1e3 * glb,
              std::filesystem::file_size(path) / 1e6, mesh.NumVertices(), mesh.NumTriangles());
  std::filesystem::remove(path);

  std::printf("\nWatertight bark vs overlapping tubes (same skeleton, same tube options):\n");
  BarkMeshOptions bark_options;
  bark_options.tube = options;
  TriangleMesh bark;
  BarkMeshSummary bark_summary;
  const double watertight = BestSeconds(
      repetitions, [&] { bark = MeshBarkWatertight(skeleton, bark_options, &bark_summary); });
  std::printf("  %s\n", bark_summary.BriefReport().c_str());
  std::printf(
      "MeshBarkWatertight         %9.2f ms  %6.2f M triangles/s  (%d triangles; goal >= 1 with "
      "repairs, issue 18)\n",
      1e3 * watertight, bark.NumTriangles() / watertight / 1e6, bark.NumTriangles());
  // Without the repair rounds (each costs a self-intersection check and a
  // meshing of the whole tree).
  BarkMeshOptions no_repairs = bark_options;
  no_repairs.repair_rounds = 0;
  TriangleMesh unrepaired;
  const double single = BestSeconds(
      repetitions, [&] { unrepaired = MeshBarkWatertight(skeleton, no_repairs, nullptr); });
  std::printf("  ... without repairs      %9.2f ms  %6.2f M triangles/s  (%d triangles)\n",
              1e3 * single, unrepaired.NumTriangles() / single / 1e6, unrepaired.NumTriangles());
  std::printf("MeshBranches (reference)   %9.2f ms  %6.2f M triangles/s  (%d triangles)\n",
              1e3 * fast, mesh.NumTriangles() / fast / 1e6, mesh.NumTriangles());
  const MeshCheck bark_check = CheckMesh(bark);
  const MeshCheck tube_check = CheckMesh(mesh);
  std::printf("  watertight: %s\n  without repairs: %s\n  tubes:      %s\n",
              bark_check.BriefReport().c_str(), CheckMesh(unrepaired).BriefReport().c_str(),
              tube_check.BriefReport().c_str());
  // Not an agreement with a reference but the watertight mesher's contract
  // (mesh/bark_mesh.h): one closed 2-manifold.
  const bool closed = bark_check.boundary_edges == 0 && bark_check.nonmanifold_edges == 0 &&
                      bark_check.misoriented_edges == 0 && bark_check.components == 1;
  if (!closed) std::fprintf(stderr, "the watertight bark is not one closed surface\n");
  const int status = agreement.ExitCode();
  return closed ? status : 1;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  sylva::KeepFreedMemoryForReuse();  // as the sylva binary does: the bark's attempts reuse it
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  return sylva::Main(quick);
}
