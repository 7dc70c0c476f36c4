// Internal to logrid::cpu: one triangle as the raster kernels read it, set up by
// triangle_setup.cpp. All edge functions are normalised so that |a| + |b| = 1: an edge
// value is the signed max-norm distance (viewport pixels) of a point from the edge's
// line, positive inside. Values are stored relative to a reference point (rx, ry), the
// corner of the triangle's pixel bounds, so that float keeps them exact enough.
#pragma once

#include <cstddef>
#include <cstdint>

#include "logrid/cpu/occlusion_buffer.hpp"

namespace logrid::cpu::detail {

inline constexpr int kTriangleEdges = 4;  // three edges and the near-plane clip line

struct RasterTriangle {
  float rx = 0, ry = 0;  // reference point, viewport pixels
  // Edge k at the reference: E(x, y) = ea (x - rx) + eb (y - ry) + ec. Edge k < 3 is
  // opposite corner k; edge 3 is the near-plane clip line (0, 0, 1 when unclipped).
  float ea[kTriangleEdges] = {}, eb[kTriangleEdges] = {}, ec[kTriangleEdges] = {};
  // A sample is a candidate when E > lo on every edge, and covered by this triangle
  // alone when E > hi on every edge. lo < hi only on edges shared with a neighbour;
  // candidates within hi of such an edge need the neighbour's other edges to pass.
  float lo[kTriangleEdges] = {}, hi[kTriangleEdges] = {};
  // The key bound at the reference (plane plus this triangle's own slack and margins).
  float za = 0, zb = 0, zc = 0;
  // No sample of the triangle gets a key below this: a tile whose keys are all at or
  // in front of it cannot change.
  float zmin = 0;
  // Rounding allowance of the kernels' block classification (raster_kernel.inl).
  float block_tol = 0;
  float band_key[3] = {};                       // added to samples in the band of edge k
  std::uint32_t nb[3] = {0, 0, 0};              // neighbour across edge k (index into the frame's
                                                // triangles), valid where interior bit k is set
  std::uint8_t nb_edge[3] = {0, 0, 0};          // the neighbour's edge shared with this one
  std::uint8_t interior = 0;                    // bit k: edge k has a neighbour
  std::int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // buffer pixels the triangle may claim
};

inline constexpr int kBlockSide = 8;  // the kernels' blocks, buffer pixels

// A tile of the buffer being rasterised: buffer pixels [x0, x1) x [y0, y1); x0 is a
// multiple of 8 and rows are padded to a multiple of 8 floats, so 8-wide stores stay
// inside the row. Buffer pixel (i, j) samples the viewport at (scale i + half, ...).
struct RasterTarget {
  float* keys = nullptr;
  std::size_t stride = 0;
  std::int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  float scale = 1;  // viewport pixels per buffer pixel
  float half = 0.5f;
  // Per block of 8 x 8 buffer pixels of the tile (row by row): an upper bound of its
  // keys, kept up to date by the kernel.
  float* block_max = nullptr;
};

// Rasterises the triangles tris[list[0..n)] into the target (key = min(key, bound)).
using RasterFunction = void (*)(const RasterTriangle* tris, const std::uint32_t* list,
                                std::size_t n, RasterTarget& target);

// The masked representation: blocks of kMaskW x kMaskH buffer pixels (bit y * kMaskW + x
// of the mask is pixel (x, y) of the block). A pixel's key is z_layer where its mask bit
// is set and z_far elsewhere; z_layer <= z_far whenever the mask has a bit set.
inline constexpr int kMaskW = 8, kMaskH = 4;
struct MaskedBlock {
  std::uint32_t mask = 0;
  float z_layer = 0;
  float z_far = 0;
};
struct MaskedTarget {
  RasterTarget tile;  // the tile's pixels, sampling (keys and block_max are unused)
  MaskedBlock* blocks = nullptr;
  std::size_t blocks_per_row = 0;
  bool unsafe_merge = false;  // test aid (OcclusionBufferDesc::unsafe_masked_merge)
};
using MaskedFunction = void (*)(const RasterTriangle* tris, const std::uint32_t* list,
                                std::size_t n, MaskedTarget& target);

// Over buffer pixels [x0, x1) x [y0, y1) of `keys` (rows `stride` floats apart): the
// nearest and farthest key and how many keys are not below `threshold`.
struct KeyRange {
  float min_key = 0;
  float max_key = 0;
  std::uint32_t at_or_beyond = 0;
};
using RangeFunction = KeyRange (*)(const float* keys, std::size_t stride, std::int32_t x0,
                                   std::int32_t y0, std::int32_t x1, std::int32_t y1,
                                   float threshold);

struct Kernels {
  RasterFunction raster = nullptr;
  RangeFunction range = nullptr;
  MaskedFunction masked = nullptr;
};

// The kernels of an ISA (not Auto); null functions if this build or CPU lacks it.
Kernels kernels(Isa isa);
Isa bestIsa();

void rasterScalar(const RasterTriangle*, const std::uint32_t*, std::size_t, RasterTarget&);
void rasterSse41(const RasterTriangle*, const std::uint32_t*, std::size_t, RasterTarget&);
void rasterAvx2(const RasterTriangle*, const std::uint32_t*, std::size_t, RasterTarget&);
void maskedScalar(const RasterTriangle*, const std::uint32_t*, std::size_t, MaskedTarget&);
void maskedSse41(const RasterTriangle*, const std::uint32_t*, std::size_t, MaskedTarget&);
void maskedAvx2(const RasterTriangle*, const std::uint32_t*, std::size_t, MaskedTarget&);
KeyRange rangeScalar(const float*, std::size_t, std::int32_t, std::int32_t, std::int32_t,
                     std::int32_t, float);
KeyRange rangeSse41(const float*, std::size_t, std::int32_t, std::int32_t, std::int32_t,
                    std::int32_t, float);
KeyRange rangeAvx2(const float*, std::size_t, std::int32_t, std::int32_t, std::int32_t,
                   std::int32_t, float);

}  // namespace logrid::cpu::detail
