// Small triangle scenes for the DDO tests: welded walls (with or without a hole or a
// crack), closed boxes, random triangles, and a brute-force check that a face marked
// valid is hidden behind geometry from every sampled viewpoint of its region.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "logrid/ddo/mesh.hpp"
#include "logrid/ddo/octree.hpp"

namespace logrid::test {

struct TriangleScene {
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  std::vector<std::uint32_t> object_first{0};

  ddo::SceneMesh mesh() const { return {positions, indices, object_first}; }
  std::uint32_t vertex(double x, double y, double z) {
    positions.insert(positions.end(), {float(x), float(y), float(z)});
    return std::uint32_t(positions.size() / 3 - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    indices.insert(indices.end(), {a, b, c});
  }
  void endObject() { object_first.push_back(std::uint32_t(indices.size() / 3)); }

  // A wall in the plane `axis` = at, spanning [u0, u1] x [v0, v1] on the other two axes
  // (in cyclic order), as n x n welded quads. `skip` leaves out quad (skip_i, skip_j);
  // `crack` duplicates the vertices of column `crack_column` moved by `crack` along u, so
  // the wall has a seam there that no edge shares.
  struct WallOptions {
    int n = 4;
    int skip_i = -1, skip_j = -1;
    int crack_column = -1;
    double crack = 0;
  };
  void wall(int axis, double at, double u0, double u1, double v0, double v1, const WallOptions& o) {
    const int t1 = (axis + 1) % 3, t2 = (axis + 2) % 3;
    auto point = [&](double u, double v) {
      double p[3];
      p[axis] = at, p[t1] = u, p[t2] = v;
      return vertex(p[0], p[1], p[2]);
    };
    std::vector<std::uint32_t> left(std::size_t(o.n + 1) * std::size_t(o.n + 1)), right = left;
    for (int i = 0; i <= o.n; ++i) {
      for (int j = 0; j <= o.n; ++j) {
        const double u = u0 + (u1 - u0) * i / o.n, v = v0 + (v1 - v0) * j / o.n;
        const std::size_t k = std::size_t(i) * std::size_t(o.n + 1) + std::size_t(j);
        left[k] = right[k] = point(u, v);
        if (i == o.crack_column) right[k] = point(u + o.crack, v);
      }
    }
    for (int i = 0; i < o.n; ++i) {
      for (int j = 0; j < o.n; ++j) {
        if (i == o.skip_i && j == o.skip_j) continue;
        auto at_ = [&](int a, int b) {
          const std::size_t k = std::size_t(a) * std::size_t(o.n + 1) + std::size_t(b);
          return a == i ? right[k] : left[k];  // the quad's left column uses `right` copies
        };
        const std::uint32_t a = at_(i, j), b = at_(i + 1, j), c = at_(i + 1, j + 1),
                            d = at_(i, j + 1);
        triangle(a, b, c);
        triangle(a, c, d);
      }
    }
    endObject();
  }
  // A closed box, 8 welded corners.
  void box(const double* lo, const double* hi) {
    std::uint32_t v[8];
    for (int i = 0; i < 8; ++i) {
      v[i] = vertex((i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1], (i & 4) ? hi[2] : lo[2]);
    }
    static const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& t : f) triangle(v[t[0]], v[t[1]], v[t[2]]);
    endObject();
  }
  // Random small triangles in [lo, hi]^3, one object.
  void clutter(std::mt19937& rng, int count, double lo, double hi, double size) {
    std::uniform_real_distribution<double> pos(lo, hi), d(-size, size);
    for (int i = 0; i < count; ++i) {
      const double c[3] = {pos(rng), pos(rng), pos(rng)};
      std::uint32_t v[3];
      for (auto& k : v) k = vertex(c[0] + d(rng), c[1] + d(rng), c[2] + d(rng));
      triangle(v[0], v[1], v[2]);
    }
    endObject();
  }
};

// Does the segment p-q meet triangle (a, b, c) at a parameter in (0, 1 - 1e-9)? Edges and
// vertices count (a segment through a shared edge is blocked by the two triangles).
inline bool segmentHitsTriangle(const double* p, const double* q, const float* a, const float* b,
                                const float* c) {
  const double e1[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
  const double e2[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
  const double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
  const double h[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                       d[0] * e2[1] - d[1] * e2[0]};
  const double det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
  if (std::fabs(det) < 1e-300) return false;
  const double inv = 1.0 / det;
  const double s[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double u = inv * (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]);
  const double qv[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                        s[0] * e1[1] - s[1] * e1[0]};
  const double v = inv * (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]);
  const double t = inv * (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]);
  constexpr double kEdge = 1e-9;
  return u >= -kEdge && v >= -kEdge && u + v <= 1 + kEdge && t > 0 && t < 1 - 1e-9;
}

inline bool segmentBlocked(const TriangleScene& s, const double* p, const double* q) {
  for (std::size_t t = 0; t < s.indices.size(); t += 3) {
    if (segmentHitsTriangle(p, q, &s.positions[s.indices[t] * 3],
                            &s.positions[s.indices[t + 1] * 3],
                            &s.positions[s.indices[t + 2] * 3])) {
      return true;
    }
  }
  return false;
}

// A viewpoint of region `r` of `face`: an anchor on the enlarged face, slopes in the
// region's cell, a height from H to 30 H. `extreme` picks corners of each range.
inline void regionViewpoint(const ddo::FaceFrame& f, const ddo::SlopeCell& c, std::mt19937& rng,
                            bool extreme, double* out) {
  std::uniform_real_distribution<double> unit(0, 1);
  auto pick = [&](double lo, double hi) {
    if (extreme) return unit(rng) < 0.5 ? lo : hi;
    return lo + (hi - lo) * unit(rng);
  };
  const double m = f.margin;
  const double a1 = pick(f.lo1 - m, f.hi1 + m), a2 = pick(f.lo2 - m, f.hi2 + m);
  const double s1 = pick(c.lo1, c.hi1), s2 = pick(c.lo2, c.hi2);
  const double h = extreme ? f.height * (unit(rng) < 0.5 ? 1.0 : 30.0)
                           : f.height * (1.0 + 29.0 * unit(rng) * unit(rng));
  f.toWorld(h, a1 + h * s1, a2 + h * s2, out);
  if (h == f.height) out[f.axis] = f.clip_plane;
}

// A point of the enlarged face: corners, edge points or interior points.
inline void facePoint(const ddo::FaceFrame& f, std::mt19937& rng, int kind, double* out) {
  std::uniform_real_distribution<double> unit(0, 1);
  const double m = f.margin;
  double u = unit(rng), v = unit(rng);
  if (kind == 0) u = std::round(u), v = std::round(v);  // a corner
  if (kind == 1) u = std::round(u);                     // an edge
  f.toWorld(0, f.lo1 - m + u * (f.hi1 - f.lo1 + 2 * m), f.lo2 - m + v * (f.hi2 - f.lo2 + 2 * m),
            out);
  out[f.axis] = f.plane;
}

struct BruteForceResult {
  std::uint64_t valid_bits = 0;    // (node, face, region) marked valid
  std::uint64_t checked_bits = 0;  // of those, checked with segments
  std::uint64_t segments = 0;
  std::uint64_t unblocked = 0;  // segments that reached a face marked valid: must stay 0
};

// For up to `max_bits` valid (node, face, region) triples (spread evenly over all of
// them), casts `per_bit` segments from viewpoints of the region to points of the face
// and counts those that no triangle blocks.
inline BruteForceResult bruteForceCheck(const TriangleScene& scene, const ddo::Octree& octree,
                                        std::uint64_t max_bits, int per_bit,
                                        std::uint32_t seed = 7) {
  BruteForceResult r;
  for (std::uint32_t n = 0; n < octree.nodes().size(); ++n) {
    for (int f = 0; f < ddo::kFaces; ++f) {
      r.valid_bits += std::uint64_t(__builtin_popcountll(octree.mask(n, f)));
    }
  }
  const std::uint64_t stride =
      std::max<std::uint64_t>(1, r.valid_bits / std::max<std::uint64_t>(1, max_bits));
  std::mt19937 rng(seed);
  std::uint64_t index = 0;
  for (std::uint32_t n = 0; n < octree.nodes().size(); ++n) {
    for (int f = 0; f < ddo::kFaces; ++f) {
      const ddo::FaceFrame frame = octree.face(n, f);
      for (std::uint32_t region = 0; region < octree.layout().count(); ++region) {
        if (!octree.valid(n, f, region)) continue;
        if (index++ % stride != 0) continue;
        ++r.checked_bits;
        const ddo::SlopeCell cell = octree.layout().cell(region);
        for (int s = 0; s < per_bit; ++s) {
          double v[3], q[3];
          regionViewpoint(frame, cell, rng, s % 4 == 0, v);
          facePoint(frame, rng, s % 3, q);
          ++r.segments;
          if (!segmentBlocked(scene, v, q)) {
            ++r.unblocked;
            ADD_FAILURE() << "node " << n << " face " << f << " region " << region
                          << ": segment from (" << v[0] << ", " << v[1] << ", " << v[2] << ") to ("
                          << q[0] << ", " << q[1] << ", " << q[2]
                          << ") reaches the face, which is marked valid";
            if (r.unblocked > 5) return r;
          }
        }
      }
    }
  }
  return r;
}

}  // namespace logrid::test
