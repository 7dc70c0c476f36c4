// A hierarchical z-buffer (Greene, Kass and Miller 1993) kept on the CPU: the HZB
// comparison method of LOG §5. Level 0 is a copy of the depth buffer's keys; each
// level above holds the farthest key of the 2x2 cells below it. After each draw the
// drawn box's rectangle is read back and propagated up (busy, not lazy: that is the
// point of the comparison). Tests read nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/depth_source.hpp"
#include "logrid/types.hpp"

namespace logrid {

class DepthPyramid {
 public:
  DepthPyramid(std::uint32_t width, std::uint32_t height);

  std::uint32_t levels() const { return static_cast<std::uint32_t>(levels_.size()); }

  // The depth buffer was just cleared to `clear_key`.
  void reset(float clear_key);

  // Reads `rect` (clipped to the viewport) from `source` into level 0 and updates the
  // levels above.
  void update(const PixelRect& rect, KeyReader& source);

  // Is any pixel of `rect` at or beyond `threshold`? Descends from the coarsest level
  // whose cells the rectangle spans at most 2x2 of, into cells that cannot decide.
  // `cells_tested` counts the cells examined.
  Visibility test(const PixelRect& rect, float threshold, std::uint64_t& cells_tested) const;

 private:
  struct Level {
    std::uint32_t width;
    std::uint32_t height;
    std::vector<float> keys;
  };
  std::vector<Level> levels_;
  mutable std::vector<std::uint64_t> work_;
  std::vector<float> scratch_;
};

}  // namespace logrid
