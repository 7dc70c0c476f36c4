// The SSE4.1 kernel: four samples at a time. Compiled with -msse4.1 (cpu/CMakeLists.txt)
// and called only where the CPU reports SSE4.1.
#include <smmintrin.h>

#include <cmath>

#include "raster/raster_triangle.hpp"

namespace logrid::cpu::detail {
namespace {

struct Lanes {
  static constexpr int kWidth = 4;
  using F = __m128;
  using M = __m128;
  static F set1(float x) { return _mm_set1_ps(x); }
  static F iota() { return _mm_setr_ps(0, 1, 2, 3); }
  static F add(F a, F b) { return _mm_add_ps(a, b); }
  static F mul(F a, F b) { return _mm_mul_ps(a, b); }
  static M gt(F a, F b) { return _mm_cmpgt_ps(a, b); }
  static M le(F a, F b) { return _mm_cmple_ps(a, b); }
  static M lt(F a, F b) { return _mm_cmplt_ps(a, b); }
  static int count(M m) { return __builtin_popcount(unsigned(_mm_movemask_ps(m))); }
  static float hmin(F a) {
    const __m128 b = _mm_min_ps(a, _mm_movehl_ps(a, a));
    return _mm_cvtss_f32(_mm_min_ss(b, _mm_shuffle_ps(b, b, 1)));
  }
  static M and_(M a, M b) { return _mm_and_ps(a, b); }
  static M or_(M a, M b) { return _mm_or_ps(a, b); }
  static M andNot(M a, M b) { return _mm_andnot_ps(b, a); }
  static int bits(M m) { return _mm_movemask_ps(m); }
  static bool any(M m) { return _mm_movemask_ps(m) != 0; }
  static F select(M m, F a, F b) { return _mm_blendv_ps(b, a, m); }
  static F min(F a, F b) { return _mm_min_ps(a, b); }
  static F max(F a, F b) { return _mm_max_ps(a, b); }
  static F load(const float* p) { return _mm_loadu_ps(p); }
  static void store(float* p, F a) { _mm_storeu_ps(p, a); }
  static M inRange(int x, int lo, int hi) {
    const __m128i lane = _mm_add_epi32(_mm_set1_epi32(x), _mm_setr_epi32(0, 1, 2, 3));
    const __m128i ge_lo = _mm_cmpgt_epi32(lane, _mm_set1_epi32(lo - 1));
    const __m128i lt_hi = _mm_cmplt_epi32(lane, _mm_set1_epi32(hi));
    return _mm_castsi128_ps(_mm_and_si128(ge_lo, lt_hi));
  }
  static float hmax(F a) {
    const __m128 b = _mm_max_ps(a, _mm_movehl_ps(a, a));
    return _mm_cvtss_f32(_mm_max_ss(b, _mm_shuffle_ps(b, b, 1)));
  }
};

#include "raster/raster_kernel.inl"

}  // namespace

void rasterSse41(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                 RasterTarget& target) {
  rasterTile<Lanes>(tris, list, n, target);
}

void maskedSse41(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                 MaskedTarget& target) {
  rasterTileMasked<Lanes>(tris, list, n, target);
}

KeyRange rangeSse41(const float* keys, std::size_t stride, std::int32_t x0, std::int32_t y0,
                    std::int32_t x1, std::int32_t y1, float threshold) {
  return keyRange<Lanes>(keys, stride, x0, y0, x1, y1, threshold);
}

}  // namespace logrid::cpu::detail
