// TriangleSetup::setUp() of four triangles at a time in AVX2 (four doubles a lane
// group). Compiled with -mavx2 (no FMA: every operation rounds as the scalar one does;
// cpu/CMakeLists.txt) and called only where the CPU reports AVX2. Each lane does the
// operations of setUp()'s path for a triangle wholly in front of the near plane, in the
// same order and with the same operands: std::min(a, b) is (b < a ? b : a), which is
// _mm256_min_pd(b, a), std::max(a, b) likewise _mm256_max_pd(b, a), so NaNs and signed
// zeros come out as they do there. Where setUp() returns early, the lane is marked
// unusable and the rest of its values are left unread. The unit test
// `TriangleSetupTest.GroupsSetUpAsOneAtATime` compares the two bit for bit.
#include <immintrin.h>

#include <cstddef>

#include "triangle_setup.hpp"

namespace logrid::cpu::detail {
namespace {

using D = __m256d;

D set1(double x) { return _mm256_set1_pd(x); }
D add(D a, D b) { return _mm256_add_pd(a, b); }
D sub(D a, D b) { return _mm256_sub_pd(a, b); }
D mul(D a, D b) { return _mm256_mul_pd(a, b); }
D div(D a, D b) { return _mm256_div_pd(a, b); }
D abs(D a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
D neg(D a) { return _mm256_xor_pd(_mm256_set1_pd(-0.0), a); }
D stdMin(D a, D b) { return _mm256_min_pd(b, a); }           // std::min(a, b)
D stdMax(D a, D b) { return _mm256_max_pd(b, a); }           // std::max(a, b)
D stdMin(D a, D b, D c) { return stdMin(stdMin(a, b), c); }  // std::min({a, b, c})
D stdMax(D a, D b, D c) { return stdMax(stdMax(a, b), c); }
D lt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
D gt(D a, D b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
D finite(D a) { return lt(abs(a), set1(__builtin_inf())); }  // std::isfinite
D select(D m, D a, D b) { return _mm256_blendv_pd(b, a, m); }
// std::clamp(v, lo, hi): lo where v < lo, else hi where hi < v, else v.
D clamp(D v, D lo, D hi) { return select(lt(v, lo), lo, select(lt(hi, v), hi, v)); }
// Four int32 (of values already clamped to their range) to the 64-bit lanes' masks.
D maskOf(__m128i m) { return _mm256_castsi256_pd(_mm256_cvtepi32_epi64(m)); }

// The transpose of four rows of four doubles.
void transpose(D& r0, D& r1, D& r2, D& r3) {
  const D t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
  const D t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
  r0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  r1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  r2 = _mm256_permute2f128_pd(t0, t2, 0x31);
  r3 = _mm256_permute2f128_pd(t1, t3, 0x31);
}
// Four consecutive doubles at p[l] + offset (bytes) of each lane l, as four lanes each.
void gather4(const char* const* p, std::size_t offset, D& f0, D& f1, D& f2, D& f3) {
  f0 = _mm256_loadu_pd(reinterpret_cast<const double*>(p[0] + offset));
  f1 = _mm256_loadu_pd(reinterpret_cast<const double*>(p[1] + offset));
  f2 = _mm256_loadu_pd(reinterpret_cast<const double*>(p[2] + offset));
  f3 = _mm256_loadu_pd(reinterpret_cast<const double*>(p[3] + offset));
  transpose(f0, f1, f2, f3);
}
D gather1(const char* const* p, std::size_t offset) {
  const auto at = [&](int l) { return *reinterpret_cast<const double*>(p[l] + offset); };
  return _mm256_setr_pd(at(0), at(1), at(2), at(3));
}
// The inverse: lane l of f0..f3 to p[l] + offset, four consecutive doubles.
void scatter4(char* const* p, std::size_t offset, D f0, D f1, D f2, D f3) {
  transpose(f0, f1, f2, f3);
  _mm256_storeu_pd(reinterpret_cast<double*>(p[0] + offset), f0);
  _mm256_storeu_pd(reinterpret_cast<double*>(p[1] + offset), f1);
  _mm256_storeu_pd(reinterpret_cast<double*>(p[2] + offset), f2);
  _mm256_storeu_pd(reinterpret_cast<double*>(p[3] + offset), f3);
}

// One corner of the four triangles.
struct Corner {
  D wx, wy, key, ex, ey, ez, px, py, pz;
};

}  // namespace

std::uint32_t TriangleSetup::transformGroupsAvx2(const SetupFrame& f, const float* positions,
                                                 std::uint32_t count, Vertex* out) {
  static_assert(offsetof(Vertex, y) == offsetof(Vertex, x) + 8 &&
                    offsetof(Vertex, w) == offsetof(Vertex, x) + 16 &&
                    offsetof(Vertex, k) == offsetof(Vertex, x) + 24 &&
                    offsetof(Vertex, sy) == offsetof(Vertex, sx) + 8 &&
                    offsetof(Vertex, sz) == offsetof(Vertex, sx) + 16 &&
                    offsetof(Vertex, sw) == offsetof(Vertex, sx) + 24,
                "the vertex fields written four at a time");
  D m[16], ra[16];
  for (int i = 0; i < 16; ++i) m[i] = set1(f.m[i]), ra[i] = set1(f.render_abs[i]);
  const D origin[3] = {set1(f.origin[0]), set1(f.origin[1]), set1(f.origin[2])};
  const D half_w = set1(f.half_w), half_h = set1(f.half_h), key_scale = set1(f.key_scale),
          key_offset = set1(f.key_offset), near_key = set1(f.near_key),
          clear_key = set1(f.clear_key), depth_scale = abs(set1(f.key_scale)), zero = set1(0.0);
  const std::uint32_t groups = count / 4 * 4;
  for (std::uint32_t i = 0; i < groups; i += 4) {
    const float* p = positions + std::size_t(i) * 3;
    const D x = _mm256_cvtps_pd(_mm_setr_ps(p[0], p[3], p[6], p[9]));
    const D y = _mm256_cvtps_pd(_mm_setr_ps(p[1], p[4], p[7], p[10]));
    const D z = _mm256_cvtps_pd(_mm_setr_ps(p[2], p[5], p[8], p[11]));
    const D q[3] = {abs(sub(x, origin[0])), abs(sub(y, origin[1])), abs(sub(z, origin[2]))};
    D clip[4], mag[4];
    for (int r = 0; r < 4; ++r) {
      clip[r] = add(add(add(mul(m[r], x), mul(m[4 + r], y)), mul(m[8 + r], z)), m[12 + r]);
      mag[r] =
          add(add(add(mul(ra[r], q[0]), mul(ra[4 + r], q[1])), mul(ra[8 + r], q[2])), ra[12 + r]);
    }
    D vx = mul(add(clip[0], clip[3]), half_w), vy = mul(add(clip[1], clip[3]), half_h);
    D vw = clip[3], vk = add(mul(key_scale, clip[2]), mul(key_offset, clip[3]));
    const D front =
        _mm256_and_pd(gt(vw, zero), _mm256_cmp_pd(sub(vk, mul(near_key, vw)), zero, _CMP_GE_OQ));
    const D within_far = _mm256_cmp_pd(sub(mul(clear_key, vw), vk), zero, _CMP_GE_OQ);
    const D inv_w = div(set1(1.0), vw);
    D wx = mul(vx, inv_w), wy = mul(vy, inv_w), key = mul(vk, inv_w);
    D ex = mul(mul(add(mag[0], mul(abs(mul(clip[0], inv_w)), mag[3])), inv_w), half_w);
    D ey = mul(mul(add(mag[1], mul(abs(mul(clip[1], inv_w)), mag[3])), inv_w), half_h);
    D ez = mul(mul(add(mag[2], mul(abs(mul(clip[2], inv_w)), mag[3])), inv_w), depth_scale);
    D px = zero, py = zero;  // a still object's pad
    char* v[4];
    for (int l = 0; l < 4; ++l) v[l] = reinterpret_cast<char*>(out + i + std::uint32_t(l));
    D sx = mag[0], sy = mag[1], sz = mag[2], sw = mag[3];
    scatter4(v, offsetof(Vertex, x), vx, vy, vw, vk);
    scatter4(v, offsetof(Vertex, sx), sx, sy, sz, sw);
    scatter4(v, offsetof(Vertex, wx), wx, wy, key, ex);
    scatter4(v, offsetof(Vertex, ey), ey, ez, px, py);
    const int in_front = _mm256_movemask_pd(front), not_beyond = _mm256_movemask_pd(within_far);
    for (int l = 0; l < 4; ++l) {
      Vertex& o = out[i + std::uint32_t(l)];
      o.front = (in_front >> l & 1) != 0;
      o.beyond_far = (not_beyond >> l & 1) == 0;
      o.pz = 0;
    }
  }
  return groups;
}

void TriangleSetup::setUpGroupAvx2(const SetupFrame& f, const SetupObject& o,
                                   const Vertex* const* corners, Work* const* work, bool* ok_out) {
  static_assert(offsetof(Vertex, wy) == offsetof(Vertex, wx) + 8 &&
                    offsetof(Vertex, key) == offsetof(Vertex, wx) + 16 &&
                    offsetof(Vertex, ex) == offsetof(Vertex, wx) + 24 &&
                    offsetof(Vertex, ez) == offsetof(Vertex, ey) + 8 &&
                    offsetof(Vertex, px) == offsetof(Vertex, ey) + 16 &&
                    offsetof(Vertex, py) == offsetof(Vertex, ey) + 24,
                "the vertex fields read four at a time");
  static_assert(offsetof(Work, zb) == offsetof(Work, za) + 8 &&
                    offsetof(Work, zc) == offsetof(Work, za) + 16 &&
                    offsetof(Work, s_x) == offsetof(Work, za) + 24 &&
                    offsetof(Work, margin) == offsetof(Work, s_y) + 8 &&
                    offsetof(Work, key_min) == offsetof(Work, s_y) + 16 &&
                    offsetof(Work, g) == offsetof(Work, s_y) + 24 &&
                    offsetof(Work, rx) == offsetof(Work, z_err) + 8 &&
                    offsetof(Work, ry) == offsetof(Work, z_err) + 16 &&
                    offsetof(Work, y0) == offsetof(Work, x0) + 4 &&
                    offsetof(Work, x1) == offsetof(Work, x0) + 8 &&
                    offsetof(Work, y1) == offsetof(Work, x0) + 12,
                "the work fields written four at a time");
  Corner v[3];
  for (int k = 0; k < 3; ++k) {
    const char* p[4];
    for (int l = 0; l < 4; ++l) p[l] = reinterpret_cast<const char*>(corners[3 * l + k]);
    Corner& c = v[k];
    gather4(p, offsetof(Vertex, wx), c.wx, c.wy, c.key, c.ex);
    gather4(p, offsetof(Vertex, ey), c.ey, c.ez, c.px, c.py);
    c.pz = gather1(p, offsetof(Vertex, pz));
  }
  const D zero = set1(0.0);
  const D d10x = sub(v[1].wx, v[0].wx), d20y = sub(v[2].wy, v[0].wy);
  const D d20x = sub(v[2].wx, v[0].wx), d10y = sub(v[1].wy, v[0].wy);
  const D area = sub(mul(d10x, d20y), mul(d20x, d10y));
  D ok = _mm256_and_pd(_mm256_cmp_pd(area, zero, _CMP_NEQ_UQ), finite(area));

  const D x_min = stdMin(v[0].wx, v[1].wx, v[2].wx), x_max = stdMax(v[0].wx, v[1].wx, v[2].wx);
  const D y_min = stdMin(v[0].wy, v[1].wy, v[2].wy), y_max = stdMax(v[0].wy, v[1].wy, v[2].wy);
  const D mag = stdMax(stdMax(stdMax(abs(x_min), abs(x_max)), abs(y_min)), abs(y_max));
  const D guard = set1(kGuardBand);
  ok = _mm256_and_pd(ok, lt(mag, guard));
  const D snap = set1(f.snap), render_k = set1(f.render_k), mag_err = mul(set1(16 * kU), mag);
  const D s_x =
      stdMax(set1(o.s_x), add(add(add(snap, mul(render_k, stdMax(v[0].ex, v[1].ex, v[2].ex))),
                                  stdMax(v[0].px, v[1].px, v[2].px)),
                              mag_err));
  const D s_y =
      stdMax(set1(o.s_y), add(add(add(snap, mul(render_k, stdMax(v[0].ey, v[1].ey, v[2].ey))),
                                  stdMax(v[0].py, v[1].py, v[2].py)),
                              mag_err));
  ok = _mm256_and_pd(ok, _mm256_and_pd(lt(s_x, guard), lt(s_y, guard)));

  // pixelBounds()
  const D pad = add(add(stdMax(s_x, s_y), set1(f.radius)), set1(1e-3));
  const D inv_scale = set1(f.inv_scale), half = set1(0.5 * f.scale);
  const D bw = set1(f.buffer_w), bh = set1(f.buffer_h), minus_one = set1(-1.0);
  const auto ceilInt = [](D x) { return _mm256_cvttpd_epi32(_mm256_ceil_pd(x)); };
  const auto floorInt = [](D x) { return _mm256_cvttpd_epi32(_mm256_floor_pd(x)); };
  const __m128i x0 = ceilInt(clamp(mul(sub(sub(x_min, pad), half), inv_scale), zero, bw));
  const __m128i y0 = ceilInt(clamp(mul(sub(sub(y_min, pad), half), inv_scale), zero, bh));
  const __m128i one = _mm_set1_epi32(1);
  const __m128i x1 = _mm_min_epi32(
      _mm_set1_epi32(f.buffer_w),
      _mm_add_epi32(floorInt(clamp(mul(sub(add(x_max, pad), half), inv_scale), minus_one, bw)),
                    one));
  const __m128i y1 = _mm_min_epi32(
      _mm_set1_epi32(f.buffer_h),
      _mm_add_epi32(floorInt(clamp(mul(sub(add(y_max, pad), half), inv_scale), minus_one, bh)),
                    one));
  ok = _mm256_and_pd(ok, maskOf(_mm_and_si128(_mm_cmplt_epi32(x0, x1), _mm_cmplt_epi32(y0, y1))));

  const D key_max = stdMax(v[0].key, v[1].key, v[2].key);
  const D key_min = stdMin(v[0].key, v[1].key, v[2].key);
  const D margin =
      stdMax(set1(o.margin),
             add(add(set1(f.quantisation), mul(render_k, add(stdMax(v[0].ez, v[1].ez, v[2].ez),
                                                             stdMax(abs(key_min), abs(key_max))))),
                 stdMax(v[0].pz, v[1].pz, v[2].pz)));
  ok = _mm256_and_pd(ok, finite(margin));

  // The edges: edge k from corner k + 1 to corner k + 2.
  const D sign = select(gt(area, zero), set1(1.0), set1(-1.0));
  D ea[3], eb[3], ec[3];
  for (int k = 0; k < 3; ++k) {
    const Corner& p = v[(k + 1) % 3];
    const Corner& q = v[(k + 2) % 3];
    const D a = sub(p.wy, q.wy), b = sub(q.wx, p.wx);
    const D n = add(abs(a), abs(b));
    ok = _mm256_and_pd(ok, gt(n, zero));
    ea[k] = div(mul(sign, a), n);
    eb[k] = div(mul(sign, b), n);
    ec[k] = neg(add(mul(ea[k], p.wx), mul(eb[k], p.wy)));
  }
  const D inv = div(set1(1.0), area);
  const D dk1 = sub(v[1].key, v[0].key), dk2 = sub(v[2].key, v[0].key);
  const D za = mul(sub(mul(dk1, d20y), mul(dk2, d10y)), inv);
  const D zb = mul(sub(mul(d10x, dk2), mul(d20x, dk1)), inv);
  D zc = sub(sub(v[0].key, mul(za, v[0].wx)), mul(zb, v[0].wy));
  ok = _mm256_and_pd(ok, _mm256_and_pd(finite(za), _mm256_and_pd(finite(zb), finite(zc))));

  // finish() of an unclipped triangle: edge 3 is (0, 0, 1) with no slack or error.
  const D s = set1(f.scale), r = set1(f.radius);
  const D x0d = _mm256_cvtepi32_pd(x0), y0d = _mm256_cvtepi32_pd(y0);
  const D rx = mul(x0d, s), ry = mul(y0d, s);
  const D dx = add(mul(_mm256_cvtepi32_pd(_mm_sub_epi32(x1, x0)), s), s);
  const D dy = add(mul(_mm256_cvtepi32_pd(_mm_sub_epi32(y1, y0)), s), s);
  const D err_k = set1(24 * kU), extent = mul(set1(2.0), add(dx, dy)), tiny = set1(1e-30);
  const D sxr = add(s_x, r), syr = add(s_y, r);
  D slack[3], err[3];
  for (int k = 0; k < 3; ++k) {
    const D at_ref = add(add(mul(ea[k], rx), mul(eb[k], ry)), ec[k]);
    ec[k] = at_ref;
    err[k] = add(mul(err_k, add(extent, abs(at_ref))), tiny);
    slack[k] = add(mul(sxr, abs(ea[k])), mul(syr, abs(eb[k])));
  }
  zc = add(add(mul(za, rx), mul(zb, ry)), zc);
  const D g = add(abs(za), abs(zb));
  const D z_err = mul(err_k, add(add(mul(abs(za), dx), mul(abs(zb), dy)), abs(zc)));

  char* w[4];
  for (int l = 0; l < 4; ++l) w[l] = reinterpret_cast<char*>(work[l]);
  const D one_d = set1(1.0);
  scatter4(w, offsetof(Work, a), ea[0], ea[1], ea[2], zero);
  scatter4(w, offsetof(Work, b), eb[0], eb[1], eb[2], zero);
  scatter4(w, offsetof(Work, c), ec[0], ec[1], ec[2], one_d);
  scatter4(w, offsetof(Work, slack), slack[0], slack[1], slack[2], zero);
  scatter4(w, offsetof(Work, err), err[0], err[1], err[2], zero);
  scatter4(w, offsetof(Work, za), za, zb, zc, s_x);
  scatter4(w, offsetof(Work, s_y), s_y, margin, key_min, g);
  D z_err_t = z_err, rx_t = rx, ry_t = ry, unused = zero;
  transpose(z_err_t, rx_t, ry_t, unused);
  const D rows[4] = {z_err_t, rx_t, ry_t, unused};
  const __m256i three = _mm256_setr_epi64x(-1, -1, -1, 0);
  // x0, y0, x1, y1 of lane l: the 4 x 4 transpose of the int32 rows.
  const __m128i t0 = _mm_unpacklo_epi32(x0, y0), t1 = _mm_unpackhi_epi32(x0, y0);
  const __m128i t2 = _mm_unpacklo_epi32(x1, y1), t3 = _mm_unpackhi_epi32(x1, y1);
  const __m128i bounds[4] = {_mm_unpacklo_epi64(t0, t2), _mm_unpackhi_epi64(t0, t2),
                             _mm_unpacklo_epi64(t1, t3), _mm_unpackhi_epi64(t1, t3)};
  const int usable = _mm256_movemask_pd(ok);
  for (int l = 0; l < 4; ++l) {
    _mm256_maskstore_pd(reinterpret_cast<double*>(w[l] + offsetof(Work, z_err)), three, rows[l]);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(w[l] + offsetof(Work, x0)), bounds[l]);
    ok_out[l] = (usable >> l & 1) != 0;
  }
}

}  // namespace logrid::cpu::detail
