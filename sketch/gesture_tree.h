// Trees grown from 3D gestures (issue 17; Murakami, Onishi, Kitamura and
// Kishino, "Modeling of Trees with 3D Gestures and Growth Simulation").
//
// Trunk-based modelling (section 4.1): each trunk stroke is resampled,
// smoothed and turned into a trunk L-string of T(length, radius, stroke)
// modules (drawn like F, never corrected) and the turns between them,
// +(yaw) &(pitch): about U, then L (then H, not needed) of the turtle's
// frame as in 4.1.3; the trunk's radius is inversely proportional
// to the stroke's speed (section 5.2). Later trunk strokes join the trunk
// at its point closest to where they start (5.2) and are pushed off the
// trunks drawn before them where they would pierce them (4.1.5). Growth
// points A(l, r, h) are put on the trunks (4.1.4) and the interactive
// L-system (sketch/lsystem.h) rewrites only the modules inside the region
// of interest, a supertoroid (eq. 3) fitted to the ROI strokes or, without
// any, to the gestures (4.2). Every new branch segment is checked against
// the branch capsules grown before it: one that would leave the region is
// shortened to its boundary, one that would collide is turned away from
// the obstacle (the bypass direction of 4.1.5), else shortened, else
// pruned with the rest of its branch. The corrections are written back
// into the L-string, whose positions are then those of the tree.
// Established segments (grown in earlier steps) keep their place: each
// step first lays them out as obstacles, then grows the new ones (two
// passes). Silhouette-based modelling (4.2): without a trunk stroke, a
// straight trunk up the region's axis, from the ground, carries the growth
// points. The grammar's own axiom is not used by gestures.
//
// Files: the region is sketch/gesture_roi.h; the trunk strokes' analysis
// sketch/gesture_trunks.h and the turtle frame and capsules
// sketch/gesture_geometry.h (both internal); the L-system growth under
// collision avoidance is gesture_tree.cc.
#ifndef SYLVA_SKETCH_GESTURE_TREE_H_
#define SYLVA_SKETCH_GESTURE_TREE_H_

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/types/skeleton_graph.h"
#include "sketch/gesture_io.h"
#include "sketch/gesture_options.h"
#include "sketch/gesture_roi.h"
#include "sketch/lsystem.h"

namespace sylva {

// The default grammar (also datasets/gesture/broadleaf.lsys): a broadleaf
// crown grown from the growth points A(l, r, h).
extern const char kDefaultGestureGrammar[];

struct GestureTree {
  SkeletonGraph skeleton;  // radii from the strokes and the grammar (world units)
  Supertoroid roi;
  bool roi_from_strokes = false;
  bool silhouette_based = false;  // no trunk stroke (4.2)
  // Per trunk stroke: its skeleton nodes, base to tip.
  std::vector<std::vector<int>> trunk_nodes;
  LsystemString lstring;     // the final L-string, corrected
  std::string lstring_text;  // as text (LsystemGrammar::ToText)
  int growth_points = 0;
  int modules = 0;
  int segments_turned = 0, segments_shortened = 0, segments_clipped = 0, segments_pruned = 0;
  int trunk_points_pushed = 0;
  double min_capsule_distance = 0.0;  // MinNonAdjacentCapsuleDistance(skeleton)
  std::string brief;
};

// Grows the tree of `gestures` with `grammar`. Throws InputError naming
// the gesture file when it has neither trunk nor ROI strokes of length.
GestureTree GrowGestureTree(const GestureSet& gestures, const LsystemGrammar& grammar,
                            const GestureTreeOptions& options);
// The grammar of options.grammar, or the default one, with the constants
// of options.defines. Throws InputError naming the grammar file (line,
// column) or Gesture.defines.
LsystemGrammar LoadGestureGrammar(const GestureTreeOptions& options);
// "NAME=VALUE,NAME=VALUE" as a map; throws InputError naming
// Gesture.defines.
std::map<std::string, double> ParseDefines(const std::string& defines);

// Two edges of a skeleton (node -> parent) are adjacent when the skeleton
// path between their nearest ends is no longer than twice the sum of their
// radii (they are one tube there: a branch leaving its parent at 30 degrees
// or more is clear of the parent's capsule beyond that path). Returns the smallest surface distance
// between non-adjacent edges' capsules (axis distance minus both radii); negative when two overlap;
// +infinity with fewer than two non-adjacent edges.
double MinNonAdjacentCapsuleDistance(const SkeletonGraph& skeleton);

// The largest distance between the stroke's polyline and the trunk's
// (both directions), over the stroke's length.
double TrunkDeviationFraction(const GestureStroke& stroke, const SkeletonGraph& skeleton,
                              const std::vector<int>& trunk_nodes);

}  // namespace sylva

#endif  // SYLVA_SKETCH_GESTURE_TREE_H_
