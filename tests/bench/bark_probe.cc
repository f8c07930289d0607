// By-hand probe of the watertight bark mesher (mesh/bark_mesh.h) on real
// QSM cylinder tables and a picture of one junction.
//
// For every QSM table (CSV with columns id, parent_id, start_x/y/z,
// axis_x/y/z, length, radius, ...: the ITSMe qsm_csv format), read by
// core/io/qsm_io.h into one skeleton per root cylinder. Prints triangles, CheckMesh of the
// watertight mesh and the overlapping tubes, and the mesh volume against the sum of the cylinders'
// volumes (pi r^2 L).
//
// --picture PATH: renders a close-up of the first trunk junction of the
// synthetic tree (seed 1) with both meshers side by side (left: watertight,
// right: MeshBranches), PNG.
//
// --skeleton PATH: a sylva skeleton (out/skeleton.json of a project).
// --classify N: synthetic trees of seeds 1..N (-S: seed S alone).
// --synth-qsm S: the laser-scan-like QSM table of seed S
// (datasets/synthetic/synthetic_qsm.h; SYLVA_QSM_NOISE=P,R sets its position
// and radius noise), meshed as mesh-qsm meshes it (SYLVA_KEEP_CONNECTORS:
// without merge_inside_parent; SYLVA_INSCRIBED: without circle_area): the
// components beyond the largest, the inside-out ones, and the volume over
// the cylinders' union.
// Every mesh's crossing triangle pairs are classified (ClassifyBarkCrossings).
//
// usage: sylva_bark_probe [--picture out.png] [--skeleton skeleton.json]
//                         [--classify N] [--synth-qsm S] [qsm.csv ...]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/geometry/rigid3.h"
#include "core/io/image_io.h"
#include "core/io/qsm_io.h"
#include "core/io/skeleton_io.h"
#include "core/util/check.h"
#include "datasets/synthetic/synthetic_qsm.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/bark_crossings.h"
#include "mesh/bark_mesh.h"
#include "mesh/mesh_checks.h"
#include "mesh/mesh_renderer.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

void Classify(const SkeletonGraph& g, const TriangleMesh& mesh,
              const std::vector<BarkTriangleOrigin>& origins);

void Probe(const SkeletonGraph& g, const std::string& name, double reference_volume,
           const BarkMeshOptions& options = BarkMeshOptions()) {
  BarkMeshSummary summary;
  std::vector<BarkTriangleOrigin> origins;
  const TriangleMesh bark = MeshBarkWatertight(g, options, &summary, &origins);
  BranchMeshSummary tube_summary;
  const TriangleMesh tubes = MeshBranches(g, BranchMeshOptions(), &tube_summary);
  const MeshCheck check = CheckMesh(bark);
  std::printf("%s: %d nodes\n  %s\n  %s\n  volume %.4f vs cylinder sum %.4f (ratio %.4f)\n",
              name.c_str(), g.NumNodes(), summary.BriefReport().c_str(),
              check.BriefReport().c_str(), check.volume, reference_volume,
              check.volume / reference_volume);
  std::printf("  overlapping tubes: %d triangles in %.3f s; %s\n", tubes.NumTriangles(),
              tube_summary.seconds, CheckMesh(tubes).BriefReport().c_str());
  Classify(g, bark, origins);
}

// Where do the crossing triangles sit? ClassifyBarkCrossings (at junctions,
// within a branch, colliding skeleton branches), then the pairs by the kinds
// of pieces their triangles were made for (tube, attachment, joint).
void Classify(const SkeletonGraph& g, const TriangleMesh& mesh,
              const std::vector<BarkTriangleOrigin>& origins) {
  std::printf("  %s\n", ClassifyBarkCrossings(g, mesh, origins).BriefReport().c_str());
  const char* kind_name[] = {"tube", "attachment", "joint"};
  std::map<std::string, int> kinds;
  for (const auto& [t1, t2] : FindSelfIntersections(mesh)) {
    std::string k1 = kind_name[origins[t1].kind], k2 = kind_name[origins[t2].kind];
    if (k2 < k1) std::swap(k1, k2);
    ++kinds[k1 + "-" + k2];
  }
  for (const auto& [name, count] : kinds) std::printf("    %-22s %d\n", name.c_str(), count);
}

void Picture(const std::string& path) {
  const SkeletonGraph g = GenerateSyntheticSkeleton(SyntheticTreeOptions(), 1);
  const std::vector<std::vector<int>> children = g.Children();
  int junction = -1;
  const std::vector<BranchAxis> axes = g.BranchAxes();
  for (int i : axes.front()) {
    if (children[i].size() >= 2) {
      junction = i;
      break;
    }
  }
  SYLVA_CHECK(junction >= 0);
  const Eigen::Vector3d target = g.nodes[junction].position;
  const Eigen::Vector3d lateral = g.nodes[children[junction].back()].position - target;
  Eigen::Vector3d side = lateral.cross(Eigen::Vector3d::UnitZ());
  if (side.norm() < 1e-9) side = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d eye = target + 0.9 * side.normalized() + Eigen::Vector3d(0, 0, 0.15);
  const Camera camera = Camera::Pinhole(640, 640, 700);
  const Rigid3d pose = LookAt(eye, target + Eigen::Vector3d(0, 0, 0.15), Eigen::Vector3d::UnitZ());
  MeshRenderOptions options;
  options.samples_per_axis = 3;
  const FloatImage left = MeshRenderer(MeshBarkWatertight(g, BarkMeshOptions(), nullptr))
                              .RenderRgba(camera, pose, options);
  const FloatImage right =
      MeshRenderer(MeshBranches(g, BranchMeshOptions(), nullptr)).RenderRgba(camera, pose, options);
  FloatImage both(2 * camera.width(), camera.height(), 4);
  for (int y = 0; y < camera.height(); ++y) {
    for (int x = 0; x < camera.width(); ++x) {
      for (int c = 0; c < 4; ++c) {
        both.at(x, y, c) = left.at(x, y, c);
        both.at(x + camera.width(), y, c) = right.at(x, y, c);
      }
    }
  }
  WriteImage(path, both);
  std::printf("picture of junction node %d (left watertight, right tubes): %s\n", junction,
              path.c_str());
}

// The inside-out components of a bark: per component (by shared vertices)
// its signed volume; the negative ones with what their triangles were made
// for (the first triangle's origin: kind, node, next, radius).
void InsideOut(const SkeletonGraph& g, const TriangleMesh& mesh,
               const std::vector<BarkTriangleOrigin>& origins) {
  std::vector<int> parent(mesh.NumVertices());
  for (int v = 0; v < mesh.NumVertices(); ++v) parent[v] = v;
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 1; k < 3; ++k) {
      const int a = find(t[0]), b = find(t[k]);
      if (a != b) parent[a] = b;
    }
  }
  std::map<int, double> volume;
  std::map<int, int> first, count;
  std::map<int, std::set<int>> kinds;
  for (int t = 0; t < mesh.NumTriangles(); ++t) {
    const Eigen::Vector3i& f = mesh.triangles[t];
    const int c = find(f[0]);
    const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>(),
                          b = mesh.vertices[f[1]].cast<double>(),
                          d = mesh.vertices[f[2]].cast<double>();
    volume[c] += a.dot(b.cross(d)) / 6;
    if (!first.count(c)) first[c] = t;
    ++count[c];
    kinds[c].insert(origins[t].kind);
  }
  int negative = 0;
  int largest = -1;
  for (const auto& [c, n] : count) {
    if (largest < 0 || n > count[largest]) largest = c;
  }
  for (const auto& [c, v] : volume) {
    if (c == largest) continue;
    const BarkTriangleOrigin& o = origins[first[c]];
    if (v < 0 || o.node < 0) continue;
    const SkeletonNode& u = g.nodes[o.node];
    const SkeletonNode& w = g.nodes[o.next];
    const Eigen::Vector3d d = (w.position - u.position).normalized();
    const Eigen::Vector3d up =
        u.parent_idx >= 0
            ? Eigen::Vector3d((u.position - g.nodes[u.parent_idx].position).normalized())
            : Eigen::Vector3d::UnitZ();
    std::printf(
        "    extra component: volume %.3g, %d triangles, node %d (r %.4f, %zu children) -> %d "
        "(r %.4f, edge %.4f, %.0f deg off the parent)\n",
        v, count[c], o.node, u.radius, g.Children()[o.node].size(), o.next, w.radius,
        (w.position - u.position).norm(), std::acos(std::clamp(d.dot(up), -1.0, 1.0)) * 180 / M_PI);
  }
  for (const auto& [c, v] : volume) {
    if (v >= 0) continue;
    ++negative;
    const BarkTriangleOrigin& o = origins[first[c]];
    std::string kind_list;
    for (int k : kinds[c]) kind_list += std::to_string(k);
    std::printf(
        "    inside out: volume %.3g, %d triangles, kinds %s, first origin kind %d node %d "
        "next %d r %.4f children %zu\n",
        v, count[c], kind_list.c_str(), o.kind, o.node, o.next,
        o.node >= 0 ? g.nodes[o.node].radius : -1.0, o.node >= 0 ? g.Children()[o.node].size() : 0);
  }
  std::printf("  %zu components, %d inside out\n", volume.size(), negative);
}

int Main(int argc, char** argv) {
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--synth-qsm") == 0 && a + 1 < argc) {
      // A generated laser-scan-like table (datasets/synthetic/synthetic_qsm.h).
      // SYLVA_QSM_NOISE=P,R: position and radius noise (default 0.3,0.1).
      SyntheticQsmOptions synth;
      if (const char* noise = std::getenv("SYLVA_QSM_NOISE")) {
        std::sscanf(noise, "%lf,%lf", &synth.position_noise, &synth.radius_noise);
      }
      const QsmModel qsm = GenerateSyntheticQsm(synth, std::atoi(argv[++a]));
      std::printf("synthetic QSM: %zu cylinders, noise %.2f/%.2f\n", qsm.cylinders.size(),
                  synth.position_noise, synth.radius_noise);
      QsmToSkeletonOptions convert;
      convert.merge_fraction = 0.1;
      convert.merge_inside_parent = std::getenv("SYLVA_KEEP_CONNECTORS") == nullptr;
      double volume = 0.0;
      BarkMeshOptions options;  // as mesh-qsm meshes
      options.tube.circle_area = std::getenv("SYLVA_INSCRIBED") == nullptr;
      for (const QsmSkeleton& part : SkeletonsFromQsm(qsm, convert)) {
        BarkMeshSummary summary;
        std::vector<BarkTriangleOrigin> origins;
        const TriangleMesh bark = MeshBarkWatertight(part.skeleton, options, &summary, &origins);
        std::printf("part of %d nodes: %s\n", part.skeleton.NumNodes(),
                    summary.BriefReport().c_str());
        InsideOut(part.skeleton, bark, origins);
        volume += CheckMesh(bark, "", false).volume;
      }
      std::printf("bark volume / cylinders' union %.4f\n", volume / QsmUnionVolume(qsm, 64, 1));
      continue;
    }
    if (std::strcmp(argv[a], "--skeleton") == 0 && a + 1 < argc) {
      const SkeletonGraph g = ReadSkeletonJson(argv[++a]);
      Probe(g, argv[a], 0.0);
      continue;
    }
    if (std::strcmp(argv[a], "--classify") == 0 && a + 1 < argc) {
      // N: seeds 1..N; -S: seed S alone.
      const int seeds = std::atoi(argv[++a]);
      for (int seed = seeds < 0 ? -seeds : 1; seed <= std::abs(seeds); ++seed) {
        const SkeletonGraph g = GenerateSyntheticSkeleton(SyntheticTreeOptions(), seed);
        std::vector<BarkTriangleOrigin> origins;
        BarkMeshSummary summary;
        const TriangleMesh bark = MeshBarkWatertight(g, BarkMeshOptions(), &summary, &origins);
        std::printf("synthetic seed %d: %d nodes\n  %s\n", seed, g.NumNodes(),
                    summary.BriefReport().c_str());
        Classify(g, bark, origins);
      }
      continue;
    }
    if (std::strcmp(argv[a], "--picture") == 0 && a + 1 < argc) {
      Picture(argv[++a]);
      continue;
    }
    // The table through sylva's reader (core/io/qsm_io.h), one skeleton per
    // root cylinder, connectors merged as `sylva mesh-qsm` does.
    const QsmModel qsm = ReadQsmCsv(argv[a]);
    QsmToSkeletonOptions convert;
    convert.merge_fraction = 0.1;
    convert.merge_inside_parent = true;
    const std::vector<QsmSkeleton> parts = SkeletonsFromQsm(qsm, convert);
    for (size_t k = 0; k < parts.size(); ++k) {
      // Volume of this part's cylinders (a cylinder spans several nodes).
      const std::set<int64_t> ids(parts[k].cylinder_ids.begin(), parts[k].cylinder_ids.end());
      double volume = 0.0;
      for (const QsmCylinder& c : qsm.cylinders) {
        if (ids.count(c.id)) volume += M_PI * c.radius * c.radius * c.length;
      }
      BarkMeshOptions options;  // as mesh-qsm meshes
      options.tube.circle_area = true;
      Probe(parts[k].skeleton, std::string(argv[a]) + " part " + std::to_string(k), volume,
            options);
    }
  }
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  return sylva::GuardedMain([&] { return sylva::Main(argc, argv); });
}
