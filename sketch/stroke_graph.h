// Drawn strokes -> the photo's attractor graph (thesis 3.2.2, the "manually
// sketched graph"): a forest whose edges point down the tree.
//
//   StrokeSet strokes = ReadStrokes(project / "edits/IMG_0001.jpg.strokes.svg", 1440, 1080);
//   AttractorGraph2D graph = GraphFromStrokes(strokes, StrokeGraphOptions());
//
// How strokes become a graph:
//   1. Each stroke is simplified (Douglas-Peucker, simplify_tolerance), which
//      drops the dense points of flattened curves but keeps corners.
//   2. Joins: for every stroke end in turn (stroke 0's start, stroke 0's end,
//      stroke 1's start, ...) that is not yet joined, the end moves onto
//      another stroke if one lies within snap_distance, and becomes a
//      junction node there: onto the nearest end or junction of another
//      stroke within snap_distance if there is one (so that three strokes
//      drawn to a fork share one node), else onto the nearest point of
//      another stroke (an existing node, or a new node splitting that
//      segment). Nodes already on the end's own stroke are never targets.
//      Strokes join only at their ends: two strokes that cross in their
//      middles stay unconnected there.
//   3. Segments longer than resample_spacing are split evenly.
//   4. The main root: if StrokeSet::root is given, the nearest point of the
//      graph (an existing node, or a new one splitting the nearest segment);
//      otherwise the lowest node (largest y; the first in node order on ties)
//      of the component with the greatest total length. Every other
//      connected component's root is its lowest node.
//   5. Orientation: every node's parent is its neighbour on the shortest
//      path (by length along the strokes) to its component's root
//      (Dijkstra; ties go to the lower node index). Where strokes form a
//      cycle, the one segment that closes it is kept as an extra leaf: a
//      copy of its farther node hangs from the nearer one, so no drawn
//      segment is lost and the result is a forest.
// Node order of the result: the main component first, each component in
// the order Dijkstra settles its nodes, so the root is node 0 and every
// parent comes before its children. source = "strokes".
#ifndef SYLVA_SKETCH_STROKE_GRAPH_H_
#define SYLVA_SKETCH_STROKE_GRAPH_H_

#include "core/types/attractor_graph.h"
#include "sketch/strokes.h"

namespace sylva {

struct StrokeGraphOptions {
  // A stroke end within this distance of another stroke joins it (pixels,
  // >= 0). About the slack of a stroke drawn with a mouse on a zoomed-out
  // photo.
  double snap_distance = 10.0;
  // Drawn points within this distance of the simplified stroke are dropped
  // (pixels, >= 0; 0 keeps every point).
  double simplify_tolerance = 0.5;
  // Segments longer than this are split evenly, so nodes are at most this
  // far apart along a stroke (pixels, > 0; infinity keeps the drawn points
  // only).
  double resample_spacing = 8.0;

  // Throws InputError naming the option that is out of range.
  void Check() const;
};

// Throws InputError if `strokes` fails StrokeSet::Check or the options are
// out of range. The result passes AttractorGraph2D::Check.
AttractorGraph2D GraphFromStrokes(const StrokeSet& strokes, const StrokeGraphOptions& options);

}  // namespace sylva

#endif  // SYLVA_SKETCH_STROKE_GRAPH_H_
