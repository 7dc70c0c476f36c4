// The scalar reference kernel: one sample at a time, the operations of every SIMD kernel.
#include <cmath>

#include "raster/raster_triangle.hpp"

namespace logrid::cpu::detail {
namespace {

struct Lanes {
  static constexpr int kWidth = 1;
  struct F {
    float v;
  };
  struct M {
    bool v;
  };
  static F set1(float x) { return {x}; }
  static F iota() { return {0.0f}; }
  static F add(F a, F b) { return {a.v + b.v}; }
  static F mul(F a, F b) { return {a.v * b.v}; }
  static M gt(F a, F b) { return {a.v > b.v}; }
  static M le(F a, F b) { return {a.v <= b.v}; }
  static M lt(F a, F b) { return {a.v < b.v}; }
  static int count(M m) { return m.v ? 1 : 0; }
  static float hmin(F a) { return a.v; }
  static M and_(M a, M b) { return {a.v && b.v}; }
  static M or_(M a, M b) { return {a.v || b.v}; }
  static M andNot(M a, M b) { return {a.v && !b.v}; }
  static int bits(M m) { return m.v ? 1 : 0; }
  static bool any(M m) { return m.v; }
  static F select(M m, F a, F b) { return m.v ? a : b; }
  static F min(F a, F b) { return {a.v < b.v ? a.v : b.v}; }
  static F max(F a, F b) { return {a.v > b.v ? a.v : b.v}; }
  static F load(const float* p) { return {*p}; }
  static void store(float* p, F a) { *p = a.v; }
  static M inRange(int x, int lo, int hi) { return {x >= lo && x < hi}; }
  static float hmax(F a) { return a.v; }
};

#include "raster/raster_kernel.inl"

}  // namespace

void rasterScalar(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                  RasterTarget& target) {
  rasterTile<Lanes>(tris, list, n, target);
}

void maskedScalar(const RasterTriangle* tris, const std::uint32_t* list, std::size_t n,
                  MaskedTarget& target) {
  rasterTileMasked<Lanes>(tris, list, n, target);
}

KeyRange rangeScalar(const float* keys, std::size_t stride, std::int32_t x0, std::int32_t y0,
                     std::int32_t x1, std::int32_t y1, float threshold) {
  return keyRange<Lanes>(keys, stride, x0, y0, x1, y1, threshold);
}

}  // namespace logrid::cpu::detail
