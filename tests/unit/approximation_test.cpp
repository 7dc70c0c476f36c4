// The approximate knobs (GridApproximation, CullerDesc::approximation): each culls what
// the exact grid must keep, only within its stated bound, and bad settings are refused.
// A 16x12 viewport with 4-pixel tiles, as in grid_test.cpp.
#include <gtest/gtest.h>

#include "logrid/cpu/software_depth.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"
#include "logrid/grid.hpp"
#include "test_sources.hpp"

namespace logrid {
namespace {

constexpr float kClear = 1.0f;  // standard convention
constexpr float kDrawn = 0.5f;

class ApproximationTest : public testing::Test {
 protected:
  ApproximationTest() : buffer_(16, 12, DepthConvention::Standard) {}

  OcclusionGrid makeGrid(const GridApproximation& a,
                         GridVariant variant = GridVariant::OcclusionState) {
    OcclusionGrid grid({16, 12, 4, variant}, a);
    grid.reset(kClear);
    return grid;
  }
  void draw(OcclusionGrid& grid, const PixelRect& r) {
    buffer_.fillRect(r, kDrawn);
    grid.markOutdated(r);
  }
  // Everything drawn except `holes` single pixels.
  void drawAllBut(OcclusionGrid& grid, std::initializer_list<std::pair<int, int>> holes) {
    draw(grid, {0, 0, 16, 12});
    for (auto [x, y] : holes) buffer_.data()[y * 16 + x] = kClear;
  }
  Visibility test(OcclusionGrid& grid, const PixelRect& r, float threshold = kClear) {
    return grid.test(r, threshold, buffer_, counts_);
  }

  cpu::SoftwareDepthBuffer buffer_;
  GridTestCounts counts_;
};

TEST_F(ApproximationTest, ExactGridSeesASinglePixelHole) {
  OcclusionGrid grid = makeGrid({});
  drawAllBut(grid, {{5, 5}});
  EXPECT_EQ(test(grid, {4, 4, 12, 8}), Visibility::Visible);
}

TEST_F(ApproximationTest, VisiblePixelThresholdCullsUpToNPixelsAndNoMore) {
  GridApproximation a;
  a.visible_pixels = 2;
  {
    OcclusionGrid grid = makeGrid(a);
    drawAllBut(grid, {{5, 5}, {9, 6}});  // 2 free pixels in two different tiles
    EXPECT_EQ(test(grid, {4, 4, 12, 8}), Visibility::Occluded);
  }
  {
    OcclusionGrid grid = makeGrid(a);
    drawAllBut(grid, {{5, 5}, {9, 6}, {10, 7}});  // 3 > 2
    EXPECT_EQ(test(grid, {4, 4, 12, 8}), Visibility::Visible);
  }
  {
    // A free up-to-date tile is counted from its record without a read: 16 > 2.
    OcclusionGrid grid = makeGrid(a);
    const std::uint64_t reads = buffer_.counters().reads;
    EXPECT_EQ(test(grid, {4, 4, 8, 8}), Visibility::Visible);
    EXPECT_EQ(buffer_.counters().reads, reads);
  }
}

TEST_F(ApproximationTest, VisiblePixelThresholdWorksForZfarToo) {
  GridApproximation a;
  a.visible_pixels = 1;
  OcclusionGrid grid = makeGrid(a, GridVariant::Zfar);
  drawAllBut(grid, {{5, 5}});
  EXPECT_EQ(test(grid, {4, 4, 12, 8}, 0.7f), Visibility::Occluded);  // box behind 0.5
  EXPECT_EQ(test(grid, {4, 4, 12, 8}, 0.3f), Visibility::Visible);   // box in front
}

TEST_F(ApproximationTest, FullFractionTurnsNearlyFullTilesFull) {
  GridApproximation a;
  a.full_free_fraction = 0.1f;  // a 4x4 tile: at most 1 free pixel of 16 counts as full
  {
    OcclusionGrid grid = makeGrid(a);
    drawAllBut(grid, {{5, 5}});
    EXPECT_EQ(test(grid, {4, 4, 8, 8}), Visibility::Occluded);
    EXPECT_LT(grid.tile(1, 1).far_key, kClear);  // recorded as full
  }
  {
    OcclusionGrid grid = makeGrid(a);
    drawAllBut(grid, {{5, 5}, {6, 6}});  // 2 of 16 > 10 %
    EXPECT_EQ(test(grid, {4, 4, 8, 8}), Visibility::Visible);
  }
}

TEST_F(ApproximationTest, RowStrideSkipsRowsAndReadsFewerPixels) {
  GridApproximation a;
  a.row_stride = 2;  // rows 4 and 6 of tile (1,1) are sampled, 5 and 7 are not
  {
    OcclusionGrid grid = makeGrid(a);
    drawAllBut(grid, {{5, 5}});
    EXPECT_EQ(test(grid, {4, 4, 8, 8}), Visibility::Occluded);
    EXPECT_EQ(buffer_.counters().pixels, 8u);  // half the tile
  }
  {
    OcclusionGrid grid = makeGrid(a);
    drawAllBut(grid, {{5, 6}});
    EXPECT_EQ(test(grid, {4, 4, 8, 8}), Visibility::Visible);
  }
}

TEST_F(ApproximationTest, BadSettingsAreRefusedWithTheValue) {
  GridApproximation a;
  a.full_free_fraction = 1.0f;
  EXPECT_NE(validateGridDesc({16, 12, 4, GridVariant::OcclusionState}, a).find("fraction 1"),
            std::string::npos);
  a.full_free_fraction = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(validateGridDesc({16, 12, 4, GridVariant::OcclusionState}, a).empty());
  a.full_free_fraction = 0.1f;
  EXPECT_NE(validateGridDesc({16, 12, 4, GridVariant::Zfar}, a).find("occlusion-state"),
            std::string::npos);
  GridApproximation s;
  s.row_stride = 0;
  EXPECT_NE(validateGridDesc({16, 12, 4, GridVariant::OcclusionState}, s).find("row stride 0"),
            std::string::npos);
  s.row_stride = 5;  // more than the tile
  EXPECT_THROW(OcclusionGrid({16, 12, 4, GridVariant::OcclusionState}, s), Error);

  CullerDesc hzb;
  hzb.method = Method::Hzb;
  hzb.approximation.visible_pixels = 4;
  EXPECT_NE(validateCullerDesc(hzb).find("hzb takes no visible-pixel threshold"),
            std::string::npos);
  CullerDesc pq;
  pq.method = Method::Pq;
  pq.approximation.row_stride = 2;
  EXPECT_NE(validateCullerDesc(pq).find("pq takes no row stride"), std::string::npos);
  pq.approximation = {};
  pq.approximation.visible_pixels = 4;
  EXPECT_EQ(validateCullerDesc(pq), "");
}

}  // namespace
}  // namespace logrid
