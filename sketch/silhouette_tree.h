// Trees from crown silhouettes: "structure from silhouettes" (Wither, Boudon,
// Cani, Godin 2009). A drawing's crown outline, and optionally smaller
// outlines drawn inside it (sub-silhouettes) and branches drawn over it,
// become a branching structure in the drawing's plane, then a 3D tree:
//   - major branches (section 3.1): the outline is cut into bumps at its
//     concavities; a branch ends at each bump's centre E, arriving along
//     the bump's axis (from E towards the bump's apex). The paper takes E
//     and that tangent from the terminal points of a geometric skeleton of
//     the silhouette; here E is where the distance to the outline peaks on
//     the way in from the apex, which is the same point for a round bump;
//   - the branching angle function (BAF, 3.2) gives the angle between the
//     parent's tangent and a child's at their junction, linear along the
//     parent from `baf_base_deg` to `baf_tip_deg` (plagiotropic below,
//     orthotropic above); the branch is the shortest of the cubic Hermite
//     curves from the parent's points B_i (leaving at the BAF's angle) to E,
//     tangents half |E - B_i| long;
//   - branches drawn over the silhouette (3.3) replace the inferred branch
//     whose ends are nearest theirs, add their angle to the BAF, and give
//     their shape to the inferred siblings (in each branch's span frame,
//     scaled by the spans' ratio, mirrored on the other side of the parent);
//   - sub-silhouettes (4.1): each branch's crown is the part of its parent's
//     outline inside a cone around the branch (from its base B along B -> E;
//     its angle from cone_min_deg for a sharp bump to cone_max_deg for a
//     round one, by the ratio of E's distance to the outline and |E - B|),
//     closed to B by two Hermite curves;
//   - coverage (4.1): where the children's crowns leave the parent's crown
//     uncovered, copies of the nearest sibling (branch and crown, turned to
//     the BAF's angle and scaled to fit inside the parent's crown) are added
//     along both sides of the parent, from its base up, unless they overlap
//     the siblings' crowns by more than max_overlap of their own area;
//   - refining and style copying (4.2): a sub-silhouette drawn by the user
//     becomes the crown of the branch whose length it covers most; the next
//     level's branches are inferred in it (the same steps, the branch as
//     the parent), and copied to the siblings without a drawn crown, in
//     span frames as above. Without a drawn sub-silhouette, each branch's
//     children are inferred in its own inferred crown. `levels` levels of
//     branches in all;
//   - 3D (section 5): the branches on each parent are placed around it by a
//     Gibbs process over their insertion points (theta, u) on the unrolled
//     parent (5.2): u stays where the drawing puts it, theta of the drawn
//     (inferred) branches stays within `drawn_spread_deg` (45) of the
//     drawing's plane on their side (5.3), and `extra_branches` more branches per drawn one
//     (copies of the nearest sibling, any theta and u between the lowest and
//     highest sibling) fill the crown in depth. The cost is the closeness
//     penalty f = 1 / (1 + alpha d) of d = |(du, dtheta / 360)|^2, or with a
//     phyllotaxis g = w1 f + w2 d_pattern, the distance to the nearest
//     privileged position of the pattern (5.4: spiral 144 degrees one branch
//     per node, decussate 90 degrees two per node, whorls of three 60
//     degrees), minimised by depletion-replacement (a random branch moved at
//     random, kept if F falls; `gibbs_iterations` trials). Each branch then
//     turns, with everything it carries, about its parent's tangent at the
//     junction from its side of the drawing's plane to its theta.
// Deterministic for a seed.
#ifndef SYLVA_SKETCH_SILHOUETTE_TREE_H_
#define SYLVA_SKETCH_SILHOUETTE_TREE_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"

namespace sylva {

// A closed outline or an open polyline in the drawing's plane: x across, y up
// (world units).
using Outline2 = std::vector<Eigen::Vector2d>;

// Whether `p` is inside the closed `outline` (even-odd rule).
bool InsideOutline(const Outline2& outline, const Eigen::Vector2d& p);
// The area the closed `outline` encloses (a simple polygon).
double OutlineArea(const Outline2& outline);

struct SilhouetteTreeOptions {
  // The BAF at the parent's base and tip, degrees from the parent's tangent.
  double baf_base_deg = 70.0;
  double baf_tip_deg = 30.0;
  // Concavities of an outline deeper than this share of its size split it
  // into bumps.
  double valley_depth = 0.04;
  // The sub-silhouette cone's angle, degrees: sharp bumps to round ones.
  double cone_min_deg = 20.0;
  double cone_max_deg = 110.0;
  // Levels of branches below the trunk (3 left wide gaps in the crowns of
  // the bundled drawings: front-view IoU median 0.27 against 0.42 with 4).
  int levels = 4;
  // Coverage: a copied branch is rejected if its crown overlaps its
  // siblings' crowns by more than this share of its area.
  double max_overlap = 0.2;
  // 3D: branches from the drawing turn at most this far out of its plane,
  // degrees (the paper's 45: people draw the branches that spread sideways).
  double drawn_spread_deg = 45.0;
  // 3D: more branches per drawn one on each parent, placed in depth.
  double extra_branches = 1.0;
  // "none" (closeness only), "spiral", "decussate" or "whorl3".
  std::string phyllotaxis = "spiral";
  // The closeness penalty's alpha (the paper's 20) and the Gibbs trials per
  // parent.
  double gibbs_alpha = 20.0;
  int gibbs_iterations = 3000;
  // Branches shorter than this share of the tree's height are not inferred.
  double min_branch_share = 0.02;
  // At most this many branches: half of them in the drawing's plane
  // (inference stops there), and the 3D tree places no extra branch beyond
  // the half and no branch at all beyond the whole (breadth first: the
  // last parents' finest twigs go first).
  int max_branches = 3000;
  uint64_t seed = 1;

  // Throws InputError naming the first invalid option (Sketch.silhouette_*).
  void Check() const;
};

// The 2D structure.
struct SilhouetteBranch {
  Outline2 points;  // from the junction B (on the parent) to the end E
  int parent = -1;  // index of the parent branch; -1 for the trunk
  double u = 0.0;   // the junction's arc-length fraction along the parent
  int level = 0;    // 0 for the trunk
  Outline2 crown;   // its (sub-)silhouette, closed
  bool drawn_shape = false, drawn_crown = false, coverage = false;
};

struct SilhouetteStructure {
  std::vector<SilhouetteBranch> branches;  // parents before children
  int drawn_branches = 0, drawn_crowns = 0, coverage_branches = 0, copied_styles = 0;
};

// The 2D structure of a tree whose trunk runs along `trunk` (from the base
// up, through the crown) with `crown` its outline; `sub_silhouettes` are
// outlines drawn inside it and `drawn_branches` branches drawn over it
// (each from its end nearer the trunk). Throws InputError if the crown
// encloses nothing or the trunk has no length.
SilhouetteStructure InferSilhouetteStructure(const Outline2& trunk, const Outline2& crown,
                                             const std::vector<Outline2>& sub_silhouettes,
                                             const std::vector<Outline2>& drawn_branches,
                                             const SilhouetteTreeOptions& options);

// Insertion points of the branches on one parent (section 5): u in [0, 1],
// theta in degrees.
struct InsertionPoint {
  double u = 0.0, theta = 0.0;
  bool fixed_u = true;  // drawn: u stays
  double theta_min = 0.0, theta_max = 360.0;
};

// The Gibbs process's cost F of `points` (sum over pairs).
double GibbsCost(const std::vector<InsertionPoint>& points, const SilhouetteTreeOptions& options);
// Depletion-replacement from the points' current positions; returns the
// final cost.
double PlaceByGibbs(const SilhouetteTreeOptions& options, uint64_t seed,
                    std::vector<InsertionPoint>* points);

struct SilhouetteTree {
  SkeletonGraph skeleton;  // radius 0: the caller assigns radii
  SilhouetteStructure structure;
  int extra_branches = 0;
};

// The 3D tree of `structure` (the drawing's plane is y = 0: x across, z up),
// skeleton edges at most `max_edge` long.
SilhouetteTree PlaceSilhouetteTree(const SilhouetteStructure& structure, double max_edge,
                                   const SilhouetteTreeOptions& options);

}  // namespace sylva

#endif  // SYLVA_SKETCH_SILHOUETTE_TREE_H_
