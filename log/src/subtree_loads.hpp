// What drawing each node's subtree would draw, summed bottom-up once per hierarchy: the
// cost models that weigh a test against the drawing it may save read it (nohc's schedule,
// the auto method's per-node test). Internal to logrid::core.
#pragma once

#include <cstdint>
#include <unordered_map>

#include "logrid/hierarchy.hpp"

namespace logrid::detail {

// Objects whose hierarchy does not know their triangles (Hierarchy::objectTriangles 0)
// count as this many.
inline constexpr std::uint32_t kAssumedTriangles = 1000;

struct SubtreeLoad {
  std::uint64_t objects = 0;  // draw calls
  std::uint64_t triangles = 0;
  std::uint64_t leaves = 0;  // nodes without children
};

// Every node reachable from the root (none for an empty hierarchy), without recursion.
std::unordered_map<NodeId, SubtreeLoad> subtreeLoads(const Hierarchy& h);

}  // namespace logrid::detail
