// Branch radii from the pipe model (thesis 5.1).
//
// Every edge of the skeleton carries `strands` particles (the "strands" of
// Holton's model, the pipes of Shinozaki's pipe model). The radius of an edge
// follows the allometric power law
//
//   r = t * S^(1/Δ)                         (thesis 5.1: d = t sqrt(S) for Δ = 2)
//
// with Δ the diameter exponent (Mandelbrot) and t fixed by the trunk: the
// root edge, which carries all S_root strands, gets `trunk_radius`. Where
// strands are conserved at a junction (a parent carries the sum of its
// children), the radii then satisfy the allometric junction rule exactly:
//
//   d0^Δ = Σ di^Δ        (eq. 5.1 for Δ = 2, Leonardo; Murray's 2.49)
//
// Radii computed this way are an estimate, not a measurement: the skeleton's
// radius_source is set to "allometric prior", and every output that carries
// these radii must say so.
#ifndef SYLVA_MESH_ALLOMETRY_H_
#define SYLVA_MESH_ALLOMETRY_H_

#include <vector>

#include "core/types/skeleton_graph.h"

namespace sylva {

// The label AssignPipeModelRadii writes into SkeletonGraph::radius_source.
inline constexpr const char* kAllometricPrior = "allometric prior";

struct AllometryOptions {
  // Δ, the diameter exponent of d0^Δ = Σ di^Δ: 2 = Leonardo da Vinci's rule
  // (area preserving, the pipe model), 2.49 = Murray's measurements, 3 =
  // space-filling (lungs). In [1, 4].
  double diameter_exponent = 2.0;
  // Radius of the root edge (the trunk at its base), in world units (> 0).
  // The pipe model fixes ratios only; the caller sets the scale, e.g. from
  // the trunk width measured in the photos (mesh/trunk_width.h).
  double trunk_radius = 0.15;
  // Smallest radius assigned, in world units, in [0, trunk_radius]. Thinner
  // edges are raised to it so that twigs stay visible; there the junction
  // rule holds only approximately. 0 keeps the pure power law.
  double min_radius = 0.002;

  // Throws InputError("Allometry.<field>", ...) naming the violated constraint.
  void Check() const;
};

// The strands each node's edge carries, as used for its radius (indexed like
// skeleton.nodes). Known counts are kept where they are consistent; the
// pipe model's conservation fills in the rest:
//   effective(i) = max(strands(i), Σ effective(children of i)),
// where a tip with unknown strands (0) counts as one strand. So a skeleton
// without strands gets the number of tips each edge leads to (every tip one
// strand), a partly known one never gets thinner towards the base, and a
// consistent one (parent = sum of children) is returned unchanged.
std::vector<double> EffectivePipeStrands(const SkeletonGraph& skeleton);

// Sets every node's radius (the radius of its edge to the parent; the
// root's is trunk_radius) to
//   max(min_radius, trunk_radius * (S_i / S_root)^(1 / Δ))
// with S = EffectivePipeStrands(), and radius_source to "allometric prior".
// Strands are left as they are. An empty skeleton is left unchanged.
// Throws InputError for bad options, Error for a skeleton failing Check().
void AssignPipeModelRadii(const AllometryOptions& options, SkeletonGraph* skeleton);

}  // namespace sylva

#endif  // SYLVA_MESH_ALLOMETRY_H_
