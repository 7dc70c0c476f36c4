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
// b), max (a > b ? a : b), load, store, inRange (lane x + l in [lo, hi)).

inline int clampMax(int a, int b) { return a > b ? a : b; }
inline int clampMin(int a, int b) { return a < b ? a : b; }

inline float clampf(float v, float lo, float hi) { return v < lo ? lo : v > hi ? hi : v; }

// The largest key of the tile (only its own columns: the row padding stays clear).
template <class L>
float tileMax(const RasterTarget& tg) {
  constexpr int kW = L::kWidth;
  typename L::F m = L::set1(-HUGE_VALF);
  for (int y = tg.y0; y < tg.y1; ++y) {
    const float* row = tg.keys + std::size_t(y) * tg.stride;
    for (int x = tg.x0; x < tg.x1; x += kW) {
      m = L::max(m, L::select(L::inRange(x, tg.x0, tg.x1), L::load(row + x), L::set1(-HUGE_VALF)));
    }
  }
  return L::hmax(m);
}

template <class L>
void rasterTile(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                RasterTarget& tg) {
  using F = typename L::F;
  using M = typename L::M;
  constexpr int kW = L::kWidth;
  const F lane_offset = L::mul(L::iota(), L::set1(tg.scale));
  const F zero = L::set1(0.0f);
  // Triangles come roughly front to back: once a tile is covered, most later ones lie
  // wholly behind everything in it and cannot change it. The tile's largest key is
  // recomputed (it only shrinks) when a skip depends on it and a few writes went by.
  float tile_max = tg.max_key;
  int writes = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const RasterTriangle& t = tris[list[i]];
    if (!(t.zmin < tile_max)) continue;
    if (writes >= 8) {
      tile_max = tileMax<L>(tg);
      writes = 0;
      if (!(t.zmin < tile_max)) continue;
    }
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
    // Wider than one group of lanes: walk only the span of each row where the edges
    // can pass (found from the edges with a usable slope; widened by two columns each
    // side for rounding, the test per sample below being the exact one).
    int left[kTriangleEdges], right[kTriangleEdges], n_left = 0, n_right = 0;
    const bool spans = x1 - x0 > kW;
    if (spans) {
      for (int k = 0; k < kTriangleEdges; ++k) {
        if (t.ea[k] >= 1e-4f) left[n_left++] = k;
        if (t.ea[k] <= -1e-4f) right[n_right++] = k;
      }
    }
    bool wrote = false;
    for (int y = y0; y < y1; ++y) {
      // Sample positions relative to the reference are exact in float (multiples of a
      // half pixel below 2^22), so every variant rounds the same products.
      const float py = float(y) * tg.scale + tg.half - t.ry;
      float re[kTriangleEdges];
      for (int k = 0; k < kTriangleEdges; ++k) re[k] = t.eb[k] * py + t.ec[k];
      int col_lo = x0, col_hi = x1;
      if (spans) {
        float lo_px = -HUGE_VALF, hi_px = HUGE_VALF;
        for (int j = 0; j < n_left; ++j) {
          const int k = left[j];
          const float bound = (t.lo[k] - re[k]) * t.inv_ea[k];
          lo_px = bound > lo_px ? bound : lo_px;
        }
        for (int j = 0; j < n_right; ++j) {
          const int k = right[j];
          const float bound = (t.lo[k] - re[k]) * t.inv_ea[k];
          hi_px = bound < hi_px ? bound : hi_px;
        }
        if (!(lo_px <= hi_px)) continue;
        const float c_lo = (lo_px - tg.half + t.rx) / tg.scale - 2.0f;
        const float c_hi = (hi_px - tg.half + t.rx) / tg.scale + 3.0f;
        if (c_lo > float(x0)) col_lo = int(clampf(c_lo, float(x0), float(x1)));
        if (c_hi < float(x1)) col_hi = int(clampf(c_hi, float(x0), float(x1)));
        if (col_lo >= col_hi) continue;
      }
      F row_e[kTriangleEdges];
      for (int k = 0; k < kTriangleEdges; ++k) row_e[k] = L::set1(re[k]);
      const F row_z = L::set1(t.zb * py + t.zc);
      float* row = tg.keys + std::size_t(y) * tg.stride;
      for (int x = tg.x0 + ((col_lo - tg.x0) / kW) * kW; x < col_hi; x += kW) {
        const F px = L::add(L::set1(float(x) * tg.scale + tg.half - t.rx), lane_offset);
        F e[kTriangleEdges];
        M cand = L::inRange(x, x0, x1);
        for (int k = 0; k < kTriangleEdges; ++k) {
          e[k] = L::add(L::mul(ea[k], px), row_e[k]);
          cand = L::and_(cand, L::gt(e[k], lo[k]));
        }
        if (!L::any(cand)) continue;
        M inside = L::gt(e[0], hi[0]);
        for (int k = 1; k < kTriangleEdges; ++k) inside = L::and_(inside, L::gt(e[k], hi[k]));
        M cover = L::and_(cand, inside);
        F key = L::add(L::mul(za, px), row_z);
        const M band = L::andNot(cand, inside);
        if (L::any(band)) {
          // Samples within the slack of a shared edge: covered if the neighbour's other
          // edges pass too (the union of both is then surely covered), with the key
          // raised by what the neighbour's plane may add there.
          M ok = band;
          F extra = zero;
          for (int k = 0; k < 3; ++k) {
            if (!(t.interior & (1u << k))) continue;
            const M bk = L::and_(band, L::le(e[k], hi[k]));
            if (!L::any(bk)) continue;
            const RasterTriangle& b = tris[t.nb[k]];
            const F pxb = L::add(L::set1(float(x) * tg.scale + tg.half - b.rx), lane_offset);
            const float pyb = float(y) * tg.scale + tg.half - b.ry;
            M pass = L::inRange(x, x0, x1);
            for (int j = 0; j < kTriangleEdges; ++j) {
              if (j == t.nb_edge[k]) continue;
              const F eb = L::add(L::mul(L::set1(b.ea[j]), pxb), L::set1(b.eb[j] * pyb + b.ec[j]));
              pass = L::and_(pass, L::gt(eb, L::set1(b.hi[j])));
            }
            ok = L::andNot(ok, L::andNot(bk, pass));
            extra = L::max(extra, L::select(bk, L::set1(t.band_key[k]), zero));
          }
          cover = L::or_(cover, ok);
          key = L::add(key, extra);
        }
        if (!L::any(cover)) continue;
        const F old = L::load(row + x);
        L::store(row + x, L::select(cover, L::min(key, old), old));
        wrote = true;
      }
    }
    writes += wrote;
  }
  tg.max_key = tile_max;
}
