// By-hand probe of the watertight bark mesher (mesh/bark_mesh.h) on real
// QSM cylinder tables and a picture of one junction.
//
// For every QSM table (CSV with columns id, parent_id, start_x/y/z,
// axis_x/y/z, length, radius, ...: the ITSMe qsm_csv format) a throwaway
// reader turns the cylinders into a skeleton (one node per cylinder end, the
// root at the first cylinder's start; a child cylinder hangs from its
// parent cylinder's end node, so laterals that leave mid-cylinder move to the
// parent's end). Prints triangles, CheckMesh of the watertight mesh and the
// overlapping tubes, and the mesh volume against the sum of the cylinders'
// volumes (pi r^2 L).
//
// --picture PATH: renders a close-up of the first trunk junction of the
// synthetic tree (seed 1) with both meshers side by side (left: watertight,
// right: MeshBranches), PNG.
//
// usage: sylva_bark_probe [--picture out.png] [qsm.csv ...]
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/geometry/rigid3.h"
#include "core/io/image_io.h"
#include "core/util/check.h"
#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/bark_mesh.h"
#include "mesh/mesh_checks.h"
#include "mesh/mesh_renderer.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

SkeletonGraph ReadQsm(const std::string& path, double* cylinder_volume) {
  std::ifstream in(path);
  SYLVA_CHECK_INPUT(in.good(), path) << "cannot open";
  std::string line;
  std::getline(in, line);
  SkeletonGraph g;
  std::map<long, int> end_node;
  *cylinder_volume = 0.0;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::vector<double> v;
    std::string cell;
    while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
    SYLVA_CHECK_INPUT(v.size() >= 10, path) << "row with " << v.size() << " columns";
    rows.push_back(v);
  }
  // Rows may list a child before its parent: add cylinders whose parent is
  // placed, until all are (a cylinder with an unknown parent is an error).
  std::vector<char> done(rows.size(), 0);
  // Further parentless cylinders (TreeQSM's detached pieces) and their
  // descendants are left out and counted.
  size_t placed = 0;
  for (size_t before = 1; placed != before;) {
    before = placed;
    for (size_t r = 0; r < rows.size(); ++r) {
      const std::vector<double>& v = rows[r];
      const long id = static_cast<long>(v[0]), parent = static_cast<long>(v[1]);
      if (done[r] || (parent != 0 && !end_node.count(parent)) || (parent == 0 && g.NumNodes() > 0)) {
        continue;
      }
      const Eigen::Vector3d start(v[2], v[3], v[4]), axis(v[5], v[6], v[7]);
      const double length = v[8], radius = v[9];
      *cylinder_volume += M_PI * radius * radius * length;
      int from;
      if (parent == 0) {
        from = g.AddNode(start, radius, -1, 0);
      } else {
        from = end_node.at(parent);
      }
      end_node[id] = g.AddNode(start + length * axis.normalized(), radius, from, 0);
      done[r] = 1;
      ++placed;
    }
  }
  if (placed < rows.size()) {
    std::printf("%s: %zu of %zu cylinders detached from the first one, left out\n", path.c_str(),
                rows.size() - placed, rows.size());
  }
  g.radius_source = "QSM cylinders";
  g.AssignOrders();
  return g;
}

void Probe(const SkeletonGraph& g, const std::string& name, double reference_volume) {
  BarkMeshSummary summary;
  const TriangleMesh bark = MeshBarkWatertight(g, BarkMeshOptions(), &summary);
  BranchMeshSummary tube_summary;
  const TriangleMesh tubes = MeshBranches(g, BranchMeshOptions(), &tube_summary);
  const MeshCheck check = CheckMesh(bark);
  std::printf("%s: %d nodes\n  %s\n  %s\n  volume %.4f vs cylinder sum %.4f (ratio %.4f)\n",
              name.c_str(), g.NumNodes(), summary.BriefReport().c_str(),
              check.BriefReport().c_str(), check.volume, reference_volume,
              check.volume / reference_volume);
  std::printf("  overlapping tubes: %d triangles in %.3f s; %s\n", tubes.NumTriangles(),
              tube_summary.seconds, CheckMesh(tubes).BriefReport().c_str());
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
    if (std::strcmp(argv[a], "--picture") == 0 && a + 1 < argc) {
      Picture(argv[++a]);
      continue;
    }
    double volume = 0.0;
    const SkeletonGraph g = ReadQsm(argv[a], &volume);
    Probe(g, argv[a], volume);
  }
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  return sylva::GuardedMain([&] { return sylva::Main(argc, argv); });
}
