#include "scene/prepare.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

// Appends one object's triangles to the mesh with its vertices regrouped locally.
// `stamp`/`local` are per-source-vertex scratch arrays reused across objects.
class MeshBuilder {
 public:
  MeshBuilder(const Scene& scene, gl::RenderMesh& mesh, bool wide)
      : scene_(scene),
        mesh_(mesh),
        wide_(wide),
        stamp_(scene.positions.size() / 3, kNone),
        local_(scene.positions.size() / 3, 0) {}

  // Triangles are given by their index into scene.indices / 3.
  template <typename TriangleRange>
  void addObject(const TriangleRange& triangles, std::uint32_t color) {
    ++object_;
    gl::RenderMesh::Draw draw;
    draw.base_vertex = static_cast<std::int32_t>(mesh_.positions.size() / 3);
    draw.first_index =
        static_cast<std::uint32_t>(wide_ ? mesh_.indices32.size() : mesh_.indices16.size());
    draw.color = color;
    std::uint32_t next = 0;
    for (std::uint32_t t : triangles) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = scene_.indices[std::size_t(t) * 3 + std::size_t(k)];
        if (stamp_[v] != object_) {
          stamp_[v] = object_;
          local_[v] = next++;
          mesh_.positions.insert(mesh_.positions.end(), &scene_.positions[std::size_t(v) * 3],
                                 &scene_.positions[std::size_t(v) * 3] + 3);
          if (!scene_.vertex_colors.empty()) mesh_.colors.push_back(scene_.vertex_colors[v]);
        }
        if (wide_) {
          mesh_.indices32.push_back(local_[v]);
        } else {
          mesh_.indices16.push_back(static_cast<std::uint16_t>(local_[v]));
        }
      }
      draw.index_count += 3;
    }
    mesh_.draws.push_back(draw);
  }

 private:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  const Scene& scene_;
  gl::RenderMesh& mesh_;
  bool wide_;
  std::uint32_t object_ = 0;
  std::vector<std::uint32_t> stamp_;
  std::vector<std::uint32_t> local_;
};

// A contiguous run of triangle numbers, or a run of a permutation.
struct IotaRange {
  std::uint32_t first, last;
  struct It {
    std::uint32_t v;
    std::uint32_t operator*() const { return v; }
    It& operator++() { return ++v, *this; }
    bool operator!=(const It& o) const { return v != o.v; }
  };
  It begin() const { return {first}; }
  It end() const { return {last}; }
};

struct SpanRange {
  const std::uint32_t* first;
  const std::uint32_t* last;
  const std::uint32_t* begin() const { return first; }
  const std::uint32_t* end() const { return last; }
};

// Whether every object fits 16-bit local indices: an object never has more distinct
// vertices than 3 * triangles, so only large objects need counting.
bool needsWideIndices(const Scene& scene,
                      const std::vector<std::pair<std::uint32_t, std::uint32_t>>& spans,
                      const std::uint32_t* order) {
  std::vector<std::uint32_t> stamp(scene.positions.size() / 3, 0);
  std::uint32_t object = 0;
  for (const auto& [first, last] : spans) {
    ++object;
    if (std::uint64_t(last - first) * 3 <= 65536) continue;
    std::uint32_t distinct = 0;
    for (std::uint32_t i = first; i < last; ++i) {
      const std::uint32_t t = order ? order[i] : i;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = scene.indices[std::size_t(t) * 3 + std::size_t(k)];
        if (stamp[v] != object) stamp[v] = object, ++distinct;
      }
    }
    if (distinct > 65536) return true;
  }
  return false;
}

// The occluder model of each chunk of a split scene (scene.hpp, OccluderSolid): the box
// of every solid one of its triangles belongs to, and its other triangles as they are.
// A chunk with no tagged triangle gets no model (its mesh is its occluder).
std::vector<OccluderModel> chunkModels(
    const Scene& scene, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& spans,
    const std::uint32_t* order) {
  std::vector<OccluderModel> models(spans.size());
  std::vector<std::uint32_t> seen(scene.occluder_solids.size(), kNoSolid);  // chunk stamp
  for (std::uint32_t c = 0; c < spans.size(); ++c) {
    OccluderModel& m = models[c];
    bool any = false;
    for (std::uint32_t i = spans[c].first; i < spans[c].second; ++i) {
      const std::uint32_t t = order[i];
      const std::uint32_t solid =
          t < scene.triangle_solids.size() ? scene.triangle_solids[t] : kNoSolid;
      if (solid == kNoSolid) {
        for (int k = 0; k < 3; ++k) {
          const float* p =
              &scene.positions[std::size_t(scene.indices[std::size_t(t) * 3 + std::size_t(k)]) * 3];
          m.indices.push_back(std::uint32_t(m.positions.size() / 3));
          m.positions.insert(m.positions.end(), p, p + 3);
        }
        continue;
      }
      any = true;
      if (seen[solid] == c) continue;
      seen[solid] = c;
      const OccluderSolid& s = scene.occluder_solids[solid];
      m.boxes.push_back(s.inside);
      if (m.reach.min.x > m.reach.max.x) m.reach = emptyBox();
      growBox(m.reach, s.around);
    }
    if (!any) m = OccluderModel{};
  }
  return models;
}

// Whether the objects' triangle ranges, and the movers', are apart: then each object's
// clusters can take the place of its triangles.
bool spansApart(const Scene& scene, std::vector<TriangleSpan> spans) {
  for (const SceneObject& o : scene.moving) {
    spans.emplace_back(o.first_index / 3, (o.first_index + o.index_count) / 3);
  }
  std::sort(spans.begin(), spans.end());
  for (std::size_t i = 1; i < spans.size(); ++i) {
    if (spans[i].first < spans[i - 1].second) return false;
  }
  return true;
}

// The object's draw (the last of `draws`, its triangles in cluster order) cut into its
// clusters' ranges.
void cutIntoClusters(const std::vector<Cluster>& clusters,
                     std::vector<gl::RenderMesh::Draw>& draws) {
  gl::RenderMesh::Draw part = draws.back();
  draws.pop_back();
  for (const Cluster& c : clusters) {
    part.index_count = c.triangles * 3;
    draws.push_back(part);
    part.first_index += part.index_count;
  }
}

// Every object (or chunk) split into clusters, each cluster an ObjectId of its own: the
// hierarchy over the clusters' boxes, one leaf each (args.max_leaf_size, which counts
// objects or triangles, is about the objects the clusters replace), and one draw per
// cluster, the clusters of an object consecutive in the index buffer over the object's
// vertices (a batch of them draws as a few ranges, MeshRenderer::drawBatch). Object i's
// triangles: order[spans[i].first, spans[i].second) of scene.indices, or without an
// order that range itself. With an order (the city's chunks, in the triangle
// hierarchy's order: static triangles [0, order's size)), the clustered triangles take
// the place of the static triangles, spans[i] then the object's; without one, of each
// object's own where no two ranges overlap (the movers' stay as they are), else they
// are appended to scene.indices. Occluder models are not kept: each cluster occludes
// with its own triangles.
template <typename ColorOf>
void prepareClusters(Scene& scene, std::vector<TriangleSpan> spans, const std::uint32_t* order,
                     ColorOf color_of, const ClusterOptions& options, const bvh::BuildArgs& args,
                     PreparedScene& out) {
  const auto cluster_start = std::chrono::steady_clock::now();
  const std::size_t objects = spans.size();
  if (!order && !spansApart(scene, spans)) {
    std::size_t end = scene.indices.size() / 3;
    for (const auto& [first, last] : spans) end += last - first;
    std::size_t at = scene.indices.size() / 3;
    scene.indices.resize(end * 3);
    for (auto& [first, last] : spans) {
      std::copy(scene.indices.begin() + std::ptrdiff_t(first) * 3,
                scene.indices.begin() + std::ptrdiff_t(last) * 3,
                scene.indices.begin() + std::ptrdiff_t(at) * 3);
      last = static_cast<std::uint32_t>(at + (last - first));
      first = static_cast<std::uint32_t>(at);
      at = last;
    }
  }
  std::vector<std::vector<Cluster>> object_clusters;
  if (order) {
    std::vector<std::uint32_t> clustered(spans.empty() ? 0 : std::size_t(spans.back().second) * 3);
    object_clusters = buildClusters(scene.positions.data(), scene.positions.size() / 3,
                                    scene.indices.data(), order, spans, clustered.data(), options);
    std::copy(clustered.begin(), clustered.end(), scene.indices.begin());
  } else {
    object_clusters =
        buildClusters(scene.positions.data(), scene.positions.size() / 3, scene.indices.data(),
                      nullptr, spans, scene.indices.data(), options);
  }
  out.cluster_ms = msSince(cluster_start);

  std::vector<Aabb> boxes;
  for (std::size_t i = 0; i < objects; ++i) {
    for (const Cluster& c : object_clusters[i]) {
      boxes.push_back(c.box);
      out.cluster_objects.push_back(static_cast<std::uint32_t>(i));
      out.cluster_cones.push_back(c.cone);
    }
  }
  bvh::BuildArgs cluster_args = args;
  cluster_args.max_leaf_size = 1;
  const auto build_start = std::chrono::steady_clock::now();
  out.hierarchy = bvh::buildOverBoxes(boxes, cluster_args);
  out.bvh_build_ms += msSince(build_start);

  MeshBuilder mesh(scene, out.mesh, needsWideIndices(scene, spans, nullptr));
  for (std::size_t i = 0; i < objects; ++i) {
    mesh.addObject(IotaRange{spans[i].first, spans[i].second}, color_of(i));
    cutIntoClusters(object_clusters[i], out.mesh.draws);
  }
  out.occluder_models.clear();
}

// Scenes split by triangles (the city): the static triangles cut into chunks by the
// hierarchy over them, each chunk an object; the movers' meshes stay after them.
void prepareChunks(Scene& scene, const bvh::BuildArgs& args, const ClusterOptions& clusters,
                   PreparedScene& out) {
  // The movers' meshes are appended after the static triangles (movers.cpp): set them
  // aside while the static triangles are split into chunks.
  std::size_t static_end = scene.indices.size();
  for (const SceneObject& o : scene.moving)
    static_end = std::min<std::size_t>(static_end, o.first_index);
  std::vector<std::uint32_t> moving_indices(scene.indices.begin() + std::ptrdiff_t(static_end),
                                            scene.indices.end());
  scene.indices.resize(static_end);
  const auto build_start = std::chrono::steady_clock::now();
  bvh::TriangleHierarchy th = bvh::buildOverTriangles(scene.positions, scene.indices, args);
  out.bvh_build_ms = msSince(build_start);
  scene.indices.insert(scene.indices.end(), moving_indices.begin(), moving_indices.end());
  out.hierarchy = std::move(th.hierarchy);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> spans;
  for (std::size_t c = 0; c + 1 < th.chunk_first.size(); ++c) {
    spans.emplace_back(th.chunk_first[c], th.chunk_first[c + 1]);
  }
  if (clusters.enabled()) {
    prepareClusters(
        scene, std::move(spans), th.triangle_order.data(), [](std::size_t) { return 0xFFFFFFFFu; },
        clusters, args, out);
    return;
  }
  const bool wide = needsWideIndices(scene, spans, th.triangle_order.data());
  MeshBuilder builder(scene, out.mesh, wide);
  for (const auto& [first, last] : spans) {
    builder.addObject(SpanRange{th.triangle_order.data() + first, th.triangle_order.data() + last},
                      0xFFFFFFFFu);
  }
  if (!scene.triangle_solids.empty()) {
    out.occluder_models = chunkModels(scene, spans, th.triangle_order.data());
  }
}

// Scenes of objects: the hierarchy over their boxes, each object one draw.
void prepareObjects(Scene& scene, const bvh::BuildArgs& args, const ClusterOptions& clusters,
                    PreparedScene& out) {
  out.source_objects = scene.objects.size();
  if (clusters.enabled()) {
    std::vector<TriangleSpan> spans;
    for (const SceneObject& o : scene.objects) {
      spans.emplace_back(o.first_index / 3, (o.first_index + o.index_count) / 3);
    }
    prepareClusters(
        scene, std::move(spans), nullptr, [&](std::size_t i) { return scene.objects[i].color; },
        clusters, args, out);
    return;
  }
  std::vector<Aabb> boxes;
  boxes.reserve(scene.objects.size());
  for (const SceneObject& o : scene.objects) boxes.push_back(o.box);
  const auto build_start = std::chrono::steady_clock::now();
  out.hierarchy = bvh::buildOverBoxes(boxes, args);
  out.bvh_build_ms = msSince(build_start);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> spans;
  for (const SceneObject& o : scene.objects) {
    spans.emplace_back(o.first_index / 3, (o.first_index + o.index_count) / 3);
  }
  const bool wide = needsWideIndices(scene, spans, nullptr);
  MeshBuilder builder(scene, out.mesh, wide);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    builder.addObject(IotaRange{spans[i].first, spans[i].second}, scene.objects[i].color);
  }
  out.occluder_models = std::move(scene.occluder_models);
}

// Moving objects after the static ones; objects over the same indices share a draw's
// geometry (the movers of one shape). With clusters each shape is clustered once and a
// mover is drawn as its shape's clusters, each a moving object of its own
// (Motion::parts) with its cone in the mesh's coordinates; the clustered triangles are
// appended to scene.indices.
void appendMovers(Scene& scene, const ClusterOptions& clusters, PreparedScene& out) {
  out.static_objects = static_cast<std::uint32_t>(out.mesh.draws.size());
  if (scene.moving.empty()) return;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> spans;
  for (const SceneObject& o : scene.moving) {
    spans.emplace_back(o.first_index / 3, (o.first_index + o.index_count) / 3);
  }
  const bool wide = !out.mesh.indices32.empty() || needsWideIndices(scene, spans, nullptr);
  if (wide && out.mesh.indices32.empty() && !out.mesh.indices16.empty()) {
    out.mesh.indices32.assign(out.mesh.indices16.begin(), out.mesh.indices16.end());
    out.mesh.indices16.clear();
  }
  MeshBuilder builder(scene, out.mesh, wide);
  std::optional<ClusterBuilder> cluster_builder;
  if (clusters.enabled()) {
    cluster_builder.emplace(scene.positions.data(), scene.positions.size() / 3, clusters);
  }
  // A shape's draws (one, or one a cluster) and clusters (none without clusters).
  struct Shape {
    std::vector<gl::RenderMesh::Draw> draws;
    std::vector<Cluster> clusters;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, Shape> shapes;  // by span
  const std::uint32_t first_object =
      out.cluster_objects.empty() ? 0 : out.cluster_objects.back() + 1;
  std::vector<std::uint32_t> clustered;
  for (std::size_t i = 0; i < scene.moving.size(); ++i) {
    const auto [it, first] = shapes.try_emplace(spans[i]);
    Shape& shape = it->second;
    if (first) {
      const std::size_t draw = out.mesh.draws.size();
      if (cluster_builder) {
        clustered.clear();
        const std::uint32_t* source = &scene.indices[std::size_t(spans[i].first) * 3];
        shape.clusters = cluster_builder->build(
            source, std::size_t(spans[i].second - spans[i].first) * 3, clustered);
        const auto at = static_cast<std::uint32_t>(scene.indices.size() / 3);
        scene.indices.insert(scene.indices.end(), clustered.begin(), clustered.end());
        builder.addObject(IotaRange{at, static_cast<std::uint32_t>(scene.indices.size() / 3)}, 0);
        cutIntoClusters(shape.clusters, out.mesh.draws);
      } else {
        builder.addObject(IotaRange{spans[i].first, spans[i].second}, 0);
      }
      shape.draws.assign(out.mesh.draws.begin() + std::ptrdiff_t(draw), out.mesh.draws.end());
      out.mesh.draws.resize(draw);
    }
    for (std::size_t c = 0; c < shape.draws.size(); ++c) {
      gl::RenderMesh::Draw draw = shape.draws[c];
      draw.color = scene.moving[i].color;
      out.mesh.draws.push_back(draw);
      if (!cluster_builder) continue;
      out.motion.parts.push_back({static_cast<std::uint32_t>(i), shape.clusters[c].box});
      out.cluster_objects.push_back(first_object + static_cast<std::uint32_t>(i));
      out.cluster_cones.push_back(shape.clusters[c].cone);
    }
  }
}

// Each object's box from the renderer's mesh (movers where they are at time 0), the
// scene's bounds, and the triangles per object (for nohc's cost model) and in all.
void measureObjects(PreparedScene& out) {
  std::vector<std::uint32_t> triangles;  // per object
  triangles.reserve(out.mesh.draws.size());
  for (const gl::RenderMesh::Draw& d : out.mesh.draws) triangles.push_back(d.index_count / 3);
  out.hierarchy.setObjectTriangles(std::move(triangles));

  out.bounds = emptyBox();
  out.object_boxes.reserve(out.mesh.draws.size());
  for (std::size_t o = 0; o < out.mesh.draws.size(); ++o) {
    if (o >= out.static_objects) {  // a mover, at time 0
      out.object_boxes.push_back(out.motion.movingBoxAt(o - out.static_objects, 0.0));
      continue;
    }
    const gl::RenderMesh::Draw& d = out.mesh.draws[o];
    Aabb box = emptyBox();
    for (std::uint32_t i = d.first_index; i < d.first_index + d.index_count; ++i) {
      const std::uint32_t local =
          out.mesh.indices16.empty() ? out.mesh.indices32[i] : out.mesh.indices16[i];
      growBox(box, &out.mesh.positions[(std::size_t(d.base_vertex) + local) * 3]);
    }
    out.object_boxes.push_back(box);
    growBox(out.bounds, box);
  }
  // Every object's triangles, each mover's counted (they share geometry but are drawn
  // one by one).
  out.triangles = 0;
  for (const gl::RenderMesh::Draw& d : out.mesh.draws) out.triangles += d.index_count / 3;
}

}  // namespace

std::size_t PreparedScene::memoryBytes() const {
  return hierarchy.memoryBytes() + mesh.memoryBytes() + object_boxes.capacity() * sizeof(Aabb) +
         cluster_objects.capacity() * sizeof(std::uint32_t) +
         cluster_cones.capacity() * sizeof(ClusterCone);
}

std::uint32_t PreparedScene::objectOf(ObjectId id) const {
  return clustered() ? cluster_objects[id] : id;
}

std::uint32_t PreparedScene::objectCount() const {
  const auto ids = static_cast<std::uint32_t>(mesh.draws.size());
  return ids ? objectOf(ids - 1) + 1 : 0;
}

// Each triangle must either lie wholly outside one clip plane, or wholly inside the clip
// volume (by a margin, so that GL's float transform clips nothing) and be clockwise in
// window space by more than its corners' error can turn. GL snaps each window corner to
// its sub-pixel grid (by up to a step in x and y, rounding or truncating) after a float
// transform relative to the render origin near the eye (a few ulps of the clip
// coordinates, about 1e-6 of the viewport's width plus height in window space; 1e-5
// taken), so a corner is off by at most e in each axis and the doubled area
// (b - a) x (c - a) by at most 2 sqrt(2) e (|b - a| + |c - a|) + 8 e^2. Computed in
// double from the mesh's own floats.
bool drawsNothingWithBackFacesCulled(const gl::RenderMesh& mesh, const gl::RenderMesh::Draw& d,
                                     const RigidTransform* t, const Camera& camera,
                                     double snap_step) {
  const Mat4d& m = camera.view_projection;
  const bool zero_to_one = camera.depth.clip_range == ClipDepthRange::ZeroToOne;
  const double e = snap_step + 1e-5 * (double(camera.width) + camera.height);
  struct Corner {
    double x, y;      // window
    double plane[6];  // >= 0 inside each clip plane
  };
  auto corner = [&](std::uint32_t i) {
    const std::uint32_t local = mesh.indices16.empty() ? mesh.indices32[i] : mesh.indices16[i];
    const float* q = &mesh.positions[(std::size_t(d.base_vertex) + local) * 3];
    double p[3] = {q[0], q[1], q[2]};
    if (t) {
      const double* r = t->rotation;
      const double w[3] = {r[0] * p[0] + r[3] * p[1] + r[6] * p[2] + t->translation.x,
                           r[1] * p[0] + r[4] * p[1] + r[7] * p[2] + t->translation.y,
                           r[2] * p[0] + r[5] * p[1] + r[8] * p[2] + t->translation.z};
      std::copy(w, w + 3, p);
    }
    double c[4];
    for (int row = 0; row < 4; ++row) {
      c[row] = m(row, 0) * p[0] + m(row, 1) * p[1] + m(row, 2) * p[2] + m(row, 3);
    }
    Corner out{};
    const double tol =
        1e-4 * (std::fabs(c[0]) + std::fabs(c[1]) + std::fabs(c[2]) + std::fabs(c[3]));
    const double planes[6] = {c[3] - c[0], c[3] + c[0], c[3] - c[1],
                              c[3] + c[1], c[3] - c[2], zero_to_one ? c[2] : c[3] + c[2]};
    for (int k = 0; k < 6; ++k) {  // the sign, or 0 within the margin of the plane
      out.plane[k] = planes[k] > tol ? 1 : planes[k] < -tol ? -1 : 0;
    }
    if (c[3] > 0) {
      out.x = (c[0] / c[3] + 1) * 0.5 * camera.width;
      out.y = (c[1] / c[3] + 1) * 0.5 * camera.height;
    }
    return out;
  };
  for (std::uint32_t i = d.first_index; i < d.first_index + d.index_count; i += 3) {
    const Corner a = corner(i), b = corner(i + 1), c = corner(i + 2);
    bool outside = false, inside = true;
    for (int k = 0; k < 6; ++k) {
      outside = outside || (a.plane[k] < 0 && b.plane[k] < 0 && c.plane[k] < 0);
      inside = inside && a.plane[k] > 0 && b.plane[k] > 0 && c.plane[k] > 0;
    }
    if (outside) continue;
    if (!inside) return false;
    const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
    const double area2 = ux * vy - uy * vx;  // > 0: counter-clockwise, a front face
    const double turn =
        2 * std::sqrt(2.0) * e * (std::hypot(ux, uy) + std::hypot(vx, vy)) + 8 * e * e;
    if (!(-area2 > turn)) return false;
  }
  return true;
}

// The cone first (cheap, and it turns most clusters down); a moving cluster's cone is in
// its mesh's coordinates, the eye taken there through the inverse of the rigid transform
// it is drawn with. Then every triangle where GL puts it (drawsNothingWithBackFacesCulled):
// the cone's margin bounds angles, not GL's snapping of small or thin triangles to its
// sub-pixel grid, which can turn a triangle seen from behind to face the eye.
bool clusterFacesAway(const PreparedScene& scene, const MotionFrame& motion, ObjectId id,
                      const Camera& camera, const DVec3& eye, double snap_step) {
  const RigidTransform* t =
      id < scene.static_objects ? nullptr : &motion.transforms[id - scene.static_objects];
  DVec3 local = eye;
  if (t) {
    const double d[3] = {eye.x - t->translation.x, eye.y - t->translation.y,
                         eye.z - t->translation.z};
    const double* r = t->rotation;  // column-major: the inverse's row c is column c
    local = {r[0] * d[0] + r[1] * d[1] + r[2] * d[2], r[3] * d[0] + r[4] * d[1] + r[5] * d[2],
             r[6] * d[0] + r[7] * d[1] + r[8] * d[2]};
  }
  return facesAway(scene.cluster_cones[id], local) &&
         drawsNothingWithBackFacesCulled(scene.mesh, scene.mesh.draws[id], t, camera, snap_step);
}

bvh::BuildArgs defaultBuildArgs(const Scene& scene) {
  bvh::BuildArgs args;
  args.max_leaf_size = scene.split_by_triangles ? 1500 : 1;
  return args;
}

PreparedScene prepareScene(Scene&& scene, const bvh::BuildArgs& args,
                           const ClusterOptions& clusters) {
  const auto start = std::chrono::steady_clock::now();
  validateScene(scene);
  if (const std::string problem = validateClusterOptions(clusters); !problem.empty()) {
    throw Error(ErrorCode::InvalidArgument, problem);
  }
  PreparedScene out;
  out.name = scene.name;
  out.origin = scene.origin;
  out.path = scene.path;
  out.near_plane = scene.near_plane;
  out.far_plane = scene.far_plane;
  out.triangles = scene.triangleCount();
  if (scene.split_by_triangles) {
    prepareChunks(scene, args, clusters, out);
  } else {
    prepareObjects(scene, args, clusters, out);
  }
  out.motion = std::move(scene.motion);
  appendMovers(scene, clusters, out);
  // Release the source geometry before computing the per-object boxes from the mesh.
  scene.positions = {};
  scene.indices = {};
  scene.vertex_colors = {};
  out.mesh.positions.shrink_to_fit();
  out.mesh.colors.shrink_to_fit();
  measureObjects(out);
  out.prepare_ms = msSince(start);
  return out;
}

}  // namespace logrid::samples
