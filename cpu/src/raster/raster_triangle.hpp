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
  // 1 / ea[k] (0 where ea[k] is 0), for the span of a row that can hold candidates.
  float inv_ea[kTriangleEdges] = {};
  float band_key[3] = {};                       // added to samples in the band of edge k
  std::uint32_t nb[3] = {0, 0, 0};              // neighbour across edge k (index into the frame's
                                                // triangles), valid where interior bit k is set
  std::uint8_t nb_edge[3] = {0, 0, 0};          // the neighbour's edge shared with this one
  std::uint8_t interior = 0;                    // bit k: edge k has a neighbour
  std::int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // buffer pixels the triangle may claim
};

// A tile of the buffer being rasterised: buffer pixels [x0, x1) x [y0, y1); x0 is a
// multiple of 8 and rows are padded to a multiple of 8 floats, so 8-wide stores stay
// inside the row. Buffer pixel (i, j) samples the viewport at (scale i + half, ...).
struct RasterTarget {
  float* keys = nullptr;
  std::size_t stride = 0;
  std::int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  float scale = 1;  // viewport pixels per buffer pixel
  float half = 0.5f;
  // In: an upper bound of every key in the tile; out: a (possibly smaller) one after.
  float max_key = 0;
};

// Rasterises the triangles tris[list[0..n)] into the target (key = min(key, bound)).
using RasterFunction = void (*)(const RasterTriangle* tris, const std::uint32_t* list,
                                std::size_t n, RasterTarget& target);

// The kernel of an ISA (not Auto); nullptr if this build or CPU lacks it.
RasterFunction rasterFunction(Isa isa);
Isa bestIsa();

void rasterScalar(const RasterTriangle*, const std::uint32_t*, std::size_t, RasterTarget&);
void rasterSse41(const RasterTriangle*, const std::uint32_t*, std::size_t, RasterTarget&);
void rasterAvx2(const RasterTriangle*, const std::uint32_t*, std::size_t, RasterTarget&);

}  // namespace logrid::cpu::detail
