// The city's occluder models (samples/scene/city.cpp, scene.hpp OccluderSolid), without
// GL, for several seeds: each building's triangles form a closed surface wound
// consistently; its occluder box lies inside that surface (no triangle meets the box,
// and points of the box are inside by ray parity); every triangle lies in a thin slab
// on a face of the lot's prism with the occluder box well behind it (the premise of the
// depth argument); and the prepared chunks' models hold the boxes of exactly the
// buildings their triangles belong to, inside the box the buffer is given.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/occluder_mesh.hpp"
#include "scene/generators.hpp"
#include "scene/occluders.hpp"
#include "scene/prepare.hpp"

namespace logrid::samples {
namespace {

using Point = std::array<float, 3>;
using Triangle = std::array<Point, 3>;

constexpr std::uint64_t kSeeds[] = {1, 2, 7};

Point vertex(const Scene& s, std::size_t triangle, int k) {
  const float* p = &s.positions[std::size_t(s.indices[triangle * 3 + std::size_t(k)]) * 3];
  return {p[0], p[1], p[2]};
}

// The triangles of each building (by solid).
std::vector<std::vector<Triangle>> buildings(const Scene& s) {
  std::vector<std::vector<Triangle>> out(s.occluder_solids.size());
  for (std::size_t t = 0; t < s.triangle_solids.size(); ++t) {
    if (s.triangle_solids[t] == kNoSolid) continue;
    out[s.triangle_solids[t]].push_back({vertex(s, t, 0), vertex(s, t, 1), vertex(s, t, 2)});
  }
  return out;
}

// Whether the ray from o along d crosses triangle t (Moller-Trumbore, double).
bool crosses(const double o[3], const double d[3], const Triangle& t) {
  double e1[3], e2[3], p[3], q[3], s[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = double(t[1][i]) - t[0][i];
    e2[i] = double(t[2][i]) - t[0][i];
    s[i] = o[i] - t[0][i];
  }
  auto cross = [](const double a[3], const double b[3], double r[3]) {
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
  };
  auto dot = [](const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  cross(d, e2, p);
  const double det = dot(e1, p);
  if (det == 0) return false;
  const double u = dot(s, p) / det;
  if (u < 0 || u > 1) return false;
  cross(s, e1, q);
  const double v = dot(d, q) / det;
  if (v < 0 || u + v > 1) return false;
  return dot(e2, q) / det > 0;
}

// Inside a closed surface: an odd number of crossings along a direction no edge of the
// axis-aligned city is parallel to.
bool insideByParity(const std::vector<Triangle>& surface, double x, double y, double z) {
  const double o[3] = {x, y, z}, d[3] = {0.3713, 0.5127, 0.7741};
  int crossings = 0;
  for (const Triangle& t : surface) crossings += crosses(o, d, t) ? 1 : 0;
  return crossings % 2 == 1;
}

TEST(CityOccluders, EveryBuildingIsAClosedConsistentlyWoundSurface) {
  for (std::uint64_t seed : kSeeds) {
    const Scene s = makeCity({0.01, seed});
    ASSERT_FALSE(s.occluder_solids.empty());
    ASSERT_EQ(s.triangle_solids.size(), s.triangleCount());
    std::size_t b = 0;
    for (const std::vector<Triangle>& surface : buildings(s)) {
      ASSERT_FALSE(surface.empty()) << "building " << b;
      // Every directed edge (by bit-identical positions) once, and its reverse once.
      std::map<std::pair<Point, Point>, int> edges;
      for (const Triangle& t : surface) {
        for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
      }
      std::size_t bad = 0;
      for (const auto& [edge, count] : edges) {
        const auto reverse = edges.find({edge.second, edge.first});
        if (count != 1 || reverse == edges.end() || reverse->second != 1) ++bad;
      }
      EXPECT_EQ(bad, 0u) << "seed " << seed << ", building " << b << ": " << bad << " of "
                         << edges.size() << " edges are not shared by exactly two triangles "
                         << "in opposite directions (a crack, a T-junction or a flipped face)";
      ++b;
    }
  }
}

TEST(CityOccluders, EachBoxLiesInsideItsBuilding) {
  for (std::uint64_t seed : kSeeds) {
    const Scene s = makeCity({0.01, seed});
    const auto surfaces = buildings(s);
    for (std::size_t b = 0; b < surfaces.size(); ++b) {
      const Aabb in = s.occluder_solids[b].inside, around = s.occluder_solids[b].around;
      ASSERT_LT(in.min.x, in.max.x);
      ASSERT_LT(in.min.y, in.max.y);
      ASSERT_LT(in.min.z, in.max.z);
      // No triangle meets the box: each triangle's own box misses it.
      std::size_t meeting = 0;
      for (const Triangle& t : surfaces[b]) {
        Aabb tb = emptyBox();
        for (const Point& p : t) growBox(tb, p.data());
        const bool apart = tb.max.x < in.min.x || tb.min.x > in.max.x || tb.max.y < in.min.y ||
                           tb.min.y > in.max.y || tb.max.z < in.min.z || tb.min.z > in.max.z;
        meeting += apart ? 0 : 1;
      }
      EXPECT_EQ(meeting, 0u) << "seed " << seed << ", building " << b;
      // So the box is wholly inside or wholly outside: its corners and centre are inside.
      for (int i = 0; i < 9; ++i) {
        const double x = i == 8 ? 0.5 * (in.min.x + in.max.x) : (i & 1) ? in.max.x : in.min.x;
        const double y = i == 8 ? 0.5 * (in.min.y + in.max.y) : (i & 2) ? in.max.y : in.min.y;
        const double z = i == 8 ? 0.5 * (in.min.z + in.max.z) : (i & 4) ? in.max.z : in.min.z;
        EXPECT_TRUE(insideByParity(surfaces[b], x, y, z))
            << "seed " << seed << ", building " << b << ", point " << i;
      }
      // A point outside the building is outside (the parity test can fail).
      EXPECT_FALSE(insideByParity(surfaces[b], around.min.x - 1.0, 1.0, around.min.z - 1.0));
    }
  }
}

TEST(CityOccluders, EveryTriangleLiesInAThinSlabOnAFaceInFrontOfTheBox) {
  // city.cpp's depth argument: with P the lot's prism (found from the roof, the highest
  // vertices), each triangle lies on the outer side of one face F of P, within its
  // window depth (0.35 m) of F's plane and within F's rectangle, and the occluder box
  // lies behind F's plane, at least as far as the triangle stands out (there: 0.5 m
  // behind walls, 0.1 m inside roof and floor).
  constexpr double kDepth = 0.35 + 1e-4, kMinGap = 0.05;
  for (std::uint64_t seed : kSeeds) {
    const Scene s = makeCity({0.01, seed});
    const auto surfaces = buildings(s);
    for (std::size_t b = 0; b < surfaces.size(); ++b) {
      const Aabb in = s.occluder_solids[b].inside, around = s.occluder_solids[b].around;
      float top = -1e30f;
      for (const Triangle& t : surfaces[b]) {
        for (const Point& p : t) top = std::max(top, p[1]);
      }
      Aabb prism = emptyBox();
      for (const Triangle& t : surfaces[b]) {
        for (const Point& p : t) {
          if (p[1] == top) growBox(prism, p.data());
        }
      }
      prism.min.y = 0;
      const double lo[3] = {prism.min.x, prism.min.y, prism.min.z};
      const double hi[3] = {prism.max.x, prism.max.y, prism.max.z};
      const double box_lo[3] = {in.min.x, in.min.y, in.min.z};
      const double box_hi[3] = {in.max.x, in.max.y, in.max.z};
      std::size_t loose = 0, outside = 0;
      for (const Triangle& t : surfaces[b]) {
        for (const Point& p : t) {
          outside += p[0] < around.min.x || p[0] > around.max.x || p[1] < around.min.y ||
                             p[1] > around.max.y || p[2] < around.min.z || p[2] > around.max.z
                         ? 1
                         : 0;
        }
        bool fits = false;
        for (int axis = 0; axis < 3; ++axis) {
          for (int side = 0; side < 2; ++side) {
            // Face F: coordinate `axis` at lo (side 0, outside below) or hi (side 1).
            const double plane = side ? hi[axis] : lo[axis];
            const double box_behind = side ? plane - box_hi[axis] : box_lo[axis] - plane;
            bool on = box_behind >= kMinGap;
            for (const Point& p : t) {
              const double out = side ? p[axis] - plane : plane - p[axis];
              on &= out >= 0 && out <= kDepth && out <= box_behind;
              for (int other = 0; other < 3; ++other) {
                if (other != axis) on &= lo[other] <= p[other] && p[other] <= hi[other];
              }
            }
            fits |= on;
          }
        }
        loose += fits ? 0 : 1;
      }
      EXPECT_EQ(outside, 0u) << "seed " << seed << ", building " << b
                             << ": vertices outside the solid's box";
      EXPECT_EQ(loose, 0u) << "seed " << seed << ", building " << b << ": of " << surfaces[b].size()
                           << " triangles, " << loose
                           << " are not in a slab on a face, in front of the box";
    }
  }
}

bool holds(const Aabb& b, const float* q) {
  return b.min.x <= q[0] && q[0] <= b.max.x && b.min.y <= q[1] && q[1] <= b.max.y &&
         b.min.z <= q[2] && q[2] <= b.max.z;
}

TEST(CityOccluders, ChunkModelsHoldTheBoxesOfTheirBuildings) {
  for (std::uint64_t seed : kSeeds) {
    Scene s = makeCity({0.01, seed});
    const std::vector<OccluderSolid> solids = s.occluder_solids;
    // Per chunk, which solids its triangles belong to, from the scene before preparing.
    const std::vector<std::uint32_t> tags = s.triangle_solids;
    const bvh::BuildArgs args = defaultBuildArgs(s);
    bvh::TriangleHierarchy th = bvh::buildOverTriangles(s.positions, s.indices, args);
    const PreparedScene p = prepareScene(std::move(s), args);
    ASSERT_EQ(p.occluder_models.size(), p.static_objects);
    ASSERT_EQ(th.chunk_first.size(), std::size_t(p.static_objects) + 1);
    std::size_t modelled = 0, model_triangles = 0, mesh_triangles = 0;
    for (std::uint32_t id = 0; id < p.static_objects; ++id) {
      std::set<std::uint32_t> expected;
      for (std::uint32_t i = th.chunk_first[id]; i < th.chunk_first[id + 1]; ++i) {
        const std::uint32_t solid = tags[th.triangle_order[i]];
        if (solid != kNoSolid) expected.insert(solid);
      }
      const OccluderModel& m = p.occluder_models[id];
      mesh_triangles += p.mesh.draws[id].index_count / 3;
      ASSERT_EQ(m.boxes.size(), expected.size()) << "object " << id;
      if (m.boxes.empty()) {
        EXPECT_TRUE(m.indices.empty()) << "object " << id << ": no box, so no model";
        continue;
      }
      ++modelled;
      model_triangles += m.indices.size() / 3 + 12 * m.boxes.size();
      Aabb reach = emptyBox();
      std::size_t matched = 0;
      for (std::uint32_t solid : expected) {
        growBox(reach, solids[solid].around);
        for (const Aabb& b : m.boxes) {
          matched += std::memcmp(&b, &solids[solid].inside, sizeof(Aabb)) == 0 ? 1 : 0;
        }
      }
      EXPECT_EQ(matched, expected.size()) << "object " << id;
      EXPECT_EQ(std::memcmp(&reach, &m.reach, sizeof(Aabb)), 0) << "object " << id;
      // Every vertex lies in the box the buffer is given (the object's with reach).
      Aabb given = p.object_boxes[id];
      growBox(given, m.reach);
      for (const Aabb& b : m.boxes) {
        EXPECT_TRUE(holds(given, &b.min.x) && holds(given, &b.max.x)) << "object " << id;
      }
      for (std::size_t v = 0; v < m.positions.size(); v += 3) {
        EXPECT_TRUE(holds(p.object_boxes[id], &m.positions[v])) << "object " << id;
      }
    }
    EXPECT_GT(modelled, p.static_objects / 2) << "most chunks are of buildings";
    EXPECT_LT(model_triangles * 20, mesh_triangles) << "the models are much smaller";
    // The buffer's meshes: each model is marked inside its solid with its mesh as the
    // fallback and holds a closed surface; clipped to the objects' boxes, every vertex of
    // a model lies in its object's box.
    for (bool within : {false, true}) {
      const cpu::OccluderMeshes& meshes = sceneOccluders(p, OccluderChoice::Model, within);
      std::size_t inside = 0;
      for (std::uint32_t id = 0; id < p.static_objects; ++id) {
        const cpu::OccluderObject& o = meshes.object(id);
        if (!o.inside_solid) continue;
        ++inside;
        EXPECT_NE(o.fallback, cpu::kNoOccluder);
        bool closed = false;
        for (std::uint32_t t = o.first_triangle; t < o.first_triangle + o.triangle_count; ++t) {
          closed |= meshes.closed()[t] != 0;
        }
        EXPECT_TRUE(closed) << "object " << id;
        if (!within) continue;
        for (std::uint32_t v = o.first_vertex; v < o.first_vertex + o.vertex_count; ++v) {
          EXPECT_TRUE(holds(p.object_boxes[id], &meshes.positions()[std::size_t(v) * 3]))
              << "object " << id << ", vertex " << v;
        }
      }
      if (within) {
        EXPECT_GT(inside, 0u);
        EXPECT_LE(inside, modelled);
      } else {
        EXPECT_EQ(inside, modelled);
      }
    }
  }
}

}  // namespace
}  // namespace logrid::samples
