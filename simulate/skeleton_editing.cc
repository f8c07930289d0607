#include "simulate/skeleton_editing.h"

#include <functional>
#include <queue>

namespace sylva {

void MarkDescendants(const SkeletonGraph& skeleton, std::vector<char>* removed) {
  const std::vector<std::vector<int>> children = skeleton.Children();
  std::vector<int> stack;
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if ((*removed)[i]) stack.push_back(i);
  }
  while (!stack.empty()) {
    const int node = stack.back();
    stack.pop_back();
    for (int child : children[node]) {
      if (!(*removed)[child]) {
        (*removed)[child] = 1;
        stack.push_back(child);
      }
    }
  }
}

void TakeStrands(const std::vector<int>& strands_taken, const std::vector<char>& removed,
                 SkeletonGraph* skeleton) {
  for (int junction = 0; junction < skeleton->NumNodes(); ++junction) {
    if (strands_taken[junction] == 0 || removed[junction]) continue;
    for (int node = junction; node >= 0; node = skeleton->nodes[node].parent_idx) {
      skeleton->nodes[node].strands -= strands_taken[junction];
    }
  }
}

SkeletonGraph WithoutNodes(const SkeletonGraph& skeleton, const std::vector<char>& removed) {
  std::vector<int> new_index(skeleton.NumNodes(), -1);
  int count = 0;
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if (!removed[i]) new_index[i] = count++;
  }
  SkeletonGraph kept;
  kept.radius_source = skeleton.radius_source;
  for (int i = 0; i < skeleton.NumNodes(); ++i) {
    if (removed[i]) continue;
    SkeletonNode node = skeleton.nodes[i];
    node.parent_idx = node.parent_idx >= 0 ? new_index[node.parent_idx] : -1;
    kept.nodes.push_back(node);
  }
  kept.AssignOrders();
  return kept;
}

SkeletonGraph ParentsFirst(const SkeletonGraph& skeleton) {
  const int root = skeleton.RootIdx();
  if (root < 0) return skeleton;
  const std::vector<std::vector<int>> children = skeleton.Children();
  // Visited smallest index first among the nodes whose parent is placed.
  std::priority_queue<int, std::vector<int>, std::greater<int>> ready;
  ready.push(root);
  std::vector<int> new_index(skeleton.NumNodes(), -1);
  SkeletonGraph ordered;
  ordered.radius_source = skeleton.radius_source;
  while (!ready.empty()) {
    const int node = ready.top();
    ready.pop();
    new_index[node] = ordered.NumNodes();
    ordered.nodes.push_back(skeleton.nodes[node]);
    const int parent = skeleton.nodes[node].parent_idx;
    ordered.nodes.back().parent_idx = parent >= 0 ? new_index[parent] : -1;
    for (int child : children[node]) ready.push(child);
  }
  return ordered;
}

}  // namespace sylva
