// A flat, upward-facing grid of n x n unit quads at y = 0 (counter-clockwise seen from
// above), one object: an open surface, whose back is what a renderer culling back faces
// does not draw.
#pragma once

#include <cstdint>

#include "scene/scene.hpp"

namespace logrid::test {

inline samples::Scene flatGrid(int n) {
  samples::Scene s;
  s.name = "grid";
  for (int z = 0; z <= n; ++z) {
    for (int x = 0; x <= n; ++x) s.positions.insert(s.positions.end(), {float(x), 0.0f, float(z)});
  }
  const auto v = [n](int x, int z) { return std::uint32_t(z * (n + 1) + x); };
  for (int z = 0; z < n; ++z) {
    for (int x = 0; x < n; ++x) {
      // Seen from +y, (x, z) -> (x, z + 1) -> (x + 1, z) turns counter-clockwise.
      s.indices.insert(s.indices.end(), {v(x, z), v(x, z + 1), v(x + 1, z)});
      s.indices.insert(s.indices.end(), {v(x + 1, z), v(x, z + 1), v(x + 1, z + 1)});
    }
  }
  samples::SceneObject o;
  o.index_count = std::uint32_t(s.indices.size());
  s.objects.push_back(o);
  samples::computeBounds(s);
  return s;
}

}  // namespace logrid::test
