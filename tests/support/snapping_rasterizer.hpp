// A reference rasteriser that behaves like the GL rasterisers the CPU occlusion buffer
// must stay behind (occlusion_buffer.hpp): triangles clipped at the near and far planes,
// window vertices snapped to a sub-pixel grid (rounded, truncated, or either, chosen per
// position as an implementation might), pixel centres covered by a top-left tie rule,
// depth either interpolated from the snapped vertices (a GPU) or from the plane of the
// unsnapped vertices at the centre (Mesa's llvmpipe, which extrapolates it), clamped,
// quantised to the depth format and depth-tested. Double precision: it models snapping
// and quantisation, not GL's float transform (the depth margin covers that, and the GL
// tests check it on real frames).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <tuple>
#include <vector>

#include "logrid/camera.hpp"
#include "occluder_scenes.hpp"

namespace logrid::test {

enum class SnapMode : std::uint8_t { Round, Truncate, Either };
enum class DepthModel : std::uint8_t { SnappedVertices, FloatPlane };

class SnappingRasterizer {
 public:
  SnappingRasterizer(const Camera& camera, int subpixel_bits, SnapMode snap, DepthModel model)
      : cam_(camera), step_(std::ldexp(1.0, -subpixel_bits)), snap_(snap), model_(model) {
    const bool reversed = camera.depth.convention == DepthConvention::Reversed;
    const bool zero_to_one = camera.depth.clip_range == ClipDepthRange::ZeroToOne;
    sign_ = reversed ? -1.0 : 1.0;
    key_scale_ = sign_ * (zero_to_one ? 1.0 : 0.5);
    key_offset_ = sign_ * (zero_to_one ? 0.0 : 0.5);
    near_key_ = nearPlaneKey(camera.depth);
    clear_key_ = clearKey(camera.depth);
    keys_.assign(std::size_t(camera.width) * camera.height, clearKey(camera.depth));
  }

  const std::vector<float>& keys() const { return keys_; }

  void draw(const TestMesh& mesh) {
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      P v[3];
      for (int k = 0; k < 3; ++k)
        v[k] = transform(&mesh.positions[mesh.indices[t + std::size_t(k)] * 3]);
      drawTriangle(v);
    }
  }

 private:
  struct P {
    double x, y, w, k;  // homogeneous window x, y, clip w, homogeneous key
    double sx, sy, sz;  // the source position (to order clip computations)
  };

  P transform(const float* p) const {
    const Mat4d& m = cam_.view_projection;
    double c[4];
    for (int r = 0; r < 4; ++r) {
      c[r] = m.m[r] * p[0] + m.m[4 + r] * p[1] + m.m[8 + r] * p[2] + m.m[12 + r];
    }
    return {(c[0] + c[3]) * 0.5 * cam_.width,
            (c[1] + c[3]) * 0.5 * cam_.height,
            c[3],
            key_scale_ * c[2] + key_offset_ * c[3],
            p[0],
            p[1],
            p[2]};
  }

  // The point where segment a-b crosses d = 0, computed the same way in both directions.
  static P cross(P a, P b, double da, double db) {
    if (std::tie(b.sx, b.sy, b.sz) < std::tie(a.sx, a.sy, a.sz)) {
      std::swap(a, b);
      std::swap(da, db);
    }
    const double t = da / (da - db);
    P r;
    r.x = a.x + t * (b.x - a.x);
    r.y = a.y + t * (b.y - a.y);
    r.w = a.w + t * (b.w - a.w);
    r.k = a.k + t * (b.k - a.k);
    r.sx = a.sx + t * (b.sx - a.sx);
    r.sy = a.sy + t * (b.sy - a.sy);
    r.sz = a.sz + t * (b.sz - a.sz);
    return r;
  }

  template <typename D>
  static std::vector<P> clip(const std::vector<P>& in, D distance) {
    std::vector<P> out;
    for (std::size_t i = 0; i < in.size(); ++i) {
      const P& a = in[i];
      const P& b = in[(i + 1) % in.size()];
      const double da = distance(a), db = distance(b);
      if (da >= 0) out.push_back(a);
      if ((da >= 0) != (db >= 0)) out.push_back(cross(a, b, da, db));
    }
    return out;
  }

  double snap(double v, double other) const {
    bool round = snap_ == SnapMode::Round;
    if (snap_ == SnapMode::Either) {
      std::uint64_t bits[2];
      std::memcpy(&bits[0], &v, 8);
      std::memcpy(&bits[1], &other, 8);
      round = ((bits[0] * 0x9E3779B97F4A7C15ull) ^ (bits[1] * 0xBF58476D1CE4E5B9ull)) >> 63;
    }
    return (round ? std::nearbyint(v / step_) : std::floor(v / step_)) * step_;
  }

  void drawTriangle(const P* v) {
    std::vector<P> poly(v, v + 3);
    poly = clip(poly, [&](const P& p) { return p.k - near_key_ * p.w; });
    if (poly.size() < 3) return;
    poly = clip(poly, [&](const P& p) { return clear_key_ * p.w - p.k; });
    if (poly.size() < 3) return;
    struct W {
      double x, y, k, xs, ys;
    };
    std::vector<W> win;
    for (const P& p : poly) {
      if (!(p.w > 0)) return;
      const double x = p.x / p.w, y = p.y / p.w;
      win.push_back({x, y, p.k / p.w, snap(x, y), snap(y, x)});
    }
    for (std::size_t i = 1; i + 1 < win.size(); ++i) fill(win[0], win[i], win[i + 1]);
  }

  template <typename T>
  void fill(T a, T b, T c) {
    double area = (b.xs - a.xs) * (c.ys - a.ys) - (c.xs - a.xs) * (b.ys - a.ys);
    if (area == 0) return;
    if (area < 0) {
      std::swap(b, c);
      area = -area;
    }
    const T* v[3] = {&a, &b, &c};
    const double uarea = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    const int x0 = std::max(0, int(std::floor(std::min({a.xs, b.xs, c.xs}))));
    const int x1 = std::min(int(cam_.width) - 1, int(std::ceil(std::max({a.xs, b.xs, c.xs}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.ys, b.ys, c.ys}))));
    const int y1 = std::min(int(cam_.height) - 1, int(std::ceil(std::max({a.ys, b.ys, c.ys}))));
    for (int py = y0; py <= y1; ++py) {
      for (int px = x0; px <= x1; ++px) {
        const double cx = px + 0.5, cy = py + 0.5;
        double e[3];
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k) {
          const T& p = *v[(k + 1) % 3];
          const T& q = *v[(k + 2) % 3];
          const double dx = q.xs - p.xs, dy = q.ys - p.ys;
          e[k] = dx * (cy - p.ys) - dy * (cx - p.xs);  // exact: multiples of the step
          // Top-left style tie rule: a fixed perturbation direction, so a centre on an
          // edge shared by two triangles on opposite sides goes to exactly one of them.
          inside = e[k] > 0 || (e[k] == 0 && (dy > 0 || (dy == 0 && dx < 0)));
        }
        if (!inside) continue;
        double key;
        if (model_ == DepthModel::SnappedVertices) {
          key = (e[0] * a.k + e[1] * b.k + e[2] * c.k) / area;
        } else {
          if (uarea == 0) continue;
          double f[3];
          for (int k = 0; k < 3; ++k) {
            const T& p = *v[(k + 1) % 3];
            const T& q = *v[(k + 2) % 3];
            f[k] = (q.x - p.x) * (cy - p.y) - (q.y - p.y) * (cx - p.x);
          }
          key = (f[0] * a.k + f[1] * b.k + f[2] * c.k) / uarea;
        }
        store(px, py, key);
      }
    }
  }

  void store(int px, int py, double key) {
    double depth = std::clamp(sign_ * key, 0.0, 1.0);
    switch (cam_.depth.format) {
      case DepthFormat::D16: depth = std::nearbyint(depth * 65535.0) / 65535.0; break;
      case DepthFormat::D24: depth = std::nearbyint(depth * 16777215.0) / 16777215.0; break;
      case DepthFormat::D32F: break;
    }
    const float k = float(sign_ * float(depth));
    float& s = keys_[std::size_t(py) * cam_.width + std::size_t(px)];
    if (k < s) s = k;
  }

  Camera cam_;
  double step_;
  SnapMode snap_;
  DepthModel model_;
  double sign_, key_scale_, key_offset_, near_key_, clear_key_;
  std::vector<float> keys_;
};

}  // namespace logrid::test
