// logrid_example: a renderer that already owns a bounding-volume hierarchy adopts logrid.
//
// The lines between the "logrid integration" markers are all a renderer writes (README.md,
// "Integrating logrid", quotes them): the hierarchy adapter (1/2), and 14 lines of code for
// the culler, the depth source, the camera and the frame (2/2). The rest is the toy application: a wall in front of
// 16 small cubes, 4 cubes beside the wall and 2 outside the view, drawn headless through
// EGL into an off-screen framebuffer. Exits with 1 unless the wall and the cubes beside it
// were drawn and every cube behind the wall or outside the view was culled.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "logrid/cpu/software_rasterizer.hpp"  // appendBox
#include "logrid/gl/context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/logrid.hpp"
#include "logrid/zread/gl_sources.hpp"

namespace {

// ---- The application as it was before logrid -----------------------------------------
struct AppBox {
  float lo[3], hi[3];
};
struct AppNode {  // the app's own BVH: children contiguous; a leaf draws one mesh
  AppBox box;
  std::uint32_t first_child = 0, child_count = 0;
  std::int32_t mesh = -1;
};
struct AppCamera {  // GL-style column-major world-to-clip matrix, eye position, viewport
  double view_projection[16];
  double eye[3];
  std::uint32_t width, height;
};
struct ToyRenderer {  // logrid's test renderer stands in for the app's, recording draws
  logrid::gl::MeshRenderer meshes;
  std::vector<std::int32_t> drawn;
  void draw(std::uint32_t mesh) {
    meshes.draw(mesh);
    drawn.push_back(std::int32_t(mesh));
  }
};

// ==== logrid integration (1/2): the app's BVH seen as a logrid::Hierarchy ==============
using logrid::Aabb, logrid::NodeId, logrid::ObjectId;
struct AppHierarchy final : logrid::Hierarchy {
  const std::vector<AppNode>& nodes;
  explicit AppHierarchy(const std::vector<AppNode>& n) : nodes(n) {}
  NodeId root() const override { return nodes.empty() ? logrid::kNoNode : 0; }
  Aabb bounds(NodeId n) const override {
    const AppBox& b = nodes[n].box;
    return {{b.lo[0], b.lo[1], b.lo[2]}, {b.hi[0], b.hi[1], b.hi[2]}};
  }
  std::uint32_t childCount(NodeId n) const override { return nodes[n].child_count; }
  NodeId child(NodeId n, std::uint32_t i) const override { return nodes[n].first_child + i; }
  std::uint32_t objectCount(NodeId n) const override { return nodes[n].mesh < 0 ? 0 : 1; }
  ObjectId object(NodeId n, std::uint32_t) const override { return ObjectId(nodes[n].mesh); }
};
// ==== end of logrid integration (1/2) ===================================================

AppBox cube(float x, float y, float z, float half) {
  return {{x - half, y - half, z - half}, {x + half, y + half, z + half}};
}

void grow(AppBox& into, const AppBox& b) {
  for (int a = 0; a < 3; ++a) {
    into.lo[a] = std::min(into.lo[a], b.lo[a]);
    into.hi[a] = std::max(into.hi[a], b.hi[a]);
  }
}

// The app's BVH over groups of boxes: root -> one node per group -> one leaf per box.
// Mesh ids number the boxes in order.
std::vector<AppNode> buildAppBvh(const std::vector<std::vector<AppBox>>& groups) {
  const AppBox empty{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
  std::vector<AppNode> nodes(1 + groups.size(), AppNode{empty});
  nodes[0].first_child = 1;
  nodes[0].child_count = std::uint32_t(groups.size());
  std::int32_t mesh = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    nodes[1 + g].first_child = std::uint32_t(nodes.size());
    nodes[1 + g].child_count = std::uint32_t(groups[g].size());
    for (const AppBox& b : groups[g]) {
      nodes.push_back({b, 0, 0, mesh++});
      grow(nodes[1 + g].box, b);
    }
    grow(nodes[0].box, nodes[1 + g].box);
  }
  return nodes;
}

logrid::gl::RenderMesh meshesOf(const std::vector<std::vector<AppBox>>& groups,
                                const std::vector<std::uint32_t>& colors) {
  logrid::gl::RenderMesh mesh;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    for (const AppBox& b : groups[g]) {
      const auto first = std::uint32_t(mesh.indices32.size());
      logrid::cpu::appendBox({{b.lo[0], b.lo[1], b.lo[2]}, {b.hi[0], b.hi[1], b.hi[2]}},
                             mesh.positions, mesh.indices32);
      mesh.draws.push_back({first, std::uint32_t(mesh.indices32.size()) - first, 0, colors[g]});
    }
  }
  return mesh;
}

int run() {
  // The scene: mesh 0 is the wall, 1-16 hide behind it, 17-20 stand beside it, 21-22 are
  // behind the camera and far to the side.
  std::vector<AppBox> hidden, beside;
  for (float z : {-2.0f, -5.0f}) {
    for (float x : {-3.0f, -1.0f, 1.0f, 3.0f}) {
      for (float y : {-1.0f, 0.5f}) hidden.push_back(cube(x, y, z, 0.4f));
    }
  }
  for (float x : {-8.0f, 8.0f}) {
    for (float y : {0.0f, 2.5f}) beside.push_back(cube(x, y, 0.0f, 0.4f));
  }
  const std::vector<std::vector<AppBox>> groups = {
      {{{-5, -3, 2}, {5, 4, 2.4f}}}, hidden, beside, {cube(0, 0, 20, 1), cube(30, 0, 0, 1)}};
  const std::vector<AppNode> nodes = buildAppBvh(groups);

  // The app's camera and its matrices (logrid's helpers used here only for brevity).
  AppCamera app{{}, {0, 2, 12}, 256, 192};
  const logrid::Mat4d vp =
      logrid::multiply(logrid::perspective(1.0, 256.0 / 192.0, 0.5, 100.0, {}),
                       logrid::lookAt({app.eye[0], app.eye[1], app.eye[2]}, {0, 0, 0}, {0, 1, 0}));
  std::copy(vp.m, vp.m + 16, app.view_projection);

  // The app's GL set-up: headless context, a framebuffer with standard 32-bit float depth.
  logrid::gl::Context context;
  logrid::gl::Framebuffer framebuffer({app.width, app.height, logrid::DepthSetup{}, false});
  framebuffer.bind();
  ToyRenderer renderer{logrid::gl::MeshRenderer(
                           meshesOf(groups, {0xFF909090u, 0xFF2020E0u, 0xFF20C020u, 0xFFE02020u})),
                       {}};
  const float kBackground[4] = {0.1f, 0.1f, 0.1f, 1.0f};

  // ==== logrid integration (2/2): at start-up, then every frame ===========================
  AppHierarchy hierarchy(nodes);
  logrid::Culler culler;                                        // lazy occlusion grid
  logrid::zread::ReadPixelsSource depth(framebuffer.handle());  // reads the app's z-buffer
  logrid::Camera camera;  // depth as GL's default: standard, [-1, 1] clip range, 32-bit float
  std::copy(app.view_projection, app.view_projection + 16, camera.view_projection.m);
  camera.width = app.width, camera.height = app.height;
  camera.render_origin = {app.eye[0], app.eye[1], app.eye[2]};  // the renderer is camera-relative

  framebuffer.clear(kBackground);  // depth cleared first; then drawn with depth test and writes
  renderer.meshes.begin(logrid::gl::Pass::Shaded, camera);
  culler.beginFrame(camera, hierarchy, {&depth});
  for (logrid::DrawBatch batch = culler.nextBatch(); !batch.empty(); batch = culler.nextBatch())
    for (logrid::ObjectId id : batch) renderer.draw(id);  // or one multi-draw per batch
  const logrid::FrameStats stats = culler.endFrame();
  renderer.meshes.end();
  // ==== end of logrid integration (2/2) ===================================================
  context.check("logrid_example");

  const auto drew = [&](std::int32_t lo, std::int32_t hi) {  // meshes [lo, hi) drawn
    return std::int32_t(std::count_if(renderer.drawn.begin(), renderer.drawn.end(),
                                      [&](std::int32_t m) { return m >= lo && m < hi; }));
  };
  std::printf("logrid_example on %s, method %s\n", context.info().renderer.c_str(),
              logrid::toString(culler.desc().method));
  std::printf("drawn %llu of 23 meshes: wall %d/1, beside the wall %d/4\n",
              static_cast<unsigned long long>(stats.objects_drawn), drew(0, 1), drew(17, 21));
  std::printf("culled: behind the wall %d/16, outside the view %d/2\n", 16 - drew(1, 17),
              2 - drew(21, 23));
  std::printf(
      "nodes visited %llu, boxes tested %llu, occluded %llu, view-culled %llu, "
      "depth pixels read %llu\n",
      static_cast<unsigned long long>(stats.nodes_visited),
      static_cast<unsigned long long>(stats.boxes_tested),
      static_cast<unsigned long long>(stats.boxes_occluded),
      static_cast<unsigned long long>(stats.boxes_view_culled),
      static_cast<unsigned long long>(stats.pixels_read));
  const bool ok = drew(0, 1) == 1 && drew(17, 21) == 4 && drew(1, 17) == 0 && drew(21, 23) == 0 &&
                  renderer.drawn.size() == 5;
  std::printf("%s\n", ok ? "logrid_example: OK"
                         : "logrid_example: FAIL: expected the wall and the 4 cubes beside it "
                           "drawn, everything else culled");
  return ok ? 0 : 1;
}

}  // namespace

int main() {
  try {
    return run();
  } catch (const logrid::Error& e) {
    std::fprintf(stderr, "logrid_example: %s\n", e.what());
    return 1;
  }
}
