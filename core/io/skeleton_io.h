// The sylva skeleton file: a tree skeleton (SkeletonGraph) as JSON.
//
// {
//   "format": "sylva-skeleton", "version": 1,
//   "units": "m",                          // unit of positions and radii ("arbitrary" if unknown)
//   "radius_source": "ground truth",       // or "allometric prior", "unknown" (see SkeletonGraph)
//   "nodes": [
//     {"position": [0, 0, 0], "radius": 0.16, "parent": -1, "order": 0, "strands": 1200},
//     {"position": [0, 0, 0.25], "radius": 0.15, "parent": 0, "order": 0, "strands": 1180},
//     ...
//   ]
// }
// Nodes are listed by index; "parent" is the index of the parent node (-1 for
// the root), "order" the branch order (0 = trunk), "strands" (optional, 0 =
// unknown) the particles carried by the edge to the parent (thesis 5.1's pipe
// model). Positions are in the world frame (+Z up, tree base at the origin).
#ifndef SYLVA_CORE_IO_SKELETON_IO_H_
#define SYLVA_CORE_IO_SKELETON_IO_H_

#include <filesystem>
#include <string>

#include "core/types/skeleton_graph.h"

namespace sylva {

// Writes atomically. Throws Error if the skeleton fails SkeletonGraph::Check().
void WriteSkeletonJson(const std::filesystem::path& path, const SkeletonGraph& skeleton,
                       const std::string& units = "arbitrary");

// Throws InputError naming the file and JSON location of any problem,
// including a broken invariant (two roots, a cycle, a negative radius).
SkeletonGraph ReadSkeletonJson(const std::filesystem::path& path, std::string* units = nullptr);

// The skeleton as an ASCII PLY graph in the layout AdTree exports through
// Easy3D (and Easy3D's viewer opens): element "vertex" with float x, y, z and
// per-vertex properties `radius` (float), `strands` and `order` (int), and
// element "edge" with an int list `vertex_indices` (child, parent). A comment
// line carries the units and the radius source (e.g. "allometric prior").
// Writes atomically.
void WriteSkeletonPly(const std::filesystem::path& path, const SkeletonGraph& skeleton,
                      const std::string& units = "arbitrary");

// Reads what WriteSkeletonPly writes (ASCII, these properties, edges from
// child to parent); throws InputError naming the file and line otherwise.
SkeletonGraph ReadSkeletonPly(const std::filesystem::path& path);

}  // namespace sylva

#endif  // SYLVA_CORE_IO_SKELETON_IO_H_
