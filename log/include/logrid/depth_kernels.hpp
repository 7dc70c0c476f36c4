// Scalar kernels that turn depth values in their native storage type into the answers
// of a DepthSource. Shared by every source that reads pixels (zread/) so that all of
// them round the same way: min keys down, max keys up, and threshold counts towards
// "not occluded".
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

// Describes a buffer: its native type, the depth convention, and the stored value of a
// cleared pixel (1 for standard, 0 for reversed).
struct DepthEncoding {
  NativeDepth native = NativeDepth::Float32;
  DepthConvention convention = DepthConvention::Standard;
};

// Summarizes `count` values at `data` (rows of `width` values, `stride` values apart).
AreaDepth summarizeDepth(const DepthEncoding& enc, const void* data, std::int32_t width,
                         std::int32_t height, std::size_t stride);

// Counts the values whose key is >= threshold.
std::uint32_t countDepthAtOrBeyond(const DepthEncoding& enc, const void* data, std::int32_t width,
                                   std::int32_t height, std::size_t stride, float threshold);

// Converts one native value to a key (exact for Float32 and Unorm16; rounded to the
// nearest float for Unorm32, an error the depth margin covers).
float nativeToKey(const DepthEncoding& enc, const void* value);

}  // namespace logrid
