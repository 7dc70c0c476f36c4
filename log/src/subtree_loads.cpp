#include "subtree_loads.hpp"

#include <vector>

namespace logrid::detail {

std::unordered_map<NodeId, SubtreeLoad> subtreeLoads(const Hierarchy& h) {
  std::unordered_map<NodeId, SubtreeLoad> loads;
  if (h.root() == kNoNode) return loads;
  // Post-order: a node's load is its objects' plus its children's.
  struct Item {
    NodeId node;
    bool done;
  };
  std::vector<Item> stack{{h.root(), false}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    const std::uint32_t children = h.childCount(it.node);
    if (!it.done) {
      stack.push_back({it.node, true});
      for (std::uint32_t i = 0; i < children; ++i) stack.push_back({h.child(it.node, i), false});
      continue;
    }
    SubtreeLoad load;
    const std::uint32_t objects = h.objectCount(it.node);
    load.objects = objects;
    for (std::uint32_t i = 0; i < objects; ++i) {
      const std::uint32_t t = h.objectTriangles(h.object(it.node, i));
      load.triangles += t ? t : kAssumedTriangles;
    }
    load.leaves = children == 0 ? 1 : 0;
    for (std::uint32_t i = 0; i < children; ++i) {
      const SubtreeLoad& c = loads[h.child(it.node, i)];
      load.objects += c.objects;
      load.triangles += c.triangles;
      load.leaves += c.leaves;
    }
    loads[it.node] = load;
  }
  return loads;
}

}  // namespace logrid::detail
