#include "triangle_setup.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace logrid::cpu::detail {
namespace {

struct H {
  double x, y, w, k;      // homogeneous window x, y, clip w, homogeneous key
  double sx, sy, sz, sw;  // magnitudes of GL's terms (|.| of a convex combination is at
                          // most the combination of the |.|s)
};

H lerp(const H& a, const H& b, double t) {
  return {a.x + t * (b.x - a.x),    a.y + t * (b.y - a.y),    a.w + t * (b.w - a.w),
          a.k + t * (b.k - a.k),    a.sx + t * (b.sx - a.sx), a.sy + t * (b.sy - a.sy),
          a.sz + t * (b.sz - a.sz), a.sw + t * (b.sw - a.sw)};
}

std::uint32_t bitsOf(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}
float fromBits(std::uint32_t b) {
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

// The float nearest to v that is not below (above) it (v finite). Without a branch: the
// set-up rounds several bounds a triangle, and which way float(v) went is as good as
// random, so a branch on it is mispredicted half the time. The step up from float(v) is
// one unit in the last place on its bits (+1 for +0 and above, -1 below), and from +-0
// the smallest subnormal.
float floatUp(double v) {
  const float f = float(v);
  const std::uint32_t b = bitsOf(f);
  const std::uint32_t toward = 1u | std::uint32_t(std::int32_t(b) >> 31);  // +1 or -1
  const std::uint32_t zero = 0u - std::uint32_t((b & 0x7FFFFFFFu) == 0);   // all ones if +-0
  const std::uint32_t up = (1u & zero) | ((b + toward) & ~zero);
  const std::uint32_t below = 0u - std::uint32_t(double(f) < v);  // all ones if f < v
  return fromBits((up & below) | (b & ~below));
}
// float(-v) is -float(v) (round to nearest is symmetric), so this steps down exactly
// where float(v) > v.
float floatDown(double v) { return -floatUp(-v); }

// floor and ceil of a double already clamped to the int range.
std::int32_t floorInt(double v) {
  const std::int32_t i = std::int32_t(v);
  return double(i) > v ? i - 1 : i;
}
std::int32_t ceilInt(double v) {
  const std::int32_t i = std::int32_t(v);
  return double(i) < v ? i + 1 : i;
}

}  // namespace

// How far a displacement of the clip coordinates by at most pad_clip (x, y, z, w) moves
// a window coordinate (scaled by `scale`) whose clip value is `c` at this w: at most
// (D_c + |c / w| D_w) / (w - D_w) times the scale; infinite where w - D_w <= 0 (the
// triangle is then left out). 0 for a still object.
double padError(const double* pad_clip, int r, double c, double w, double scale) {
  if (pad_clip[3] == 0 && pad_clip[r] == 0) return 0;
  const double den = w - pad_clip[3];
  if (!(den > 0)) return HUGE_VAL;
  return (pad_clip[r] + std::fabs(c / w) * pad_clip[3]) / den * scale;
}

void TriangleSetup::transform(const SetupFrame& f, const SetupObject& o, const float* positions,
                              std::uint32_t count) {
  if (vertices_.size() < count) vertices_.resize(count);  // (kept: no refill per object)
  const double depth_scale = std::fabs(f.key_scale);
  for (int r = 0; r < 4; ++r) pad_clip_[r] = o.moved ? o.pad * f.clip_abs[r] : 0.0;
  const double* rot = o.rotation;
  std::uint32_t i = 0;
#if LOGRID_CPU_X86
  // A still object's vertices four at a time, the rest (and a moving object's) below.
  if (groups_ && !o.moved) i = transformGroupsAvx2(f, positions, count, vertices_.data());
#endif
  for (; i < count; ++i) {
    double x = positions[i * 3], y = positions[i * 3 + 1], z = positions[i * 3 + 2];
    if (o.moved) {  // placed where the application draws it ("Moving objects")
      const double px = x, py = y, pz = z;
      x = rot[0] * px + rot[3] * py + rot[6] * pz + o.translation[0];
      y = rot[1] * px + rot[4] * py + rot[7] * pz + o.translation[1];
      z = rot[2] * px + rot[5] * py + rot[8] * pz + o.translation[2];
    }
    double clip[4], mag[4];
    const double q[3] = {std::fabs(x - f.origin[0]), std::fabs(y - f.origin[1]),
                         std::fabs(z - f.origin[2])};
    for (int r = 0; r < 4; ++r) {
      clip[r] = f.m[r] * x + f.m[4 + r] * y + f.m[8 + r] * z + f.m[12 + r];
      mag[r] = f.render_abs[r] * q[0] + f.render_abs[4 + r] * q[1] + f.render_abs[8 + r] * q[2] +
               f.render_abs[12 + r];
    }
    Vertex& v = vertices_[i];
    v.x = (clip[0] + clip[3]) * f.half_w;
    v.y = (clip[1] + clip[3]) * f.half_h;
    v.w = clip[3];
    v.k = f.key_scale * clip[2] + f.key_offset * clip[3];
    v.sx = mag[0], v.sy = mag[1], v.sz = mag[2], v.sw = mag[3];
    // In front of the near plane (key >= near key: K - near_key W >= 0 with W > 0) and
    // not beyond the far one: then its window position, key and GL's float error there
    // (projection.hpp: (S + |ndc| S_w) / w per axis, and with the largest key for depth).
    v.front = v.w > 0 && v.k - f.near_key * v.w >= 0;
    v.beyond_far = !(f.clear_key * v.w - v.k >= 0);
    if (v.front) {
      const double inv_w = 1.0 / v.w;
      v.wx = v.x * inv_w, v.wy = v.y * inv_w, v.key = v.k * inv_w;
      v.ex = (v.sx + std::fabs(clip[0] * inv_w) * v.sw) * inv_w * f.half_w;
      v.ey = (v.sy + std::fabs(clip[1] * inv_w) * v.sw) * inv_w * f.half_h;
      v.ez = (v.sz + std::fabs(clip[2] * inv_w) * v.sw) * inv_w * depth_scale;
      v.px = padError(pad_clip_, 0, clip[0], v.w, f.half_w);
      v.py = padError(pad_clip_, 1, clip[1], v.w, f.half_h);
      v.pz = padError(pad_clip_, 2, clip[2], v.w, depth_scale);
    }
  }
}

bool TriangleSetup::pixelBounds(const SetupFrame& f, double x_min, double x_max, double y_min,
                                double y_max, Work& t) const {
  // Claims reach up to the slack (plus the sample spread) outside an edge shared with a
  // neighbour; beyond that nothing of this triangle is claimed.
  const double pad = std::max(t.s_x, t.s_y) + f.radius + 1e-3;
  const double inv = f.inv_scale, half = 0.5 * f.scale;
  // (Magnitudes are below the guard band, so the clamped values fit an int.)
  const double w = f.buffer_w, h = f.buffer_h;
  t.x0 = ceilInt(std::clamp((x_min - pad - half) * inv, 0.0, w));
  t.y0 = ceilInt(std::clamp((y_min - pad - half) * inv, 0.0, h));
  t.x1 = std::min(f.buffer_w, floorInt(std::clamp((x_max + pad - half) * inv, -1.0, w)) + 1);
  t.y1 = std::min(f.buffer_h, floorInt(std::clamp((y_max + pad - half) * inv, -1.0, h)) + 1);
  return t.x0 < t.x1 && t.y0 < t.y1;
}

bool TriangleSetup::setUp(const SetupFrame& f, const SetupObject& o, const std::uint32_t* corners,
                          std::uint32_t first_vertex, std::uint8_t closed, Work& t) const {
  const Vertex* v[3];
  for (int k = 0; k < 3; ++k) v[k] = &vertices_[corners[k] - first_vertex];
  t.clipped = !(v[0]->front && v[1]->front && v[2]->front);
  if (!t.clipped) {
    // Wholly in front of the near plane: plain window-space set-up.
    if (v[0]->beyond_far || v[1]->beyond_far || v[2]->beyond_far) return false;
    const double area = windowArea(v);
    if (!(area != 0) || !std::isfinite(area)) return false;
    if (facingAway(f, area, closed)) return false;
    const double x_min = std::min({v[0]->wx, v[1]->wx, v[2]->wx});
    const double x_max = std::max({v[0]->wx, v[1]->wx, v[2]->wx});
    const double y_min = std::min({v[0]->wy, v[1]->wy, v[2]->wy});
    const double y_max = std::max({v[0]->wy, v[1]->wy, v[2]->wy});
    const double mag =
        std::max({std::fabs(x_min), std::fabs(x_max), std::fabs(y_min), std::fabs(y_max)});
    if (!(mag < kGuardBand)) return false;
    // How far GL may move this triangle's vertices: snapping, the float error of the
    // transform, and that of clipping (GL's new vertices, its guard band) at these
    // magnitudes; never less than the object's floor. Likewise the depth margin.
    // A moving object's pad adds to both (0 for a still one: the same sums).
    t.s_x = std::max(o.s_x, f.snap + f.render_k * std::max({v[0]->ex, v[1]->ex, v[2]->ex}) +
                                std::max({v[0]->px, v[1]->px, v[2]->px}) + 16 * kU * mag);
    t.s_y = std::max(o.s_y, f.snap + f.render_k * std::max({v[0]->ey, v[1]->ey, v[2]->ey}) +
                                std::max({v[0]->py, v[1]->py, v[2]->py}) + 16 * kU * mag);
    if (!(t.s_x < kGuardBand && t.s_y < kGuardBand)) return false;  // a pad it cannot bound
    if (!pixelBounds(f, x_min, x_max, y_min, y_max, t)) return false;
    const double key_max = std::max({v[0]->key, v[1]->key, v[2]->key});
    t.key_min = std::min({v[0]->key, v[1]->key, v[2]->key});
    t.margin =
        std::max(o.margin, f.quantisation +
                               f.render_k * (std::max({v[0]->ez, v[1]->ez, v[2]->ez}) +
                                             std::max(std::fabs(t.key_min), std::fabs(key_max))) +
                               std::max({v[0]->pz, v[1]->pz, v[2]->pz}));
    if (!std::isfinite(t.margin)) return false;
    // Edge k runs from corner k+1 to corner k+2: E = a (x - x1) + b (y - y1), positive
    // inside once oriented counter-clockwise. Two triangles on the same two vertices in
    // opposite order get exactly opposite a and b.
    const double sign = area > 0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; ++k) {
      const Vertex& p = *v[(k + 1) % 3];
      const Vertex& q = *v[(k + 2) % 3];
      const double a = p.wy - q.wy, b = q.wx - p.wx;
      const double n = std::fabs(a) + std::fabs(b);
      if (!(n > 0)) return false;
      t.a[k] = sign * a / n;
      t.b[k] = sign * b / n;
      t.c[k] = -(t.a[k] * p.wx + t.b[k] * p.wy);
    }
    const double inv = 1.0 / area;
    const double dk1 = v[1]->key - v[0]->key, dk2 = v[2]->key - v[0]->key;
    t.za = (dk1 * (v[2]->wy - v[0]->wy) - dk2 * (v[1]->wy - v[0]->wy)) * inv;
    t.zb = ((v[1]->wx - v[0]->wx) * dk2 - (v[2]->wx - v[0]->wx) * dk1) * inv;
    t.zc = v[0]->key - t.za * v[0]->wx - t.zb * v[0]->wy;
    if (!std::isfinite(t.za) || !std::isfinite(t.zb) || !std::isfinite(t.zc)) return false;
    t.a[3] = 0, t.b[3] = 0, t.c[3] = 1;
    finish(f, t);
    return true;
  }
  return setUpClipped(f, o, v, t);
}

bool TriangleSetup::setUpClipped(const SetupFrame& f, const SetupObject& o, const Vertex* const* vp,
                                 Work& t) const {
  H v[3];
  for (int k = 0; k < 3; ++k) {
    const Vertex& p = *vp[k];
    v[k] = {p.x, p.y, p.w, p.k, p.sx, p.sy, p.sz, p.sw};
  }
  // Crossing the near plane (K - near_key W >= 0 in homogeneous form): GL clips it. Its
  // coverage is the triangle's region (edge functions in homogeneous form need no
  // clipping) cut by the clip line, an edge of its own.
  double d_near[3];
  int behind = 0;
  for (int k = 0; k < 3; ++k) {
    d_near[k] = v[k].k - f.near_key * v[k].w;
    if (!(d_near[k] >= 0)) ++behind;
  }
  if (behind == 3) return false;

  // The visible polygon (for its pixel bounds, magnitudes and GL's errors at its corners).
  H poly[4];
  int count = 0;
  for (int k = 0; k < 3; ++k) {
    const int n = (k + 1) % 3;
    if (d_near[k] >= 0) poly[count++] = v[k];
    if ((d_near[k] >= 0) != (d_near[n] >= 0)) {
      poly[count++] = lerp(v[k], v[n], d_near[k] / (d_near[k] - d_near[n]));
    }
  }
  double x_min = HUGE_VAL, x_max = -HUGE_VAL, y_min = HUGE_VAL, y_max = -HUGE_VAL, mag = 0;
  double err_x = 0, err_y = 0, err_z = 0, key_mag = 0;
  double pad_x = 0, pad_y = 0, pad_z = 0;  // a moving object's pad (0 for a still one)
  t.key_min = HUGE_VAL;
  const double depth_scale = std::fabs(f.key_scale);
  for (int i = 0; i < count; ++i) {
    const H& p = poly[i];
    // Beyond the far plane (GL clips it) or not in front of the eye: leave it out.
    if (!(p.w > 0) || !(f.clear_key * p.w - p.k >= 0)) return false;
    const double inv_w = 1.0 / p.w;
    const double x = p.x * inv_w, y = p.y * inv_w, key = p.k * inv_w;
    x_min = std::min(x_min, x), x_max = std::max(x_max, x);
    y_min = std::min(y_min, y), y_max = std::max(y_max, y);
    mag = std::max({mag, std::fabs(x), std::fabs(y)});
    const double xn = x / f.half_w - 1.0, yn = y / f.half_h - 1.0;
    const double zn = (key - f.key_offset) / f.key_scale;
    err_x = std::max(err_x, (p.sx + std::fabs(xn) * p.sw) * inv_w * f.half_w);
    err_y = std::max(err_y, (p.sy + std::fabs(yn) * p.sw) * inv_w * f.half_h);
    err_z = std::max(err_z, (p.sz + std::fabs(zn) * p.sw) * inv_w * depth_scale);
    pad_x = std::max(pad_x, padError(pad_clip_, 0, p.w * xn, p.w, f.half_w));
    pad_y = std::max(pad_y, padError(pad_clip_, 1, p.w * yn, p.w, f.half_h));
    pad_z = std::max(pad_z, padError(pad_clip_, 2, p.w * zn, p.w, depth_scale));
    key_mag = std::max(key_mag, std::fabs(key));
    t.key_min = std::min(t.key_min, key);
  }
  if (!(mag < kGuardBand)) return false;
  t.s_x = std::max(o.s_x, f.snap + f.render_k * err_x + pad_x + 16 * kU * mag);
  t.s_y = std::max(o.s_y, f.snap + f.render_k * err_y + pad_y + 16 * kU * mag);
  t.margin = std::max(o.margin, f.quantisation + f.render_k * (err_z + key_mag) + pad_z);
  if (!(t.s_x < kGuardBand && t.s_y < kGuardBand) || !std::isfinite(t.margin)) return false;
  if (!pixelBounds(f, x_min, x_max, y_min, y_max, t)) return false;

  // Edge k = v[k+1] x v[k+2]: E_k(p) = det[v_k+1; v_k+2; (px, py, 1)], and
  // E_k = beta_k det / W(P) for the point P of the triangle seen at p, so the inside is
  // where every E_k has the sign of det, and sum_k E_k K_k / det is the key plane.
  double a[3], b[3], c[3];
  for (int k = 0; k < 3; ++k) {
    const H& p = v[(k + 1) % 3];
    const H& q = v[(k + 2) % 3];
    a[k] = p.y * q.w - p.w * q.y;
    b[k] = p.w * q.x - p.x * q.w;
    c[k] = p.x * q.y - p.y * q.x;
  }
  const double det = a[0] * v[0].x + b[0] * v[0].y + c[0] * v[0].w;
  if (!(det != 0) || !std::isfinite(det)) return false;
  t.za = (a[0] * v[0].k + a[1] * v[1].k + a[2] * v[2].k) / det;
  t.zb = (b[0] * v[0].k + b[1] * v[1].k + b[2] * v[2].k) / det;
  t.zc = (c[0] * v[0].k + c[1] * v[1].k + c[2] * v[2].k) / det;
  if (!std::isfinite(t.za) || !std::isfinite(t.zb) || !std::isfinite(t.zc)) return false;
  const double sign = det > 0 ? 1.0 : -1.0;
  for (int k = 0; k < 3; ++k) {
    const double n = std::fabs(a[k]) + std::fabs(b[k]);
    if (!(n > 0) || !std::isfinite(n)) return false;
    t.a[k] = sign * a[k] / n;
    t.b[k] = sign * b[k] / n;
    t.c[k] = sign * c[k] / n;
  }
  const double n = std::fabs(t.za) + std::fabs(t.zb);
  if (!(n > 0)) return false;
  t.a[3] = t.za / n;
  t.b[3] = t.zb / n;
  t.c[3] = (t.zc - f.near_key) / n;
  finish(f, t);
  return true;
}

void TriangleSetup::finish(const SetupFrame& f, Work& t) const {
  // Reference point and the float error of evaluating planes relative to it: three
  // roundings of terms each at most the extent or the value at the reference, and up to
  // seven more where the kernels step down a block row by row (raster_kernel.inl).
  const double s = f.scale, r = f.radius;
  t.rx = double(t.x0) * s;
  t.ry = double(t.y0) * s;
  const double dx = double(t.x1 - t.x0) * s + s, dy = double(t.y1 - t.y0) * s + s;
  for (int k = 0; k < kTriangleEdges; ++k) {
    const double at_ref = t.a[k] * t.rx + t.b[k] * t.ry + t.c[k];
    t.c[k] = at_ref;
    t.err[k] = f.exact_coverage ? 0.0 : 24 * kU * (2 * (dx + dy) + std::fabs(at_ref)) + 1e-30;
    t.slack[k] =
        f.exact_coverage ? 0.0 : (t.s_x + r) * std::fabs(t.a[k]) + (t.s_y + r) * std::fabs(t.b[k]);
  }
  if (!t.clipped) t.slack[3] = 0, t.err[3] = 0;
  t.zc = t.za * t.rx + t.zb * t.ry + t.zc;
  t.g = std::fabs(t.za) + std::fabs(t.zb);
  t.z_err = 24 * kU * (std::fabs(t.za) * dx + std::fabs(t.zb) * dy + std::fabs(t.zc));
}

bool TriangleSetup::useGroups(bool on) {
#if LOGRID_CPU_X86
  groups_ = on && __builtin_cpu_supports("avx2");
#else
  groups_ = false;
#endif
  return groups_;
}

std::size_t TriangleSetup::run(const SetupFrame& f, const OccluderMeshes& meshes,
                               const SetupObject& o, std::vector<RasterTriangle>& out,
                               std::size_t& count) {
  const OccluderObject& obj = meshes.object(o.occluder);
  transform(f, o, meshes.positions().data() + std::size_t(obj.first_vertex) * 3, obj.vertex_count);

  if (work_.size() < obj.triangle_count) work_.resize(obj.triangle_count);
  const std::uint32_t* indices = meshes.indices().data() + std::size_t(obj.first_triangle) * 3;
  const std::uint8_t* closed = meshes.closed().data() + obj.first_triangle;
  // Groups of four triangles wholly in front of the near plane (setUpGroupAvx2), the
  // rest one at a time; w.out holds 0 for a usable triangle until numbered below.
  const bool groups = groups_ && !f.exact_coverage;
  const Vertex* lane_corners[12];
  Work* lane_work[4];
  bool lane_ok[4];
  int lanes = 0;
  const auto setUpLanes = [&] {
    for (int l = lanes; l < 4; ++l) {  // the unused lanes repeat lane 0 into a spare
      for (int k = 0; k < 3; ++k) lane_corners[3 * l + k] = lane_corners[k];
      lane_work[l] = &spare_;
    }
#if LOGRID_CPU_X86
    setUpGroupAvx2(f, o, lane_corners, lane_work, lane_ok);
#endif
    for (int l = 0; l < lanes; ++l) lane_work[l]->out = lane_ok[l] ? 0 : kNoNeighbour;
    lanes = 0;
  };
  for (std::uint32_t t = 0; t < obj.triangle_count; ++t) {
    Work& w = work_[t];
    // A mirroring transform turns a closed surface's winding round; a singular one
    // leaves no side facing away.
    const std::uint8_t c = o.orientation == 0                    ? 0
                           : o.orientation < 0 && closed[t] != 0 ? std::uint8_t(3 - closed[t])
                                                                 : closed[t];
    const std::uint32_t* corners = indices + std::size_t(t) * 3;
    if (groups) {
      const Vertex* v[3];
      for (int k = 0; k < 3; ++k) v[k] = &vertices_[corners[k] - obj.first_vertex];
      if (v[0]->front && v[1]->front && v[2]->front &&
          !(v[0]->beyond_far || v[1]->beyond_far || v[2]->beyond_far)) {
        // Facing away: left out here as setUp() leaves it out, not set up in a lane.
        if (facingAway(f, windowArea(v), c)) {
          w.out = kNoNeighbour;
          continue;
        }
        for (int k = 0; k < 3; ++k) lane_corners[3 * lanes + k] = v[k];
        lane_work[lanes] = &w;
        w.clipped = false;
        if (++lanes == 4) setUpLanes();
        continue;
      }
    }
    w.out = setUp(f, o, corners, obj.first_vertex, c, w) ? 0 : kNoNeighbour;
  }
  if (lanes > 0) setUpLanes();
  std::uint32_t next = std::uint32_t(count);
  for (std::uint32_t t = 0; t < obj.triangle_count; ++t) {
    if (work_[t].out != kNoNeighbour) work_[t].out = next++;
  }

  const std::uint32_t* adjacency = meshes.adjacency().data();
  const double r = f.radius;
  if (out.size() < next) out.resize(std::max<std::size_t>(next, 2 * out.size()));
  count = next;
  for (std::uint32_t t = 0; t < obj.triangle_count; ++t) {
    const Work& w = work_[t];
    if (w.out == kNoNeighbour) continue;
    RasterTriangle& rt = out[w.out];
    rt.interior = 0;
    for (int k = 0; k < 3; ++k) rt.band_key[k] = 0, rt.nb[k] = 0, rt.nb_edge[k] = 0;
    rt.rx = float(w.rx);
    rt.ry = float(w.ry);
    const double g = w.g, z_err = w.z_err;
    for (int k = 0; k < kTriangleEdges; ++k) {
      rt.ea[k] = float(w.a[k]);
      rt.eb[k] = float(w.b[k]);
      rt.ec[k] = float(w.c[k]);
      rt.hi[k] = float(w.slack[k] + w.err[k]);
      rt.lo[k] = f.exact_coverage ? -1e-30f : rt.hi[k];
    }
    for (int k = 0; k < 3 && !f.exact_coverage; ++k) {
      // A neighbour across edge k: a usable triangle on the edge whose normalised edge
      // function is exactly the opposite of this one's (the same two window points in
      // the other order), i.e. it lies on the other side on screen; one on the same
      // side is a fold. Where more than two triangles share the edge, any such one will do.
      const std::uint32_t self = (obj.first_triangle + t) * 3 + std::uint32_t(k);
      const Work* n = nullptr;
      int k2 = 0;
      for (std::uint32_t e = adjacency[self]; e != kNoNeighbour && e != self; e = adjacency[e]) {
        const Work& cand = work_[e / 3 - obj.first_triangle];
        const int ke = int(e % 3);
        if (cand.out != kNoNeighbour && cand.a[ke] == -w.a[k] && cand.b[ke] == -w.b[k]) {
          n = &cand;
          k2 = ke;
          break;
        }
      }
      if (!n) continue;
      rt.interior |= std::uint8_t(1u << k);
      rt.nb[k] = n->out;
      rt.nb_edge[k] = std::uint8_t(k2);
      rt.lo[k] = float(-w.slack[k]);
      if (!f.exact_depth) {
        // The neighbour's plane exceeds this one's by at most (g + g_n) times the
        // distance from the edge (at most the slack, the sample spread, and rounding),
        // and the neighbour's vertices move too.
        const double distance = std::max(w.s_x, w.s_y) + 2 * r + w.err[k] + 1e-6;
        rt.band_key[k] = floatUp(((g + n->g) * distance + std::fabs(n->za) * n->s_x +
                                  std::fabs(n->zb) * n->s_y + n->z_err) *
                                 (1 + 4 * kU));
      }
    }
    rt.za = float(w.za);
    rt.zb = float(w.zb);
    double own = std::fabs(w.za) * r + std::fabs(w.zb) * r;  // the samples' spread
    if (!f.exact_depth) own += std::fabs(w.za) * w.s_x + std::fabs(w.zb) * w.s_y + w.margin + z_err;
    rt.zc = floatUp(w.zc + own);  // never below the double bound
    // Every claimed sample lies within the slack and the spread of the triangle, where
    // the plane is at least its nearest vertex's key less the gradient over that reach.
    const double reach = std::max(w.s_x, w.s_y) + r + 1e-3;
    rt.zmin = floatDown(w.key_min - g * reach - z_err);
    // The kernels classify blocks from corner values: each a sum of two products and a
    // constant, rounded four times, every term at most the samples' reach or |ec|.
    double ec_max = 0;
    for (int k = 0; k < kTriangleEdges; ++k) ec_max = std::max(ec_max, std::fabs(w.c[k]));
    const double reach_px = double(w.x1 - w.x0 + 1) * f.scale + double(w.y1 - w.y0 + 1) * f.scale;
    rt.block_tol = floatUp(8 * kU * (2 * reach_px + ec_max) + 1e-30);
    rt.x0 = w.x0, rt.y0 = w.y0, rt.x1 = w.x1, rt.y1 = w.y1;
  }
  return obj.triangle_count;
}

}  // namespace logrid::cpu::detail
