// Pictures of attractor graphs for reports and for checking livewire by eye.
#ifndef SYLVA_RECONSTRUCT_ATTRACTORS_OVERLAY_H_
#define SYLVA_RECONSTRUCT_ATTRACTORS_OVERLAY_H_

#include "core/types/attractor_graph.h"
#include "core/types/float_image.h"

namespace sylva {

// The photo (RGB; an RGBA photo is composited over white by its alpha) with
// the graph drawn on it, antialiased: edges in magenta, tips as small yellow
// dots, junctions (nodes with two or more children) as cyan rings and the main
// root as a red disc with a white rim. Line widths scale with the image (about
// 1 pixel per 300 of its shorter side, at least 1). Pixels away from the
// drawing keep the photo's values exactly. Returns an RGB image of the photo's
// size. The graph must refer to an image of that size.
FloatImage DrawAttractorOverlay(const FloatImage& photo, const AttractorGraph2D& graph);

}  // namespace sylva

#endif  // SYLVA_RECONSTRUCT_ATTRACTORS_OVERLAY_H_
