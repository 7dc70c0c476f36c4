// Clusters (samples/scene/clusters.hpp, prepareScene's ClusterOptions): meshoptimizer's
// clusters hold every triangle of their object once, each with its winding, within the
// limits asked for and inside the object's box; a clustered scene draws exactly the
// whole scene's triangles, one ObjectId per cluster, each mapped back to its object.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "flat_grid.hpp"
#include "logrid/error.hpp"
#include "scene/clusters.hpp"
#include "scene/generators.hpp"
#include "scene/movers.hpp"
#include "scene/prepare.hpp"

namespace logrid::samples {
namespace {

using Triangle = std::array<std::uint32_t, 3>;

// The triangle rotated so that its smallest index comes first: the same triangle with
// the same winding compares equal, the flipped one does not.
Triangle canonical(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

std::vector<Triangle> trianglesOf(const std::uint32_t* indices, std::size_t count) {
  std::vector<Triangle> out;
  for (std::size_t i = 0; i < count; i += 3) {
    out.push_back(canonical(indices[i], indices[i + 1], indices[i + 2]));
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool contains(const Aabb& outer, const Aabb& inner) {
  return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
         inner.max.x <= outer.max.x && inner.max.y <= outer.max.y && inner.max.z <= outer.max.z;
}

// The scene `make` builds, prepared whole and in clusters of at most `triangles`.
struct WholeAndClustered {
  PreparedScene whole, clustered;
};
template <typename Make>
WholeAndClustered prepareBoth(const Make& make, std::uint32_t triangles) {
  Scene plain = make();
  const bvh::BuildArgs args = defaultBuildArgs(plain);
  WholeAndClustered out;
  out.whole = prepareScene(std::move(plain), args);
  ClusterOptions options;
  options.triangles = triangles;
  out.clustered = prepareScene(make(), args, options);
  return out;
}

TEST(Clusters, KeepEveryTriangleWithItsWindingWithinTheLimits) {
  const Scene forest = makeForest({0.02, 3, TreeParts::Whole});
  for (const auto& [size, method] :
       {std::pair{4u, ClusterMethod::Grow}, std::pair{64u, ClusterMethod::Grow},
        std::pair{128u, ClusterMethod::Grow}, std::pair{512u, ClusterMethod::Grow},
        std::pair{4u, ClusterMethod::Scan}, std::pair{128u, ClusterMethod::Scan}}) {
    ClusterOptions options;
    options.triangles = size;
    options.method = method;
    ClusterBuilder builder(forest.positions.data(), forest.positions.size() / 3, options);
    std::size_t clusters = 0;
    for (std::size_t o = 0; o < forest.objects.size(); o += 7) {
      const SceneObject& object = forest.objects[o];
      const std::uint32_t* indices = &forest.indices[object.first_index];
      std::vector<std::uint32_t> out;
      const std::vector<Cluster> made = builder.build(indices, object.index_count, out);
      ASSERT_EQ(trianglesOf(out.data(), out.size()), trianglesOf(indices, object.index_count))
          << "object " << o << ", clusters of " << size << ", method " << int(method);
      std::size_t at = 0;
      for (const Cluster& c : made) {
        EXPECT_GT(c.triangles, 0u);
        EXPECT_LE(c.triangles, size);
        std::vector<std::uint32_t> vertices(out.begin() + std::ptrdiff_t(at),
                                            out.begin() + std::ptrdiff_t(at + c.triangles * 3));
        std::sort(vertices.begin(), vertices.end());
        const auto distinct = std::unique(vertices.begin(), vertices.end()) - vertices.begin();
        EXPECT_LE(std::uint32_t(distinct), options.maxVertices());
        Aabb box = emptyBox();
        for (std::uint32_t v : vertices) growBox(box, &forest.positions[std::size_t(v) * 3]);
        EXPECT_TRUE(contains(c.box, box) && contains(box, c.box)) << "the cluster's own box";
        EXPECT_TRUE(contains(object.box, c.box));
        at += c.triangles * 3;
      }
      clusters += made.size();
    }
    EXPECT_GT(clusters, 0u);
  }
}

TEST(Clusters, AClusteredSceneDrawsTheWholeScenesTrianglesOneIdPerCluster) {
  for (const std::string name : {"forest", "city"}) {
    SCOPED_TRACE(name);
    auto make = [&] {
      Scene s = name == "city" ? makeCity({0.01, 1}) : makeForest({0.03, 1, TreeParts::Whole});
      addMovers(s, 3, 1);
      return s;
    };
    const WholeAndClustered both = prepareBoth(make, 64);
    const PreparedScene &whole = both.whole, &clustered = both.clustered;

    ASSERT_TRUE(clustered.clustered());
    EXPECT_FALSE(whole.clustered());
    EXPECT_EQ(clustered.triangles, whole.triangles);
    EXPECT_EQ(clustered.objectCount(), whole.objectCount());
    EXPECT_GT(clustered.static_objects, whole.static_objects);
    ASSERT_EQ(clustered.cluster_objects.size(), clustered.mesh.draws.size());
    EXPECT_EQ(clustered.cluster_cones.size(), clustered.mesh.draws.size());
    // The hierarchy holds every cluster once, one a leaf.
    std::vector<int> seen(clustered.static_objects, 0);
    for (NodeId n = 0; n < clustered.hierarchy.nodes().size(); ++n) {
      const std::uint32_t k = clustered.hierarchy.objectCount(n);
      EXPECT_LE(k, 1u);
      for (std::uint32_t i = 0; i < k; ++i) ++seen[clustered.hierarchy.object(n, i)];
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(seen.size()));

    // Each object's clusters: consecutive ids and index ranges over its vertices, inside
    // its box, adding up to its triangles; the movers' after them.
    std::vector<std::uint32_t> triangles(whole.objectCount(), 0);
    std::vector<Aabb> boxes(whole.objectCount(), emptyBox());
    for (ObjectId id = 0; id < clustered.mesh.draws.size(); ++id) {
      const std::uint32_t o = clustered.objectOf(id);
      ASSERT_LT(o, whole.objectCount());
      if (id > 0) {
        EXPECT_GE(o, clustered.objectOf(id - 1));
      }
      triangles[o] += clustered.mesh.draws[id].index_count / 3;
      growBox(boxes[o], clustered.object_boxes[id]);
      if (id > 0 && o == clustered.objectOf(id - 1)) {
        const gl::RenderMesh::Draw &a = clustered.mesh.draws[id - 1], &b = clustered.mesh.draws[id];
        EXPECT_EQ(b.first_index, a.first_index + a.index_count);
        EXPECT_EQ(b.base_vertex, a.base_vertex);
      }
    }
    for (std::uint32_t o = 0; o < whole.objectCount(); ++o) {
      EXPECT_EQ(triangles[o], whole.mesh.draws[o].index_count / 3) << "object " << o;
      EXPECT_TRUE(contains(whole.object_boxes[o], boxes[o])) << "object " << o;
    }
    // Each mover is clustered too: its clusters are moving objects (Motion::parts) that
    // move with it, each in its part of the mover's mesh box.
    const std::uint32_t movers = whole.objectCount() - whole.static_objects;
    const std::size_t moving = clustered.mesh.draws.size() - clustered.static_objects;
    EXPECT_GT(moving, movers);
    ASSERT_EQ(clustered.motion.movingObjects(), moving);
    const std::uint32_t first_mover = whole.static_objects;  // its object number
    for (std::size_t k = 0; k < moving; ++k) {
      const ObjectId id = clustered.static_objects + ObjectId(k);
      const std::uint32_t mover = clustered.motion.moverOf(k);
      EXPECT_EQ(clustered.objectOf(id), first_mover + mover) << "moving object " << k;
      EXPECT_TRUE(contains(clustered.motion.movers[mover].mesh_box, clustered.motion.meshBoxOf(k)));
    }
    EXPECT_EQ(clustered.objectOf(ObjectId(clustered.mesh.draws.size() - 1)),
              whole.objectCount() - 1);
  }
}

// A small city with six vehicles, everything in clusters of at most 16 triangles.
PreparedScene cityWithClusteredVehicles() {
  Scene city = makeCity({0.01, 1});
  addMovers(city, 6, 3);
  ClusterOptions options;
  options.triangles = 16;
  const bvh::BuildArgs args = defaultBuildArgs(city);
  return prepareScene(std::move(city), args, options);
}

// A moving cluster is said to face away only where its triangles, turned and moved as the
// renderer draws them at that time, all face away from the eye: checked from eyes all
// around the city's vehicles at several times (and it must be said of some).
TEST(Clusters, AMovingClusterFacesAwayOnlyWhereItsMovedTrianglesDo) {
  const PreparedScene p = cityWithClusteredVehicles();
  const gl::RenderMesh& mesh = p.mesh;
  auto vertex = [&](const gl::RenderMesh::Draw& d, std::uint32_t i, const RigidTransform& t) {
    const std::uint32_t local = mesh.indices16.empty() ? mesh.indices32[i] : mesh.indices16[i];
    const float* q = &mesh.positions[(std::size_t(d.base_vertex) + local) * 3];
    const double* r = t.rotation;
    return DVec3{r[0] * q[0] + r[3] * q[1] + r[6] * q[2] + t.translation.x,
                 r[1] * q[0] + r[4] * q[1] + r[7] * q[2] + t.translation.y,
                 r[2] * q[0] + r[5] * q[1] + r[8] * q[2] + t.translation.z};
  };
  auto sub = [](const DVec3& a, const DVec3& b) { return DVec3{a.x - b.x, a.y - b.y, a.z - b.z}; };
  std::size_t away = 0, checked = 0;
  MotionFrame frame;
  frame.boxes = p.object_boxes;
  for (double time : {0.0, 7.5, 31.0}) {
    evaluateMotion(p.motion, p.static_objects, time, frame);
    for (ObjectId id = p.static_objects; id < mesh.draws.size(); ++id) {
      const Aabb& b = frame.boxes[id];
      const DVec3 centre{(double(b.min.x) + b.max.x) / 2, (double(b.min.y) + b.max.y) / 2,
                         (double(b.min.z) + b.max.z) / 2};
      const RigidTransform& t = frame.transforms[id - p.static_objects];
      const gl::RenderMesh::Draw& d = mesh.draws[id];
      for (int e = 0; e < 26; ++e) {       // the 26 directions of a cube's faces, edges, corners
        const int k = e < 13 ? e : e + 1;  // 13 is the centre
        const int dx = k % 3 - 1, dy = k / 3 % 3 - 1, dz = k / 9 - 1;
        const DVec3 eye{centre.x + 40.0 * dx, centre.y + 40.0 * dy, centre.z + 40.0 * dz};
        Camera camera;
        camera.width = camera.height = 512;
        camera.view_projection =
            multiply(perspective(1.0, 1.0, 0.5, 500, camera.depth),
                     lookAt(eye, centre, dx == 0 && dz == 0 ? DVec3{1, 0, 0} : DVec3{0, 1, 0}));
        ++checked;
        if (!clusterFacesAway(p, frame, id, camera, eye, 1.0 / 256)) continue;
        ++away;
        for (std::uint32_t i = d.first_index; i < d.first_index + d.index_count; i += 3) {
          const DVec3 a = vertex(d, i, t), b1 = vertex(d, i + 1, t), c = vertex(d, i + 2, t);
          const DVec3 u = sub(b1, a), v = sub(c, a), w = sub(eye, a);
          const DVec3 n{u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
          ASSERT_LT(n.x * w.x + n.y * w.y + n.z * w.z, 0.0)
              << "moving object " << id - p.static_objects << " at time " << time
              << ": a triangle faces the eye";
        }
      }
    }
  }
  EXPECT_GT(away, 0u) << "no moving cluster ever faced away of " << checked;
}

// A moving cluster's box (Motion::movingBoxAt: its part of the mesh moved) holds each of
// its vertices as the renderer draws it (mesh_renderer.hpp): u_rotation * p + u_offset
// in float, u_offset = translation - render_origin rounded once, here with the eye a few
// metres from the vehicle; the point drawn is that plus the origin. Beyond the box by at
// most the rounding of that last float sum (u of its size), which the render error of
// projection.hpp covers. Fails when a part gets another cluster's box (no other unit
// test does); Movers.BoxesHoldEveryVertexAsAFloatRendererPlacesIt shows the pad.
TEST(Clusters, AMovingClustersBoxHoldsItsVerticesAsTheRendererDrawsThem) {
  const PreparedScene p = cityWithClusteredVehicles();
  const gl::RenderMesh& mesh = p.mesh;
  constexpr double kU = 1.0 / 16777216.0;
  MotionFrame frame;
  frame.boxes = p.object_boxes;
  std::size_t checked = 0;
  for (double time : {0.0, 7.5, 31.0, 1234.5}) {
    evaluateMotion(p.motion, p.static_objects, time, frame);
    for (ObjectId id = p.static_objects; id < mesh.draws.size(); ++id) {
      const Aabb& box = frame.boxes[id];
      const RigidTransform& t = frame.transforms[id - p.static_objects];
      float r[9];
      for (int k = 0; k < 9; ++k) r[k] = static_cast<float>(t.rotation[k]);
      const double eye[3] = {double(float(box.max.x + 3.1)), double(float(box.max.y + 1.7)),
                             double(float(box.min.z - 2.3))};
      const float offset[3] = {float(t.translation.x - eye[0]), float(t.translation.y - eye[1]),
                               float(t.translation.z - eye[2])};
      const double lo[3] = {box.min.x, box.min.y, box.min.z};
      const double hi[3] = {box.max.x, box.max.y, box.max.z};
      const gl::RenderMesh::Draw& d = mesh.draws[id];
      for (std::uint32_t i = d.first_index; i < d.first_index + d.index_count; ++i) {
        const std::uint32_t local = mesh.indices16.empty() ? mesh.indices32[i] : mesh.indices16[i];
        const float* q = &mesh.positions[(std::size_t(d.base_vertex) + local) * 3];
        for (int row = 0; row < 3; ++row) {
          const float turned = r[row] * q[0] + r[3 + row] * q[1] + r[6 + row] * q[2];
          const float relative = turned + offset[row];
          const double drawn = double(relative) + eye[row];
          const double slack = kU * std::fabs(double(relative));
          ASSERT_TRUE(lo[row] - slack <= drawn && drawn <= hi[row] + slack)
              << "moving object " << id - p.static_objects << " at time " << time << ": axis "
              << row << " drawn at " << drawn << ", box " << lo[row] << " to " << hi[row];
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 0u);
}

TEST(Clusters, OptionsOutsideMeshoptimizersLimitsAreRefusedByName) {
  for (const auto& [triangles, vertices, needle] :
       {std::tuple{6u, 0u, "cluster size 6 triangles is invalid"},
        std::tuple{516u, 0u, "cluster size 516"}, std::tuple{64u, 2u, "vertex limit 2"},
        std::tuple{64u, 256u, "vertex limit 256"}}) {
    ClusterOptions o;
    o.triangles = triangles;
    o.vertices = vertices;
    const std::string problem = validateClusterOptions(o);
    EXPECT_NE(problem.find(needle), std::string::npos) << problem;
    Scene s = makeForest({0.01, 1, TreeParts::Whole});
    const bvh::BuildArgs args = defaultBuildArgs(s);
    try {
      (void)prepareScene(std::move(s), args, o);
      ADD_FAILURE() << "accepted " << triangles << "/" << vertices;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(validateClusterOptions({}).empty());
  ClusterOptions fine;
  fine.triangles = 124;
  fine.vertices = 255;
  EXPECT_TRUE(validateClusterOptions(fine).empty());
  fine.threads = 1025;
  EXPECT_NE(validateClusterOptions(fine).find("cluster threads 1025"), std::string::npos);
}

bool sameCluster(const Cluster& a, const Cluster& b) {
  const auto same3 = [](const double* x, const double* y) {
    return x[0] == y[0] && x[1] == y[1] && x[2] == y[2];
  };
  return a.triangles == b.triangles && a.box.min.x == b.box.min.x && a.box.min.y == b.box.min.y &&
         a.box.min.z == b.box.min.z && a.box.max.x == b.box.max.x && a.box.max.y == b.box.max.y &&
         a.box.max.z == b.box.max.z && same3(a.cone.apex, b.cone.apex) &&
         same3(a.cone.axis, b.cone.axis) && a.cone.cutoff == b.cone.cutoff &&
         a.cone.reach == b.cone.reach;
}

TEST(Clusters, TheSameForAnyNumberOfThreadsAsOneObjectAfterAnother) {
  // The city's chunks in the triangle hierarchy's order (gathered), and the forest's
  // trees in place: buildClusters on 1, 2 and 5 threads writes what one ClusterBuilder
  // writes object after object.
  for (const std::string name : {"city", "forest"}) {
    SCOPED_TRACE(name);
    Scene s = name == "city" ? makeCity({0.02, 1}) : makeForest({0.05, 1, TreeParts::Whole});
    std::vector<TriangleSpan> spans;
    std::vector<std::uint32_t> order;
    if (name == "city") {
      const bvh::TriangleHierarchy th =
          bvh::buildOverTriangles(s.positions, s.indices, defaultBuildArgs(s));
      for (std::size_t c = 0; c + 1 < th.chunk_first.size(); ++c) {
        spans.emplace_back(th.chunk_first[c], th.chunk_first[c + 1]);
      }
      order = th.triangle_order;
    } else {
      for (const SceneObject& o : s.objects) {
        spans.emplace_back(o.first_index / 3, (o.first_index + o.index_count) / 3);
      }
    }
    ASSERT_GT(spans.size(), 20u);
    ClusterOptions options;
    options.triangles = 64;
    ClusterBuilder builder(s.positions.data(), s.positions.size() / 3, options);
    std::vector<std::uint32_t> expected(s.indices.size());
    std::vector<std::vector<Cluster>> expected_clusters;
    for (const auto& [first, last] : spans) {
      std::vector<std::uint32_t> object;
      for (std::uint32_t i = first; i < last; ++i) {
        const std::uint32_t t = order.empty() ? i : order[i];
        object.insert(object.end(), &s.indices[std::size_t(t) * 3],
                      &s.indices[std::size_t(t) * 3] + 3);
      }
      expected_clusters.push_back(
          builder.build(object.data(), object.size(), &expected[std::size_t(first) * 3]));
    }
    for (unsigned threads : {1u, 2u, 5u}) {
      SCOPED_TRACE(threads);
      options.threads = threads;
      std::vector<std::uint32_t> indices = s.indices;
      std::vector<std::uint32_t> out(indices.size());
      std::uint32_t* written = order.empty() ? indices.data() : out.data();
      const std::vector<std::vector<Cluster>> clusters =
          buildClusters(s.positions.data(), s.positions.size() / 3, indices.data(),
                        order.empty() ? nullptr : order.data(), spans, written, options);
      ASSERT_EQ(clusters.size(), spans.size());
      for (const auto& [first, last] : spans) {
        ASSERT_TRUE(std::equal(expected.begin() + std::ptrdiff_t(first) * 3,
                               expected.begin() + std::ptrdiff_t(last) * 3,
                               written + std::size_t(first) * 3))
            << "triangles " << first << " to " << last;
      }
      for (std::size_t o = 0; o < spans.size(); ++o) {
        ASSERT_EQ(clusters[o].size(), expected_clusters[o].size()) << "object " << o;
        for (std::size_t c = 0; c < clusters[o].size(); ++c) {
          ASSERT_TRUE(sameCluster(clusters[o][c], expected_clusters[o][c]))
              << "object " << o << ", cluster " << c;
        }
      }
    }
  }
}

// Each object's triangles as the renderer draws them, by their corners' positions:
// sorted, so that two meshes of the same triangles compare equal.
std::vector<std::array<float, 9>> drawnTriangles(const PreparedScene& p, std::uint32_t object) {
  std::vector<std::array<float, 9>> out;
  for (ObjectId id = 0; id < p.mesh.draws.size(); ++id) {
    if (p.objectOf(id) != object) continue;
    const gl::RenderMesh::Draw& d = p.mesh.draws[id];
    for (std::uint32_t i = d.first_index; i < d.first_index + d.index_count; i += 3) {
      std::array<float, 9> t{};
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t local =
            p.mesh.indices16.empty() ? p.mesh.indices32[i + k] : p.mesh.indices16[i + k];
        const float* v = &p.mesh.positions[(std::size_t(d.base_vertex) + local) * 3];
        std::copy(v, v + 3, t.begin() + k * 3);
      }
      out.push_back(t);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Clusters, ObjectsThatShareTrianglesEachGetThemAll) {
  // Objects whose index ranges overlap (allowed: validateScene does not refuse it)
  // cannot be clustered in place; each still draws all of its triangles.
  auto make = [] {
    Scene s = makeForest({0.01, 1, TreeParts::Whole});
    s.objects.push_back(s.objects[1]);
    // The second half of object 0 and the first half of the next.
    SceneObject across;
    across.first_index = s.objects[0].first_index + s.objects[0].index_count / 6 * 3;
    across.index_count =
        s.objects[1].first_index + s.objects[1].index_count / 6 * 3 - across.first_index;
    across.box = emptyBox();
    for (std::uint32_t i = across.first_index; i < across.first_index + across.index_count; ++i) {
      growBox(across.box, &s.positions[std::size_t(s.indices[i]) * 3]);
    }
    s.objects.push_back(across);
    s.occluder_models.resize(s.objects.size());
    return s;
  };
  const WholeAndClustered both = prepareBoth(make, 64);
  const PreparedScene &whole = both.whole, &clustered = both.clustered;
  ASSERT_EQ(clustered.objectCount(), whole.objectCount());
  ASSERT_GT(clustered.static_objects, whole.static_objects);
  for (std::uint32_t o = 0; o < whole.objectCount(); ++o) {
    EXPECT_EQ(drawnTriangles(clustered, o), drawnTriangles(whole, o)) << "object " << o;
  }
}

}  // namespace
}  // namespace logrid::samples

namespace logrid::samples {
namespace {

TEST(Clusters, AFlatSurfaceFacesAwayFromBelowOnly) {
  Scene grid = test::flatGrid(16);
  ClusterOptions options;
  options.triangles = 64;
  ClusterBuilder builder(grid.positions.data(), grid.positions.size() / 3, options);
  std::vector<std::uint32_t> out;
  const std::vector<Cluster> clusters =
      builder.build(grid.indices.data(), grid.indices.size(), out);
  ASSERT_GT(clusters.size(), 4u);
  for (const Cluster& c : clusters) {
    ASSERT_LT(c.cone.cutoff, 1.0) << "a flat cluster has a cone";
    const DVec3 centre{0.5 * (c.box.min.x + c.box.max.x), 0, 0.5 * (c.box.min.z + c.box.max.z)};
    // Below: every triangle shows its back. Above, level with it, or just under its
    // plane seen at a grazing angle: not said to face away.
    EXPECT_TRUE(facesAway(c.cone, {centre.x, -10, centre.z}));
    EXPECT_TRUE(facesAway(c.cone, {centre.x + 30, -20, centre.z - 30}));
    EXPECT_FALSE(facesAway(c.cone, {centre.x, 10, centre.z}));
    EXPECT_FALSE(facesAway(c.cone, {centre.x + 50, 0, centre.z}));
    EXPECT_FALSE(facesAway(c.cone, {centre.x + 100, -0.2, centre.z}));  // 0.002 rad below
  }
}

TEST(Clusters, TheConesOfTheScenes) {
  // Some clusters of each scene can be said to face away (a cone that is not void); how
  // many is printed (round solids need smaller clusters than flat walls).
  for (const std::string name : {"forest", "city", "office"}) {
    Scene s = name == "city"     ? makeCity({0.01, 1})
              : name == "office" ? makeOffice({0.35, 1})
                                 : makeForest({0.03, 1, TreeParts::Whole});
    const bvh::BuildArgs args = defaultBuildArgs(s);
    ClusterOptions options;
    options.triangles = 64;
    const PreparedScene p = prepareScene(std::move(s), args, options);
    std::size_t with_cone = 0;
    for (const ClusterCone& c : p.cluster_cones) with_cone += c.cutoff <= 1;
    std::printf("%s: %zu of %zu clusters of 64 triangles have a cone\n", name.c_str(), with_cone,
                p.cluster_cones.size());
    EXPECT_GT(with_cone, 0u) << name;
  }
}

}  // namespace
}  // namespace logrid::samples
