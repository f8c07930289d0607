// Livewire tracing of 2D attractor graphs (thesis 3.2.2, after Chodorowski
// et al. 2005): from seed points on the tree in a photo, least-cost paths run
// through the image to one target point (the tree base, or the first
// branching on the trunk); the union of those paths, merged where they meet,
// is the attractor graph of that photo.
//
// The least-cost paths come from OpenCV's Intelligent Scissors
// (cv::segmentation::IntelligentScissorsMB, Mortensen & Barrett 1995): one
// Dijkstra map from the target serves every seed. Its three per-pixel
// features are not the usual edge features (which follow the *boundary* of
// an object) but features of the tree's *interior*, so that paths run along
// branches:
//   - "non-edge" is 1 on background pixels (matte < matte_threshold) and 0 on
//     the tree: every step off the tree costs weight_outside;
//   - the "gradient magnitude" cost is low on branch centre lines: a blend of
//     1 / (1 + d) (d = distance to the background in pixels of the traced
//     copy, so paths keep to the middle of thick branches) and the photo's
//     luminance (bark is darker than the leaves and sky around it; weight
//     photo_weight);
//   - the "gradient direction" is the direction of steepest ascent of the
//     smoothed distance d: the direction term rewards steps across it, i.e.
//     along the branch's axis.
// All three only depend on the photo, the matte and the options, so the
// result is deterministic.
#ifndef SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_H_
#define SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types/attractor_graph.h"
#include "core/types/float_image.h"

namespace sylva {

struct LivewireOptions {
  // How seed points are chosen when the caller gives none (all inside the
  // matte, at most num_seeds of them):
  //   "silhouette":     random points on the matte's outline (the thesis'
  //                     choice), drawn with `seed`;
  //   "farthest_point": farthest-point sampling by geodesic distance inside
  //                     the matte, starting from the target (the crown's
  //                     extremities first);
  //   "skeleton_tips":  end points of the matte's morphological skeleton,
  //                     the num_seeds farthest (geodesically) from the target.
  // Measured on 5 synthetic trees x 8 views (512 px; sylva_livewire_probe),
  // mean 2D Chamfer to the projected skeleton (orders <= 2) at 32 seeds:
  // silhouette 6.5 px, farthest_point 7.0, skeleton_tips 12.9; silhouette
  // improves to 5.2 / 4.9 / 4.8 px at 64 / 96 / 128 seeds and is the fastest.
  std::string seeds = "silhouette";
  // Number of automatic seed points (>= 1); see above for the choice of 96.
  int num_seeds = 96;
  // Seed of the random choices ("silhouette").
  uint64_t seed = 1;
  // Tracing runs on a copy whose longest side is at most this many pixels
  // (>= 16); the graph is scaled back to full resolution.
  int max_image_size = 768;
  // A pixel belongs to the tree if its matte value is >= this (alpha, (0, 1)).
  double matte_threshold = 0.5;
  // Douglas-Peucker tolerance of the final graph, in pixels of the full
  // image (>= 0; 0 keeps one node per traced pixel).
  double simplify_tolerance = 1.0;
  // Twigs of the traced graph shorter than this fraction of the image's
  // longer side are removed (AttractorGraph2D::WithoutTwigs), repeatedly:
  // outline seeds on the trunk and the crown's edge add short side paths
  // that are no main branch. In [0, 1); 0 keeps every path.
  double min_twig_length = 0.0;

  // Intelligent Scissors weights (each >= 0, sum > 0), see the file comment:
  // per step off the matte, per unit of turning against the branch axis,
  // and per unit of centre-line cost.
  double weight_outside = 0.6;
  double weight_direction = 0.1;
  double weight_centerline = 0.3;
  // Share of the photo's luminance in the centre-line cost, in [0, 1]
  // (0 = the matte's distance transform alone).
  double photo_weight = 0.3;
  // SnapGraphToImage: every drawn node moves to the cheapest pixel of the
  // centre-line cost within this radius (pixels of the full image, >= 0)
  // before its edges are traced.
  double snap_radius = 8.0;

  // Throws InputError("Attractors.<field>", ...) for the first violated
  // constraint.
  void Check() const;
};

struct LivewireSummary {
  int seeds = 0;  // seed points used
  int paths = 0;  // paths that added at least one node
  int nodes = 0;  // nodes of the final (simplified) graph
  double seconds = 0;
  double megapixels = 0;  // size of the full-resolution photo
  std::string BriefReport() const;
};

// Traces the attractor graph of one photo.
//   photo: RGB(A) in [0, 1]; matte: one channel, alpha, the same size.
//   target: where every path ends (pixel coordinates, COLMAP convention:
//     the centre of pixel (i, j) is (i + 0.5, j + 0.5)); inside the image.
//   user_seeds: used instead of automatic seeds when non-empty (inside the
//     image).
// Returns the paths from each seed to the target merged where they share
// pixels: the first path to reach a pixel owns it; a later path stops where it
// first meets an earlier one and joins it there, so every branching is a node.
// Simplified by options.simplify_tolerance; root = the target node (exactly at
// `target`); source "livewire". Throws InputError for a size mismatch, a
// target or seed outside the image, an empty matte or bad options.
AttractorGraph2D TraceAttractorGraph(const FloatImage& photo, const FloatImage& matte,
                                     const Eigen::Vector2d& target,
                                     const std::vector<Eigen::Vector2d>& user_seeds,
                                     const LivewireOptions& options,
                                     LivewireSummary* summary = nullptr);

// Drawn strokes snapped to the image: every node of `drawn` moves to the
// cheapest centre-line pixel within options.snap_radius, then every edge is
// replaced by the livewire path between its two end nodes (same topology,
// denser nodes), then the graph is simplified. Source "strokes+livewire".
// `drawn` must refer to an image of the photo's size.
AttractorGraph2D SnapGraphToImage(const AttractorGraph2D& drawn, const FloatImage& photo,
                                  const FloatImage& matte, const LivewireOptions& options);

// A fallback target when no 3D base is known: in the lowest image row that
// has a pixel with matte >= threshold, the longest run of such pixels
// (leftmost if tied), pixels [x0, x1) of row y; returns ((x0 + x1) / 2,
// y + 0.5): the middle of that run at the height of the row's pixel centres.
// Throws InputError if no pixel reaches the threshold.
Eigen::Vector2d MatteFootPoint(const FloatImage& matte, double threshold);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_ATTRACTORS_LIVEWIRE_H_
