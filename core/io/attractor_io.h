// The sylva attractor graph file: one photo's 2D attractor graph
// (AttractorGraph2D, thesis 3.2.2) as JSON. The attractor stage writes
// PROJECT/out/attractors/<photo>.json; a person may place a file of the same
// format in PROJECT/edits/attractors/<photo>.json to override it.
//
// {
//   "format": "sylva-attractor-graph", "version": 1,
//   "image": "IMG_0001.jpg",               // the photo the coordinates refer to
//   "width": 1440, "height": 1080,         // that photo's size in pixels (> 0)
//   "source": "livewire",                  // optional: "livewire", "strokes", "edited", ...
//   "root": 0,                             // the main root (-1 only if there are no nodes)
//   "nodes": [[720.5, 1050.5], [721.0, 980.25], ...],
//   "edges": [[1, 0], ...]
// }
// "nodes" are [x, y] positions in the photo's pixels, x to the right and y
// down, the centre of pixel (i, j) at (i + 0.5, j + 0.5) (COLMAP's
// convention). Each edge is [child, parent]: it points down the tree, from a
// node to the next node towards the tree base. A node has at most one parent;
// nodes without one are roots (strokes that touch nothing else make further
// components); the edges must not form a cycle; "root" must be a root.
// Positions may lie outside the image.
#ifndef SYLVA_CORE_IO_ATTRACTOR_IO_H_
#define SYLVA_CORE_IO_ATTRACTOR_IO_H_

#include <filesystem>
#include <string>

#include "core/types/attractor_graph.h"

namespace sylva {

// Writes atomically, one node and one edge per line. Throws Error if the
// graph fails AttractorGraph2D::Check().
void WriteAttractorGraphJson(const std::filesystem::path& path, const AttractorGraph2D& graph,
                             const std::string& image_name);

// Throws InputError naming the file and the JSON location of any problem:
// wrong format or version, a missing key, a size that is not positive, a
// number that is not finite, an index out of range, a node with two parents,
// a cycle, a root that has a parent. `image_name` (optional) receives "image".
AttractorGraph2D ReadAttractorGraphJson(const std::filesystem::path& path,
                                        std::string* image_name = nullptr);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_ATTRACTOR_IO_H_
