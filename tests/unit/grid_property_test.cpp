// Property test: over random depth buffers, random draws and random boxes, the grid
// never answers "occluded" where a brute-force scan of the box's rectangle finds a
// pixel at or beyond the threshold, and never "visible" where it finds none. Fixed
// seeds; at least 100,000 tests per variant and convention, with every kind of source,
// viewports from 1x1 to odd sizes, tile sizes from 1 pixel to larger than the viewport,
// and tests asked one at a time (test()) or in batches of up to six (plan(), submit(),
// collect(), apply(), resolve()), with draws between a batch's submit and its apply.
#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "logrid/cpu/software_depth.hpp"
#include "logrid/grid.hpp"
#include "test_sources.hpp"

namespace logrid {
namespace {

struct Tally {
  std::uint64_t tests = 0;
  std::uint64_t missed = 0;         // grid occluded, brute force visible: a bug
  std::uint64_t false_visible = 0;  // grid visible, brute force occluded
  std::uint64_t pixels_read = 0;
  std::uint64_t brute_pixels = 0;
};

PixelRect randomRect(std::mt19937& rng, std::int32_t w, std::int32_t h) {
  const std::int32_t x0 = std::int32_t(rng() % std::uint32_t(w));
  const std::int32_t y0 = std::int32_t(rng() % std::uint32_t(h));
  // Mostly small rectangles, sometimes screen-filling.
  const std::int32_t max_w = rng() % 8 == 0 ? w : std::max(1, w / 3);
  const std::int32_t max_h = rng() % 8 == 0 ? h : std::max(1, h / 3);
  const std::int32_t x1 = std::min(w, x0 + 1 + std::int32_t(rng() % std::uint32_t(max_w)));
  const std::int32_t y1 = std::min(h, y0 + 1 + std::int32_t(rng() % std::uint32_t(max_h)));
  return {x0, y0, x1, y1};
}

bool bruteVisible(const cpu::SoftwareDepthBuffer& b, const PixelRect& r, float threshold) {
  for (std::int32_t y = r.y0; y < r.y1; ++y) {
    for (std::int32_t x = r.x0; x < r.x1; ++x) {
      if (depthKey(b.convention(), b.at(std::uint32_t(x), std::uint32_t(y))) >= threshold) {
        return true;
      }
    }
  }
  return false;
}

enum class SourceKind { Software, CountOnly, Batched };

void score(Tally& tally, Visibility v, bool truth) {
  ++tally.tests;
  if (v == Visibility::Occluded && truth) ++tally.missed;
  if (v == Visibility::Visible && !truth) ++tally.false_visible;
}

// Up to six tests through the batched path. The truth of a planned test is taken when the
// batch is submitted (answers describe the buffer then); a synchronous source may see a
// draw between submit and apply, which must leave the drawn tiles outdated.
template <typename Threshold, typename Draw>
void batchedTests(std::mt19937& rng, OcclusionGrid& grid, const cpu::SoftwareDepthBuffer& buffer,
                  DepthSource& source, bool synchronous, Tally& tally, Threshold threshold,
                  Draw draw) {
  const std::int32_t w = std::int32_t(buffer.width()), h = std::int32_t(buffer.height());
  GridBatch batch;
  GridTestCounts counts;
  std::vector<std::pair<PixelRect, float>> planned;
  const int n = 1 + int(rng() % 6);
  for (int k = 0; k < n; ++k) {
    const PixelRect r = randomRect(rng, w, h);
    const float t = threshold();
    const std::optional<Visibility> v = grid.plan(r, t, source.traits(), &batch, counts);
    if (v) {
      score(tally, *v, bruteVisible(buffer, r, t));
    } else {
      planned.emplace_back(r, t);
    }
  }
  ASSERT_EQ(batch.tests(), planned.size());
  std::vector<bool> truth;
  for (const auto& [r, t] : planned) truth.push_back(bruteVisible(buffer, r, t));
  grid.submit(batch, source);
  if (synchronous && rng() % 2 == 0) draw();
  source.collect();
  grid.apply(batch);
  for (std::size_t i = 0; i < planned.size(); ++i)
    score(tally, grid.resolve(batch, i), truth[i]);
}

Tally run(GridVariant variant, DepthConvention convention, SourceKind kind, std::uint32_t seed,
          std::uint64_t min_tests) {
  std::mt19937 rng(seed);
  const std::uint32_t tile_sizes[] = {1, 2, 3, 7, 8, 16, 32, 64, 256};
  const float clear = convention == DepthConvention::Reversed ? -0.0f : 1.0f;
  auto randomKey = [&] {
    // Quantised so that thresholds often land exactly on stored depths.
    const float standard = float(rng() % 64) / 64.0f;
    return convention == DepthConvention::Reversed ? -standard : standard;
  };
  Tally tally;
  while (tally.tests < min_tests) {
    const std::int32_t w = rng() % 10 == 0 ? 1 : 1 + std::int32_t(rng() % 97);
    const std::int32_t h = rng() % 10 == 0 ? 1 : 1 + std::int32_t(rng() % 61);
    const std::uint32_t ts = tile_sizes[rng() % std::size(tile_sizes)];
    cpu::SoftwareDepthBuffer buffer(std::uint32_t(w), std::uint32_t(h), convention);
    test::CountOnlySource count_only(buffer);
    test::BatchedSource batched(buffer);
    DepthSource& source = kind == SourceKind::Software    ? static_cast<DepthSource&>(buffer)
                          : kind == SourceKind::CountOnly ? static_cast<DepthSource&>(count_only)
                                                          : static_cast<DepthSource&>(batched);
    OcclusionGrid grid({std::uint32_t(w), std::uint32_t(h), ts, variant});
    grid.reset(clear);
    const bool busy = kind != SourceKind::CountOnly && rng() % 4 == 0;
    for (int step = 0; step < 60; ++step) {
      if (rng() % 3 == 0) {
        // Draw: fill a rectangle at a random depth; tell the grid (lazily or busily).
        const PixelRect r = randomRect(rng, w, h);
        buffer.fillRect(r, windowDepth(convention, randomKey()));
        if (busy && variant == GridVariant::OcclusionState) {
          grid.refreshNow(r, source);
        } else {
          grid.markOutdated(r);
        }
        continue;
      }
      if (rng() % 4 == 0) {
        batchedTests(
            rng, grid, buffer, source, kind == SourceKind::Software, tally,
            [&] { return variant == GridVariant::OcclusionState ? clear : randomKey(); },
            [&] {
              const PixelRect d = randomRect(rng, w, h);
              buffer.fillRect(d, windowDepth(convention, randomKey()));
              grid.markOutdated(d);
            });
        continue;
      }
      const PixelRect r = randomRect(rng, w, h);
      const float threshold = variant == GridVariant::OcclusionState ? clear : randomKey();
      GridTestCounts counts;
      const std::uint64_t before = source.counters().pixels + buffer.counters().pixels;
      const Visibility v = grid.test(r, threshold, source, counts);
      tally.pixels_read += source.counters().pixels + buffer.counters().pixels - before;
      tally.brute_pixels += std::uint64_t(r.area());
      const bool truth = bruteVisible(buffer, r, threshold);
      ++tally.tests;
      if (v == Visibility::Occluded && truth) ++tally.missed;
      if (v == Visibility::Visible && !truth) ++tally.false_visible;
    }
  }
  return tally;
}

struct Case {
  GridVariant variant;
  DepthConvention convention;
  SourceKind kind;
};

std::string caseName(const testing::TestParamInfo<Case>& param) {
  static const char* const kKinds[] = {"software", "count_only", "batched"};
  std::string s = std::string(toString(param.param.variant)) + "_" +
                  toString(param.param.convention) + "_" + kKinds[int(param.param.kind)];
  for (char& ch : s) ch = ch == '-' ? '_' : ch;
  return s;
}

class GridPropertyTest : public testing::TestWithParam<Case> {};

TEST_P(GridPropertyTest, NeverOccludedWhereAPixelShows) {
  const Case c = GetParam();
  const std::uint32_t seed = 1000 + 100 * std::uint32_t(c.variant) +
                             10 * std::uint32_t(c.convention) + std::uint32_t(c.kind);
  const Tally t = run(c.variant, c.convention, c.kind, seed, 100000);
  EXPECT_EQ(t.missed, 0u) << "the grid culled boxes with visible pixels";
  // Relative to its rectangle the grid is exact: a "visible" answer always has a pixel.
  EXPECT_EQ(t.false_visible, 0u);
  RecordProperty("tests", std::to_string(t.tests));
  RecordProperty("false_visible", std::to_string(t.false_visible));
  std::printf(
      "[ property ] %s %s: %llu tests, %llu missed, %llu false visible, pixels read %.1f%% "
      "of a per-box scan\n",
      toString(c.variant), toString(c.convention), (unsigned long long)t.tests,
      (unsigned long long)t.missed, (unsigned long long)t.false_visible,
      100.0 * double(t.pixels_read) / double(t.brute_pixels));
}

INSTANTIATE_TEST_SUITE_P(
    AllVariants, GridPropertyTest,
    testing::Values(
        Case{GridVariant::OcclusionState, DepthConvention::Standard, SourceKind::Software},
        Case{GridVariant::OcclusionState, DepthConvention::Reversed, SourceKind::Software},
        Case{GridVariant::Zfar, DepthConvention::Standard, SourceKind::Software},
        Case{GridVariant::Zfar, DepthConvention::Reversed, SourceKind::Software},
        Case{GridVariant::OcclusionState, DepthConvention::Standard, SourceKind::CountOnly},
        Case{GridVariant::Zfar, DepthConvention::Reversed, SourceKind::CountOnly},
        Case{GridVariant::OcclusionState, DepthConvention::Reversed, SourceKind::Batched},
        Case{GridVariant::Zfar, DepthConvention::Standard, SourceKind::Batched}),
    caseName);

}  // namespace
}  // namespace logrid
