#include "triangle_setup.hpp"

#include <algorithm>
#include <cmath>

namespace logrid::cpu::detail {
namespace {

constexpr double kU = 1.0 / 16777216.0;  // float unit roundoff, 2^-24
// Window coordinates beyond this many pixels are too coarse in float for the kernels.
constexpr double kGuardBand = 4194304.0;  // 2^22

struct H {
  double x, y, w, k;
};

H lerp(const H& a, const H& b, double t) {
  return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.w + t * (b.w - a.w),
          a.k + t * (b.k - a.k)};
}

}  // namespace

bool TriangleSetup::setUp(const SetupFrame& f, const SetupObject& o, const std::uint32_t* corners,
                          std::uint32_t first_vertex, Work& t) const {
  H v[3];
  for (int k = 0; k < 3; ++k) {
    const Vertex& p = vertices_[corners[k] - first_vertex];
    v[k] = {p.x, p.y, p.w, p.k};
  }
  // Near plane: key >= near key, i.e. K - near_key W >= 0 in homogeneous form. A
  // triangle that crosses it is clipped by GL; its coverage is the triangle's region
  // (edge functions in homogeneous form need no clipping) cut by the clip line.
  double d_near[3];
  int behind = 0;
  for (int k = 0; k < 3; ++k) {
    d_near[k] = v[k].k - f.near_key * v[k].w;
    if (!(d_near[k] >= 0)) ++behind;
  }
  if (behind == 3) return false;
  t.clipped = behind > 0;

  // The visible polygon (for its pixel bounds and magnitudes).
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
  for (int i = 0; i < count; ++i) {
    const H& p = poly[i];
    // Beyond the far plane (GL clips it) or not in front of the eye: leave it out.
    if (!(p.w > 0) || !(f.clear_key * p.w - p.k >= 0)) return false;
    const double x = p.x / p.w, y = p.y / p.w;
    x_min = std::min(x_min, x), x_max = std::max(x_max, x);
    y_min = std::min(y_min, y), y_max = std::max(y_max, y);
    mag = std::max({mag, std::fabs(x), std::fabs(y)});
  }
  if (!(mag < kGuardBand)) return false;

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
  if (t.clipped) {
    const double n = std::fabs(t.za) + std::fabs(t.zb);
    if (!(n > 0)) return false;
    t.a[3] = t.za / n;
    t.b[3] = t.zb / n;
    t.c[3] = (t.zc - f.near_key) / n;
  } else {
    t.a[3] = 0, t.b[3] = 0, t.c[3] = 1;
  }

  // How far GL may move this triangle's vertices: the object's bound, plus the float
  // error of clipping (GL's new vertices, its guard band) at these magnitudes.
  t.s_x = o.s_x + 16 * kU * mag;
  t.s_y = o.s_y + 16 * kU * mag;
  const double r = f.radius;
  // Claims reach up to the slack (plus the sample spread) outside an edge shared with a
  // neighbour; beyond that nothing of this triangle is claimed.
  const double pad = std::max(t.s_x, t.s_y) + r + 1e-3;
  const double s = f.scale, half = 0.5 * s;
  t.x0 = std::int32_t(std::max(0.0, std::ceil((x_min - pad - half) / s)));
  t.y0 = std::int32_t(std::max(0.0, std::ceil((y_min - pad - half) / s)));
  t.x1 = std::int32_t(std::min(double(f.buffer_w), std::floor((x_max + pad - half) / s) + 1));
  t.y1 = std::int32_t(std::min(double(f.buffer_h), std::floor((y_max + pad - half) / s) + 1));
  if (t.x0 >= t.x1 || t.y0 >= t.y1) return false;

  // Reference point and the float error of evaluating planes relative to it: three
  // roundings of terms each at most the extent or the value at the reference.
  t.rx = double(t.x0) * s;
  t.ry = double(t.y0) * s;
  const double dx = double(t.x1 - t.x0) * s + s, dy = double(t.y1 - t.y0) * s + s;
  for (int k = 0; k < kTriangleEdges; ++k) {
    const double at_ref = t.a[k] * t.rx + t.b[k] * t.ry + t.c[k];
    t.c[k] = at_ref;
    t.err[k] = f.exact_coverage ? 0.0 : 8 * kU * (2 * (dx + dy) + std::fabs(at_ref)) + 1e-30;
    t.slack[k] =
        f.exact_coverage ? 0.0 : (t.s_x + r) * std::fabs(t.a[k]) + (t.s_y + r) * std::fabs(t.b[k]);
  }
  if (!t.clipped) t.slack[3] = 0, t.err[3] = 0;
  t.zc = t.za * t.rx + t.zb * t.ry + t.zc;
  return true;
}

std::size_t TriangleSetup::run(const SetupFrame& f, const OccluderMeshes& meshes,
                               const SetupObject& o, std::vector<RasterTriangle>& out) {
  const OccluderObject& obj = meshes.object(o.occluder);
  vertices_.resize(obj.vertex_count);
  const float* positions = meshes.positions().data() + std::size_t(obj.first_vertex) * 3;
  for (std::uint32_t i = 0; i < obj.vertex_count; ++i) {
    const double x = positions[i * 3], y = positions[i * 3 + 1], z = positions[i * 3 + 2];
    double clip[4];
    for (int r = 0; r < 4; ++r)
      clip[r] = f.m[r] * x + f.m[4 + r] * y + f.m[8 + r] * z + f.m[12 + r];
    vertices_[i] = {(clip[0] + clip[3]) * f.half_w, (clip[1] + clip[3]) * f.half_h, clip[3],
                    f.key_scale * clip[2] + f.key_offset * clip[3]};
  }

  work_.resize(obj.triangle_count);
  const std::uint32_t* indices = meshes.indices().data() + std::size_t(obj.first_triangle) * 3;
  std::uint32_t next = std::uint32_t(out.size());
  for (std::uint32_t t = 0; t < obj.triangle_count; ++t) {
    Work& w = work_[t];
    w.out = setUp(f, o, indices + std::size_t(t) * 3, obj.first_vertex, w) ? next++ : kNoNeighbour;
  }

  const std::uint32_t* adjacency = meshes.adjacency().data() + std::size_t(obj.first_triangle) * 3;
  const double r = f.radius;
  for (std::uint32_t t = 0; t < obj.triangle_count; ++t) {
    const Work& w = work_[t];
    if (w.out == kNoNeighbour) continue;
    RasterTriangle rt;
    rt.rx = float(w.rx);
    rt.ry = float(w.ry);
    const double g = std::fabs(w.za) + std::fabs(w.zb);
    const double z_err = 8 * kU *
                         (std::fabs(w.za) * (w.x1 - w.x0 + 1) * f.scale +
                          std::fabs(w.zb) * (w.y1 - w.y0 + 1) * f.scale + std::fabs(w.zc));
    for (int k = 0; k < kTriangleEdges; ++k) {
      rt.ea[k] = float(w.a[k]);
      rt.eb[k] = float(w.b[k]);
      rt.ec[k] = float(w.c[k]);
      rt.hi[k] = float(w.slack[k] + w.err[k]);
      rt.lo[k] = f.exact_coverage ? -1e-30f : rt.hi[k];
    }
    for (int k = 0; k < 3 && !f.exact_coverage; ++k) {
      const std::uint32_t nb = adjacency[t * 3 + std::uint32_t(k)];
      if (nb == kNoNeighbour) continue;
      const std::uint32_t t2 = nb / 3 - obj.first_triangle;
      const int k2 = int(nb % 3);
      const Work& n = work_[t2];
      // Neighbours on opposite sides of the shared edge have exactly opposite normalised
      // edge functions (the same cross product, negated); the same side is a fold.
      if (n.out == kNoNeighbour || n.a[k2] != -w.a[k] || n.b[k2] != -w.b[k]) continue;
      rt.interior |= std::uint8_t(1u << k);
      rt.nb[k] = n.out;
      rt.nb_edge[k] = std::uint8_t(k2);
      rt.lo[k] = float(-w.slack[k]);
      if (!f.exact_depth) {
        // The neighbour's plane exceeds this one's by at most (g + g_n) times the
        // distance from the edge (at most the slack, the sample spread, and rounding),
        // and the neighbour's vertices move too.
        const double gn = std::fabs(n.za) + std::fabs(n.zb);
        const double distance = std::max(w.s_x, w.s_y) + 2 * r + w.err[k] + 1e-6;
        const double n_err = 8 * kU *
                             (std::fabs(n.za) * (n.x1 - n.x0 + 1) * f.scale +
                              std::fabs(n.zb) * (n.y1 - n.y0 + 1) * f.scale + std::fabs(n.zc));
        rt.band_key[k] =
            float((g + gn) * distance + std::fabs(n.za) * n.s_x + std::fabs(n.zb) * n.s_y + n_err) *
            (1 + 4 * float(kU));
      }
    }
    rt.za = float(w.za);
    rt.zb = float(w.zb);
    double own = std::fabs(w.za) * r + std::fabs(w.zb) * r;  // the samples' spread
    if (!f.exact_depth) own += std::fabs(w.za) * w.s_x + std::fabs(w.zb) * w.s_y + o.margin + z_err;
    // Rounded up, so that the float bound is never below the double one.
    const double bound = w.zc + own;
    float zc = float(bound);
    if (double(zc) < bound) zc = std::nextafter(zc, HUGE_VALF);
    rt.zc = zc;
    (void)g;
    rt.x0 = w.x0, rt.y0 = w.y0, rt.x1 = w.x1, rt.y1 = w.y1;
    out.push_back(rt);
  }
  return obj.triangle_count;
}

}  // namespace logrid::cpu::detail
