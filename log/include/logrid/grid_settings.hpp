// The lazy occlusion grid's settings, as CullerDesc and MethodInfo name them: its
// variant and the knobs that trade accuracy for speed. The grid itself (grid.hpp) is the
// culler's internal; an integrating application needs only these.
#pragma once

#include <cstdint>

namespace logrid {

enum class GridVariant : std::uint8_t {
  OcclusionState,  // free / partial / full per tile (§3)
  Zfar,            // farthest depth per tile (§4)
};

const char* toString(GridVariant);

// Settings that trade accuracy for speed. All off by default; with any of them on the
// grid is no longer conservative (a box with a few visible pixels may be culled).
// culler.hpp (CullerDesc::approximation) documents what each gives up.
struct GridApproximation {
  // A test answers occluded when at most this many pixels of the box's rectangle are
  // at or beyond the threshold (0: exact). Such counting tests are never batched.
  std::uint32_t visible_pixels = 0;
  // Occlusion-state variant: a tile, or the part of a border tile under a box, counts
  // as full when at most this fraction of its (sampled) pixels are free (0: exact).
  float full_free_fraction = 0;
  // Reads sample every k-th pixel row of a tile or area, starting with its first row
  // (1: every row). Counts are scaled back by k.
  std::uint32_t row_stride = 1;

  bool exact() const { return visible_pixels == 0 && full_free_fraction == 0 && row_stride == 1; }
};

}  // namespace logrid
