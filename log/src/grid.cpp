#include "logrid/grid.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <sstream>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"

namespace logrid {

const char* toString(GridVariant v) { return v == GridVariant::Zfar ? "zfar" : "occlusion-state"; }

namespace {

std::uint64_t tileCount(std::uint64_t width, std::uint64_t height, std::uint64_t tile) {
  return ((width + tile - 1) / tile) * ((height + tile - 1) / tile);
}

}  // namespace

std::string validateGridDesc(const GridDesc& desc, const GridApproximation& approximation) {
  std::ostringstream out;
  if (desc.width < 1 || desc.height < 1 || desc.width > kMaxViewportSide ||
      desc.height > kMaxViewportSide) {
    out << "grid: viewport " << desc.width << "x" << desc.height
        << " is out of range; each side must be between 1 and " << kMaxViewportSide;
  } else if (desc.tile_size < 1) {
    out << "grid: tile size " << desc.tile_size << " is invalid; use 1 pixel or more";
  } else if (tileCount(desc.width, desc.height, desc.tile_size) > kMaxGridTiles) {
    std::uint32_t smallest = desc.tile_size;
    while (tileCount(desc.width, desc.height, smallest) > kMaxGridTiles) ++smallest;
    out << "grid: a " << desc.width << "x" << desc.height << " viewport with tile size "
        << desc.tile_size << " has " << tileCount(desc.width, desc.height, desc.tile_size)
        << " tiles, more than the " << kMaxGridTiles << " a grid may hold; use a tile size of "
        << smallest << " or more";
  } else if (desc.variant != GridVariant::OcclusionState && desc.variant != GridVariant::Zfar) {
    out << "grid: unknown variant " << int(desc.variant);
  } else if (!(approximation.full_free_fraction >= 0 && approximation.full_free_fraction < 1)) {
    out << "grid: full-tile free fraction " << approximation.full_free_fraction
        << " is invalid; use 0 (exact) up to but not including 1";
  } else if (approximation.full_free_fraction > 0 && desc.variant == GridVariant::Zfar) {
    out << "grid: the full-tile free fraction applies to the occlusion-state variant only";
  } else if (approximation.row_stride < 1 || approximation.row_stride > desc.tile_size) {
    out << "grid: row stride " << approximation.row_stride
        << " is invalid; use 1 (every row) up to the tile size " << desc.tile_size;
  }
  return out.str();
}

Result<OcclusionGrid> OcclusionGrid::create(const GridDesc& desc,
                                            const GridApproximation& approximation) {
  std::string problem = validateGridDesc(desc, approximation);
  if (!problem.empty()) return Status(ErrorCode::InvalidArgument, std::move(problem));
  return OcclusionGrid(Checked{}, desc, approximation);
}

OcclusionGrid::OcclusionGrid(Checked, const GridDesc& desc, const GridApproximation& approximation)
    : desc_(desc), approx_(approximation) {
  const std::uint64_t ts = desc.tile_size;
  tiles_x_ = static_cast<std::uint32_t>((desc.width + ts - 1) / ts);
  tiles_y_ = static_cast<std::uint32_t>((desc.height + ts - 1) / ts);
  const std::size_t n = std::size_t(tiles_x_) * tiles_y_;
  near_.assign(n, 1.0f);
  far_.assign(n, 1.0f);
  outdated_.assign(n, 0);
  hidden_.assign(n, 1.0f);
  hidden_some_.assign(n, 0);
  // Cells a quarter of a tile a side, or whole tiles where that would make too many.
  cell_ = std::max<std::uint32_t>(1, desc.tile_size / 4);
  if (tileCount(desc.width, desc.height, cell_) > kMaxGridTiles) cell_ = desc.tile_size;
  cells_x_ = static_cast<std::uint32_t>((desc.width + cell_ - 1) / cell_);
  cells_y_ = static_cast<std::uint32_t>((desc.height + cell_ - 1) / cell_);
  cell_hidden_.assign(std::size_t(cells_x_) * cells_y_, 1.0f);
  stamp_.assign(n, 0);
  planned_.assign(n, 0);
  pending_.reserve(n);
  requests_.reserve(n);
  owners_.reserve(n);
  answers_.reserve(n);
}

void GridBatch::clear() {
  submitted_ = false;
  requests_.clear();
  answers_.clear();
  reads_.clear();
  tests_.clear();
  test_reads_.clear();
}

PixelRect OcclusionGrid::tileRect(std::uint32_t tx, std::uint32_t ty) const {
  const std::uint64_t ts = desc_.tile_size;
  PixelRect r;
  r.x0 = static_cast<std::int32_t>(tx * ts);
  r.y0 = static_cast<std::int32_t>(ty * ts);
  r.x1 = static_cast<std::int32_t>(std::min<std::uint64_t>((tx + 1) * ts, desc_.width));
  r.y1 = static_cast<std::int32_t>(std::min<std::uint64_t>((ty + 1) * ts, desc_.height));
  return r;
}

PixelRect OcclusionGrid::viewport() const {
  return {0, 0, std::int32_t(desc_.width), std::int32_t(desc_.height)};
}

bool OcclusionGrid::insideViewport(const PixelRect& rect) const {
  return !rect.empty() && rect.x0 >= 0 && rect.y0 >= 0 && rect.x1 <= std::int32_t(desc_.width) &&
         rect.y1 <= std::int32_t(desc_.height);
}

TileRecord OcclusionGrid::tile(std::uint32_t tx, std::uint32_t ty) const {
  assert(tx < tiles_x_ && ty < tiles_y_ && "OcclusionGrid::tile: tile out of range");
  const std::size_t i = std::size_t(ty) * tiles_x_ + tx;
  return {near_[i], far_[i], outdated_[i] != 0, hidden_[i]};
}

void OcclusionGrid::reset(float clear_key) {
  clear_key_ = clear_key;
  fill(clear_key);
}

void OcclusionGrid::fill(float key) {
  std::fill(near_.begin(), near_.end(), key);
  std::fill(far_.begin(), far_.end(), key);
  std::fill(outdated_.begin(), outdated_.end(), std::uint8_t{0});
  // What was known hidden was hidden by what the clear took away.
  std::fill(hidden_.begin(), hidden_.end(), key);
  std::fill(hidden_some_.begin(), hidden_some_.end(), std::uint8_t{0});
  std::fill(cell_hidden_.begin(), cell_hidden_.end(), key);
  for (std::uint32_t t : planned_tiles_) planned_[t] = 0;
  planned_tiles_.clear();
  ++epoch_;
}

namespace {

PixelRect intersect(const PixelRect& a, const PixelRect& b) {
  return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}

float below(float key) { return std::nextafter(key, -std::numeric_limits<float>::infinity()); }

// The summary of a read that spans several requests (rows of a sampled tile).
AreaDepth mergeSummaries(const AreaRequest* requests, const AreaAnswer* answers, std::size_t first,
                         std::size_t end, std::uint32_t& sampled) {
  // Seeded from the first row so that a NaN from the source stays NaN (and visible).
  AreaDepth merged = answers[first].depth;
  sampled = std::uint32_t(requests[first].rect.area());
  for (std::size_t r = first + 1; r < end; ++r) {
    merged.min_key = std::min(merged.min_key, answers[r].depth.min_key);
    merged.max_key = std::max(merged.max_key, answers[r].depth.max_key);
    merged.free_pixels += answers[r].depth.free_pixels;
    sampled += std::uint32_t(requests[r].rect.area());
  }
  return merged;
}

// The pixels counted, and the pixels sampled, by the requests [first, end) of one read.
void sumCounts(const AreaRequest* requests, const AreaAnswer* answers, std::size_t first,
               std::size_t end, std::uint32_t& count, std::uint32_t& sampled) {
  count = 0;
  sampled = 0;
  for (std::size_t r = first; r < end; ++r) {
    count += answers[r].count;
    sampled += std::uint32_t(requests[r].rect.area());
  }
}

// A tile index with its internal/border class packed into the top bit.
constexpr std::uint32_t kInternalBit = 0x80000000u;

// The order of §3's steps: a rectangle's internal tiles, then its border tiles.
constexpr bool kInternalFirst[] = {true, false};

}  // namespace

// The tiles a pixel rectangle touches, and the ones it covers completely.
struct OcclusionGrid::TileSpan {
  std::uint32_t x0, x1, y0, y1;     // touched, inclusive
  std::int64_t ix0, ix1, iy0, iy1;  // internal, inclusive; empty when ix0 > ix1 or iy0 > iy1

  bool internal(std::uint32_t tx, std::uint32_t ty) const {
    return tx >= ix0 && tx <= ix1 && ty >= iy0 && ty <= iy1;
  }
};

OcclusionGrid::TileSpan OcclusionGrid::tileSpan(const PixelRect& r) const {
  const std::uint64_t ts = desc_.tile_size;
  TileSpan s;
  s.x0 = static_cast<std::uint32_t>(std::uint64_t(r.x0) / ts);
  s.x1 = static_cast<std::uint32_t>(std::uint64_t(r.x1 - 1) / ts);
  s.y0 = static_cast<std::uint32_t>(std::uint64_t(r.y0) / ts);
  s.y1 = static_cast<std::uint32_t>(std::uint64_t(r.y1 - 1) / ts);
  // A tile is internal when its extent, clipped to the viewport, lies inside r.
  s.ix0 = std::uint64_t(r.x0) == s.x0 * ts ? s.x0 : std::int64_t{s.x0} + 1;
  s.iy0 = std::uint64_t(r.y0) == s.y0 * ts ? s.y0 : std::int64_t{s.y0} + 1;
  s.ix1 = std::uint64_t(r.x1) >= std::min<std::uint64_t>((s.x1 + 1) * ts, desc_.width)
              ? std::int64_t{s.x1}
              : std::int64_t{s.x1} - 1;
  s.iy1 = std::uint64_t(r.y1) >= std::min<std::uint64_t>((s.y1 + 1) * ts, desc_.height)
              ? std::int64_t{s.y1}
              : std::int64_t{s.y1} - 1;
  return s;
}

template <typename Visit>
bool OcclusionGrid::forEachTile(const TileSpan& s, Visit&& visit) const {
  for (std::uint32_t ty = s.y0; ty <= s.y1; ++ty) {
    for (std::uint32_t tx = s.x0; tx <= s.x1; ++tx) {
      if (visit(std::size_t(ty) * tiles_x_ + tx, s.internal(tx, ty))) return true;
    }
  }
  return false;
}

template <typename Visit>
bool OcclusionGrid::forEachTileOf(const TileSpan& s, bool internal, Visit&& visit) const {
  return forEachTile(
      s, [&](std::size_t i, bool tile_internal) { return tile_internal == internal && visit(i); });
}

void OcclusionGrid::markOutdated(const PixelRect& rect) {
  const PixelRect r = intersect(rect, viewport());
  if (r.empty()) return;
  const TileSpan s = tileSpan(r);
  ++draw_stamp_;
  for (std::uint32_t ty = s.y0; ty <= s.y1; ++ty) {
    const std::size_t row = std::size_t(ty) * tiles_x_;
    std::fill(outdated_.data() + row + s.x0, outdated_.data() + row + s.x1 + 1, std::uint8_t{1});
    std::fill(stamp_.data() + row + s.x0, stamp_.data() + row + s.x1 + 1, draw_stamp_);
  }
}

std::uint32_t OcclusionGrid::recordCovered(const DrawnQuad& quad, const CoverageRule& rule) {
  double xlo = HUGE_VAL, xhi = -HUGE_VAL, ylo = HUGE_VAL, yhi = -HUGE_VAL;
  for (const auto& corner : quad.window) {
    xlo = std::min(xlo, corner[0]), xhi = std::max(xhi, corner[0]);
    ylo = std::min(ylo, corner[1]), yhi = std::max(yhi, corner[1]);
  }
  // The tiles under the quad's box (NaN corners give an empty range).
  const auto clampTo = [](double v, std::uint32_t n) {
    return v >= double(n) ? std::int32_t(n) : v > 0 ? std::int32_t(v) : 0;
  };
  const PixelRect box{clampTo(std::floor(xlo), desc_.width), clampTo(std::floor(ylo), desc_.height),
                      clampTo(std::ceil(xhi), desc_.width), clampTo(std::ceil(yhi), desc_.height)};
  if (box.empty()) return 0;
  // The cells it covers entirely. Keys only shrink within a frame: the nearer of two
  // bounds holds.
  const QuadCoverage coverage(quad, rule);
  bool any = false;
  for (std::uint32_t cy = std::uint32_t(box.y0) / cell_; cy * cell_ < std::uint32_t(box.y1); ++cy) {
    for (std::uint32_t cx = std::uint32_t(box.x0) / cell_; cx * cell_ < std::uint32_t(box.x1);
         ++cx) {
      const PixelRect cell{std::int32_t(cx * cell_), std::int32_t(cy * cell_),
                           std::int32_t(std::min(desc_.width, (cx + 1) * cell_)),
                           std::int32_t(std::min(desc_.height, (cy + 1) * cell_))};
      if (!coverage.covers(cell)) continue;
      float& key = cell_hidden_[std::size_t(cy) * cells_x_ + cx];
      key = std::min(key, quad.far_key);
      any = true;
    }
  }
  if (!any) return 0;
  // The tiles' summaries.
  std::uint32_t recorded = 0;
  forEachTile(tileSpan(box), [&](std::size_t i, bool) {
    const float whole = hiddenOfTile(i);
    if (whole < hidden_[i]) ++recorded;
    hidden_[i] = whole;
    hidden_some_[i] = 1;
    return false;
  });
  return recorded;
}

float OcclusionGrid::hiddenAt(std::uint32_t x, std::uint32_t y) const {
  assert(x < desc_.width && y < desc_.height && "OcclusionGrid::hiddenAt: pixel out of range");
  return cell_hidden_[std::size_t(y / cell_) * cells_x_ + x / cell_];
}

float OcclusionGrid::largestHidden(const PixelRect& r, float enough) const {
  float largest = -std::numeric_limits<float>::infinity();
  for (std::uint32_t cy = std::uint32_t(r.y0) / cell_; cy * cell_ < std::uint32_t(r.y1); ++cy) {
    const float* row = cell_hidden_.data() + std::size_t(cy) * cells_x_;
    for (std::uint32_t cx = std::uint32_t(r.x0) / cell_; cx * cell_ < std::uint32_t(r.x1); ++cx) {
      largest = std::max(largest, row[cx]);
      if (!(largest < enough)) return largest;
    }
  }
  return largest;
}

float OcclusionGrid::hiddenOfTile(std::size_t index) const {
  return largestHidden(tileRectOf(index), std::numeric_limits<float>::infinity());
}

float OcclusionGrid::hiddenUnder(std::size_t index) const {
  const PixelRect t = intersect(tileRectOf(index), test_rect_);
  if (t.empty()) return hidden_[index];
  return largestHidden(t, hidden_threshold_);
}

OcclusionGrid::Decision OcclusionGrid::decideFromRecord(std::size_t i, bool internal,
                                                        float threshold) const {
  if (tileHides(i, threshold)) return Decision::Occluded;
  if (outdated_[i]) return Decision::Undecided;
  if (near_[i] >= threshold) return Decision::Visible;  // every pixel at or beyond
  // An exact record of an internal tile: its farthest pixel lies inside the box's area.
  const bool exact = exact_records_ || desc_.variant == GridVariant::OcclusionState;
  if (internal && exact) return Decision::Visible;
  return Decision::Undecided;
}

void OcclusionGrid::applySummary(std::size_t i, const AreaDepth& area, std::uint32_t sampled) {
  near_[i] = area.min_key;
  far_[i] = area.max_key;
  outdated_[i] = 0;
  // Approximation only: few enough free pixels count as full. (The exact grid never
  // reads free_pixels here, so a source may leave it 0 unless the fraction is used.)
  if (approx_.full_free_fraction > 0 && desc_.variant == GridVariant::OcclusionState &&
      far_[i] >= clear_key_ && !countShows(area.free_pixels, sampled, clear_key_)) {
    far_[i] = below(clear_key_);
  }
}

void OcclusionGrid::applyCount(std::size_t i, std::uint32_t count, std::uint32_t sampled,
                               float threshold) {
  // Every far key a tile has held is an upper bound of its pixels (keys only shrink), so
  // a count tightens the bound and never loosens it: another read of the same batch may
  // already have tightened it further.
  if (threshold >= clear_key_) {
    // Counted at the clear key, so `count` is the number of free pixels: an exact state.
    far_[i] =
        std::min(far_[i], countShows(count, sampled, threshold) ? clear_key_ : below(clear_key_));
    near_[i] = count == sampled ? clear_key_ : -std::numeric_limits<float>::infinity();
    outdated_[i] = 0;
  } else if (count == 0) {
    // Only a bound: every pixel is in front of the threshold.
    far_[i] = std::min(far_[i], below(threshold));
    near_[i] = -std::numeric_limits<float>::infinity();
    outdated_[i] = 0;
  }
}

bool OcclusionGrid::countShows(std::uint32_t count, std::uint32_t sampled, float threshold) const {
  // Exact: any pixel shows. Approximate: more than the allowed fraction of the free
  // pixels (the fraction applies to occlusion-state tests, at the clear key, only).
  const double fraction = threshold >= clear_key_ ? double(approx_.full_free_fraction) : 0.0;
  return count > 0 && double(count) > fraction * sampled;
}

void OcclusionGrid::appendRead(const PixelRect& area, AreaAsk ask, float threshold,
                               std::vector<AreaRequest>& requests) const {
  const std::int32_t stride = std::int32_t(approx_.row_stride);
  if (stride == 1) {
    requests.push_back({area, ask, threshold});
    return;
  }
  for (std::int32_t y = area.y0; y < area.y1; y += stride) {
    requests.push_back({{area.x0, y, area.x1, y + 1}, ask, threshold});
  }
}

Visibility OcclusionGrid::test(const PixelRect& rect, float threshold, DepthSource& source,
                               GridTestCounts& counts, float hidden_threshold) {
  assert(insideViewport(rect) &&
         "OcclusionGrid::test: rect must be non-empty and inside the viewport");
  exact_records_ = source.traits().reads_depth;
  hidden_threshold_ = hidden_threshold;
  test_rect_ = rect;
  if (approx_.visible_pixels > 0) return testCounting(rect, threshold, source, counts);
  const TileSpan s = tileSpan(rect);
  if (recordsShow(s, threshold, counts)) return Visibility::Visible;
  return readsShow(s, rect, threshold, source, counts, nullptr, 0) ? Visibility::Visible
                                                                   : Visibility::Occluded;
}

bool OcclusionGrid::readsShow(const TileSpan& s, const PixelRect& rect, float threshold,
                              DepthSource& source, GridTestCounts& counts, const PixelRect* away,
                              std::size_t away_count) {
  // Steps 3 and 4: the tiles the records could not decide: internal ones refreshed
  // over the whole tile, border ones read over their intersection with the rectangle.
  for (const bool internal : kInternalFirst) {
    pending_.clear();
    forEachUndecided(s, internal, threshold, counts, [&](std::size_t i) {
      if (away_count > 0 && meetsAny(readArea(i, internal, rect), away, away_count)) {
        return false;
      }
      pending_.push_back(static_cast<std::uint32_t>(i));
      return false;
    });
    if (!pending_.empty() &&
        readPending(rect, threshold, internal, source, counts) == Visibility::Visible) {
      return true;
    }
  }
  return false;
}

bool OcclusionGrid::recordsShow(const TileSpan& s, float threshold, GridTestCounts& counts) const {
  // Steps 1 and 2 (§3): records of up-to-date tiles, internal ones first.
  for (const bool internal : kInternalFirst) {
    const bool shown = forEachTileOf(s, internal, [&](std::size_t i) {
      if (outdated_[i]) return false;
      const Decision d = decideFromRecord(i, internal, threshold);
      if (d == Decision::Undecided) return false;
      ++counts.tiles_tested;
      return d == Decision::Visible;
    });
    if (shown) return true;
  }
  return false;
}

template <typename Take>
bool OcclusionGrid::forEachUndecided(const TileSpan& s, bool internal, float threshold,
                                     GridTestCounts& counts, Take&& take) const {
  return forEachTileOf(s, internal, [&](std::size_t i) {
    if (!outdated_[i] && decideFromRecord(i, internal, threshold) != Decision::Undecided) {
      return false;  // decided in steps 1 and 2
    }
    if (tileHides(i, threshold)) {
      ++counts.tiles_tested;  // outdated, but its stale zfar (or hidden key) is in front
      return false;
    }
    return take(i);
  });
}

PixelRect OcclusionGrid::readArea(std::size_t index, bool whole, const PixelRect& rect) const {
  const PixelRect tile = tileRectOf(index);
  return whole ? tile : intersect(tile, rect);
}

PixelRect OcclusionGrid::tileRectOf(std::size_t index) const {
  return tileRect(static_cast<std::uint32_t>(index % tiles_x_),
                  static_cast<std::uint32_t>(index / tiles_x_));
}

Visibility OcclusionGrid::readPending(const PixelRect& rect, float threshold, bool internal,
                                      DepthSource& source, GridTestCounts& counts) {
  const DepthSourceTraits traits = source.traits();
  // A synchronous source answers one tile at a time so the test can stop at the first
  // visible one (§3); an asynchronous source gets every read of the step at once.
  const std::size_t step = traits.asynchronous ? pending_.size() : 1;
  for (std::size_t first = 0; first < pending_.size(); first += step) {
    const std::size_t n = std::min(step, pending_.size() - first);
    const std::uint32_t* tiles = pending_.data() + first;
    counts.tiles_tested += n;
    counts.tiles_read += n;
    const bool visible =
        internal && traits.reads_depth
            ? summarizeTiles(tiles, n, threshold, source)
            : countTiles(tiles, n, internal ? nullptr : &rect, threshold, source).shows;
    if (visible) return Visibility::Visible;
  }
  return Visibility::Occluded;
}

void OcclusionGrid::readTiles(const std::uint32_t* tiles, std::size_t n, const PixelRect* clip,
                              AreaAsk ask, float threshold, DepthSource& source) {
  requests_.clear();
  owners_.clear();
  for (std::size_t k = 0; k < n; ++k) {
    const PixelRect tile = tileRectOf(tiles[k]);
    appendRead(clip ? intersect(tile, *clip) : tile, ask, threshold, requests_);
    owners_.resize(requests_.size(), std::uint32_t(k));
  }
  answers_.resize(requests_.size());
  source.submit(requests_.data(), requests_.size(), answers_.data());
  source.collect();
}

bool OcclusionGrid::summarizeTiles(const std::uint32_t* tiles, std::size_t n, float threshold,
                                   DepthSource& source) {
  readTiles(tiles, n, nullptr, AreaAsk::Summary, threshold, source);
  bool shows = false;
  std::size_t r = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t first = r;
    while (r < requests_.size() && owners_[r] == k) ++r;
    std::uint32_t sampled = 0;
    const AreaDepth merged = mergeSummaries(requests_.data(), answers_.data(), first, r, sampled);
    applySummary(tiles[k], merged, sampled);
    shows |= !(far_[tiles[k]] < threshold);  // NaN shows
  }
  return shows;
}

OcclusionGrid::CountResult OcclusionGrid::countTiles(const std::uint32_t* tiles, std::size_t n,
                                                     const PixelRect* clip, float threshold,
                                                     DepthSource& source) {
  readTiles(tiles, n, clip, AreaAsk::Count, threshold, source);
  CountResult result;
  std::size_t r = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t first = r;
    while (r < requests_.size() && owners_[r] == k) ++r;
    std::uint32_t count = 0, sampled = 0;
    sumCounts(requests_.data(), answers_.data(), first, r, count, sampled);
    if (!clip) applyCount(tiles[k], count, sampled, threshold);
    result.shows |= countShows(count, sampled, threshold);
    result.pixels += std::uint64_t(count) * approx_.row_stride;
  }
  return result;
}

void OcclusionGrid::refreshNow(const PixelRect& rect, DepthSource& source) {
  const PixelRect r = intersect(rect, viewport());
  if (r.empty()) return;
  const TileSpan s = tileSpan(r);
  pending_.clear();
  forEachTile(s, [&](std::size_t i, bool) {
    // Full tiles stay full (LOG §5, BOG).
    if (!(far_[i] < clear_key_)) pending_.push_back(static_cast<std::uint32_t>(i));
    return false;
  });
  if (pending_.empty()) return;
  if (source.traits().reads_depth) {
    summarizeTiles(pending_.data(), pending_.size(), clear_key_, source);
  } else {
    // Free-pixel counts: exact states; for zfar a bound only when nothing is free.
    countTiles(pending_.data(), pending_.size(), nullptr, clear_key_, source);
  }
}

Visibility OcclusionGrid::testCounting(const PixelRect& rect, float threshold, DepthSource& source,
                                       GridTestCounts& counts) {
  const TileSpan s = tileSpan(rect);
  const std::uint64_t allowed = approx_.visible_pixels;
  std::uint64_t seen = 0;
  pending_.clear();
  const bool shown = forEachTile(s, [&](std::size_t i, bool) {
    if (tileHides(i, threshold)) {
      ++counts.tiles_tested;  // nothing of this tile shows
      return false;
    }
    if (!outdated_[i] && near_[i] >= threshold) {
      ++counts.tiles_tested;  // every pixel under the box shows
      seen += std::uint64_t(intersect(tileRectOf(i), rect).area());
      return seen > allowed;
    }
    pending_.push_back(static_cast<std::uint32_t>(i));
    return false;
  });
  if (shown) return Visibility::Visible;
  const std::size_t step = source.traits().asynchronous ? pending_.size() : 1;
  for (std::size_t first = 0; first < pending_.size(); first += step) {
    const std::size_t n = std::min(step, pending_.size() - first);
    counts.tiles_tested += n;
    counts.tiles_read += n;
    seen += countTiles(pending_.data() + first, n, &rect, threshold, source).pixels;
    if (seen > allowed) return Visibility::Visible;
  }
  return Visibility::Occluded;
}

// ---------------------------------------------------------------------------
// Decisions from the records alone
// ---------------------------------------------------------------------------

std::optional<Visibility> OcclusionGrid::decideFromRecords(const PixelRect& rect, float threshold,
                                                           GridTestCounts& counts,
                                                           std::vector<std::uint32_t>* undecided) {
  const TileSpan s = tileSpan(rect);
  if (recordsShow(s, threshold, counts)) return Visibility::Visible;
  // What steps 3 and 4 would read.
  bool open = false;
  for (const bool internal : kInternalFirst) {
    const bool stopped = forEachUndecided(s, internal, threshold, counts, [&](std::size_t i) {
      if (!undecided) return true;
      undecided->push_back(std::uint32_t(i) | (internal ? kInternalBit : 0u));
      open = true;
      return false;
    });
    if (stopped) return std::nullopt;
  }
  if (open) return std::nullopt;
  return Visibility::Occluded;
}

std::optional<Visibility> OcclusionGrid::decide(const PixelRect& rect, float threshold,
                                                GridTestCounts& counts, float hidden_threshold) {
  assert(insideViewport(rect) &&
         "OcclusionGrid::decide: rect must be non-empty and inside the viewport");
  hidden_threshold_ = hidden_threshold;
  test_rect_ = rect;
  return decideFromRecords(rect, threshold, counts, nullptr);
}

bool OcclusionGrid::readsUnder(const PixelRect& rect, float threshold,
                               const DepthSourceTraits& source, float hidden_threshold,
                               const PixelRect* undrawn, std::size_t count) {
  assert(insideViewport(rect) &&
         "OcclusionGrid::readsUnder: rect must be non-empty and inside the viewport");
  if (approx_.visible_pixels > 0) {
    // Counting tests read (parts of) any tile under the rectangle.
    const TileSpan s = tileSpan(rect);
    const PixelRect first = tileRect(s.x0, s.y0), last = tileRect(s.x1, s.y1);
    return meetsAny({first.x0, first.y0, last.x1, last.y1}, undrawn, count);
  }
  exact_records_ = source.reads_depth;
  hidden_threshold_ = hidden_threshold;
  test_rect_ = rect;
  undecided_.clear();
  GridTestCounts scratch;
  if (decideFromRecords(rect, threshold, scratch, &undecided_)) return false;
  for (const std::uint32_t packed : undecided_) {
    const PixelRect area = readArea(packed & ~kInternalBit, (packed & kInternalBit) != 0, rect);
    if (meetsAny(area, undrawn, count)) return true;
  }
  return false;
}

std::optional<Visibility> OcclusionGrid::testAwayFrom(const PixelRect& rect, float threshold,
                                                      DepthSource& source, GridTestCounts& counts,
                                                      float hidden_threshold,
                                                      const PixelRect* undrawn, std::size_t count) {
  assert(insideViewport(rect) &&
         "OcclusionGrid::testAwayFrom: rect must be non-empty and inside the viewport");
  if (approx_.visible_pixels > 0) return std::nullopt;
  exact_records_ = source.traits().reads_depth;
  hidden_threshold_ = hidden_threshold;
  test_rect_ = rect;
  const TileSpan s = tileSpan(rect);
  if (recordsShow(s, threshold, counts) ||
      readsShow(s, rect, threshold, source, counts, undrawn, count)) {
    return Visibility::Visible;
  }
  return std::nullopt;
}

bool OcclusionGrid::readsUnder(const GridBatch& batch, const PixelRect* undrawn,
                               std::size_t count) const {
  for (const AreaRequest& request : batch.requests_) {
    if (meetsAny(request.rect, undrawn, count)) return true;
  }
  return false;
}

// ---------------------------------------------------------------------------
// Batched tests
// ---------------------------------------------------------------------------

std::optional<Visibility> OcclusionGrid::plan(const PixelRect& rect, float threshold,
                                              const DepthSourceTraits& source, GridBatch* to,
                                              GridTestCounts& counts, float hidden_threshold) {
  assert(insideViewport(rect) &&
         "OcclusionGrid::plan: rect must be non-empty and inside the viewport");
  assert(approx_.visible_pixels == 0 && "OcclusionGrid::plan: counting tests are not batched");
  assert((!to || !to->submitted_) && "OcclusionGrid::plan: the batch was already submitted");
  exact_records_ = source.reads_depth;
  hidden_threshold_ = hidden_threshold;
  test_rect_ = rect;
  undecided_.clear();
  if (const auto decided = decideFromRecords(rect, threshold, counts, &undecided_)) {
    return decided;
  }
  if (!to) return std::nullopt;
  GridBatch& batch = *to;
  if (batch.empty()) {
    batch.reads_depth_ = source.reads_depth;
    batch.epoch_ = epoch_;
  }

  GridBatch::Test test{std::uint32_t(batch.test_reads_.size()), 0, threshold};
  const AreaAsk whole_ask = batch.reads_depth_ ? AreaAsk::Summary : AreaAsk::Count;
  for (std::uint32_t packed : undecided_) {
    const std::uint32_t tile = packed & ~kInternalBit;
    const bool whole = (packed & kInternalBit) != 0;
    ++counts.tiles_tested;
    if (whole && planned_[tile] != 0) {
      // Another test of the batch already reads this whole tile; a count is shared only
      // at the same threshold.
      const std::uint32_t shared = planned_[tile] - 1;
      if (whole_ask == AreaAsk::Summary || batch.reads_[shared].threshold == threshold) {
        batch.test_reads_.push_back(shared);
        ++test.reads;
        continue;
      }
    }
    const PixelRect area = readArea(tile, whole, rect);
    GridBatch::Read read{tile, whole, threshold, std::uint32_t(batch.requests_.size()), 0};
    appendRead(area, whole ? whole_ask : AreaAsk::Count, threshold, batch.requests_);
    read.count = std::uint32_t(batch.requests_.size()) - read.first;
    const std::uint32_t index = std::uint32_t(batch.reads_.size());
    batch.reads_.push_back(read);
    batch.test_reads_.push_back(index);
    ++test.reads;
    ++counts.tiles_read;
    if (whole) {
      if (planned_[tile] == 0) planned_tiles_.push_back(tile);
      planned_[tile] = index + 1;
    }
  }
  batch.tests_.push_back(test);
  return std::nullopt;
}

void OcclusionGrid::submit(GridBatch& batch, DepthSource& source) {
  assert(!batch.submitted_ && "OcclusionGrid::submit: the batch was already submitted");
  for (std::uint32_t t : planned_tiles_) planned_[t] = 0;
  planned_tiles_.clear();
  batch.answers_.assign(batch.requests_.size(), AreaAnswer{});
  batch.submitted_stamp_ = draw_stamp_;
  batch.submitted_ = true;
  if (!batch.requests_.empty()) {
    source.submit(batch.requests_.data(), batch.requests_.size(), batch.answers_.data());
  }
}

void OcclusionGrid::apply(GridBatch& batch) {
  assert(batch.submitted_ && "OcclusionGrid::apply: submit the batch first");
  if (batch.epoch_ != epoch_) return;  // the buffer was cleared since: resolve() says visible
  for (const GridBatch::Read& read : batch.reads_) {
    if (!read.whole) continue;
    const std::size_t first = read.first, end = read.first + read.count;
    if (batch.requests_[first].ask == AreaAsk::Summary) {
      std::uint32_t sampled = 0;
      applySummary(
          read.tile,
          mergeSummaries(batch.requests_.data(), batch.answers_.data(), first, end, sampled),
          sampled);
    } else {
      std::uint32_t count = 0, sampled = 0;
      sumCounts(batch.requests_.data(), batch.answers_.data(), first, end, count, sampled);
      applyCount(read.tile, count, sampled, read.threshold);
    }
    // Drawn over after the read was issued: the far bound holds, the rest does not.
    if (stamp_[read.tile] > batch.submitted_stamp_) outdated_[read.tile] = 1;
  }
}

Visibility OcclusionGrid::resolve(const GridBatch& batch, std::size_t index) const {
  if (!batch.submitted_ || batch.epoch_ != epoch_) return Visibility::Visible;
  const GridBatch::Test& test = batch.tests_[index];
  for (std::uint32_t k = 0; k < test.reads; ++k) {
    const GridBatch::Read& read = batch.reads_[batch.test_reads_[test.first_read + k]];
    bool shows;
    if (read.whole) {
      shows = !(far_[read.tile] < test.threshold);  // the record apply() refreshed; NaN shows
    } else {
      std::uint32_t count = 0, sampled = 0;
      sumCounts(batch.requests_.data(), batch.answers_.data(), read.first,
                std::size_t(read.first) + read.count, count, sampled);
      shows = countShows(count, sampled, test.threshold);
    }
    if (shows) return Visibility::Visible;
  }
  return Visibility::Occluded;
}

void OcclusionGrid::refreshOutdated(DepthSource& source, GridTestCounts& counts) {
  refreshMarked(source, counts, nullptr);
}

void OcclusionGrid::refreshOutdated(const PixelRect* rects, std::size_t count, DepthSource& source,
                                    GridTestCounts& counts) {
  wanted_.assign(outdated_.size(), 0);
  bool any = false;
  for (std::size_t k = 0; k < count; ++k) {
    const PixelRect r = intersect(rects[k], viewport());
    if (r.empty()) continue;
    const TileSpan s = tileSpan(r);
    for (std::uint32_t ty = s.y0; ty <= s.y1; ++ty) {
      const std::size_t row = std::size_t(ty) * tiles_x_;
      for (std::uint32_t tx = s.x0; tx <= s.x1; ++tx)
        any |= (wanted_[row + tx] = outdated_[row + tx]);
    }
  }
  if (any) refreshMarked(source, counts, wanted_.data());
}

void OcclusionGrid::refreshMarked(DepthSource& source, GridTestCounts& counts,
                                  const std::uint8_t* wanted) {
  refresh_.clear();
  exact_records_ = source.traits().reads_depth;
  refresh_.reads_depth_ = exact_records_;
  refresh_.epoch_ = epoch_;
  const AreaAsk ask = refresh_.reads_depth_ ? AreaAsk::Summary : AreaAsk::Count;
  for (std::size_t i = 0; i < outdated_.size(); ++i) {
    if (!outdated_[i] || (wanted && !wanted[i])) continue;
    GridBatch::Read read{std::uint32_t(i), true, clear_key_,
                         std::uint32_t(refresh_.requests_.size()), 0};
    appendRead(tileRectOf(i), ask, clear_key_, refresh_.requests_);
    read.count = std::uint32_t(refresh_.requests_.size()) - read.first;
    refresh_.reads_.push_back(read);
  }
  if (refresh_.reads_.empty()) return;
  counts.tiles_read += refresh_.reads_.size();
  submit(refresh_, source);
  source.collect();
  apply(refresh_);
}

}  // namespace logrid
