// The margins of projection.hpp on the real rasteriser: for each term, a scene in which
// shrinking the term (ProjectionSettings) makes logrid cull a box that GL draws, while
// the default settings keep it. The ground truth is GL itself: the box is drawn after
// the occluder inside a GL_SAMPLES_PASSED query, with GL_LEQUAL (the culler's contract
// allows it) or GL_LESS, and writes nothing. logrid's answer is the zfar grid's test
// (log-zfar) reading the same framebuffer through glReadPixels.
// tests/unit/margin_test.cpp has the same terms in exact arithmetic and explains the
// constructions; the numbers found here on llvmpipe are in the comments.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "gl_test_context.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/mesh_renderer.hpp"
#include "logrid/grid.hpp"
#include "logrid/projection.hpp"
#include "logrid/zread/gl_sources.hpp"
#include "margin_helpers.hpp"

namespace logrid {
namespace {

// An axis-aligned rectangle in the plane z = const: a box of zero depth.
struct Quad {
  float x0, y0, x1, y1, z;
  Aabb box() const { return {{x0, y0, z}, {x1, y1, z}}; }
};

// One draw (object) per quad, two triangles each.
gl::RenderMesh quadMesh(const std::vector<Quad>& quads) {
  gl::RenderMesh mesh;
  for (const Quad& q : quads) {
    const std::uint32_t base = std::uint32_t(mesh.positions.size() / 3);
    for (int i = 0; i < 4; ++i) {
      mesh.positions.push_back((i & 1) ? q.x1 : q.x0);
      mesh.positions.push_back((i & 2) ? q.y1 : q.y0);
      mesh.positions.push_back(q.z);
    }
    gl::RenderMesh::Draw d;
    d.first_index = std::uint32_t(mesh.indices32.size());
    d.index_count = 6;
    for (std::uint32_t k : {0u, 1u, 2u, 1u, 3u, 2u}) mesh.indices32.push_back(base + k);
    mesh.draws.push_back(d);
  }
  return mesh;
}

// Draws objects [first, last) with the framebuffer's depth state (GL_LESS, writes on).
void drawObjects(gl::MeshRenderer& renderer, const Camera& cam, ObjectId first, ObjectId last) {
  renderer.begin(gl::Pass::DepthOnly, cam);
  for (ObjectId id = first; id < last; ++id) renderer.draw(id);
  renderer.end();
}

// The samples of object `id` that pass the depth test `func`, drawn without writes.
std::uint32_t samplesPassed(gl::MeshRenderer& renderer, const Camera& cam, ObjectId id,
                            GLenum func) {
  GLuint query = 0;
  glCreateQueries(GL_SAMPLES_PASSED, 1, &query);
  glDepthFunc(func);
  glDepthMask(GL_FALSE);
  renderer.begin(gl::Pass::DepthOnly, cam);
  glBeginQuery(GL_SAMPLES_PASSED, query);
  renderer.draw(id);
  glEndQuery(GL_SAMPLES_PASSED);
  renderer.end();
  GLuint samples = 0;
  glGetQueryObjectuiv(query, GL_QUERY_RESULT, &samples);
  glDeleteQueries(1, &query);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  gl::checkGlErrors("samplesPassed");
  return samples;
}

using test::zfarCulls;  // tests/support/margin_helpers.hpp

// test::pixelCamera with standard depth in [-1, 1] held in `format`.
Camera pixelCamera(std::uint32_t w, std::uint32_t h, DepthFormat format) {
  return test::pixelCamera(w, h,
                           {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, format});
}

const float kBlack[4] = {0, 0, 0, 1};

// 1. D16 quantisation. A wall over the whole view and a box's front face in the same plane,
// at window depth (30000 + 0.49) / 65535: the buffer stores 30000 / 65535 (llvmpipe
// rounds to nearest; a truncating GPU stores the same), 0.49 step = 7.5e-6 in front of
// the box's nearest key. Drawn with GL_LEQUAL the box passes on all 64 of its pixels.
// Without the quantisation term the margin is the render-error term alone (4.1e-6), and
// the box is culled.
TEST(MarginGlTest, D16QuantisationTermIsNeeded) {
  LOGRID_REQUIRE_GL();
  const Camera cam = pixelCamera(16, 16, DepthFormat::D16);
  const float z = -float((30000 + 0.49) / 65535.0);
  const std::vector<Quad> quads = {{0, 0, 16, 16, z}, {4, 4, 12, 12, z}};  // wall, box face
  gl::Framebuffer fb({16, 16, cam.depth, false});
  fb.bind();
  fb.clear(kBlack);
  gl::MeshRenderer renderer(quadMesh(quads));
  drawObjects(renderer, cam, 0, 1);
  EXPECT_EQ(samplesPassed(renderer, cam, 1, GL_LEQUAL), 64u);  // the box shows
  std::uint16_t stored = 0;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fb.handle());
  glReadPixels(8, 8, 1, 1, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, &stored);
  EXPECT_EQ(stored, 30000);

  zread::ReadPixelsSource source(fb.handle());
  orThrow(source.beginFrame(cam));
  ProjectionSettings shrunk;
  shrunk.quantisation_scale = 0;
  const Aabb box{{4, 4, z - 0.25f}, {12, 12, z}};  // the box whose front face was drawn
  EXPECT_FALSE(zfarCulls(Projector(cam), box, source)) << "default settings";
  EXPECT_TRUE(zfarCulls(Projector(cam, shrunk), box, source))
      << "without the quantisation term the box should be (wrongly) culled";
  gl::checkGlErrors("D16QuantisationTermIsNeeded");
}

// 2 and 3. Float transform and interpolation. 64 walls at 64 depths, each filling a
// 16 x 16 block of a 128 x 128 view, and over each wall a coplanar duplicate (a decal,
// a second pass drawn with GL_LEQUAL), in 32F depth: GL draws every duplicate (64
// samples each), and the default margin keeps every one. With render_error_ulps = 0
// there is no margin at all, and the duplicates over the walls that the float pipeline
// put a little in front of their exact depth are culled. On llvmpipe (Mesa 22.3): 4 of
// 64 camera-relative (1 float step, 6e-8, in front) and 4 of 64 when rendering in world
// space 1e4 units from the origin (up to 8.9e-7 in front, while the world-space default
// margin there is 4e-4 to 2e-2).
TEST(MarginGlTest, RenderErrorTermIsNeeded) {
  LOGRID_REQUIRE_GL();
  int culled_total = 0;
  for (const bool world_space : {false, true}) {
    SCOPED_TRACE(world_space ? "world space, 1e4 from the origin" : "camera-relative");
    const test::CoplanarWalls scene = test::coplanarWalls(world_space);
    const Camera& cam = scene.cam;
    std::vector<Quad> quads;  // walls 0..63, duplicates 64..127
    for (const std::vector<Aabb>* boxes : {&scene.walls, &scene.duplicates}) {
      for (const Aabb& b : *boxes) quads.push_back({b.min.x, b.min.y, b.max.x, b.max.y, b.min.z});
    }
    gl::Framebuffer fb({cam.width, cam.height, cam.depth, false});
    fb.bind();
    fb.clear(kBlack);
    gl::MeshRenderer renderer(quadMesh(quads));
    drawObjects(renderer, cam, 0, 64);
    zread::ReadPixelsSource source(fb.handle());
    orThrow(source.beginFrame(cam));
    ProjectionSettings shrunk;
    shrunk.render_error_ulps = 0;
    const Projector safe(cam), exact(cam, shrunk);
    int culled = 0;
    double needed_ulps = 0;  // the render_error_ulps that would just keep every duplicate
    for (ObjectId id = 64; id < 128; ++id) {
      ASSERT_EQ(samplesPassed(renderer, cam, id, GL_LEQUAL), 64u) << "duplicate " << id - 64;
      const Aabb box = quads[id].box();
      EXPECT_FALSE(zfarCulls(safe, box, source)) << "default settings cull duplicate " << id - 64;
      culled += zfarCulls(exact, box, source);
      const BoxProjection p = safe.project(box);
      std::vector<float> keys(std::size_t(p.rect.area()));
      source.readKeys(p.rect, keys.data());
      const double nearest_stored = *std::max_element(keys.begin(), keys.end());
      needed_ulps = std::max(
          needed_ulps, (double(p.near_key) - nearest_stored) / double(p.margin) * kRenderErrorUlps);
    }
    std::printf(
        "[ margin ] GL %s: %d of 64 coplanar duplicates culled with "
        "render_error_ulps = 0, none with the default; %.2f ulps would do here\n",
        world_space ? "world space 1e4 away" : "camera-relative", culled, needed_ulps);
    culled_total += culled;
  }
  // A rasteriser that computed every depth exactly would cull none; any float pipeline
  // errs in front for some of these 128 planes.
  EXPECT_GT(culled_total, 0);
  gl::checkGlErrors("RenderErrorTermIsNeeded");
}

// 4. Sub-pixel snapping. The rasteriser moves vertices to its sub-pixel grid
// (GL_SUBPIXEL_BITS; 8 on llvmpipe). A box's left edge 3/8 of a sub-pixel step right of
// the centres of pixel column 3 (3.5 + 3 * 2^-11 on llvmpipe) snaps onto them, and
// a left edge includes the centres it passes through: GL draws the box on the 8 pixels of
// column 3 although its exact footprint leaves them out. An occluder covers columns 4 to
// 15 in front. With subpixel_bits = 16 (no widening) the box's rectangle starts at column
// 4, all behind the occluder, and the box is culled; the default widening, 1/32 pixel for
// GL's minimum of 4 bits, keeps column 3. So does subpixel_bits = GL_SUBPIXEL_BITS (a
// widening of half the rasteriser's own step), but not one bit more (a quarter step).
TEST(MarginGlTest, SubpixelSnappingTermIsNeeded) {
  LOGRID_REQUIRE_GL();
  GLint bits = 0;
  glGetIntegerv(GL_SUBPIXEL_BITS, &bits);
  ASSERT_GE(bits, 4) << "GL requires at least 4 sub-pixel bits";
  if (bits > 14)
    GTEST_SKIP() << "GL_SUBPIXEL_BITS " << bits << ": snapping is below the test's reach";
  const Camera cam = pixelCamera(16, 16, DepthFormat::D32F);
  const float left = 3.5f + std::ldexp(3.0f, -bits - 3);
  const std::vector<Quad> quads = {{4, 0, 16, 16, -0.25f}, {left, 4, 12, 12, -0.5f}};
  gl::Framebuffer fb({16, 16, cam.depth, false});
  fb.bind();
  fb.clear(kBlack);
  gl::MeshRenderer renderer(quadMesh(quads));
  drawObjects(renderer, cam, 0, 1);
  EXPECT_EQ(samplesPassed(renderer, cam, 1, GL_LESS), 8u) << "the box shows in column 3";

  zread::ReadPixelsSource source(fb.handle());
  orThrow(source.beginFrame(cam));
  ProjectionSettings shrunk;
  shrunk.subpixel_bits = 16;
  const Aabb box{{left, 4, -0.75f}, {12, 12, -0.5f}};
  EXPECT_EQ(Projector(cam, shrunk).project(box).rect.x0, 4);
  EXPECT_FALSE(zfarCulls(Projector(cam), box, source)) << "default settings";
  EXPECT_TRUE(zfarCulls(Projector(cam, shrunk), box, source))
      << "without the snapping term the box should be (wrongly) culled";
  // The smallest widening that holds here is half a step of the rasteriser's own grid.
  ProjectionSettings own;
  own.subpixel_bits = bits;
  EXPECT_FALSE(zfarCulls(Projector(cam, own), box, source));
  own.subpixel_bits = bits + 1;
  EXPECT_TRUE(zfarCulls(Projector(cam, own), box, source));
  gl::checkGlErrors("SubpixelSnappingTermIsNeeded");
}

}  // namespace
}  // namespace logrid
