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

}  // namespace sylva

#endif  // SYLVA_CORE_IO_SKELETON_IO_H_
