// The lazy occlusion grid (LOG §1, §3, §4): a low-resolution grid of tiles over the
// depth buffer, each with an occlusion record that is refreshed only when a test needs
// it and something was drawn over it since.
//
// Each tile keeps two depth keys and a flag:
//   far_key   an upper bound of the keys of the tile's pixels ("zfar" of §4),
//   near_key  a lower bound of them, valid only while the tile is up to date,
//   outdated  set when something is drawn over the tile, cleared when it is read.
// The occlusion-state variant (§3) reads them as states: free (near_key == clear key),
// full (far_key < clear key), partial otherwise.
//
// Within a frame the application only draws with a depth test that keeps the nearer
// fragment, so a pixel's key never grows. far_key therefore stays an upper bound after
// later draws, and a tile that was full (or whose zfar was in front of a box) stays so
// without being read again: an outdated tile is read only when its stale far_key can
// no longer decide the test. Clearing the depth buffer mid-frame breaks this: call
// fill() with the cleared value after any clear (Culler::noteDepthCleared does).
//
// A test asks whether any pixel of a rectangle has a key >= a threshold:
//   occlusion-state semantics:  threshold = the clear key (a pixel is free), valid only
//                               while everything drawn lies in front of the box (the
//                               two-list order of culler.hpp guarantees it);
//   depth semantics (zfar):     threshold = the box's nearest key minus its margin
//                               (BoxProjection::occlusionThreshold()), valid in any
//                               order. Either variant answers either kind of test.
// The tiles under the rectangle are asked in the order of §3:
//   1. up-to-date internal tiles (decided from the record),
//   2. up-to-date border tiles (decided from the record when free or full),
//   3. the remaining internal tiles: refreshed with a read of the whole tile,
//   4. the remaining border tiles: a read of their intersection with the rectangle.
// test() asks the source one tile at a time and stops at the first tile where the box
// may show (the paper's order, for a synchronous source). The batched form — plan() for
// many tests, one submit() and collect(), apply(), resolve() — reads every tile that
// steps 1 and 2 left undecided, for every test of the batch at once (the lookahead of
// culler.hpp): more pixels, far fewer waits for the renderer. Both give the same
// answer for a test against the same depth buffer.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "logrid/coverage.hpp"
#include "logrid/depth_source.hpp"
#include "logrid/error.hpp"
#include "logrid/grid_settings.hpp"
#include "logrid/stats.hpp"
#include "logrid/types.hpp"

namespace logrid {

struct GridDesc {
  std::uint32_t width = 0;  // viewport in pixels, >= 1
  std::uint32_t height = 0;
  std::uint32_t tile_size = 32;  // tile side in pixels, >= 1 (may exceed the viewport)
  GridVariant variant = GridVariant::OcclusionState;
};

// The most tiles a grid may have (about 60 bytes each with the scratch of a test):
// 2^24, e.g. an 8192x8192 viewport with 2-pixel tiles.
inline constexpr std::uint64_t kMaxGridTiles = std::uint64_t{1} << 24;

// Returns an empty string if the descriptor is usable, else a message naming the field.
std::string validateGridDesc(const GridDesc& desc, const GridApproximation& approximation = {});

struct TileRecord {
  float near_key = 0;
  float far_key = 0;
  bool outdated = false;
  float hidden_key = 0;  // OcclusionGrid::recordCovered(); the clear key where none
};

class OcclusionGrid;

// The reads of several tests, submitted to a depth source together. Filled by
// OcclusionGrid::plan(); submitted by OcclusionGrid::submit(); after the source's
// collect(), OcclusionGrid::apply() updates the records and resolve() answers each test.
class GridBatch {
 public:
  std::size_t tests() const { return tests_.size(); }
  bool empty() const { return tests_.empty(); }
  std::size_t requests() const { return requests_.size(); }
  void clear();

 private:
  friend class OcclusionGrid;
  struct Read {
    std::uint32_t tile;
    bool whole;           // a whole-tile refresh (updates the record), else an intersection
    float threshold;      // Count reads
    std::uint32_t first;  // first request (a read of a sampled tile spans several rows)
    std::uint32_t count;
  };
  struct Test {
    std::uint32_t first_read;  // into test_reads_
    std::uint32_t reads;
    float threshold;
  };
  bool reads_depth_ = true;  // the source answers Summary requests
  bool submitted_ = false;
  std::uint64_t submitted_stamp_ = 0;  // the grid's draw stamp when submitted
  std::uint64_t epoch_ = 0;            // the grid's fill epoch when planned
  std::vector<AreaRequest> requests_;
  std::vector<AreaAnswer> answers_;
  std::vector<Read> reads_;
  std::vector<Test> tests_;
  std::vector<std::uint32_t> test_reads_;
};

class OcclusionGrid {
 public:
  // The hidden threshold of a test that no hidden key decides (test(), recordCovered()).
  static constexpr float kNoHiddenThreshold = -std::numeric_limits<float>::infinity();

  // The result form (error.hpp): the grid, or validateGridDesc()'s problem
  // (ErrorCode::InvalidArgument).
  static Result<OcclusionGrid> create(const GridDesc& desc,
                                      const GridApproximation& approximation = {});
  // The throwing form: throws logrid::Error where create() fails.
  explicit OcclusionGrid(const GridDesc& desc, const GridApproximation& approximation = {});

  const GridDesc& desc() const { return desc_; }
  const GridApproximation& approximation() const { return approx_; }
  std::uint32_t tilesX() const { return tiles_x_; }
  std::uint32_t tilesY() const { return tiles_y_; }
  PixelRect tileRect(std::uint32_t tx, std::uint32_t ty) const;
  TileRecord tile(std::uint32_t tx, std::uint32_t ty) const;

  // The depth buffer was just cleared to `clear_key`: every tile is free and up to date.
  // Starts a frame.
  void reset(float clear_key);
  // The depth buffer was cleared mid-frame to `key` (the clear key, or a nearer value):
  // every tile holds exactly `key` and is up to date. Batches planned before are void.
  void fill(float key);

  // Something was drawn over `rect`: its tiles become outdated. Reads nothing.
  void markOutdated(const PixelRect& rect);
  // A convex quad whose coverage the CPU knows (coverage.hpp): GL draws it, or it is a
  // valid occluder (occluder_source.hpp) that the frame's own geometry covers, at or in
  // front of its keys, wherever GL would draw it. Every cell of the hidden grid (a
  // quarter of a tile a side, hiddenCell()) that it covers entirely by `rule` gets
  // quad.far_key as its hidden key (where that is nearer than the cell's): a box whose
  // hidden threshold (test(), plan(), decide()) lies beyond the hidden keys of every
  // cell its rectangle meets in a tile is hidden there, whatever the test's own
  // threshold, without a read. Cells covered by different quads count alike, so a tile
  // may be hidden by several. Nothing else of the record changes: the quad is no draw
  // (a drawn one is announced with markOutdated()). Returns the tiles this quad leaves
  // hidden as a whole where they were not, or hidden nearer.
  std::uint32_t hiddenCell() const { return cell_; }
  std::uint32_t recordCovered(const DrawnQuad& quad, const CoverageRule& rule);
  // The hidden key of the cell that holds pixel (x, y) (inside the viewport).
  float hiddenAt(std::uint32_t x, std::uint32_t y) const;
  // Every outdated tile, refreshed with one batch of whole-tile reads (submit and
  // collect). Used after drawing a known-visible set first (temporal coherence).
  void refreshOutdated(DepthSource& source, GridTestCounts& counts);
  // The same for the outdated tiles that touch any of `rects` (clipped to the viewport).
  void refreshOutdated(const PixelRect* rects, std::size_t count, DepthSource& source,
                       GridTestCounts& counts);

  // Busy update (the paper's BOG): reads at once every tile under `rect` that is not
  // full, and leaves them up to date.
  void refreshNow(const PixelRect& rect, DepthSource& source);

  // Is any pixel of `rect` at or beyond `threshold`? Returns Visible at the first tile
  // that may show the box, Occluded if none does. `rect` must be non-empty and inside
  // the viewport. Reads only outdated or undecided tiles, in the order described above.
  // A tile whose hidden key (recordCovered()) lies in front of `hidden_threshold` (the
  // box's depth threshold, BoxProjection::occlusionThreshold()) hides the box there
  // without a read; the default decides nothing so.
  Visibility test(const PixelRect& rect, float threshold, DepthSource& source,
                  GridTestCounts& counts, float hidden_threshold = kNoHiddenThreshold);

  // What the records alone decide (steps 1 and 2, and outdated tiles whose stale far key
  // is still in front of the threshold): Visible or Occluded, or nothing where a tile
  // would have to be read. Reads nothing; the grid as a pre-filter of hardware queries
  // (log+hwq).
  std::optional<Visibility> decide(const PixelRect& rect, float threshold, GridTestCounts& counts,
                                   float hidden_threshold = kNoHiddenThreshold);

  // Would test() of `rect` read pixels that any of `undrawn` (`count` rectangles of
  // what is to be drawn but is not drawn yet) may cover? What the records decide reads
  // nothing; an undecided internal tile is read whole, a border tile where it meets
  // `rect`. Where it would not, the test may read before they are drawn: what it reads
  // is what it would read after. Counts nothing.
  bool readsUnder(const PixelRect& rect, float threshold, const DepthSourceTraits& source,
                  float hidden_threshold, const PixelRect* undrawn, std::size_t count);
  // The same for the reads of a planned batch (plan()).
  bool readsUnder(const GridBatch& batch, const PixelRect* undrawn, std::size_t count) const;
  // test() over the tiles whose reads meet none of `undrawn`: Visible where one of them
  // shows the box; nothing otherwise (the other tiles wait for `undrawn` to be drawn, and
  // a border tile read here is read again then). Nothing for counting tests.
  std::optional<Visibility> testAwayFrom(const PixelRect& rect, float threshold,
                                         DepthSource& source, GridTestCounts& counts,
                                         float hidden_threshold, const PixelRect* undrawn,
                                         std::size_t count);

  // Batched tests. plan() decides from the records what they can (Visible or Occluded,
  // returned at once), and otherwise adds the test to `batch` with the reads that decide
  // it (whole outdated internal tiles, shared between tests; intersections of border
  // tiles) and returns nothing; with no batch it only returns nothing. Not for counting
  // tests (approximation.visible_pixels).
  std::optional<Visibility> plan(const PixelRect& rect, float threshold,
                                 const DepthSourceTraits& source, GridBatch* batch,
                                 GridTestCounts& counts,
                                 float hidden_threshold = kNoHiddenThreshold);
  // Submits the batch's reads to the source (the caller then calls source.collect()).
  void submit(GridBatch& batch, DepthSource& source);
  // After collect(): refreshes the records of the whole tiles read. A tile drawn over
  // after the batch was submitted keeps its new far bound but stays outdated.
  void apply(GridBatch& batch);
  // The answer of test `index` (in plan() order) of an applied batch.
  // (Counts nothing: plan() counted the tiles the test reads.)
  Visibility resolve(const GridBatch& batch, std::size_t index) const;

 private:
  struct Checked {};  // the desc and approximation were validated
  OcclusionGrid(Checked, const GridDesc& desc, const GridApproximation& approximation);

  enum class Decision : std::uint8_t { Occluded, Visible, Undecided };
  Decision decideFromRecord(std::size_t index, bool internal, float threshold) const;
  // Is the tile in front of the test, by its far key (a bound even while outdated: keys
  // only shrink within a frame), or by the hidden keys of its cells under the test's
  // rectangle?
  bool tileHides(std::size_t index, float threshold) const {
    return far_[index] < threshold || hidden_[index] < hidden_threshold_ ||
           (hidden_some_[index] && hiddenUnder(index) < hidden_threshold_);
  }
  // The largest hidden key of the tile's cells that meet test_rect_.
  float hiddenUnder(std::size_t index) const;
  // The largest hidden key of the tile's cells.
  float hiddenOfTile(std::size_t index) const;
  // The largest hidden key of the cells `r` meets, or the first one found not below
  // `enough` (the answer is then only known to be at least that).
  float largestHidden(const PixelRect& r, float enough) const;
  // The tiles a pixel rectangle touches, and the internal ones (inside it whole).
  struct TileSpan;
  TileSpan tileSpan(const PixelRect& rect) const;
  // The span's tiles row by row as visit(index, internal), or those of one class as
  // visit(index); stops at the first visit that returns true, and then returns true.
  template <typename Visit>
  bool forEachTile(const TileSpan& span, Visit&& visit) const;
  template <typename Visit>
  bool forEachTileOf(const TileSpan& span, bool internal, Visit&& visit) const;
  // Steps 1 and 2 (§3): true at the first up-to-date tile whose record shows the box.
  bool recordsShow(const TileSpan& span, float threshold, GridTestCounts& counts) const;
  // Steps 3 and 4 (test()) over the undecided tiles whose reads meet none of `away`
  // (`away_count` rectangles): true at the first read that shows the box.
  bool readsShow(const TileSpan& span, const PixelRect& rect, float threshold, DepthSource& source,
                 GridTestCounts& counts, const PixelRect* away, std::size_t away_count);
  // The tiles of one class that only a read can decide, as take(index) (stopping as
  // forEachTile does); outdated tiles whose stale far key is in front count as tested.
  template <typename Take>
  bool forEachUndecided(const TileSpan& span, bool internal, float threshold,
                        GridTestCounts& counts, Take&& take) const;
  PixelRect viewport() const;
  bool insideViewport(const PixelRect& rect) const;
  // Steps 1 and 2 and the stale-far rule over the tiles of `rect`: Visible at the first
  // tile that shows the box; Occluded if every tile hides it; otherwise nothing, after
  // collecting the tiles a read must decide into *undecided (packed with kInternalBit),
  // or at the first such tile when undecided is null.
  std::optional<Visibility> decideFromRecords(const PixelRect& rect, float threshold,
                                              GridTestCounts& counts,
                                              std::vector<std::uint32_t>* undecided);
  void refreshMarked(DepthSource& source, GridTestCounts& counts, const std::uint8_t* wanted);
  void applySummary(std::size_t index, const AreaDepth& area, std::uint32_t sampled);
  void applyCount(std::size_t index, std::uint32_t count, std::uint32_t sampled, float threshold);
  // Appends the requests of a read of `area` (the area itself, or every row_stride-th
  // row of it) to `requests`.
  void appendRead(const PixelRect& area, AreaAsk ask, float threshold,
                  std::vector<AreaRequest>& requests) const;
  PixelRect tileRectOf(std::size_t index) const;
  // What a test of `rect` reads of tile `index`: all of it (an internal tile refreshed
  // whole), else its part inside `rect`.
  PixelRect readArea(std::size_t index, bool whole, const PixelRect& rect) const;
  // Is a counted area (count of `sampled` pixels at or beyond the threshold) visible?
  bool countShows(std::uint32_t count, std::uint32_t sampled, float threshold) const;
  // The counting test used when approximation.visible_pixels > 0.
  Visibility testCounting(const PixelRect& rect, float threshold, DepthSource& source,
                          GridTestCounts& counts);
  // Reads the tiles in pending_ (whole tiles if internal, else their intersection with
  // rect) and returns Visible as soon as one shows pixels at or beyond threshold.
  Visibility readPending(const PixelRect& rect, float threshold, bool internal, DepthSource& source,
                         GridTestCounts& counts);
  // Submits one request per tile (whole, or clipped to *clip) and collects the answers
  // into answers_ (owners_ maps each request to its tile in `tiles`).
  void readTiles(const std::uint32_t* tiles, std::size_t n, const PixelRect* clip, AreaAsk ask,
                 float threshold, DepthSource& source);
  // Summarises whole tiles and refreshes their records; true if any shows pixels at or
  // beyond threshold.
  bool summarizeTiles(const std::uint32_t* tiles, std::size_t n, float threshold,
                      DepthSource& source);
  // Counts pixels at or beyond threshold in each tile (clipped to *clip when given;
  // whole tiles also refresh their records). Returns the estimated pixel total.
  struct CountResult {
    bool shows = false;        // some tile shows the box
    std::uint64_t pixels = 0;  // pixels at or beyond threshold, scaled by the row stride
  };
  CountResult countTiles(const std::uint32_t* tiles, std::size_t n, const PixelRect* clip,
                         float threshold, DepthSource& source);

  GridDesc desc_;
  GridApproximation approx_;
  std::uint32_t tiles_x_ = 0;
  std::uint32_t tiles_y_ = 0;
  float clear_key_ = 1.0f;
  bool exact_records_ = true;  // records hold exact min/max (set per test from the source)
  float hidden_threshold_ = kNoHiddenThreshold;  // the test's (set per test)
  PixelRect test_rect_;                          // the test's rectangle (set per test)
  std::vector<float> near_;
  std::vector<float> far_;
  std::vector<std::uint8_t> outdated_;
  // Per cell of cell_ pixels a side, a key behind which everything is hidden by what the
  // frame draws (recordCovered()); the clear key where nothing is known. Per tile, the
  // largest of its cells' and whether any of its cells is hidden. Not a record of the
  // depth buffer: reads neither set nor need it, draws leave it.
  std::uint32_t cell_ = 1;
  std::uint32_t cells_x_ = 0;
  std::uint32_t cells_y_ = 0;
  std::vector<float> cell_hidden_;
  std::vector<float> hidden_;
  std::vector<std::uint8_t> hidden_some_;
  // Draw stamps: stamp_[tile] is the value of draw_stamp_ when the tile was last drawn
  // over, so that a batch's answers do not mark a tile drawn over since as up to date.
  std::vector<std::uint64_t> stamp_;
  std::uint64_t draw_stamp_ = 0;
  std::uint64_t epoch_ = 0;  // advanced by fill(): batches of an earlier epoch are void
  // While planning a batch: per tile, 1 + the index of its whole-tile read (0: none).
  std::vector<std::uint32_t> planned_;
  std::vector<std::uint32_t> planned_tiles_;

  // Scratch reused across tests so that a test never allocates once warmed up.
  std::vector<std::uint32_t> pending_;
  std::vector<AreaRequest> requests_;
  std::vector<std::uint32_t> owners_;  // per entry of requests_: index into pending_
  std::vector<AreaAnswer> answers_;
  std::vector<std::uint32_t> undecided_;  // plan(): tiles steps 1 and 2 left open
  std::vector<std::uint8_t> wanted_;      // refreshOutdated(rects): tiles under the rects
  GridBatch refresh_;                     // refreshOutdated()
};

#if LOGRID_HAS_EXCEPTIONS
inline OcclusionGrid::OcclusionGrid(const GridDesc& desc, const GridApproximation& approximation)
    : OcclusionGrid(orThrow(create(desc, approximation))) {}
#endif

}  // namespace logrid
