// Each branch of the lazy occlusion grid's test order (LOG §3, §4), by construction.
// A 16x12 viewport with 4-pixel tiles: 4x3 tiles, tile (tx, ty) covers
// [4 tx, 4 tx + 4) x [4 ty, 4 ty + 4).
#include <gtest/gtest.h>

#include "logrid/cpu/software_depth.hpp"
#include "logrid/error.hpp"
#include "logrid/grid.hpp"
#include "test_sources.hpp"

namespace logrid {
namespace {

std::string conventionName(const testing::TestParamInfo<DepthConvention>& param) {
  return toString(param.param);
}

class GridTest : public testing::TestWithParam<DepthConvention> {
 protected:
  GridTest() : buffer_(16, 12, GetParam()) {}

  OcclusionGrid makeGrid(GridVariant variant) {
    OcclusionGrid grid({16, 12, 4, variant});
    grid.reset(clear());
    return grid;
  }
  float clear() const { return GetParam() == DepthConvention::Reversed ? -0.0f : 1.0f; }
  // Window depth for a key, and drawing a rectangle at a key.
  float depthOf(float key) const { return windowDepth(GetParam(), key); }
  void draw(OcclusionGrid& grid, const PixelRect& r, float key) {
    buffer_.fillRect(r, depthOf(key));
    grid.markOutdated(r);
  }
  Visibility test(OcclusionGrid& grid, const PixelRect& r, float threshold) {
    return grid.test(r, threshold, buffer_, counts_);
  }
  std::uint64_t reads() const { return buffer_.counters().reads; }
  std::uint64_t pixels() const { return buffer_.counters().pixels; }

  cpu::SoftwareDepthBuffer buffer_;
  GridTestCounts counts_;
};

// Keys used below: 0.5 is "something drawn"; for reversed they are negative.
float key(DepthConvention c, float standard_key) {
  return c == DepthConvention::Reversed ? standard_key - 1.0f : standard_key;
}

TEST_P(GridTest, Step1UpToDateInternalTileNotFullIsVisibleWithoutReading) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  EXPECT_EQ(test(grid, {4, 4, 8, 8}, clear()), Visibility::Visible);
  EXPECT_EQ(reads(), 0u);
  EXPECT_EQ(counts_.tiles_tested, 1u);
}

TEST_P(GridTest, Step2UpToDateFreeBorderTileIsVisibleWithoutReading) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  EXPECT_EQ(test(grid, {5, 5, 7, 7}, clear()), Visibility::Visible);  // inside tile (1,1)
  EXPECT_EQ(reads(), 0u);
}

TEST_P(GridTest, Step3OutdatedInternalTilesAreReadWholeAndFullOnesOcclude) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  draw(grid, {0, 0, 16, 12}, key(GetParam(), 0.5f));
  EXPECT_TRUE(grid.tile(1, 1).outdated);
  EXPECT_EQ(test(grid, {4, 4, 12, 8}, clear()), Visibility::Occluded);  // tiles (1,1), (2,1)
  EXPECT_EQ(reads(), 2u);
  EXPECT_EQ(pixels(), 32u);
  EXPECT_FALSE(grid.tile(1, 1).outdated);
  EXPECT_LT(grid.tile(1, 1).far_key, clear());  // full
  // The same box again: the records decide, nothing is read.
  EXPECT_EQ(test(grid, {4, 4, 12, 8}, clear()), Visibility::Occluded);
  EXPECT_EQ(reads(), 2u);
}

TEST_P(GridTest, Step3PartialInternalTileIsVisible) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  draw(grid, {4, 4, 6, 8}, key(GetParam(), 0.5f));  // left half of tile (1,1)
  EXPECT_EQ(test(grid, {4, 4, 8, 8}, clear()), Visibility::Visible);
  EXPECT_EQ(reads(), 1u);
  EXPECT_EQ(pixels(), 16u);
  const TileRecord t = grid.tile(1, 1);
  EXPECT_FALSE(t.outdated);
  EXPECT_EQ(t.far_key, clear());  // partial: some pixel free
  EXPECT_LT(t.near_key, clear());
}

TEST_P(GridTest, Step4BorderTilesAreReadOnlyOverTheIntersection) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  draw(grid, {0, 0, 16, 12}, key(GetParam(), 0.5f));
  EXPECT_EQ(test(grid, {5, 5, 7, 7}, clear()), Visibility::Occluded);
  EXPECT_EQ(reads(), 1u);
  EXPECT_EQ(pixels(), 4u);                // 2x2, not the 4x4 tile
  EXPECT_TRUE(grid.tile(1, 1).outdated);  // an intersection does not refresh the tile
}

TEST_P(GridTest, Step4PartialBorderTileDecidesByTheIntersection) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  draw(grid, {4, 4, 6, 8}, key(GetParam(), 0.5f));
  EXPECT_EQ(test(grid, {4, 4, 8, 8}, clear()), Visibility::Visible);  // refresh: partial
  // Up to date and partial: a border box over the drawn half is occluded, over the
  // free half visible, each after reading just its intersection.
  const std::uint64_t before = pixels();
  EXPECT_EQ(test(grid, {4, 5, 6, 7}, clear()), Visibility::Occluded);
  EXPECT_EQ(pixels() - before, 4u);
  EXPECT_EQ(test(grid, {6, 5, 8, 7}, clear()), Visibility::Visible);
}

TEST_P(GridTest, OutdatedTilesThatStillOccludeAreNotReadAgain) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  draw(grid, {0, 0, 16, 12}, key(GetParam(), 0.5f));
  EXPECT_EQ(test(grid, {0, 0, 16, 12}, clear()), Visibility::Occluded);
  const std::uint64_t before = reads();
  draw(grid, {0, 0, 16, 12}, key(GetParam(), 0.25f));  // keys only shrink
  EXPECT_TRUE(grid.tile(0, 0).outdated);
  EXPECT_EQ(test(grid, {0, 0, 16, 12}, clear()), Visibility::Occluded);
  EXPECT_EQ(reads(), before);
}

TEST_P(GridTest, ZfarComparesTheBoxDepthWithTheTileZfar) {
  OcclusionGrid grid = makeGrid(GridVariant::Zfar);
  const DepthConvention c = GetParam();
  draw(grid, {0, 0, 16, 12}, key(c, 0.5f));
  // Behind the drawn depth: occluded; in front: visible.
  EXPECT_EQ(test(grid, {4, 4, 12, 8}, key(c, 0.6f)), Visibility::Occluded);
  EXPECT_EQ(reads(), 2u);
  EXPECT_EQ(test(grid, {4, 4, 12, 8}, key(c, 0.4f)), Visibility::Visible);
  EXPECT_EQ(reads(), 2u);  // decided by the exact up-to-date record
  // Exactly at the stored depth: visible (a pixel at the threshold may show).
  EXPECT_EQ(test(grid, {4, 4, 12, 8}, key(c, 0.5f)), Visibility::Visible);
  // A nearer object over one tile: its zfar is refreshed only when needed.
  draw(grid, {4, 4, 8, 8}, key(c, 0.3f));
  EXPECT_EQ(test(grid, {4, 4, 8, 8}, key(c, 0.6f)), Visibility::Occluded);  // stale zfar 0.5
  EXPECT_EQ(reads(), 2u);
  EXPECT_EQ(test(grid, {4, 4, 8, 8}, key(c, 0.4f)), Visibility::Occluded);  // refreshed: 0.3
  EXPECT_EQ(reads(), 3u);
}

TEST_P(GridTest, ZfarBorderTileWhosePixelsAllLieBehindIsVisibleWithoutReading) {
  OcclusionGrid grid = makeGrid(GridVariant::Zfar);
  const DepthConvention c = GetParam();
  draw(grid, {0, 0, 16, 12}, key(c, 0.5f));
  EXPECT_EQ(test(grid, {0, 0, 16, 12}, key(c, 0.6f)), Visibility::Occluded);  // all refreshed
  const std::uint64_t before = reads();
  EXPECT_EQ(test(grid, {5, 5, 7, 7}, key(c, 0.4f)), Visibility::Visible);  // near_key >= t
  EXPECT_EQ(reads(), before);
}

TEST_P(GridTest, PredicateOnlySourceGivesTheSameAnswers) {
  test::CountOnlySource queries(buffer_);
  const DepthConvention c = GetParam();
  for (GridVariant v : {GridVariant::OcclusionState, GridVariant::Zfar}) {
    OcclusionGrid a = makeGrid(v), b = makeGrid(v);
    buffer_.clear();
    draw(a, {0, 0, 10, 12}, key(c, 0.5f));
    b.markOutdated({0, 0, 10, 12});
    draw(a, {3, 3, 5, 5}, key(c, 0.2f));
    b.markOutdated({3, 3, 5, 5});
    const PixelRect rects[] = {{0, 0, 16, 12}, {0, 0, 8, 8}, {1, 1, 9, 11},
                               {8, 0, 12, 4},  {3, 3, 5, 5}, {9, 0, 11, 12}};
    for (const PixelRect& r : rects) {
      for (float t : {key(c, 0.1f), key(c, 0.3f), key(c, 0.6f)}) {
        const float threshold = v == GridVariant::OcclusionState ? clear() : t;
        GridTestCounts ca, cb;
        EXPECT_EQ(a.test(r, threshold, buffer_, ca), b.test(r, threshold, queries, cb))
            << toString(v) << " rect " << r.x0 << "," << r.y0 << "," << r.x1 << "," << r.y1;
      }
    }
    EXPECT_GT(queries.counters().queries, 0u);
  }
}

TEST_P(GridTest, BatchedSourceGetsAllOutdatedTilesInOneCall) {
  test::BatchedSource batched(buffer_);
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  draw(grid, {0, 0, 16, 12}, key(GetParam(), 0.5f));
  EXPECT_EQ(grid.test({0, 0, 16, 12}, clear(), batched, counts_), Visibility::Occluded);
  EXPECT_EQ(batched.batches, 1);  // twelve internal tiles, one batch
  EXPECT_EQ(batched.counters().reads, 12u);
}

TEST_P(GridTest, BusyRefreshReadsTilesThatAreNotFull) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  buffer_.fillRect({0, 0, 8, 4}, depthOf(key(GetParam(), 0.5f)));
  grid.refreshNow({0, 0, 8, 4}, buffer_);
  EXPECT_EQ(reads(), 2u);
  EXPECT_FALSE(grid.tile(0, 0).outdated);
  EXPECT_LT(grid.tile(0, 0).far_key, clear());
  grid.refreshNow({0, 0, 8, 4}, buffer_);  // both full now: nothing to read
  EXPECT_EQ(reads(), 2u);
}

// What a test would read, against rectangles still to be drawn: the records decide
// without a read; an undecided internal tile is read whole, a border tile where it meets
// the box. A test that reads none of them may read before they are drawn.
TEST_P(GridTest, ReadsUnderNamesWhatTheTestWouldReadOnly) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  const DepthSourceTraits traits = buffer_.traits();
  const float none = OcclusionGrid::kNoHiddenThreshold;
  const auto under = [&](const PixelRect& box, const PixelRect& undrawn) {
    return grid.readsUnder(box, clear(), traits, none, &undrawn, 1);
  };
  // Nothing drawn: every tile is up to date and free, decided without a read.
  EXPECT_FALSE(under({4, 4, 8, 8}, {0, 0, 16, 12}));
  draw(grid, {4, 4, 8, 8}, key(GetParam(), 0.5f));  // tile (1,1) outdated
  // Internal tile (1,1) is read whole: anything drawn over it counts, even outside the box.
  EXPECT_TRUE(under({4, 4, 8, 8}, {7, 7, 9, 9}));
  EXPECT_FALSE(under({4, 4, 8, 8}, {8, 4, 16, 12}));  // beside it
  // A border box in tile (1,1) reads only its part of the tile.
  EXPECT_TRUE(under({5, 5, 7, 7}, {6, 6, 7, 7}));
  EXPECT_FALSE(under({5, 5, 7, 7}, {7, 4, 8, 8}));  // same tile, beside the box
  // Up-to-date free tile (0,0) shows the box first: no read, whatever is undrawn.
  EXPECT_FALSE(under({2, 2, 8, 8}, {4, 4, 8, 8}));
  // Several rectangles: any one the test reads under counts.
  const PixelRect two[] = {{12, 0, 16, 4}, {4, 4, 5, 5}};
  EXPECT_TRUE(grid.readsUnder({4, 4, 8, 8}, clear(), traits, none, two, 2));
  EXPECT_FALSE(grid.readsUnder({4, 4, 8, 8}, clear(), traits, none, two, 1));
  EXPECT_EQ(reads(), 0u);  // asking reads nothing
  // The batch form: the reads planned, not the boxes.
  GridBatch batch;
  EXPECT_FALSE(grid.plan({4, 4, 8, 8}, clear(), traits, &batch, counts_).has_value());
  const PixelRect beside{8, 4, 16, 12}, over{7, 7, 9, 9};
  EXPECT_FALSE(grid.readsUnder(batch, &beside, 1));
  EXPECT_TRUE(grid.readsUnder(batch, &over, 1));
}

// A test that reads both under and away from what is still to be drawn reads away from it
// first: a tile there that shows the box decides it; else nothing, and nothing under the
// undrawn rectangles was read.
TEST_P(GridTest, TestAwayFromReadsOnlyTilesTheUndrawnCannotReach) {
  OcclusionGrid grid = makeGrid(GridVariant::OcclusionState);
  const float k = key(GetParam(), 0.5f);
  draw(grid, {0, 0, 16, 4}, k);
  draw(grid, {0, 8, 16, 12}, k);
  draw(grid, {0, 4, 6, 8}, k);   // tile (1,1): its left half only
  draw(grid, {8, 4, 16, 8}, k);  // tile (2,1): full
  const float none = OcclusionGrid::kNoHiddenThreshold;
  const PixelRect box{4, 4, 12, 8};  // internal tiles (1,1) and (2,1)
  const PixelRect over_full{8, 4, 12, 8}, over_partial{4, 4, 8, 8};
  // Tile (1,1) lies away from the undrawn rectangle and shows the box.
  EXPECT_EQ(grid.testAwayFrom(box, clear(), buffer_, counts_, none, &over_full, 1),
            Visibility::Visible);
  EXPECT_EQ(reads(), 1u);
  draw(grid, {0, 0, 16, 12}, k);  // everything outdated and full again
  // Only tile (2,1) may be read now: full, so nothing is decided.
  EXPECT_FALSE(grid.testAwayFrom(box, clear(), buffer_, counts_, none, &over_partial, 1));
  EXPECT_EQ(reads(), 2u);
  EXPECT_TRUE(grid.tile(1, 1).outdated);
  EXPECT_FALSE(grid.tile(2, 1).outdated);
}

INSTANTIATE_TEST_SUITE_P(Conventions, GridTest,
                         testing::Values(DepthConvention::Standard, DepthConvention::Reversed),
                         conventionName);

TEST(GridDescTest, InvalidDescriptorsThrowWithTheValue) {
  try {
    OcclusionGrid grid({640, 480, 0, GridVariant::Zfar});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tile size 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(OcclusionGrid({0, 480, 32, GridVariant::Zfar}), Error);
  EXPECT_THROW(OcclusionGrid({640, kMaxViewportSide + 1, 32, GridVariant::Zfar}), Error);
  EXPECT_NO_THROW(OcclusionGrid({1, 1, 4000000000u, GridVariant::Zfar}));
}

TEST(GridDescTest, TilesCoverOddViewportsExactly) {
  for (std::uint32_t ts : {1u, 3u, 7u, 32u, 256u, 1000u}) {
    OcclusionGrid grid({641, 479, ts, GridVariant::OcclusionState});
    std::int64_t area = 0;
    for (std::uint32_t y = 0; y < grid.tilesY(); ++y) {
      for (std::uint32_t x = 0; x < grid.tilesX(); ++x) area += grid.tileRect(x, y).area();
    }
    EXPECT_EQ(area, 641 * 479) << "tile " << ts;
    const PixelRect last = grid.tileRect(grid.tilesX() - 1, grid.tilesY() - 1);
    EXPECT_EQ(last.x1, 641);
    EXPECT_EQ(last.y1, 479);
  }
}

}  // namespace
}  // namespace logrid
