#include "logrid/cpu/software_rasterizer.hpp"

#include <algorithm>
#include <cmath>

namespace logrid::cpu {

SoftwareRasterizer::SoftwareRasterizer(const Camera& camera, SoftwareDepthBuffer& depth,
                                       std::vector<std::uint32_t>* ids, Coverage coverage)
    : camera_(camera), depth_(depth), ids_(ids), coverage_(coverage) {
  const Mat4d m = multiply(camera.view_projection, translation(camera.render_origin));
  for (int i = 0; i < 16; ++i) m_[i] = static_cast<float>(m.m[i]);
  const bool reversed = camera.depth.convention == DepthConvention::Reversed;
  const bool zero_to_one = camera.depth.clip_range == ClipDepthRange::ZeroToOne;
  const float low = zero_to_one ? 0.0f : -1.0f;
  const float ge_low[4] = {0, 0, 1, -low}, le_one[4] = {0, 0, -1, 1};
  std::copy_n(reversed ? le_one : ge_low, 4, near_plane_);
  std::copy_n(reversed ? ge_low : le_one, 4, far_plane_);
  depth_scale_ = zero_to_one ? 1.0f : 0.5f;
  depth_offset_ = zero_to_one ? 0.0f : 0.5f;
}

void SoftwareRasterizer::draw(const std::vector<float>& positions,
                              const std::vector<std::uint32_t>& indices, std::uint32_t id) {
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    drawTriangle(&positions[indices[t] * 3], &positions[indices[t + 1] * 3],
                 &positions[indices[t + 2] * 3], id);
  }
}

void SoftwareRasterizer::drawTriangle(const float* a, const float* b, const float* c,
                                      std::uint32_t id) {
  const float* in[3] = {a, b, c};
  std::vector<V> poly(3);
  const DVec3& o = camera_.render_origin;
  for (int k = 0; k < 3; ++k) {
    const float q[3] = {float(in[k][0] - o.x), float(in[k][1] - o.y), float(in[k][2] - o.z)};
    for (int r = 0; r < 4; ++r) {
      poly[std::size_t(k)].c[r] = m_[r] * q[0] + m_[4 + r] * q[1] + m_[8 + r] * q[2] + m_[12 + r];
    }
  }
  // Sutherland-Hodgman against the near and far planes.
  for (const float* plane : {near_plane_, far_plane_}) {
    std::vector<V> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const V& p = poly[i];
      const V& q = poly[(i + 1) % poly.size()];
      const float dp =
          plane[0] * p.c[0] + plane[1] * p.c[1] + plane[2] * p.c[2] + plane[3] * p.c[3];
      const float dq =
          plane[0] * q.c[0] + plane[1] * q.c[1] + plane[2] * q.c[2] + plane[3] * q.c[3];
      if (dp >= 0) out.push_back(p);
      if ((dp >= 0) != (dq >= 0)) {
        const float t = dp / (dp - dq);
        V x;
        for (int r = 0; r < 4; ++r) x.c[r] = p.c[r] + t * (q.c[r] - p.c[r]);
        out.push_back(x);
      }
    }
    poly.swap(out);
    if (poly.size() < 3) return;
  }
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) rasterize(poly[0], poly[i], poly[i + 1], id);
}

void SoftwareRasterizer::rasterize(const V& a, const V& b, const V& c, std::uint32_t id) {
  const V* v[3] = {&a, &b, &c};
  float x[3], y[3], z[3];
  const float w_px = float(camera_.width), h_px = float(camera_.height);
  for (int k = 0; k < 3; ++k) {
    const float w = v[k]->c[3];
    if (!(w > 0)) return;
    x[k] = (v[k]->c[0] / w * 0.5f + 0.5f) * w_px;
    y[k] = (v[k]->c[1] / w * 0.5f + 0.5f) * h_px;
    z[k] = v[k]->c[2] / w * depth_scale_ + depth_offset_;
  }
  const double area =
      (double(x[1]) - x[0]) * (double(y[2]) - y[0]) - (double(x[2]) - x[0]) * (double(y[1]) - y[0]);
  if (area == 0 || !std::isfinite(area)) return;
  const int x0 = std::max(0, int(std::floor(std::min({x[0], x[1], x[2]}))));
  const int x1 = std::min(int(camera_.width) - 1, int(std::ceil(std::max({x[0], x[1], x[2]}))));
  const int y0 = std::max(0, int(std::floor(std::min({y[0], y[1], y[2]}))));
  const int y1 = std::min(int(camera_.height) - 1, int(std::ceil(std::max({y[0], y[1], y[2]}))));
  const bool reversed = camera_.depth.convention == DepthConvention::Reversed;
  // Inner coverage: e[k] = distance to edge k * |edge k| / |area|. Snapping moves each
  // vertex by up to one sub-pixel step per axis (1/16 pixel if a rasteriser truncates
  // with GL's minimum of 4 bits), which shifts an edge along its normal by up to
  // step * (|dx| + |dy|) / |edge k|; the float window coordinates add a few ulps of the
  // largest coordinate. A centre farther inside than both is covered by any GL.
  const double largest = std::max({std::fabs(x[0]), std::fabs(x[1]), std::fabs(x[2]),
                                   std::fabs(y[0]), std::fabs(y[1]), std::fabs(y[2])});
  const double slack = 1.0 / 16.0 + 8.0 * 1.2e-7 * largest;
  double inner[3];
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double dx = std::fabs(double(x[j]) - x[i]), dy = std::fabs(double(y[j]) - y[i]);
    inner[k] = slack * (dx + dy) / std::fabs(area);
  }
  for (int py = y0; py <= y1; ++py) {
    for (int px = x0; px <= x1; ++px) {
      const double sx = px + 0.5, sy = py + 0.5;
      double e[3];
      for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        e[k] = ((double(x[j]) - x[i]) * (sy - y[i]) - (double(y[j]) - y[i]) * (sx - x[i])) / area;
      }
      if (e[0] < 0 || e[1] < 0 || e[2] < 0) continue;
      if (coverage_ == Coverage::Inner &&
          !(e[0] > inner[0] && e[1] > inner[1] && e[2] > inner[2])) {
        continue;
      }
      float d = float(e[0] * z[0] + e[1] * z[1] + e[2] * z[2]);
      d = std::clamp(d, 0.0f, 1.0f);
      float& stored = depth_.data()[std::size_t(py) * camera_.width + std::size_t(px)];
      if (reversed ? d > stored : d < stored) {
        stored = d;
        if (ids_) (*ids_)[std::size_t(py) * camera_.width + std::size_t(px)] = id;
      }
    }
  }
}

void appendBox(const Aabb& box, std::vector<float>& positions,
               std::vector<std::uint32_t>& indices) {
  const std::uint32_t base = static_cast<std::uint32_t>(positions.size() / 3);
  for (int i = 0; i < 8; ++i) {
    positions.push_back((i & 1) ? box.max.x : box.min.x);
    positions.push_back((i & 2) ? box.max.y : box.min.y);
    positions.push_back((i & 4) ? box.max.z : box.min.z);
  }
  static const std::uint32_t faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                             {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                             {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) {
    for (std::uint32_t k : f) indices.push_back(base + k);
  }
}

}  // namespace logrid::cpu
