// log+hwq: the lazy occlusion grid as the pre-filter of hardware occlusion queries.
//
// Every box a query schedule would query is first put to the grid's records (LOG §3
// steps 1 and 2, with depth semantics as in §4, since the schedules draw what they find
// visible at once): a tile whose far key lies in front of the box's nearest key hides it,
// a tile all of whose pixels lie at or beyond it (a free tile) shows it, and the records
// read nothing to say so. Only the boxes the records cannot decide are queried, with the
// schedule CullerDesc::queries.schedule chooses.
//
// The records are refreshed lazily: the tiles under the boxes left undecided are read
// (through the application's DepthSource, in one batch) just before the schedule waits
// for a query answer. The renderer is flushed at that moment anyway, so on a tiler the
// reads add transfers, not stalls, and the boxes the traversal reaches after the wait find
// those tiles up to date. Internal to logrid::core.
#pragma once

#include <optional>
#include <vector>

#include "logrid/depth_source.hpp"
#include "logrid/grid.hpp"
#include "logrid/projection.hpp"
#include "testers.hpp"

namespace logrid::detail {

class GridPrefilter {
 public:
  GridPrefilter(BoxTester& grid, GridTestCounts& counts) : grid_(grid), counts_(counts) {}

  // What the records decide for a box that projects Inside; nothing if a query must.
  std::optional<Visibility> decide(const BoxProjection& p);
  // Reads the outdated tiles under the boxes left undecided since the last refresh.
  void refresh();

 private:
  BoxTester& grid_;
  GridTestCounts& counts_;
  std::vector<PixelRect> wanted_;
};

}  // namespace logrid::detail
