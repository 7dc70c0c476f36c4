// The full-tile rule of CPU-known coverage (logrid/coverage.hpp) against GL's rasteriser:
// quads are drawn with gl::OccluderRenderer (as ddo+log draws its occluders), and every
// tile the rule records for them must hold, at every pixel, a key at or in front of the
// quad's far key. Each margin of the rule is then shrunk and a quad found for which GL
// leaves a recorded tile with a pixel beyond the recorded key: a box behind the tile there
// would be culled (occlusion state: the tile counts as full; depth tests: the far key
// counts as the tile's farthest) while GL shows it.
//   * the edge error (snapping): an edge 3/8 of llvmpipe's sub-pixel step (1/256) beyond
//     a row or column of pixel centres snaps onto them, and GL's fill rule leaves centres
//     on a right or top edge out;
//   * the quantisation step (D16): a constant-depth quad is stored up to a step beyond its
//     key;
// The render error (the float NDC depth, the viewport transform, interpolation) is not
// shown apart on llvmpipe: with round-to-nearest a constant key cannot be stored beyond
// its upward-rounded float, and 256 slightly sloped quads (D32F, render_error_ulps = 0)
// stored none beyond it either. The term stays by the derivation in coverage.hpp (it is
// the term tests/gl/margin_gl_test.cpp shows necessary for boxes), and the first test
// checks it holds for sloped quads in every format.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "gl_state_probe.hpp"
#include "gl_test_context.hpp"
#include "logrid/coverage.hpp"
#include "logrid/ddo/selector.hpp"
#include "logrid/gl/framebuffer.hpp"
#include "logrid/gl/occluder_renderer.hpp"
#include "logrid/grid.hpp"

namespace logrid {
namespace {

constexpr std::uint32_t kSide = 64, kTile = 8;
const float kBackground[4] = {0, 0, 0, 1};

Camera cameraFor(DepthConvention convention, DepthFormat format) {
  Camera c;
  c.width = c.height = kSide;
  c.depth.convention = convention;
  c.depth.clip_range = convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                               : ClipDepthRange::NegativeOneToOne;
  c.depth.format = format;
  return c;
}

struct Outcome {
  std::uint64_t recorded = 0;  // tiles the rule recorded
  std::uint64_t beyond = 0;    // pixels of recorded tiles GL left beyond the recorded key
};

// Draws each quad alone (corners in window coordinates, key = plane) and compares the
// cells recordCovered() records under `settings` with what GL stored.
Outcome drawAndCompare(const Camera& camera, const std::vector<std::vector<double>>& quads,
                       const ProjectionSettings& settings) {
  gl::FramebufferDesc fd;
  fd.width = fd.height = kSide;
  fd.depth = camera.depth;
  gl::Framebuffer framebuffer(fd);
  gl::OccluderRenderer renderer;
  const CoverageRule rule = coverageRule(camera, settings);
  Outcome out;
  for (const std::vector<double>& q : quads) {
    const double window[4][2] = {{q[0], q[1]}, {q[2], q[3]}, {q[4], q[5]}, {q[6], q[7]}};
    const double plane[3] = {q[8], q[9], q[10]};
    const std::optional<ddo::Occluder> o = ddo::makeOccluder(window, plane, 1, camera, settings);
    if (!o) continue;
    test::setDefaultGlState(int(kSide), int(kSide));
    framebuffer.bind();
    framebuffer.clear(kBackground);
    renderer.draw({*o}, camera, framebuffer.handle());
    const std::vector<float> depth = framebuffer.readDepth();
    OcclusionGrid grid({kSide, kSide, kTile, GridVariant::OcclusionState});
    grid.reset(clearKey(camera.depth));
    DrawnQuad drawn;
    for (int i = 0; i < 4; ++i)
      drawn.window[i][0] = window[i][0], drawn.window[i][1] = window[i][1];
    drawn.near_key = o->near_key;
    drawn.far_key = o->far_key;
    out.recorded += grid.recordCovered(drawn, rule);
    for (std::uint32_t y = 0; y < kSide; ++y) {
      for (std::uint32_t x = 0; x < kSide; ++x) {
        const float recorded = grid.hiddenAt(x, y);          // the key of the pixel's cell
        if (!(recorded < clearKey(camera.depth))) continue;  // not recorded
        const float stored = depthKey(camera.depth.convention, depth[y * kSide + x]);
        out.beyond += stored > recorded;
      }
    }
  }
  return out;
}

// Axis-aligned quads whose right (or top) edge lies 3/8 of a 1/256 step beyond the last
// pixel centres of a tile, and whose left (or bottom) edge lies on a tile border, at a
// constant mid-range key.
std::vector<std::vector<double>> snappingQuads(const Camera& camera) {
  const double nudge = 3.0 / 8.0 / 256.0;
  const double key = 0.5 * (double(nearPlaneKey(camera.depth)) + double(clearKey(camera.depth)));
  std::vector<std::vector<double>> quads;
  for (int m = 1; m <= 4; ++m) {
    const double lo = 8.0, hi = 8.0 * m + 7.5 + nudge;
    quads.push_back({lo, lo, hi, lo, hi, 56.0, lo, 56.0, key, 0, 0});  // right edge
    quads.push_back({lo, lo, 56.0, lo, 56.0, hi, lo, hi, key, 0, 0});  // top edge
  }
  return quads;
}

// Whole-viewport quads at random constant keys between the planes.
std::vector<std::vector<double>> constantQuads(const Camera& camera, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const double a = nearPlaneKey(camera.depth), b = clearKey(camera.depth);
  std::uniform_real_distribution<double> t(0.2, 0.8);
  std::vector<std::vector<double>> quads;
  for (int i = 0; i < 64; ++i) {
    const double key = a + t(rng) * (b - a);
    quads.push_back(
        {0, 0, double(kSide), 0, double(kSide), double(kSide), 0, double(kSide), key, 0, 0});
  }
  return quads;
}

// Whole-viewport quads at random keys with a slight random slope (interpolated keys).
std::vector<std::vector<double>> slopedQuads(const Camera& camera, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const double a = nearPlaneKey(camera.depth), b = clearKey(camera.depth);
  std::uniform_real_distribution<double> t(0.2, 0.8), slope(-2e-8, 2e-8);
  std::vector<std::vector<double>> quads;
  for (int i = 0; i < 256; ++i) {
    const double key = a + t(rng) * (b - a);
    quads.push_back({0, 0, double(kSide), 0, double(kSide), double(kSide), 0, double(kSide), key,
                     slope(rng), slope(rng)});
  }
  return quads;
}

TEST(CoverageGl, RecordedTilesHoldNoPixelBeyondTheRecordedKey) {
  LOGRID_REQUIRE_GL();
  for (DepthConvention convention : {DepthConvention::Standard, DepthConvention::Reversed}) {
    for (DepthFormat format : {DepthFormat::D16, DepthFormat::D24, DepthFormat::D32F}) {
      const Camera camera = cameraFor(convention, format);
      std::vector<std::vector<double>> quads = snappingQuads(camera);
      for (auto& q : constantQuads(camera, 7)) quads.push_back(q);
      for (auto& q : slopedQuads(camera, 9)) quads.push_back(q);
      // Sloped and rotated quads over several tiles.
      std::mt19937 rng(11);
      std::uniform_real_distribution<double> pos(-8, 72), slope(-1e-3, 1e-3);
      for (int i = 0; i < 64; ++i) {
        const double cx = pos(rng) * 0.5 + 16, cy = pos(rng) * 0.5 + 16, r = 10 + pos(rng) * 0.3;
        const double t = pos(rng);
        std::vector<double> q;
        for (int k = 0; k < 4; ++k) {
          q.push_back(cx + r * std::cos(t + k * 1.5707963));
          q.push_back(cy + r * std::sin(t + k * 1.5707963));
        }
        const double mid =
            0.5 * (double(nearPlaneKey(camera.depth)) + double(clearKey(camera.depth)));
        q.push_back(mid - slope(rng) * 32 - slope(rng) * 32);
        q.push_back(slope(rng));
        q.push_back(slope(rng));
        quads.push_back(q);
      }
      const Outcome o = drawAndCompare(camera, quads, {});
      EXPECT_EQ(o.beyond, 0u) << toString(convention) << " " << int(format);
      EXPECT_GT(o.recorded, 0u) << "the test recorded nothing";
    }
  }
}

TEST(CoverageGl, WithoutTheEdgeErrorASnappedEdgeLeavesARecordedPixelFree) {
  LOGRID_REQUIRE_GL();
  const Camera camera = cameraFor(DepthConvention::Standard, DepthFormat::D24);
  ProjectionSettings shrunk;
  shrunk.subpixel_bits = 16;     // no snapping
  shrunk.render_error_ulps = 0;  // no float error of the outline (nor of the keys)
  const Outcome bad = drawAndCompare(camera, snappingQuads(camera), shrunk);
  EXPECT_GT(bad.beyond, 0u) << "no snapped edge left a pixel of a recorded tile free";
  const Outcome good = drawAndCompare(camera, snappingQuads(camera), {});
  EXPECT_EQ(good.beyond, 0u);
}

TEST(CoverageGl, WithoutTheQuantisationStepAD16KeyIsStoredBeyondTheRecordedKey) {
  LOGRID_REQUIRE_GL();
  const Camera camera = cameraFor(DepthConvention::Standard, DepthFormat::D16);
  ProjectionSettings shrunk;
  shrunk.quantisation_scale = 0;
  const Outcome bad = drawAndCompare(camera, constantQuads(camera, 3), shrunk);
  EXPECT_GT(bad.beyond, 0u);
  EXPECT_EQ(drawAndCompare(camera, constantQuads(camera, 3), {}).beyond, 0u);
}

// Two quads drawn together, side by side at one constant key, meeting at x = `meet` on
// the left one's right edge and the right one's left edge (`gap` pixels apart), over the
// whole height. Returns the depth keys GL stored and, through `quads`, what was drawn.
std::vector<float> drawPair(const Camera& camera, double meet, double gap,
                            std::vector<DrawnQuad>& quads) {
  const double key = 0.5 * (double(nearPlaneKey(camera.depth)) + double(clearKey(camera.depth)));
  const double plane[3] = {key, 0, 0};
  const double left[4][2] = {{0, 0}, {meet, 0}, {meet, kSide}, {0, kSide}};
  const double right[4][2] = {
      {meet + gap, 0}, {double(kSide), 0}, {double(kSide), kSide}, {meet + gap, kSide}};
  std::vector<ddo::Occluder> occluders;
  quads.clear();
  for (const auto* w : {&left, &right}) {
    const std::optional<ddo::Occluder> o = ddo::makeOccluder(*w, plane, 1, camera);
    EXPECT_TRUE(o.has_value());
    if (!o) continue;
    occluders.push_back(*o);
    DrawnQuad q;
    for (int i = 0; i < 4; ++i) q.window[i][0] = (*w)[i][0], q.window[i][1] = (*w)[i][1];
    q.near_key = o->near_key;
    q.far_key = o->far_key;
    quads.push_back(q);
  }
  gl::FramebufferDesc fd;
  fd.width = fd.height = kSide;
  fd.depth = camera.depth;
  gl::Framebuffer framebuffer(fd);
  gl::OccluderRenderer renderer;
  test::setDefaultGlState(int(kSide), int(kSide));
  framebuffer.bind();
  framebuffer.clear(kBackground);
  renderer.draw(occluders, camera, framebuffer.handle());
  return framebuffer.readDepth();
}

// Adjacent quads hide a tile together cell by cell (the union, OcclusionGrid::
// recordCovered), and no recorded cell holds a pixel beyond its key. A rule that took
// the union at the tile's corner samples alone (each inside some quad) would record a
// tile through whose middle a gap of 1/128 pixel runs along a column of pixel centres:
// GL draws neither quad there, and a box behind the tile would be culled while it shows
// through the gap.
TEST(CoverageGl, AdjacentQuadsHideTheirCellsAndAGapBetweenThemIsNotHidden) {
  LOGRID_REQUIRE_GL();
  for (DepthConvention convention : {DepthConvention::Standard, DepthConvention::Reversed}) {
    const Camera camera = cameraFor(convention, DepthFormat::D24);
    const CoverageRule rule = coverageRule(camera, {});
    const float clear = clearKey(camera.depth);
    // Meeting on a cell border (x = 12, tiles of 8, cells of 2): every cell hidden.
    std::vector<DrawnQuad> quads;
    std::vector<float> depth = drawPair(camera, 12.0, 0.0, quads);
    OcclusionGrid grid({kSide, kSide, kTile, GridVariant::OcclusionState});
    grid.reset(clear);
    for (const DrawnQuad& q : quads) grid.recordCovered(q, rule);
    EXPECT_LT(grid.tile(1, 3).hidden_key, clear) << "tile 1 lies across the meeting edge";
    std::uint64_t beyond = 0;
    for (std::uint32_t i = 0; i < kSide * kSide; ++i) {
      const float stored = depthKey(convention, depth[i]);
      beyond += stored > grid.hiddenAt(i % kSide, i / kSide);
    }
    EXPECT_EQ(beyond, 0u);
    // A gap along the centres of column 13 (x = 13.5): pixels GL leaves free.
    const double gap = 2.0 / 256;  // both edges on llvmpipe's 1/256 sub-pixel grid
    depth = drawPair(camera, 13.5 - gap / 2, gap, quads);
    std::uint64_t free_in_column = 0;
    for (std::uint32_t y = 0; y < kSide; ++y) {
      free_in_column += !(depthKey(convention, depth[y * kSide + 13]) < clear);
    }
    ASSERT_EQ(free_in_column, kSide) << "GL drew into the gap: the test shows nothing";
    OcclusionGrid gapped({kSide, kSide, kTile, GridVariant::OcclusionState});
    gapped.reset(clear);
    for (const DrawnQuad& q : quads) gapped.recordCovered(q, rule);
    for (std::uint32_t y = 0; y < kSide; ++y) {
      EXPECT_EQ(gapped.hiddenAt(13, y), clear) << "the gap's cell is hidden at row " << y;
    }
    EXPECT_EQ(gapped.tile(1, 3).hidden_key, clear);
    // The union at the tile's corner samples (each in some quad by the edge margin):
    // tile 1 (x in [8, 16)) counts as covered, and GL left a pixel of it free.
    bool corners_covered = true;
    for (const std::int32_t x : {8, 15}) {
      for (const std::int32_t y : {24, 31}) {
        bool some = false;
        for (const DrawnQuad& q : quads) some = some || coversRect(q, {x, y, x + 1, y + 1}, rule);
        corners_covered = corners_covered && some;
      }
    }
    EXPECT_TRUE(corners_covered) << "the corner-sample union would not record the tile";
    EXPECT_FALSE(depthKey(convention, depth[24 * kSide + 13]) < clear)
        << "a pixel of that tile holds a key: the corner union would be safe here";
  }
}

}  // namespace
}  // namespace logrid
