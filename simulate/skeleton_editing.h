// Removing parts of a skeleton while keeping it a consistent rooted tree.
// Internal to simulate/ (the matte pruning and the consolidation share it).
#ifndef SYLVA_SIMULATE_SKELETON_EDITING_H_
#define SYLVA_SIMULATE_SKELETON_EDITING_H_

#include <vector>

#include "core/types/skeleton_graph.h"

namespace sylva {

// Marks every descendant of a marked node.
void MarkDescendants(const SkeletonGraph& skeleton, std::vector<char>* removed);

// Takes `strands_taken[j]` strands off junction j and every ancestor of it
// (junctions that are themselves removed are skipped).
void TakeStrands(const std::vector<int>& strands_taken, const std::vector<char>& removed,
                 SkeletonGraph* skeleton);

// The skeleton without the marked nodes (none of which may have an unmarked
// child), in the same relative order, orders reassigned.
SkeletonGraph WithoutNodes(const SkeletonGraph& skeleton, const std::vector<char>& removed);

// The same skeleton with its nodes reordered so that every parent comes
// before its children (after re-parenting), otherwise in their present
// order: a skeleton already so ordered is returned unchanged.
SkeletonGraph ParentsFirst(const SkeletonGraph& skeleton);

}  // namespace sylva

#endif  // SYLVA_SIMULATE_SKELETON_EDITING_H_
