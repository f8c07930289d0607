// By-hand probe of the watertight bark mesher (mesh/bark_mesh.h) on real
// QSM cylinder tables and a picture of one junction.
//
// For every QSM table (CSV with columns id, parent_id, start_x/y/z,
// axis_x/y/z, length, radius, ...: the ITSMe qsm_csv format), read by
// core/io/qsm_io.h into one skeleton per root cylinder. Prints triangles, CheckMesh of the watertight mesh and the
// overlapping tubes, and the mesh volume against the sum of the cylinders'
// volumes (pi r^2 L).
//
// --picture PATH: renders a close-up of the first trunk junction of the
// synthetic tree (seed 1) with both meshers side by side (left: watertight,
// right: MeshBranches), PNG.
//
// --skeleton PATH: a sylva skeleton (out/skeleton.json of a project).
//
// usage: sylva_bark_probe [--picture out.png] [--skeleton skeleton.json] [qsm.csv ...]
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
#include "core/geometry/polyline.h"
#include "core/util/check.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/bark_mesh.h"
#include "mesh/mesh_checks.h"
#include "mesh/mesh_renderer.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

void Classify(const SkeletonGraph& g, const TriangleMesh& mesh,
              const std::vector<BarkTriangleOrigin>& origins);

void Probe(const SkeletonGraph& g, const std::string& name, double reference_volume) {
  BarkMeshSummary summary;
  std::vector<BarkTriangleOrigin> origins;
  const TriangleMesh bark = MeshBarkWatertight(g, BarkMeshOptions(), &summary, &origins);
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

// Where do the crossing triangles sit? Each pair is named by the pieces its
// triangles were made for (tube, attachment of a lateral, convex joint) and
// by how far apart those pieces' nodes are in the skeleton (edges). Far
// pairs whose skeleton edges come closer than the sum of their radii are
// branches that collide in the skeleton itself, not at a junction.
void Classify(const SkeletonGraph& g, const TriangleMesh& mesh,
              const std::vector<BarkTriangleOrigin>& origins) {
  const std::vector<std::pair<int, int>> pairs = FindSelfIntersections(mesh);
  auto hops = [&](int a, int b) {  // edges on the tree path between nodes a and b
    std::map<int, int> up_a;
    int k = 0;
    for (int x = a; x >= 0; x = g.nodes[x].parent_idx) up_a[x] = k++;
    int steps_b = 0;
    for (int x = b; x >= 0; x = g.nodes[x].parent_idx, ++steps_b) {
      const auto it = up_a.find(x);
      if (it != up_a.end()) return it->second + steps_b;
    }
    return 1 << 20;
  };
  // A tube triangle's nearest skeleton edge (by surface distance) along its
  // chain, which follows the axis children down (or the parents up).
  std::vector<int> axis_child(g.NumNodes(), -1);
  for (const BranchAxis& axis : g.BranchAxes()) {
    for (size_t k = 0; k + 1 < axis.size(); ++k) {
      if (axis_child[axis[k]] < 0 || k > 0) axis_child[axis[k]] = axis[k + 1];
    }
  }
  auto nodes_of = [&](int t) {
    const BarkTriangleOrigin& o = origins[t];
    if (o.kind != BarkTriangleOrigin::kTube) {
      std::vector<int> n = {o.node};
      if (o.next >= 0) n.push_back(o.next);
      return n;
    }
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) c += mesh.vertices[mesh.triangles[t][k]].cast<double>() / 3.0;
    const bool down = g.nodes[o.next].parent_idx == o.node;
    int a = o.node, b = o.next, best_a = a, best_b = b;
    double best = 1e300;
    for (int steps = 0; steps < 100000 && b >= 0; ++steps) {
      double s = 0;
      const double d =
          std::sqrt(SegmentDistance2(c, g.nodes[a].position, g.nodes[b].position, &s));
      const int child = down ? b : a;
      if (std::abs(d - g.nodes[child].radius) < best) {
        best = std::abs(d - g.nodes[child].radius);
        best_a = a;
        best_b = b;
      }
      a = b;
      b = down ? axis_child[b] : g.nodes[b].parent_idx;
    }
    return std::vector<int>{best_a, best_b};
  };
  const char* kind_name[] = {"tube", "attachment", "joint"};
  std::map<std::string, int> classes;
  int colliding = 0;
  for (const auto& [t1, t2] : pairs) {
    const BarkTriangleOrigin& o1 = origins[t1];
    const BarkTriangleOrigin& o2 = origins[t2];
    int h = 1 << 20;
    const std::vector<int> n1 = nodes_of(t1), n2 = nodes_of(t2);
    for (int a : n1)
      for (int b : n2) h = std::min(h, hops(a, b));
    const bool same = o1.kind == o2.kind && o1.node == o2.node && o1.next == o2.next;
    std::string k1 = kind_name[o1.kind], k2 = kind_name[o2.kind];
    if (k2 < k1) std::swap(k1, k2);
    const std::string relation =
        same ? "same piece" : h == 0 ? "share a node" : h <= 3 ? "1-3 edges apart" : "far";
    ++classes[k1 + "-" + k2 + ", " + relation];
    if (!same && (h <= 3 || o1.kind == BarkTriangleOrigin::kJoint || o2.kind == BarkTriangleOrigin::kJoint) && std::getenv("SYLVA_PROBE_VERBOSE") != nullptr) {
      std::printf("      %s (%d,%d) nearest edge (%d,%d) x %s (%d,%d) nearest edge (%d,%d)\n",
                  kind_name[o1.kind], o1.node, o1.next, n1[0], n1.back(), kind_name[o2.kind],
                  o2.node, o2.next, n2[0], n2.back());
      for (int t : {t1, t2}) {
        std::printf("       tri %d:", t);
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d v = mesh.vertices[mesh.triangles[t][k]].cast<double>();
          const Eigen::Vector3d rel = v - g.nodes[o2.node].position;
          std::printf(" (%.4f %.4f %.4f)", rel.x(), rel.y(), rel.z());
        }
        std::printf("\n");
      }
    }
    if (!same && h > 3) {
      // Do the skeleton edges next to the two pieces collide?
      auto child_of = [&](const std::vector<int>& n) {
        return n.size() > 1 && g.nodes[n[1]].parent_idx == n[0] ? n[1] : n[0];
      };
      const int e1 = child_of(n1), e2 = child_of(n2);
      const int p1 = g.nodes[e1].parent_idx, p2 = g.nodes[e2].parent_idx;
      if (p1 >= 0 && p2 >= 0) {
        double dmin = 1e300;
        for (int s = 0; s <= 50; ++s) {
          const Eigen::Vector3d p =
              g.nodes[p1].position + (g.nodes[e1].position - g.nodes[p1].position) * (s / 50.0);
          dmin = std::min(dmin, std::sqrt(SegmentDistance2(p, g.nodes[p2].position,
                                                           g.nodes[e2].position)));
        }
        if (dmin < g.nodes[p1].radius + g.nodes[p2].radius) ++colliding;
      }
    }
  }
  std::printf("  %zu crossing pairs (%d far pairs next to colliding skeleton edges)\n  %s\n",
              pairs.size(), colliding, ClassifyBarkCrossings(g, mesh, origins).BriefReport().c_str());
  for (const auto& [name, count] : classes) std::printf("    %-40s %d\n", name.c_str(), count);
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
  const FloatImage left =
      MeshRenderer(MeshBarkWatertight(g, BarkMeshOptions(), nullptr)).RenderRgba(camera, pose, options);
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

int Main(int argc, char** argv) {
  for (int a = 1; a < argc; ++a) {
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
        const TriangleMesh bark = MeshBarkWatertight(g, BarkMeshOptions(), nullptr, &origins);
        std::printf("synthetic seed %d: %d nodes, %d triangles\n", seed, g.NumNodes(),
                    bark.NumTriangles());
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
    const std::vector<QsmSkeleton> parts = SkeletonsFromQsm(qsm, convert);
    for (size_t k = 0; k < parts.size(); ++k) {
      // Volume of this part's cylinders (a cylinder spans several nodes).
      const std::set<int64_t> ids(parts[k].cylinder_ids.begin(), parts[k].cylinder_ids.end());
      double volume = 0.0;
      for (const QsmCylinder& c : qsm.cylinders) {
        if (ids.count(c.id)) volume += M_PI * c.radius * c.radius * c.length;
      }
      Probe(parts[k].skeleton, std::string(argv[a]) + " part " + std::to_string(k), volume);
    }
  }
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  return sylva::GuardedMain([&] { return sylva::Main(argc, argv); });
}
