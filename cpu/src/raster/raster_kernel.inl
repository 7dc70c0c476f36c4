// Internal to logrid::cpu: the raster kernel, written once over a lane type L and
// compiled once per ISA (raster_scalar.cpp, raster_sse41.cpp, raster_avx2.cpp), each
// time inside that file's anonymous namespace. Every variant performs the same float
// operations in the same order (no FMA contraction: -ffp-contract=off), so they write
// bit-identical buffers; tests/unit/occlusion_buffer_test.cpp checks it.
//
// Deliberately free of standard-library templates: an inline function instantiated in
// an AVX2 file could be picked by the linker for callers compiled without AVX2.
//
// L provides: kWidth, F (kWidth floats), M (kWidth booleans), set1, iota (0, 1, ...),
// add, mul, gt, le, and_, or_, andNot (a & ~b), any, select (m ? a : b), min (a < b ? a :
// b), max (a > b ? a : b), load, store, inRange (lane x + l in [lo, hi)), bits (lane l's
// boolean as bit l).

inline int clampMax(int a, int b) { return a > b ? a : b; }
inline int clampMin(int a, int b) { return a < b ? a : b; }

inline float clampf(float v, float lo, float hi) { return v < lo ? lo : v > hi ? hi : v; }

// The largest key of a block of the tile (only its own columns: the row padding stays
// clear).
template <class L>
float blockMax(const RasterTarget& tg, int xa, int xb, int ya, int yb) {
  constexpr int kW = L::kWidth;
  typename L::F m = L::set1(-HUGE_VALF);
  for (int y = ya; y < yb; ++y) {
    const float* row = tg.keys + std::size_t(y) * tg.stride;
    for (int x = tg.x0 + ((xa - tg.x0) / kW) * kW; x < xb; x += kW) {
      m = L::max(m, L::select(L::inRange(x, xa, xb), L::load(row + x), L::set1(-HUGE_VALF)));
    }
  }
  return L::hmax(m);
}

// Forced inlining for the per-row fast path below (the compilers otherwise call it once
// per row of eight samples).
#ifndef LOGRID_RASTER_INLINE
#if defined(__GNUC__) || defined(__clang__)
#define LOGRID_RASTER_INLINE inline __attribute__((always_inline))
#else
#define LOGRID_RASTER_INLINE inline
#endif
#endif

// The samples of a row in the band of a shared edge (`band`: candidates not inside every
// edge by its `hi`): claimed if the neighbour's other edges pass too (the union of both
// is then surely covered), with the key raised by what the neighbour's plane may add
// there. Returns `cover` with the band's claimed samples added; adds to `sample_key`.
template <class L>
typename L::M claimBand(const RasterTriangle* tris, const RasterTriangle& t, const RasterTarget& tg,
                        int x, int y, typename L::M columns, const typename L::F* e,
                        const typename L::F* hi, typename L::M cover, typename L::M band,
                        typename L::F& sample_key) {
  using F = typename L::F;
  using M = typename L::M;
  const F zero = L::set1(0.0f);
  const F lane_offset = L::mul(L::iota(), L::set1(tg.scale));
  M ok = band;
  F extra = zero;
  for (int k = 0; k < 3; ++k) {
    if (!(t.interior & (1u << k))) continue;
    const M bk = L::and_(band, L::le(e[k], hi[k]));
    if (!L::any(bk)) continue;
    const RasterTriangle& b = tris[t.nb[k]];
    const F pxb = L::add(L::set1(float(x) * tg.scale + tg.half - b.rx), lane_offset);
    const float pyb = float(y) * tg.scale + tg.half - b.ry;
    M pass = columns;
    for (int j = 0; j < kTriangleEdges; ++j) {
      if (j == t.nb_edge[k]) continue;
      const F eb = L::add(L::mul(L::set1(b.ea[j]), pxb), L::set1(b.eb[j] * pyb + b.ec[j]));
      pass = L::and_(pass, L::gt(eb, L::set1(b.hi[j])));
    }
    ok = L::andNot(ok, L::andNot(bk, pass));
    extra = L::max(extra, L::select(bk, L::set1(t.band_key[k]), zero));
  }
  sample_key = L::add(sample_key, extra);
  return L::or_(cover, ok);
}

// One row of lanes of a triangle: which samples it claims (`cand` holds the lanes that
// pass every edge's `lo`) and the key bound of each. Samples within the slack of a shared
// edge go to claimBand. e[k] are the edge values at the row's samples, px their x
// relative to t's reference. Inlined: most rows end before the band.
template <class L>
LOGRID_RASTER_INLINE typename L::M claimRow(const RasterTriangle* tris, const RasterTriangle& t,
                                            const RasterTarget& tg, int x, int y,
                                            typename L::M columns, const typename L::F* e,
                                            const typename L::F* lo, const typename L::F* hi,
                                            typename L::F key, typename L::F& sample_key) {
  using M = typename L::M;
  M cand = columns;
  for (int k = 0; k < kTriangleEdges; ++k) cand = L::and_(cand, L::gt(e[k], lo[k]));
  sample_key = key;
  if (!L::any(cand)) return cand;
  M inside = L::gt(e[0], hi[0]);
  for (int k = 1; k < kTriangleEdges; ++k) inside = L::and_(inside, L::gt(e[k], hi[k]));
  M cover = L::and_(cand, inside);
  const M band = L::andNot(cand, inside);
  if (!L::any(band)) return cover;
  return claimBand<L>(tris, t, tg, x, y, columns, e, hi, cover, band, sample_key);
}

// A block of samples [xa, xb) x [ya, yb) of a triangle, every test per sample, going
// down each column of lanes with the edge values and the key stepped one row at a time
// (setup's rounding allowance covers the additions: at most kBlock - 1 of them).
template <class L>
bool rasterPartial(const RasterTriangle* tris, const RasterTriangle& t, const RasterTarget& tg,
                   int xa, int xb, int ya, int yb, const typename L::F* ea, const typename L::F* lo,
                   const typename L::F* hi, typename L::F za) {
  using F = typename L::F;
  using M = typename L::M;
  constexpr int kW = L::kWidth;
  const F lane_offset = L::mul(L::iota(), L::set1(tg.scale));
  // Sample positions relative to the reference are exact in float (multiples of a half
  // pixel below 2^22), so every variant rounds the same products.
  const float py = float(ya) * tg.scale + tg.half - t.ry;
  F step[kTriangleEdges];
  for (int k = 0; k < kTriangleEdges; ++k) step[k] = L::set1(t.eb[k] * tg.scale);
  const F z_step = L::set1(t.zb * tg.scale);
  bool wrote = false;
  for (int x = tg.x0 + ((xa - tg.x0) / kW) * kW; x < xb; x += kW) {
    const F px = L::add(L::set1(float(x) * tg.scale + tg.half - t.rx), lane_offset);
    const M columns = L::inRange(x, xa, xb);
    F e[kTriangleEdges];
    for (int k = 0; k < kTriangleEdges; ++k) {
      e[k] = L::add(L::mul(ea[k], px), L::set1(t.eb[k] * py + t.ec[k]));
    }
    F key = L::add(L::mul(za, px), L::set1(t.zb * py + t.zc));
    float* row = tg.keys + std::size_t(ya) * tg.stride + std::size_t(x);
    for (int y = ya; y < yb; ++y, row += tg.stride) {
      F sample_key;
      const M cover = claimRow<L>(tris, t, tg, x, y, columns, e, lo, hi, key, sample_key);
      if (L::any(cover)) {
        const F old = L::load(row);
        L::store(row, L::select(cover, L::min(sample_key, old), old));
        wrote = true;
      }
      for (int k = 0; k < kTriangleEdges; ++k) e[k] = L::add(e[k], step[k]);
      key = L::add(key, z_step);
    }
  }
  return wrote;
}

// Blocks of kBlock x kBlock samples are classified from their corners: outside an edge
// (skipped), inside every edge by more than its slack (filled with the key plane, no
// test per sample), or partial (tested per sample). The classification uses the same
// float operations in every variant and widens each test by the rounding it can make,
// so a block is only skipped or filled where every sample would be.
constexpr int kBlock = kBlockSide;

template <class L>
void rasterTile(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                RasterTarget& tg) {
  using F = typename L::F;
  constexpr int kW = L::kWidth;
  const F lane_offset = L::mul(L::iota(), L::set1(tg.scale));
  // Triangles come roughly front to back: once a block of the tile is covered, most
  // later ones lie wholly behind everything in it and cannot change it. Each block's
  // largest key is kept (tg.block_max, recomputed after every write to the block), and
  // the tile's is the largest of them.
  const int blocks_x = (tg.x1 - tg.x0 + kBlock - 1) / kBlock;
  const int blocks = blocks_x * ((tg.y1 - tg.y0 + kBlock - 1) / kBlock);
  float tile_max = -HUGE_VALF;
  for (int b = 0; b < blocks; ++b)
    tile_max = tg.block_max[b] > tile_max ? tg.block_max[b] : tile_max;
  for (std::size_t i = 0; i < n; ++i) {
    const RasterTriangle& t = tris[list[i]];
    if (!(t.zmin < tile_max)) continue;
    const int x0 = clampMax(t.x0, tg.x0), x1 = clampMin(t.x1, tg.x1);
    const int y0 = clampMax(t.y0, tg.y0), y1 = clampMin(t.y1, tg.y1);
    if (x0 >= x1 || y0 >= y1) continue;
    F ea[kTriangleEdges], lo[kTriangleEdges], hi[kTriangleEdges];
    for (int k = 0; k < kTriangleEdges; ++k) {
      ea[k] = L::set1(t.ea[k]);
      lo[k] = L::set1(t.lo[k]);
      hi[k] = L::set1(t.hi[k]);
    }
    const F za = L::set1(t.za);
    bool wrote = false;
    // The classification's rounding allowance: three roundings of terms at most the
    // reach of the triangle's samples from its reference, or the value there.
    const float tol = t.block_tol;
    for (int by = tg.y0 + ((y0 - tg.y0) / kBlock) * kBlock; by < y1; by += kBlock) {
      const int ya = clampMax(by, y0), yb = clampMin(by + kBlock, y1);
      const float py0 = float(ya) * tg.scale + tg.half - t.ry;
      const float py1 = float(yb - 1) * tg.scale + tg.half - t.ry;
      // The edges are linear: over a block their extremes are at the corners.
      float y_min[kTriangleEdges], y_max[kTriangleEdges];
      for (int k = 0; k < kTriangleEdges; ++k) {
        const float b0 = t.eb[k] * py0 + t.ec[k], b1 = t.eb[k] * py1 + t.ec[k];
        y_min[k] = (b0 < b1 ? b0 : b1) - tol;
        y_max[k] = (b0 > b1 ? b0 : b1) + tol;
      }
      for (int bx = tg.x0 + ((x0 - tg.x0) / kBlock) * kBlock; bx < x1; bx += kBlock) {
        float& block_max = tg.block_max[((by - tg.y0) / kBlock) * blocks_x + (bx - tg.x0) / kBlock];
        if (!(t.zmin < block_max)) continue;
        const int xa = clampMax(bx, x0), xb = clampMin(bx + kBlock, x1);
        const float px0 = float(xa) * tg.scale + tg.half - t.rx;
        const float px1 = float(xb - 1) * tg.scale + tg.half - t.rx;
        bool outside = false, inside = true;
        for (int k = 0; k < kTriangleEdges; ++k) {
          const float a0 = t.ea[k] * px0, a1 = t.ea[k] * px1;
          outside |= !((a0 > a1 ? a0 : a1) + y_max[k] > t.lo[k]);
          inside &= (a0 < a1 ? a0 : a1) + y_min[k] > t.hi[k];
        }
        if (outside) continue;
        const int block_x1 = clampMin(bx + kBlock, tg.x1), block_y1 = clampMin(by + kBlock, tg.y1);
        if (!inside) {
          if (rasterPartial<L>(tris, t, tg, xa, xb, ya, yb, ea, lo, hi, za)) {
            block_max = blockMax<L>(tg, bx, block_x1, by, block_y1);
            wrote = true;
          }
          continue;
        }
        const F z_step = L::set1(t.zb * tg.scale);
        for (int x = bx; x < xb; x += kW) {
          const F px = L::add(L::set1(float(x) * tg.scale + tg.half - t.rx), lane_offset);
          const typename L::M columns = L::inRange(x, xa, xb);
          F key = L::add(L::mul(za, px), L::set1(t.zb * py0 + t.zc));
          float* row = tg.keys + std::size_t(ya) * tg.stride + std::size_t(x);
          for (int y = ya; y < yb; ++y, row += tg.stride) {
            const F old = L::load(row);
            L::store(row, L::select(columns, L::min(key, old), old));
            key = L::add(key, z_step);
          }
        }
        block_max = blockMax<L>(tg, bx, block_x1, by, block_y1);
        wrote = true;
      }
    }
    if (wrote) {
      tile_max = -HUGE_VALF;
      for (int b = 0; b < blocks; ++b) {
        tile_max = tg.block_max[b] > tile_max ? tg.block_max[b] : tile_max;
      }
    }
  }
}

// Nearest and farthest key of a rectangle and the count of keys not below `threshold`
// (a NaN would count: no key is NaN, but a count must never fall short).
template <class L>
KeyRange keyRange(const float* keys, std::size_t stride, int x0, int y0, int x1, int y1,
                  float threshold) {
  using F = typename L::F;
  using M = typename L::M;
  constexpr int kW = L::kWidth;
  F lo = L::set1(HUGE_VALF), hi = L::set1(-HUGE_VALF);
  const F t = L::set1(threshold);
  std::uint32_t count = 0;
  for (int y = y0; y < y1; ++y) {
    const float* row = keys + std::size_t(y) * stride;
    for (int x = x0; x < x1; x += kW) {
      const M in = L::inRange(x, x0, x1);
      const F v = L::load(row + x);
      lo = L::min(lo, L::select(in, v, L::set1(HUGE_VALF)));
      hi = L::max(hi, L::select(in, v, L::set1(-HUGE_VALF)));
      count += std::uint32_t(L::count(L::andNot(in, L::lt(v, t))));
    }
  }
  KeyRange r;
  r.min_key = L::hmin(lo);
  r.max_key = L::hmax(hi);
  r.at_or_beyond = count;
  return r;
}

// The masked representation (OcclusionBufferDesc::representation, raster_triangle.hpp):
// a triangle lands on a block of kMaskW x kMaskH buffer pixels as one coverage mask and
// one key, the largest key bound of the samples it claims there. Merging keeps every
// pixel's key at or behind the smaller of its old key and the triangle's bound there,
// so the block never claims more than the per-pixel buffer would (the argument is in
// occlusion_buffer.hpp). Returns whether the block's far key changed.
inline bool mergeMasked(MaskedBlock& b, std::uint32_t valid, std::uint32_t claimed, float key,
                        bool unsafe_merge) {
  if (!(key < b.z_far)) return false;  // behind every pixel's bound: nothing to gain
  const std::uint32_t layer = b.mask & valid;
  const float nearer = b.z_layer < key ? b.z_layer : key;
  if (layer != 0 && ((layer | claimed) | ~valid) == ~0u && !unsafe_merge) {
    // Layer and triangle cover the block together: the farther of the two keys becomes
    // the far key, and the pixels whose bound is the nearer stay in the layer (the
    // pixels of both take the nearer).
    const float farther = b.z_layer < key ? key : b.z_layer;
    b.mask = b.z_layer < key ? layer : claimed;
    b.z_layer = nearer;
    b.z_far = farther;
    if ((b.mask | ~valid) == ~0u) b.z_far = nearer, b.mask = 0, b.z_layer = -HUGE_VALF;
    return true;
  }
  // Else the triangle joins the layer, whose key must then stay at or behind every pixel
  // of the union: its own pixels the triangle leaves, the triangle's new pixels, and the
  // pixels of both (the nearer of the two bounds). (Masked occlusion culling would start
  // a new layer from a triangle nearer the far key than the layer's, the old layer's
  // pixels falling back to the far key; on the forest that kept fewer pixels covered
  // and drew more objects, so the layer always grows here.)
  float joined = -HUGE_VALF;
  if (layer & ~claimed) joined = b.z_layer;
  if (claimed & ~layer) joined = joined > key ? joined : key;
  if (claimed & layer) joined = joined > nearer ? joined : nearer;
  if (unsafe_merge && layer != 0) joined = nearer;  // test aid: too near for the union
  b.mask = layer | claimed;
  b.z_layer = joined;
  if ((b.mask | ~valid) != ~0u) return false;
  // The layer covers the block: it becomes the far key.
  b.z_far = b.z_layer;
  b.mask = 0;
  b.z_layer = -HUGE_VALF;
  return true;
}

// Rasterises triangles into the masked blocks of a tile: each block is classified from
// its corners as rasterTile does, then every sample of a partial block is tested as
// rasterPartial does (the same edge and key values, stepped at most kMaskH - 1 times),
// and the claimed samples merged into the block as one mask and one key.
template <class L>
void rasterTileMasked(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                      MaskedTarget& mt) {
  using F = typename L::F;
  using M = typename L::M;
  constexpr int kW = L::kWidth;
  const RasterTarget& tg = mt.tile;
  const F lane_offset = L::mul(L::iota(), L::set1(tg.scale));
  const int bx0 = tg.x0 / kMaskW, by0 = tg.y0 / kMaskH;
  const int bx1 = (tg.x1 + kMaskW - 1) / kMaskW, by1 = (tg.y1 + kMaskH - 1) / kMaskH;
  auto block = [&](int bx, int by) -> MaskedBlock& {
    return mt.blocks[std::size_t(by) * mt.blocks_per_row + std::size_t(bx)];
  };
  float tile_max = -HUGE_VALF;
  for (int by = by0; by < by1; ++by) {
    for (int bx = bx0; bx < bx1; ++bx) {
      tile_max = block(bx, by).z_far > tile_max ? block(bx, by).z_far : tile_max;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const RasterTriangle& t = tris[list[i]];
    if (!(t.zmin < tile_max)) continue;
    const int x0 = clampMax(t.x0, tg.x0), x1 = clampMin(t.x1, tg.x1);
    const int y0 = clampMax(t.y0, tg.y0), y1 = clampMin(t.y1, tg.y1);
    if (x0 >= x1 || y0 >= y1) continue;
    F ea[kTriangleEdges], lo[kTriangleEdges], hi[kTriangleEdges], step[kTriangleEdges];
    for (int k = 0; k < kTriangleEdges; ++k) {
      ea[k] = L::set1(t.ea[k]);
      lo[k] = L::set1(t.lo[k]);
      hi[k] = L::set1(t.hi[k]);
      step[k] = L::set1(t.eb[k] * tg.scale);
    }
    const F za = L::set1(t.za);
    const F z_step = L::set1(t.zb * tg.scale);
    const float tol = t.block_tol;
    bool far_changed = false;
    for (int by = y0 / kMaskH; by * kMaskH < y1; ++by) {
      const int ya = clampMax(by * kMaskH, y0), yb = clampMin(by * kMaskH + kMaskH, y1);
      const float py0 = float(ya) * tg.scale + tg.half - t.ry;
      const float py1 = float(yb - 1) * tg.scale + tg.half - t.ry;
      float y_min[kTriangleEdges], y_max[kTriangleEdges];
      for (int k = 0; k < kTriangleEdges; ++k) {
        const float b0 = t.eb[k] * py0 + t.ec[k], b1 = t.eb[k] * py1 + t.ec[k];
        y_min[k] = (b0 < b1 ? b0 : b1) - tol;
        y_max[k] = (b0 > b1 ? b0 : b1) + tol;
      }
      const int valid_rows = clampMin(tg.y1 - by * kMaskH, kMaskH);
      for (int bx = x0 / kMaskW; bx * kMaskW < x1; ++bx) {
        MaskedBlock& b = block(bx, by);
        if (!(t.zmin < b.z_far)) continue;
        const int xa = clampMax(bx * kMaskW, x0), xb = clampMin(bx * kMaskW + kMaskW, x1);
        const float px0 = float(xa) * tg.scale + tg.half - t.rx;
        const float px1 = float(xb - 1) * tg.scale + tg.half - t.rx;
        bool outside = false, inside = true;
        for (int k = 0; k < kTriangleEdges; ++k) {
          const float a0 = t.ea[k] * px0, a1 = t.ea[k] * px1;
          outside |= !((a0 > a1 ? a0 : a1) + y_max[k] > t.lo[k]);
          inside &= (a0 < a1 ? a0 : a1) + y_min[k] > t.hi[k];
        }
        if (outside) continue;
        std::uint32_t claimed = 0;
        F block_key = L::set1(-HUGE_VALF);
        for (int x = bx * kMaskW; x < xb; x += kW) {
          const F px = L::add(L::set1(float(x) * tg.scale + tg.half - t.rx), lane_offset);
          const M columns = L::inRange(x, xa, xb);
          F e[kTriangleEdges];
          for (int k = 0; k < kTriangleEdges; ++k) {
            e[k] = L::add(L::mul(ea[k], px), L::set1(t.eb[k] * py0 + t.ec[k]));
          }
          F key = L::add(L::mul(za, px), L::set1(t.zb * py0 + t.zc));
          const int shift = x - bx * kMaskW;
          for (int y = ya; y < yb; ++y) {
            M cover = columns;
            F sample_key = key;
            if (!inside)
              cover = claimRow<L>(tris, t, tg, x, y, columns, e, lo, hi, key, sample_key);
            block_key = L::max(block_key, L::select(cover, sample_key, L::set1(-HUGE_VALF)));
            claimed |= std::uint32_t(L::bits(cover)) << ((y - by * kMaskH) * kMaskW + shift);
            for (int k = 0; k < kTriangleEdges; ++k) e[k] = L::add(e[k], step[k]);
            key = L::add(key, z_step);
          }
        }
        if (claimed == 0) continue;
        const int valid_cols = clampMin(tg.x1 - bx * kMaskW, kMaskW);
        const std::uint32_t row_bits = (1u << valid_cols) - 1u;
        std::uint32_t valid = 0;
        for (int r = 0; r < valid_rows; ++r) valid |= row_bits << (r * kMaskW);
        far_changed |= mergeMasked(b, valid, claimed, L::hmax(block_key), mt.unsafe_merge);
      }
    }
    if (far_changed) {
      tile_max = -HUGE_VALF;
      for (int by = by0; by < by1; ++by) {
        for (int bx = bx0; bx < bx1; ++bx) {
          tile_max = block(bx, by).z_far > tile_max ? block(bx, by).z_far : tile_max;
        }
      }
    }
  }
}
