// Benchmark of the two ways to mesh twigs (mesh/twigs.h, thesis 5.4), side
// by side on the same grown skeletons:
//   joined   (the reference): MeshBarkWatertight of the skeleton with its
//            twigs, one closed surface;
//   separate: MeshBarkWatertight of RemoveTwigs(grown) plus MeshTwigTubes,
//            a closed bark and one closed tube per twig axis.
// For each it prints the triangles, the meshing seconds (best of a few
// runs) and CheckMesh's verdict on the bark (closed 2-manifold? components,
// crossing triangle pairs), which is where Twigs.separate_above comes from.
//
// Trees: the synthetic generator's default tree (seeds 1-3), radii as
// generated, twigs grown with the default TwigOptions and no density grid
// (the rate as is); then, on seed 1, the twig rate scaled to see how the
// joined mesher's time grows with the number of twigs.
//
// usage: sylva_twig_mesh_benchmark [--quick]   (--quick: smoke test, seed 1,
// fewer twigs, one run, no self-intersection test)
#include <cstdio>
#include <cstring>
#include <string>

#include "datasets/synthetic/synthetic_tree.h"
#include "mesh/bark_mesh.h"
#include "mesh/mesh_checks.h"
#include "mesh/twigs.h"
#include "tests/bench/probe_main.h"

namespace sylva {
namespace {

struct Meshed {
  int bark_triangles = 0;
  int twig_triangles = 0;
  double seconds = 0.0;
  MeshCheck bark_check;
};

Meshed MeshJoined(const SkeletonGraph& grown, int repetitions, bool crossings) {
  Meshed out;
  TriangleMesh bark;
  out.seconds = BestSeconds(repetitions, [&] {
    bark = MeshBarkWatertight(grown, BarkMeshOptions(), nullptr);
  });
  out.bark_triangles = bark.NumTriangles();
  out.bark_check = CheckMesh(bark, "", crossings);
  return out;
}

Meshed MeshSeparate(const SkeletonGraph& grown, const TwigSummary& summary, int repetitions,
                    bool crossings) {
  Meshed out;
  TriangleMesh bark, twigs;
  out.seconds = BestSeconds(repetitions, [&] {
    bark = MeshBarkWatertight(RemoveTwigs(grown, summary), BarkMeshOptions(), nullptr);
    twigs = MeshTwigTubes(grown, summary, BranchMeshOptions(), TwigMeshOptions());
  });
  out.bark_triangles = bark.NumTriangles();
  out.twig_triangles = twigs.NumTriangles();
  out.bark_check = CheckMesh(bark, "", crossings);
  return out;
}

std::string Verdict(const MeshCheck& check) {
  char text[160];
  std::snprintf(text, sizeof(text), "%s, %d comp, %lld crossing pairs",
                check.boundary_edges + check.nonmanifold_edges + check.misoriented_edges == 0
                    ? "closed"
                    : "OPEN",
                check.components, static_cast<long long>(check.self_intersections));
  return text;
}

void PrintRow(const char* label, int twigs, const Meshed& m) {
  std::printf("  %-9s %6d twigs  bark %8d tri  twig tubes %8d tri  %7.2f s  bark: %s\n", label,
              twigs, m.bark_triangles, m.twig_triangles, m.seconds, Verdict(m.bark_check).c_str());
}

int Main(bool quick) {
  std::printf("Twig meshing benchmark (%s): joined (reference) vs separate\n",
              quick ? "quick mode" : "full mode");
  const int repetitions = quick ? 1 : 2;
  const bool crossings = !quick;
  TwigOptions twig_options;
  if (quick) twig_options.twigs_per_length = 0.3;
  const int num_seeds = quick ? 1 : 3;
  for (int seed = 1; seed <= num_seeds; ++seed) {
    const SkeletonGraph skeleton = GenerateSyntheticSkeleton(SyntheticTreeOptions(), seed);
    TwigSummary summary;
    const SkeletonGraph grown = GrowTwigs(skeleton, DensityGrid(), twig_options, &summary);
    const double bare_seconds = BestSeconds(repetitions, [&] {
      MeshBarkWatertight(skeleton, BarkMeshOptions(), nullptr);
    });
    const int bare_triangles = MeshBarkWatertight(skeleton, BarkMeshOptions(), nullptr).NumTriangles();
    std::printf("Seed %d: %d nodes, %d twigs (%d nodes added); bark without twigs %d tri in %.2f s\n",
                seed, skeleton.NumNodes(), summary.twigs, summary.nodes_added, bare_triangles,
                bare_seconds);
    const Meshed joined = MeshJoined(grown, repetitions, crossings);
    const Meshed separate = MeshSeparate(grown, summary, repetitions, crossings);
    PrintRow("joined", summary.twigs, joined);
    PrintRow("separate", summary.twigs, separate);
    std::printf("  joined / separate: time x%.2f, triangles x%.2f\n",
                joined.seconds / separate.seconds,
                static_cast<double>(joined.bark_triangles) /
                    (separate.bark_triangles + separate.twig_triangles));
  }
  // How the joined mesher scales with the number of twigs (seed 1).
  std::printf("Scaling with the twig rate (seed 1):\n");
  const SkeletonGraph skeleton = GenerateSyntheticSkeleton(SyntheticTreeOptions(), 1);
  const std::vector<double> rates =
      quick ? std::vector<double>{0.1} : std::vector<double>{0.05, 0.1, 0.2, 0.4, 0.8, 1.5};
  for (double rate : rates) {
    TwigOptions scaled = twig_options;
    scaled.twigs_per_length = rate;
    TwigSummary summary;
    const SkeletonGraph grown = GrowTwigs(skeleton, DensityGrid(), scaled, &summary);
    std::printf(" rate %.2f per twig length:\n", rate);
    PrintRow("joined", summary.twigs, MeshJoined(grown, repetitions, false));
    PrintRow("separate", summary.twigs, MeshSeparate(grown, summary, repetitions, false));
  }
  return 0;
}

}  // namespace
}  // namespace sylva

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  return sylva::GuardedMain([&] { return sylva::Main(quick); });
}
