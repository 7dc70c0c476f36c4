// Each term of the depth margin and of the rectangle widening in projection.hpp ("Why the
// margins have their values") is needed: shrinking it through ProjectionSettings makes
// logrid cull a box that the renderer shows, while the default settings draw it.
//
// What "needed" means: logrid must answer visible whenever the box's own geometry would
// pass the depth test. The culler's contract (culler.hpp) allows GL_LEQUAL (GL_GEQUAL for
// reversed depth), under which a face drawn where an occluder already is, or a hair behind
// it but stored as the same depth value, passes. So each case draws an occluder, then asks
// about a box whose front face is coplanar with it or a hair behind it, or, for the pixel
// rectangle, a box that shows only through pixels next to the occluder.
//
// Here the effects are computed exactly: the quantisation of a unorm depth buffer and the
// snapping of vertices to a sub-pixel grid are arithmetic, and the float error of the
// transform is that of the software rasteriser's float pipeline (zread). The same terms
// are shown on the real GL rasteriser in tests/gl/margin_gl_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

#include "logrid/bvh/bvh.hpp"
#include "logrid/cpu/software_rasterizer.hpp"
#include "logrid/culler.hpp"
#include "logrid/grid.hpp"
#include "logrid/projection.hpp"
#include "margin_helpers.hpp"

namespace logrid {
namespace {

constexpr Method kGridMethods[] = {Method::LogState, Method::LogZfar, Method::Bog, Method::Hzb,
                                   Method::Pq};

const DepthSetup kStandard32F{DepthConvention::Standard, ClipDepthRange::NegativeOneToOne,
                              DepthFormat::D32F};

using test::pixelCamera;  // tests/support/margin_helpers.hpp
using test::zfarCulls;

// The value a unorm buffer of `levels` = 2^n - 1 stores for window depth d: rounded to
// the nearest level, as GL recommends and llvmpipe does.
double quantise(double d, double levels) { return std::round(d * levels) / levels; }

// One object of a frame: its box, and how drawing it changes the emulated depth buffer
// (the pixels it covers and the value the buffer then holds there; nearer wins).
struct Object {
  Aabb box;
  PixelRect covers;
  float stored = 0;
};

CullerDesc descFor(Method method, const ProjectionSettings& settings) {
  CullerDesc desc;
  desc.method = method;
  desc.tile_size = 4;
  desc.projection = settings;
  return desc;
}

// Culls one frame over `objects` (a hierarchy with one object per leaf), "drawing" each
// drawn object into a software buffer; returns the objects drawn.
std::set<ObjectId> cullFrame(const Camera& cam, const std::vector<Object>& objects, Method method,
                             const ProjectionSettings& settings) {
  std::vector<Aabb> boxes;
  for (const Object& o : objects) boxes.push_back(o.box);
  const bvh::FlatHierarchy hierarchy = bvh::buildOverBoxes(boxes);
  cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
  Culler culler(descFor(method, settings));
  std::set<ObjectId> drawn;
  culler.cullFrame(cam, hierarchy, depth, [&](ObjectId id) {
    drawn.insert(id);
    depth.fillRect(objects[id].covers, objects[id].stored);
  });
  return drawn;
}

// ---------------------------------------------------------------------------------------
// The sizes the header claims.
// ---------------------------------------------------------------------------------------

TEST(MarginTest, TermsHaveTheSizesTheHeaderClaims) {
  EXPECT_EQ(quantisationStep(DepthFormat::D16), 1.0 / 65535.0);
  EXPECT_EQ(quantisationStep(DepthFormat::D24), 1.0 / 16777215.0);
  EXPECT_EQ(quantisationStep(DepthFormat::D32F), 0.0);
  EXPECT_EQ(kUnitRoundoff, std::ldexp(1.0, -24));
  EXPECT_EQ(kRenderErrorUlps, 32.0);
  const ProjectionSettings defaults;
  EXPECT_EQ(defaults.render_error_ulps, kRenderErrorUlps);
  EXPECT_EQ(defaults.quantisation_scale, 1.0);
  EXPECT_EQ(defaults.subpixel_bits, 4);

  // A unit box 10 ahead of a camera at the render origin (near 0.1, far 1000).
  const Aabb box{{-0.5f, -0.5f, -10.5f}, {0.5f, 0.5f, -9.5f}};
  auto marginFor = [&](DepthFormat format, const ProjectionSettings& settings) {
    Camera cam;
    cam.width = 640;
    cam.height = 480;
    cam.depth = {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, format};
    cam.view_projection = perspective(M_PI / 3, 640.0 / 480, 0.1, 1000, cam.depth);
    return double(Projector(cam, settings).project(box).margin);
  };
  ProjectionSettings no_render_error, no_quantisation;
  no_render_error.render_error_ulps = 0;
  no_quantisation.quantisation_scale = 0;
  // 32F: only the render error, 32 u (E + key) with E about 1 and key about 1: 3.8e-6.
  const double m32 = marginFor(DepthFormat::D32F, defaults);
  EXPECT_GT(m32, 3.0e-6);
  EXPECT_LT(m32, 4.5e-6);
  EXPECT_EQ(marginFor(DepthFormat::D32F, no_render_error), 0.0);
  // D16 and D24: one quantisation step on top of the same render error.
  const double m16 = marginFor(DepthFormat::D16, defaults);
  const double m24 = marginFor(DepthFormat::D24, defaults);
  EXPECT_NEAR(m16 - marginFor(DepthFormat::D16, no_quantisation), 1.0 / 65535, 1e-11);
  EXPECT_NEAR(m24 - marginFor(DepthFormat::D24, no_quantisation), 1.0 / 16777215, 1e-12);
  EXPECT_NEAR(marginFor(DepthFormat::D16, no_render_error), 1.0 / 65535, 1e-11);
  EXPECT_NEAR(m16, 1.0 / 65535 + m32, 1e-11);
  EXPECT_NEAR(m24, 1.0 / 16777215 + m32, 1e-12);

  // Sub-pixel snapping: 4 bits widen the rectangle by half a 1/16 step, 1/32 pixel (plus
  // the x/y render error, about 4e-5 pixel here). A left edge 1/32 - 1e-3 pixel right of
  // a pixel centre keeps that pixel, 1/32 + 1e-3 does not.
  const Camera cam = pixelCamera(16, 16, kStandard32F);
  const Projector projector(cam);
  const float edge = 3.5f + 1.0f / 32;
  EXPECT_EQ(projector.project({{edge - 1e-3f, 4, -0.6f}, {12, 12, -0.5f}}).rect.x0, 3);
  EXPECT_EQ(projector.project({{edge + 1e-3f, 4, -0.6f}, {12, 12, -0.5f}}).rect.x0, 4);
}

// ---------------------------------------------------------------------------------------
// 1. Quantisation.
// ---------------------------------------------------------------------------------------

// D16: a wall over the whole view at window depth (30000 - 0.45) / 65535 is stored as
// 30000 / 65535; a box whose front face lies 0.9 step behind the wall, at
// (30000 + 0.45) / 65535, is stored as the same 30000 / 65535, so drawn with GL_LEQUAL it
// shows on all 64 pixels of its front face. Without the quantisation term the wall's
// stored value lies 0.45 step (6.9e-6) in front of the box's nearest key, more than the
// render-error term for the box (4.1e-6), and every method culls the box.
TEST(MarginTest, D16QuantisationTermIsNeeded) {
  const double levels = 65535.0;
  const Camera cam = pixelCamera(
      16, 16, {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D16});
  const float wall_depth = float((30000 - 0.45) / levels);
  const float box_depth = float((30000 + 0.45) / levels);
  const double stored = quantise(wall_depth, levels);
  ASSERT_EQ(stored, quantise(box_depth, levels));  // LEQUAL passes: the box shows
  ASSERT_EQ(stored * levels, 30000.0);
  const std::vector<Object> objects = {
      {{{0, 0, -wall_depth}, {16, 16, -wall_depth}}, {0, 0, 16, 16}, float(stored)},
      {{{4, 4, -box_depth - 0.25f}, {12, 12, -box_depth}}, {4, 4, 12, 12}, float(stored)}};

  ProjectionSettings shrunk;
  shrunk.quantisation_scale = 0;
  const BoxProjection full = Projector(cam).project(objects[1].box);
  const BoxProjection cut = Projector(cam, shrunk).project(objects[1].box);
  EXPECT_LT(stored, double(cut.occlusionThreshold()));   // culled without the term
  EXPECT_GE(stored, double(full.occlusionThreshold()));  // visible with it
  EXPECT_NEAR(box_depth - stored, 0.45 / levels, 3e-8);  // the stored value is nearer by
  EXPECT_LT(double(cut.margin), 0.45 / levels);          // more than the rest of the margin

  for (Method method : kGridMethods) {
    SCOPED_TRACE(toString(method));
    EXPECT_EQ(cullFrame(cam, objects, method, {}).count(1), 1u) << "default settings";
    EXPECT_EQ(cullFrame(cam, objects, method, shrunk).count(1), 0u)
        << "without the quantisation term the box should be (wrongly) culled";
  }
}

// D24 with reversed depth, far away: reversed-Z keys shrink with distance and so does the
// render-error term (about 5.7e-6 times the window depth), so at window depth 1e-3
// (100 near-distances away) one D24 step (6e-8) is ten times the rest of the margin. A
// wall at (16777 + 0.45) / 16777215 and a box 0.9 step behind it at (16777 - 0.45) /
// 16777215 are both stored as 16777 / 16777215; drawn with GL_GEQUAL the box shows.
// (A D24 step is about u, so it matters only where the render-error term, 32 u (E + key),
// is small too: reversed depth far away, or a zero-to-one orthographic projection right
// at its near plane. With a standard perspective E is at least about 1/2, the
// render-error term alone is 16 D24 steps or more, and shrinking the D24 term changes no
// answer.)
TEST(MarginTest, D24QuantisationTermIsNeededWithReversedDepthFarAway) {
  const double levels = 16777215.0, near = 0.1;
  Camera cam;
  cam.width = 32;
  cam.height = 32;
  cam.depth = {DepthConvention::Reversed, ClipDepthRange::ZeroToOne, DepthFormat::D24};
  cam.view_projection = perspective(1.0, 1.0, near, INFINITY, cam.depth);
  // Window depth is near / distance: place the planes at the distances that give the
  // wanted depths, then take the depths of the float planes.
  const float wall_z = -float(near / ((16777 + 0.45) / levels));
  const float box_z = -float(near / ((16777 - 0.45) / levels));
  const double wall_depth = near / -double(wall_z), box_depth = near / -double(box_z);
  const double stored = quantise(wall_depth, levels);
  ASSERT_EQ(stored, quantise(box_depth, levels));  // GEQUAL passes: the box shows
  ASSERT_EQ(stored * levels, 16777.0);
  const float big = 1e3f, small = 5.0f;  // the wall fills the view; the box 2 x 2 pixels
  const std::vector<Object> objects = {
      {{{-big, -big, wall_z}, {big, big, wall_z}}, {0, 0, 32, 32}, float(stored)},
      {{{-small, -small, box_z - 10}, {small, small, box_z}}, {8, 8, 24, 24}, float(stored)}};

  ProjectionSettings shrunk;
  shrunk.quantisation_scale = 0;
  const BoxProjection cut = Projector(cam, shrunk).project(objects[1].box);
  ASSERT_EQ(cut.cls, ProjectionClass::Inside);
  EXPECT_LT(double(cut.margin), 0.1 / levels);
  for (Method method : kGridMethods) {
    SCOPED_TRACE(toString(method));
    EXPECT_EQ(cullFrame(cam, objects, method, {}).count(1), 1u) << "default settings";
    EXPECT_EQ(cullFrame(cam, objects, method, shrunk).count(1), 0u)
        << "without the quantisation term the box should be (wrongly) culled";
  }
}

// ---------------------------------------------------------------------------------------
// 2 and 3. The float error of the renderer's transform and interpolation.
// ---------------------------------------------------------------------------------------

// The software rasteriser transforms in float as a GPU does. 64 walls at 64 depths, each
// filling a 16 x 16 block; over each, a box that is the wall's own plane (a coplanar
// duplicate, as a decal or a second pass drawn with GL_LEQUAL). The float pipeline puts
// some walls a few float steps in front of their exact depth; with render_error_ulps = 0
// (and 32F depth, so no other term) the duplicate over such a wall is culled although it
// would be drawn. Camera-relative rendering (render_origin = eye) and world-space
// rendering 1e4 units from the origin both show it; the default margin covers all.
TEST(MarginTest, RenderErrorTermIsNeededForAFloatPipeline) {
  for (const bool world_space : {false, true}) {
    SCOPED_TRACE(world_space ? "world space, 1e4 from the origin" : "camera-relative");
    const test::CoplanarWalls scene = test::coplanarWalls(world_space);
    const Camera& cam = scene.cam;
    cpu::SoftwareDepthBuffer depth(cam.width, cam.height, cam.depth.convention);
    cpu::SoftwareRasterizer raster(cam, depth, nullptr);
    for (std::size_t i = 0; i < scene.walls.size(); ++i) {
      std::vector<float> positions;
      std::vector<std::uint32_t> indices;
      cpu::appendBox(scene.walls[i], positions, indices);
      raster.draw(positions, indices, std::uint32_t(i));
    }
    ProjectionSettings shrunk;
    shrunk.render_error_ulps = 0;
    const Projector safe(cam), exact(cam, shrunk);
    int culled_shrunk = 0;
    for (const Aabb& box : scene.duplicates) {
      EXPECT_FALSE(zfarCulls(safe, box, depth)) << "default settings cull a coplanar duplicate";
      culled_shrunk += zfarCulls(exact, box, depth);
    }
    std::printf(
        "[ margin ] float pipeline, %s: %d of 64 coplanar duplicates culled with "
        "render_error_ulps = 0, none with the default\n",
        world_space ? "world space 1e4 away" : "camera-relative", culled_shrunk);
    EXPECT_GT(culled_shrunk, 0);
  }
}

// ---------------------------------------------------------------------------------------
// 4. Sub-pixel snapping.
// ---------------------------------------------------------------------------------------

// A rasteriser with 8 sub-pixel bits (llvmpipe, current GPUs) moves a vertex at
// x = 3.5 + 2^-10 to round(x * 256) / 256 = 3.5, onto the centres of pixel column 3,
// which a left edge includes (the top-left rule). An occluder covers columns 4 to 15 in
// front; the box behind it shows through its 8 pixels in column 3. With subpixel_bits =
// 16 (no widening) the box's rectangle starts at column 4, all behind the occluder, and
// every method culls it; the default widening (1/32 pixel) keeps column 3.
TEST(MarginTest, SubpixelSnappingTermIsNeeded) {
  const Camera cam = pixelCamera(16, 16, kStandard32F);
  const float left = 3.5f + std::ldexp(1.0f, -10);
  const double snapped = std::round(double(left) * 256) / 256;
  ASSERT_EQ(snapped, 3.5);  // on the centre of column 3: covered by the left edge
  const std::vector<Object> objects = {
      {{{4, 0, -0.25f}, {16, 16, -0.25f}}, {4, 0, 16, 16}, 0.25f},  // occluder, in front
      {{{left, 4, -0.75f}, {12, 12, -0.5f}}, {3, 4, 12, 12}, 0.5f}};

  ProjectionSettings shrunk;
  shrunk.subpixel_bits = 16;
  EXPECT_EQ(Projector(cam, shrunk).project(objects[1].box).rect.x0, 4);  // misses column 3
  EXPECT_EQ(Projector(cam).project(objects[1].box).rect.x0, 3);
  for (Method method : kGridMethods) {
    SCOPED_TRACE(toString(method));
    EXPECT_EQ(cullFrame(cam, objects, method, {}).count(1), 1u) << "default settings";
    EXPECT_EQ(cullFrame(cam, objects, method, shrunk).count(1), 0u)
        << "without the snapping term the box should be (wrongly) culled";
  }
}

}  // namespace
}  // namespace logrid
