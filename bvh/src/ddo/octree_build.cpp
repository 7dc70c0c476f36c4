#include "octree_build.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace logrid::ddo::detail {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

void grow(Aabb& box, const float* p) {
  box.min.x = std::min(box.min.x, p[0]), box.max.x = std::max(box.max.x, p[0]);
  box.min.y = std::min(box.min.y, p[1]), box.max.y = std::max(box.max.y, p[1]);
  box.min.z = std::min(box.min.z, p[2]), box.max.z = std::max(box.max.z, p[2]);
}

void grow(Aabb& box, const Aabb& b) {
  box.min.x = std::min(box.min.x, b.min.x), box.max.x = std::max(box.max.x, b.max.x);
  box.min.y = std::min(box.min.y, b.min.y), box.max.y = std::max(box.max.y, b.max.y);
  box.min.z = std::min(box.min.z, b.min.z), box.max.z = std::max(box.max.z, b.max.z);
}

struct Work {
  std::uint32_t node;
  std::size_t begin, end;  // into the triangle order
};

// The root cell: a cube a little larger than the mesh's bounds, so that no vertex lies
// on the root's faces.
OctreeParams rootParams(const SceneMesh& mesh, const BuildArgs& args) {
  Aabb scene{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) grow(scene, mesh.vertex(mesh.corner(t, k)));
  }
  OctreeParams params;
  params.regions = args.regions;
  params.leaf_triangles = args.leaf_triangles;
  params.max_depth = args.max_depth;
  params.face_margin = kFaceMargin;
  const double lo[3] = {scene.min.x, scene.min.y, scene.min.z};
  const double hi[3] = {scene.max.x, scene.max.y, scene.max.z};
  double side = 0, scale = 0;
  for (int a = 0; a < 3; ++a) {
    side = std::max(side, hi[a] - lo[a]);
    scale = std::max({scale, std::fabs(lo[a]), std::fabs(hi[a])});
  }
  side = side * (1.0 + 1.0 / 256.0) + 1e-6 * scale;
  if (!(side > 0)) side = 1.0;
  for (int a = 0; a < 3; ++a) params.root_lo[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * side;
  params.root_side = side;
  return params;
}

// Splits the node of `w` at its cell's middle planes: its triangles sorted by the octant
// of their centroid (a counting sort through `scratch`), a child appended to `nodes` and
// to `queue` for each octant that holds any.
void splitNode(const SceneMesh& mesh, const Octree& geometry, const Work& w,
               std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& scratch,
               std::vector<OctreeNode>& nodes, std::vector<Work>& queue) {
  const OctreeNode parent = nodes[w.node];
  const std::size_t count = w.end - w.begin;
  double mid[3];
  for (int a = 0; a < 3; ++a) {
    mid[a] = geometry.plane(a, parent.level + 1u, 2ull * parent.cell[a] + 1);
  }
  std::size_t bucket[9] = {0};
  auto octantOf = [&](std::uint32_t t) {
    int o = 0;
    for (int a = 0; a < 3; ++a) {
      const double c =
          (double(mesh.vertex(mesh.corner(t, 0))[a]) + double(mesh.vertex(mesh.corner(t, 1))[a]) +
           double(mesh.vertex(mesh.corner(t, 2))[a])) /
          3.0;
      if (c >= mid[a]) o |= 1 << a;
    }
    return o;
  };
  std::vector<std::uint8_t> octant(count);
  for (std::size_t i = 0; i < count; ++i) {
    octant[i] = std::uint8_t(octantOf(order[w.begin + i]));
    ++bucket[octant[i] + 1];
  }
  for (int o = 0; o < 8; ++o) bucket[o + 1] += bucket[o];
  std::size_t fill[8];
  std::copy(bucket, bucket + 8, fill);
  for (std::size_t i = 0; i < count; ++i) scratch[w.begin + fill[octant[i]]++] = order[w.begin + i];
  std::copy(scratch.begin() + std::ptrdiff_t(w.begin), scratch.begin() + std::ptrdiff_t(w.end),
            order.begin() + std::ptrdiff_t(w.begin));

  nodes[w.node].first_child = std::uint32_t(nodes.size());
  std::uint8_t mask = 0;
  for (int o = 0; o < 8; ++o) {
    if (bucket[o + 1] == bucket[o]) continue;
    mask = std::uint8_t(mask | (1u << o));
    OctreeNode child;
    child.level = std::uint8_t(parent.level + 1);
    for (int a = 0; a < 3; ++a) child.cell[a] = 2 * parent.cell[a] + ((o >> a) & 1u);
    child.triangle_count = std::uint32_t(bucket[o + 1] - bucket[o]);
    queue.push_back({std::uint32_t(nodes.size()), w.begin + bucket[o], w.begin + bucket[o + 1]});
    nodes.push_back(child);
  }
  nodes[w.node].child_mask = mask;
}

// Bounds bottom-up (`queue` is breadth first: children after their parent), and the
// object lists of the leaves; answers the concatenated lists.
std::vector<ObjectId> boundsAndObjects(const SceneMesh& mesh, const std::vector<Work>& queue,
                                       const std::vector<std::uint32_t>& order,
                                       std::vector<OctreeNode>& nodes) {
  std::vector<ObjectId> objects;
  const std::vector<std::uint32_t>& runs = *mesh.object_first;
  std::vector<ObjectId> leaf_objects;
  for (std::size_t qi = queue.size(); qi-- > 0;) {
    const Work w = queue[qi];
    OctreeNode& n = nodes[w.node];
    n.bounds = {{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
    if (!n.leaf()) {
      for (std::uint32_t c = 0; c < n.childCount(); ++c)
        grow(n.bounds, nodes[n.first_child + c].bounds);
      continue;
    }
    leaf_objects.clear();
    for (std::size_t i = w.begin; i < w.end; ++i) {
      const std::uint32_t t = order[i];
      for (int k = 0; k < 3; ++k) grow(n.bounds, mesh.vertex(mesh.corner(t, k)));
      const auto it = std::upper_bound(runs.begin(), runs.end(), t);
      leaf_objects.push_back(ObjectId(it - runs.begin() - 1));
    }
    std::sort(leaf_objects.begin(), leaf_objects.end());
    leaf_objects.erase(std::unique(leaf_objects.begin(), leaf_objects.end()), leaf_objects.end());
    n.first_object = std::uint32_t(objects.size());
    n.object_count = std::uint32_t(leaf_objects.size());
    objects.insert(objects.end(), leaf_objects.begin(), leaf_objects.end());
  }
  return objects;
}

}  // namespace

Octree subdivide(const SceneMesh& mesh, const BuildArgs& args) {
  const OctreeParams params = rootParams(mesh, args);
  const Octree geometry(params, {}, {});  // for its plane() arithmetic
  const std::size_t triangles = mesh.triangleCount();
  std::vector<OctreeNode> nodes(1);
  nodes[0].triangle_count = std::uint32_t(triangles);
  std::vector<std::uint32_t> order(triangles), scratch(triangles);
  for (std::size_t t = 0; t < triangles; ++t) order[t] = std::uint32_t(t);
  // Breadth first: a node's children are appended together, after every earlier node.
  std::vector<Work> queue{{0, 0, triangles}};
  for (std::size_t qi = 0; qi < queue.size(); ++qi) {
    const Work w = queue[qi];
    if (w.end - w.begin <= args.leaf_triangles || nodes[w.node].level >= args.max_depth) continue;
    splitNode(mesh, geometry, w, order, scratch, nodes, queue);
  }
  std::vector<ObjectId> objects = boundsAndObjects(mesh, queue, order, nodes);
  return Octree(params, std::move(nodes), std::move(objects));
}

}  // namespace logrid::ddo::detail
