// Scalar kernels that turn depth values in their native storage type into the answers
// of a DepthSource. Shared by every source that reads pixels (logrid::PixelSource of
// pixel_source.hpp and its subclasses in cpu/, zread/ and applications) so that all of
// them round the same way: min keys down, max keys up, and threshold counts towards "not
// occluded".
#pragma once

#include <cstddef>
#include <cstdint>

#include "logrid/depth_source.hpp"
#include "logrid/types.hpp"

namespace logrid {

// How depth values are stored in the array a kernel scans.
enum class NativeDepth : std::uint8_t {
  Float32,  // window depth as float (D32F read as GL_FLOAT, software buffers)
  Unorm16,  // D16 read as GL_UNSIGNED_SHORT: depth = v / 65535
  Unorm32,  // D24 read as GL_UNSIGNED_INT:   depth = v / 4294967295
};

inline std::size_t nativeDepthBytes(NativeDepth n) { return n == NativeDepth::Unorm16 ? 2 : 4; }

// Describes a buffer: its native type and the depth convention. The convention also
// fixes the stored value of a cleared pixel, which AreaDepth::free_pixels counts: 1 (the
// largest value) for standard, 0 for reversed.
struct DepthEncoding {
  NativeDepth native = NativeDepth::Float32;
  DepthConvention convention = DepthConvention::Standard;
};

// Summarizes the width x height values at `data` (rows of `width` values, the start of
// each row `stride` values after the previous one's): the nearest and farthest key,
// rounded outwards, and the number of cleared values.
AreaDepth summarizeDepth(const DepthEncoding& enc, const void* data, std::int32_t width,
                         std::int32_t height, std::size_t stride);

// Counts the width x height values at `data` (laid out as above) whose key is >=
// threshold; NaN values count.
std::uint32_t countDepthAtOrBeyond(const DepthEncoding& enc, const void* data, std::int32_t width,
                                   std::int32_t height, std::size_t stride, float threshold);

// Converts one native value to a key (exact for Float32 and Unorm16; rounded to the
// nearest float for Unorm32, an error the depth margin covers).
float nativeToKey(const DepthEncoding& enc, const void* value);

}  // namespace logrid
