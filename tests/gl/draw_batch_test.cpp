// MeshRenderer::drawBatch (logrid/gl/mesh_renderer.hpp): a batch draws exactly what its
// objects draw one call each (the same colour and depth images), in fewer calls: ranges
// that follow each other merged, one multi-draw per colour, transformed objects one per
// run of the same transform and colour (a moving object's clusters).
#include <gtest/gtest.h>

#include <vector>

#include "gl_test_context.hpp"
#include "logrid/camera.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"

namespace logrid {
namespace {

constexpr std::uint32_t kRed = 0xFF0000FFu, kBlue = 0xFFFF0000u;

// Eight boxes in a row across the view, at staggered depths so that some overlap: the
// first four one object's clusters (consecutive ranges over shared vertices, red), the
// next two red objects of their own, the last two blue.
gl::RenderMesh rowOfBoxes() {
  gl::RenderMesh mesh;
  std::vector<std::uint32_t> indices;
  for (int i = 0; i < 8; ++i) {
    const float x = -7.0f + 1.8f * float(i), z = -float(i % 3);
    gl::RenderMesh::Draw d;
    d.first_index = std::uint32_t(indices.size());
    // The clusters of object 0 index its vertices from one base vertex (0); the others
    // start their own.
    const std::uint32_t base = std::uint32_t(mesh.positions.size() / 3);
    cpu::appendBox({{x, -1, z}, {x + 2, 1, z + 1.5f}}, mesh.positions, indices);
    d.index_count = std::uint32_t(indices.size()) - d.first_index;
    d.color = i < 6 ? kRed : kBlue;
    if (i >= 4) {  // appendBox numbers the vertices from the array's start
      for (std::size_t k = d.first_index; k < indices.size(); ++k) indices[k] -= base;
      d.base_vertex = std::int32_t(base);
    }
    mesh.draws.push_back(d);
  }
  mesh.indices32 = indices;
  return mesh;
}

Camera rowCamera() {
  Camera cam;
  cam.width = 96;
  cam.height = 48;
  cam.view_projection = multiply(perspective(1.0, 2.0, 0.5, 100, cam.depth),
                                 lookAt({0, 2, 12}, {0, 0, 0}, {0, 1, 0}));
  return cam;
}

struct Images {
  std::vector<std::uint8_t> color;
  std::vector<float> depth;
};

template <typename Draw>
Images render(gl::MeshRenderer& renderer, gl::Pass pass, const Camera& cam, Draw draw) {
  gl::Framebuffer fb({cam.width, cam.height, cam.depth, pass == gl::Pass::ObjectIds});
  const float black[4] = {0, 0, 0, 1};
  fb.bind();
  fb.clear(black);
  if (pass == gl::Pass::ObjectIds) fb.selectIdPass(true);
  renderer.begin(pass, cam);
  draw();
  renderer.end();
  return {fb.readColor(), fb.readDepth()};
}

// Draws `batch` with drawBatch and one by one, checks that both give the same colour and
// depth images, and returns drawBatch's calls.
std::uint64_t batchedCalls(gl::MeshRenderer& renderer, gl::Pass pass, const Camera& cam,
                           const std::vector<ObjectId>& batch) {
  SCOPED_TRACE(int(pass));
  const Images one_by_one = render(renderer, pass, cam, [&] {
    for (ObjectId id : batch) renderer.draw(id);
  });
  const std::uint64_t before = renderer.drawCalls();
  const Images batched =
      render(renderer, pass, cam, [&] { renderer.drawBatch(batch.data(), batch.size()); });
  const std::uint64_t calls = renderer.drawCalls() - before;
  EXPECT_EQ(batched.color, one_by_one.color);
  EXPECT_EQ(batched.depth, one_by_one.depth);
  return calls;
}

TEST(DrawBatchTest, DrawsWhatItsObjectsDrawOneByOneInFewerCalls) {
  LOGRID_REQUIRE_GL();
  const gl::RenderMesh mesh = rowOfBoxes();
  gl::MeshRenderer renderer(mesh);
  const Camera cam = rowCamera();
  // A batch in an order of the culler's (not the index buffer's), and a transformed object.
  const std::vector<ObjectId> batch = {5, 2, 0, 7, 1, 3, 6, 4};
  gl::ObjectTransform lifted;
  lifted.translation = {0, 0.5, 0};
  renderer.setTransform(4, lifted);

  // Shaded: object 4 alone (transformed); red: the clusters 0-3 one range, 5 another,
  // in one call; blue: one call. Depth only: colours do not matter, one call.
  EXPECT_EQ(batchedCalls(renderer, gl::Pass::Shaded, cam, batch), 3u);
  EXPECT_EQ(batchedCalls(renderer, gl::Pass::DepthOnly, cam, batch), 2u);
  // Something was drawn at all, and both colours show.
  const Images shaded = render(renderer, gl::Pass::Shaded, cam,
                               [&] { renderer.drawBatch(batch.data(), batch.size()); });
  int red = 0, blue = 0;
  for (std::size_t p = 0; p < shaded.color.size(); p += 4) {
    red += shaded.color[p] > 40 && shaded.color[p + 2] < 10;
    blue += shaded.color[p + 2] > 40 && shaded.color[p] < 10;
  }
  EXPECT_GT(red, 100);
  EXPECT_GT(blue, 100);
}

// The clusters of a moving object share its transform: drawn together, one call per
// transform and colour, and exactly as one by one.
TEST(DrawBatchTest, ObjectsWithOneTransformAreDrawnTogether) {
  LOGRID_REQUIRE_GL();
  const gl::RenderMesh mesh = rowOfBoxes();
  gl::MeshRenderer renderer(mesh);
  const Camera cam = rowCamera();
  gl::ObjectTransform turned, lifted;
  turned.rotation[0] = turned.rotation[8] = 0.8f;  // a turn about +y (0.6, 0.8)
  turned.rotation[2] = -0.6f, turned.rotation[6] = 0.6f;
  turned.translation = {0.25, -0.5, 0};
  lifted.translation = {0, 0.5, 0};
  for (ObjectId id : {0u, 1u, 2u, 3u, 6u}) renderer.setTransform(id, turned);
  renderer.setTransform(7, lifted);
  const std::vector<ObjectId> batch = {7, 2, 5, 0, 6, 3, 4, 1};
  // Shaded: 4 and 5 (red, no transform) one call; turned: 0-3 (red) one, 6 (blue)
  // another; 7 lifted. Depth only: 4-5; 0-3 and 6; 7.
  EXPECT_EQ(batchedCalls(renderer, gl::Pass::Shaded, cam, batch), 4u);
  EXPECT_EQ(batchedCalls(renderer, gl::Pass::DepthOnly, cam, batch), 3u);
}

TEST(DrawBatchTest, TheIdPassDrawsEachObjectWithItsOwnId) {
  LOGRID_REQUIRE_GL();
  const gl::RenderMesh mesh = rowOfBoxes();
  gl::MeshRenderer renderer(mesh);
  const Camera cam = rowCamera();
  const std::vector<ObjectId> batch = {3, 1, 2, 0};
  const std::uint64_t before = renderer.drawCalls();
  gl::Framebuffer a({cam.width, cam.height, cam.depth, true});
  gl::Framebuffer b({cam.width, cam.height, cam.depth, true});
  for (gl::Framebuffer* fb : {&a, &b}) {
    fb->bind();
    const float black[4] = {0, 0, 0, 1};
    fb->clear(black);
    fb->selectIdPass(true);
    renderer.begin(gl::Pass::ObjectIds, cam);
    if (fb == &a) {
      renderer.drawBatch(batch.data(), batch.size());
    } else {
      for (ObjectId id : batch) renderer.draw(id);
    }
    renderer.end();
  }
  EXPECT_EQ(renderer.drawCalls() - before, 8u);  // one call per object, both ways
  EXPECT_EQ(a.readObjectIds(), b.readObjectIds());
}

}  // namespace
}  // namespace logrid
