// The AVX2 kernel: eight samples at a time. Compiled with -mavx2 (no FMA, so that it
// rounds as the scalar kernel does; cpu/CMakeLists.txt) and called only where the CPU
// reports AVX2.
#include <immintrin.h>

#include <cmath>

#include "raster/raster_triangle.hpp"

namespace logrid::cpu::detail {
namespace {

struct Lanes {
  static constexpr int kWidth = 8;
  using F = __m256;
  using M = __m256;
  static F set1(float x) { return _mm256_set1_ps(x); }
  static F iota() { return _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7); }
  static F add(F a, F b) { return _mm256_add_ps(a, b); }
  static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static M gt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
  static M le(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
  static M lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
  static int count(M m) { return __builtin_popcount(unsigned(_mm256_movemask_ps(m))); }
  static float hmin(F a) {
    __m128 b = _mm_min_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    b = _mm_min_ps(b, _mm_movehl_ps(b, b));
    return _mm_cvtss_f32(_mm_min_ss(b, _mm_shuffle_ps(b, b, 1)));
  }
  static M and_(M a, M b) { return _mm256_and_ps(a, b); }
  static M or_(M a, M b) { return _mm256_or_ps(a, b); }
  static M andNot(M a, M b) { return _mm256_andnot_ps(b, a); }
  static int bits(M m) { return _mm256_movemask_ps(m); }
  static bool any(M m) { return _mm256_movemask_ps(m) != 0; }
  static F select(M m, F a, F b) { return _mm256_blendv_ps(b, a, m); }
  static F min(F a, F b) { return _mm256_min_ps(a, b); }
  static F max(F a, F b) { return _mm256_max_ps(a, b); }
  static F load(const float* p) { return _mm256_loadu_ps(p); }
  static void store(float* p, F a) { _mm256_storeu_ps(p, a); }
  static M inRange(int x, int lo, int hi) {
    const __m256i lane =
        _mm256_add_epi32(_mm256_set1_epi32(x), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256i ge_lo = _mm256_cmpgt_epi32(lane, _mm256_set1_epi32(lo - 1));
    const __m256i lt_hi = _mm256_cmpgt_epi32(_mm256_set1_epi32(hi), lane);
    return _mm256_castsi256_ps(_mm256_and_si256(ge_lo, lt_hi));
  }
  static float hmax(F a) {
    __m128 b = _mm_max_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    b = _mm_max_ps(b, _mm_movehl_ps(b, b));
    return _mm_cvtss_f32(_mm_max_ss(b, _mm_shuffle_ps(b, b, 1)));
  }
};

#include "raster/raster_kernel.inl"

}  // namespace

void rasterAvx2(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                RasterTarget& target) {
  rasterTile<Lanes>(tris, list, n, target);
}

void maskedAvx2(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                MaskedTarget& target) {
  rasterTileMasked<Lanes>(tris, list, n, target);
}

KeyRange rangeAvx2(const float* keys, std::size_t stride, std::int32_t x0, std::int32_t y0,
                   std::int32_t x1, std::int32_t y1, float threshold) {
  return keyRange<Lanes>(keys, stride, x0, y0, x1, y1, threshold);
}

}  // namespace logrid::cpu::detail
