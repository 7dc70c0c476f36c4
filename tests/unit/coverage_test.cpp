// The full-tile rule of CPU-known coverage (coverage.hpp, OcclusionGrid::recordCovered):
// a quad records the cells (a quarter of a tile a side) whose every pixel sample lies
// inside it by more than the renderer's edge error, at tile and viewport borders, near the near and
// far planes, and never for a quad seen edge-on. tests/gl/coverage_gl_test.cpp checks it against
// GL.
#include <gtest/gtest.h>

#include <cmath>

#include "logrid/coverage.hpp"
#include "logrid/cpu/software_depth.hpp"
#include "logrid/grid.hpp"

namespace logrid {
namespace {

// A 100x80 viewport (tiles of 32: the last column 4 pixels wide, the last row 16).
Camera viewport(DepthConvention convention = DepthConvention::Standard, bool multisample = false) {
  Camera c;
  c.width = 100;
  c.height = 80;
  c.depth.convention = convention;
  c.depth.clip_range = convention == DepthConvention::Reversed ? ClipDepthRange::ZeroToOne
                                                               : ClipDepthRange::NegativeOneToOne;
  c.multisample = multisample;
  return c;
}

DrawnQuad rectQuad(double x0, double y0, double x1, double y1, float near_key = 0.5f,
                   float far_key = 0.6f) {
  DrawnQuad q;
  const double corners[4][2] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  for (int i = 0; i < 4; ++i) q.window[i][0] = corners[i][0], q.window[i][1] = corners[i][1];
  q.near_key = near_key;
  q.far_key = far_key;
  return q;
}

// The edge error of the default rule at this viewport: half a 4-bit sub-pixel step per
// axis (1/32), and the float error, far below it.
double edgeOf(const CoverageRule& rule) { return std::hypot(rule.snap, rule.snap); }

TEST(CoverageRule, DefaultsFollowTheProjectionMargins) {
  const CoverageRule rule = coverageRule(viewport());
  EXPECT_DOUBLE_EQ(rule.snap, 1.0 / 32);
  EXPECT_DOUBLE_EQ(rule.render_error, kRenderErrorUlps * kUnitRoundoff);
  EXPECT_EQ(rule.near_limit, nearPlaneKey(viewport().depth));
  EXPECT_EQ(rule.far_limit, 1.0f);
  ProjectionSettings none;
  none.subpixel_bits = 16;
  EXPECT_EQ(coverageRule(viewport(), none).snap, 0.0);
}

TEST(CoverageRule, ATileIsCoveredWhenItsCornerCentresLieInsideByTheEdgeError) {
  const CoverageRule rule = coverageRule(viewport());
  const double e = edgeOf(rule);
  const PixelRect tile{32, 32, 64, 64};
  // Exactly the tile's outline: every centre lies half a pixel inside.
  EXPECT_TRUE(coversRect(rectQuad(32, 32, 64, 64), tile, rule));
  // The left edge moved right to just beyond the edge error from the first centre column.
  EXPECT_TRUE(coversRect(rectQuad(32.5 - 1.01 * e, 32, 64, 64), tile, rule));
  EXPECT_FALSE(coversRect(rectQuad(32.5 - 0.99 * e, 32, 64, 64), tile, rule));
  // The same on the top edge (the last centre row is 63.5).
  EXPECT_TRUE(coversRect(rectQuad(32, 32, 64, 63.5 + 1.01 * e), tile, rule));
  EXPECT_FALSE(coversRect(rectQuad(32, 32, 64, 63.5 + 0.99 * e), tile, rule));
  // One pixel column short of the tile.
  EXPECT_FALSE(coversRect(rectQuad(33, 32, 64, 64), tile, rule));
}

TEST(CoverageRule, ARotatedQuadCoversTheTilesItsShrunkOutlineHolds) {
  const CoverageRule rule = coverageRule(viewport());
  // A diamond around (48, 48) with half-diagonal r: the tile [32, 64)^2's corner centres
  // (15.5, 15.5) from the centre lie inside when 31 < r minus the edge error times sqrt 2.
  auto diamond = [](double r) {
    DrawnQuad q = rectQuad(0, 0, 0, 0);
    const double c[4][2] = {{48 - r, 48}, {48, 48 - r}, {48 + r, 48}, {48, 48 + r}};
    for (int i = 0; i < 4; ++i) q.window[i][0] = c[i][0], q.window[i][1] = c[i][1];
    return q;
  };
  const double e = edgeOf(rule);
  EXPECT_TRUE(coversRect(diamond(31 + std::sqrt(2.0) * e * 1.01), {32, 32, 64, 64}, rule));
  EXPECT_FALSE(coversRect(diamond(31 + std::sqrt(2.0) * e * 0.99), {32, 32, 64, 64}, rule));
}

TEST(CoverageRule, MultisampledBuffersNeedTheWholePixel) {
  const CoverageRule rule = coverageRule(viewport(DepthConvention::Standard, true));
  const double e = edgeOf(rule);
  EXPECT_FALSE(coversRect(rectQuad(32, 32, 64, 64), {32, 32, 64, 64}, rule));
  EXPECT_TRUE(coversRect(rectQuad(32 - 1.01 * e, 32 - 1.01 * e, 64 + 1.01 * e, 64 + 1.01 * e),
                         {32, 32, 64, 64}, rule));
}

TEST(CoverageRule, NothingIsCoveredWithinTheEdgeErrorOfTheNearOrFarPlane) {
  for (DepthConvention convention : {DepthConvention::Standard, DepthConvention::Reversed}) {
    const CoverageRule rule = coverageRule(viewport(convention));
    const float near_plane = rule.near_limit, clear = rule.far_limit;
    const float mid = 0.5f * (near_plane + clear);
    const PixelRect tile{0, 0, 32, 32};
    EXPECT_TRUE(coversRect(rectQuad(0, 0, 40, 40, mid, mid), tile, rule));
    // A key at the near plane may be clipped away; just beyond it is drawn.
    EXPECT_FALSE(coversRect(rectQuad(0, 0, 40, 40, near_plane, mid), tile, rule));
    EXPECT_TRUE(
        coversRect(rectQuad(0, 0, 40, 40, std::nextafter(near_plane, clear), mid), tile, rule));
    // Reaching the far plane: not known to be drawn, and not full anyway.
    EXPECT_FALSE(coversRect(rectQuad(0, 0, 40, 40, mid, clear), tile, rule));
    EXPECT_FALSE(coversRect(rectQuad(0, 0, 40, 40, mid, NAN), tile, rule));
  }
}

TEST(CoverageRule, AQuadSeenEdgeOnOrNotConvexCoversNothing) {
  const CoverageRule rule = coverageRule(viewport());
  const PixelRect tile{0, 0, 32, 32};
  DrawnQuad q = rectQuad(-10, -10, 50, 50);
  EXPECT_TRUE(coversRect(q, tile, rule));
  // Edge on: all four corners on one line (through the tile).
  const double line[4][2] = {{-10, -10}, {20, 20}, {50, 50}, {5, 5}};
  for (int i = 0; i < 4; ++i) q.window[i][0] = line[i][0], q.window[i][1] = line[i][1];
  EXPECT_FALSE(coversRect(q, tile, rule));
  // Nearly edge on: a sliver thinner than a pixel.
  EXPECT_FALSE(coversRect(rectQuad(-10, 16, 50, 16.05), {0, 16, 32, 17}, rule));
  // Two corners swapped: a bow tie, whose edges' half-planes would hold the centre.
  const double bow[4][2] = {{-10, -10}, {50, 50}, {50, -10}, {-10, 50}};
  for (int i = 0; i < 4; ++i) q.window[i][0] = bow[i][0], q.window[i][1] = bow[i][1];
  EXPECT_FALSE(coversRect(q, tile, rule));
  // A repeated corner (a triangle): not a quad the rule knows.
  const double tri[4][2] = {{-10, -10}, {100, -10}, {100, -10}, {-10, 100}};
  for (int i = 0; i < 4; ++i) q.window[i][0] = tri[i][0], q.window[i][1] = tri[i][1];
  EXPECT_FALSE(coversRect(q, tile, rule));
  // A NaN corner.
  q = rectQuad(-10, -10, 50, 50);
  q.window[2][0] = NAN;
  EXPECT_FALSE(coversRect(q, tile, rule));
}

TEST(CoverageRule, EitherOrientationCovers) {
  const CoverageRule rule = coverageRule(viewport());
  DrawnQuad q = rectQuad(-10, -10, 50, 50);
  std::swap(q.window[1][0], q.window[3][0]);
  std::swap(q.window[1][1], q.window[3][1]);
  EXPECT_TRUE(coversRect(q, {0, 0, 32, 32}, rule));
}

// The grid records what the rule covers, and nothing else: cells a quarter of a tile a
// side (8 pixels at 32), each covered entirely by the quad.
TEST(RecordCovered, FullTilesAtTileAndViewportBordersAndPartialOnesLeftAlone) {
  const Camera camera = viewport();
  const CoverageRule rule = coverageRule(camera);
  OcclusionGrid grid({camera.width, camera.height, 32, GridVariant::OcclusionState});
  grid.reset(1.0f);
  ASSERT_EQ(grid.tilesX(), 4u);
  ASSERT_EQ(grid.tilesY(), 3u);
  ASSERT_EQ(grid.hiddenCell(), 8u);
  // From x = 30 (tile 0 partly: its last cell, x from 24, partly too) to beyond the
  // viewport's right side (tile 3 is 4 wide), y from 0 to 64 exactly (tile rows 0, 1).
  const DrawnQuad q = rectQuad(30, 0, 140, 64, 0.5f, 0.625f);
  grid.markOutdated({30, 0, 100, 64});
  EXPECT_EQ(grid.recordCovered(q, rule), 6u);
  for (std::uint32_t ty = 0; ty < 3; ++ty) {
    for (std::uint32_t tx = 0; tx < 4; ++tx) {
      const bool full = tx >= 1 && ty <= 1;
      EXPECT_EQ(grid.tile(tx, ty).hidden_key, full ? 0.625f : 1.0f) << tx << ", " << ty;
      // The record of the depth buffer is not touched.
      EXPECT_EQ(grid.tile(tx, ty).far_key, 1.0f) << tx << ", " << ty;
    }
  }
  for (std::uint32_t y = 0; y < 80; ++y) {
    for (std::uint32_t x = 0; x < 100; ++x) {
      const bool hidden = x >= 32 && y < 64;
      EXPECT_EQ(grid.hiddenAt(x, y), hidden ? 0.625f : 1.0f) << x << ", " << y;
    }
  }
  // A nearer quad tightens the bound, a farther one does not loosen it.
  EXPECT_EQ(grid.recordCovered(rectQuad(64, 0, 96, 32, 0.5f, 0.55f), rule), 1u);
  EXPECT_EQ(grid.tile(2, 0).hidden_key, 0.55f);
  EXPECT_EQ(grid.recordCovered(rectQuad(64, 0, 96, 32, 0.5f, 0.75f), rule), 0u);
  EXPECT_EQ(grid.tile(2, 0).hidden_key, 0.55f);
  // Outside the viewport, or NaN: nothing.
  EXPECT_EQ(grid.recordCovered(rectQuad(200, 0, 300, 64), rule), 0u);
  EXPECT_EQ(grid.recordCovered(rectQuad(NAN, 0, 300, 64), rule), 0u);
  // A clear forgets them (what hid the cells is gone).
  grid.fill(1.0f);
  EXPECT_EQ(grid.tile(2, 0).hidden_key, 1.0f);
  EXPECT_EQ(grid.hiddenAt(70, 10), 1.0f);
}

TEST(RecordCovered, HiddenCellsDecideEveryTestBehindThemWithoutARead) {
  const Camera camera = viewport();
  cpu::SoftwareDepthBuffer buffer(camera.width, camera.height, DepthConvention::Standard);
  OcclusionGrid grid({camera.width, camera.height, 32, GridVariant::OcclusionState});
  grid.reset(1.0f);
  // Something drawn over the left tiles (0.3 over x in [0, 70)): they are outdated.
  buffer.fillRect({0, 0, 70, 80}, 0.3f);
  grid.markOutdated({0, 0, 70, 80});
  // An occluder hidden behind it, recorded without being drawn: cells x in [0, 64).
  const std::uint32_t recorded =
      grid.recordCovered(rectQuad(0, 0, 70, 80, 0.59f, 0.61f), coverageRule(camera));
  EXPECT_EQ(recorded, 6u);  // tile columns 0 and 1, every row (the last is 16 high)
  GridTestCounts counts;
  // A box behind (hidden threshold 0.7) over the two covered columns: occluded whatever
  // the test's own threshold (occlusion state: the clear key), without a read.
  EXPECT_EQ(grid.test({5, 5, 60, 75}, 1.0f, buffer, counts, 0.7f), Visibility::Occluded);
  EXPECT_EQ(buffer.counters().reads, 0u);
  // The cells under a border tile's part of the box count, not the whole tile: x up to
  // 64 lies in hidden cells, though tile 2 (x from 64) is not hidden as a whole.
  EXPECT_EQ(grid.test({40, 5, 64, 75}, 1.0f, buffer, counts, 0.7f), Visibility::Occluded);
  EXPECT_EQ(buffer.counters().reads, 0u);
  // One pixel into the next cell (x = 64, not hidden): the tile is read (and the box,
  // behind what is drawn there, shows beyond x = 70 only: the read finds it occluded
  // over [64, 65)).
  EXPECT_EQ(grid.test({40, 5, 65, 75}, 1.0f, buffer, counts, 0.7f), Visibility::Occluded);
  EXPECT_GT(buffer.counters().reads, 0u);
  // A box in front of the hidden key is not decided by it: the tiles are read.
  const std::uint64_t before = buffer.counters().reads;
  EXPECT_EQ(grid.test({5, 5, 20, 20}, 0.2f, buffer, counts, 0.2f), Visibility::Visible);
  EXPECT_GT(buffer.counters().reads, before);
  // Without a hidden threshold (log-state's tests) the cells decide nothing.
  const std::uint64_t again = buffer.counters().reads;
  OcclusionGrid plain({camera.width, camera.height, 32, GridVariant::OcclusionState});
  plain.reset(1.0f);
  plain.markOutdated({0, 0, 100, 80});
  plain.recordCovered(rectQuad(0, 0, 70, 80, 0.59f, 0.61f), coverageRule(camera));
  EXPECT_EQ(plain.test({75, 5, 95, 75}, 1.0f, buffer, counts), Visibility::Visible);
  EXPECT_GT(buffer.counters().reads, again);
}

// Cells covered by different quads hide a tile together (the union of adjacent quads),
// but a cell that no one quad covers entirely is not hidden, even where the quads leave
// no pixel centre of it free: the rule looks at one quad at a time.
TEST(RecordCovered, AdjacentQuadsHideTheTileTheyCoverTogether) {
  const Camera camera = viewport();
  const CoverageRule rule = coverageRule(camera);
  OcclusionGrid grid({camera.width, camera.height, 32, GridVariant::OcclusionState});
  grid.reset(1.0f);
  // Tile (1, 0) is x in [32, 64): the left quad ends at x = 48 (a cell border), the right
  // one starts there. Neither covers the tile alone.
  EXPECT_EQ(grid.recordCovered(rectQuad(20, 0, 48, 40, 0.5f, 0.6f), rule), 0u);
  EXPECT_EQ(grid.tile(1, 0).hidden_key, 1.0f);
  EXPECT_EQ(grid.recordCovered(rectQuad(48, 0, 80, 40, 0.5f, 0.62f), rule), 1u);
  EXPECT_EQ(grid.tile(1, 0).hidden_key, 0.62f);  // the farther of the two
  EXPECT_EQ(grid.hiddenAt(40, 10), 0.6f);
  EXPECT_EQ(grid.hiddenAt(50, 10), 0.62f);
  // Meeting inside a cell (x = 44): that cell is hidden by neither, nor is the tile.
  OcclusionGrid split({camera.width, camera.height, 32, GridVariant::OcclusionState});
  split.reset(1.0f);
  split.recordCovered(rectQuad(20, 0, 44, 40, 0.5f, 0.6f), rule);
  split.recordCovered(rectQuad(44, 0, 80, 40, 0.5f, 0.6f), rule);
  EXPECT_EQ(split.tile(1, 0).hidden_key, 1.0f);
  EXPECT_EQ(split.hiddenAt(44, 10), 1.0f);
  EXPECT_EQ(split.hiddenAt(39, 10), 0.6f);
  EXPECT_EQ(split.hiddenAt(48, 10), 0.6f);
}

}  // namespace
}  // namespace logrid
