// Meshes and cameras for the CPU occlusion buffer's tests (tests/unit/occlusion_buffer_test.cpp,
// tests/gl/occlusion_buffer_gl_test.cpp): closed meshes with shared vertices (boxes, UV
// spheres), open ones (height fields), meshes with seams that share positions but not
// indices, sliver fans, triangle soups, and a ground quad reaching behind the eye.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/cpu/occlusion_buffer.hpp"
#include "logrid/cpu/software_rasterizer.hpp"

namespace logrid::test {

struct TestMesh {
  std::vector<float> positions;  // xyz
  std::vector<std::uint32_t> indices;
};

inline void addVertex(TestMesh& m, double x, double y, double z) {
  m.positions.push_back(float(x));
  m.positions.push_back(float(y));
  m.positions.push_back(float(z));
}

inline std::uint32_t vertexCount(const TestMesh& m) {
  return std::uint32_t(m.positions.size() / 3);
}

// A UV sphere (or ellipsoid) with shared vertices: closed, consistently wound.
inline TestMesh sphere(double cx, double cy, double cz, double rx, double ry, double rz, int slices,
                       int stacks) {
  TestMesh m;
  addVertex(m, cx, cy + ry, cz);
  for (int k = 1; k < stacks; ++k) {
    const double phi = M_PI * k / stacks;
    for (int s = 0; s < slices; ++s) {
      const double a = 2 * M_PI * s / slices;
      addVertex(m, cx + rx * std::sin(phi) * std::cos(a), cy + ry * std::cos(phi),
                cz + rz * std::sin(phi) * std::sin(a));
    }
  }
  addVertex(m, cx, cy - ry, cz);
  const std::uint32_t bottom = vertexCount(m) - 1;
  auto ring = [&](int k, int s) { return std::uint32_t(1 + k * slices + (s % slices)); };
  for (int s = 0; s < slices; ++s) {
    m.indices.insert(m.indices.end(), {0u, ring(0, s + 1), ring(0, s)});
    for (int k = 0; k + 1 < stacks - 1; ++k) {
      m.indices.insert(m.indices.end(), {ring(k, s), ring(k, s + 1), ring(k + 1, s + 1)});
      m.indices.insert(m.indices.end(), {ring(k, s), ring(k + 1, s + 1), ring(k + 1, s)});
    }
    m.indices.insert(m.indices.end(), {bottom, ring(stacks - 2, s), ring(stacks - 2, s + 1)});
  }
  return m;
}

inline TestMesh box(const Aabb& b) {
  TestMesh m;
  cpu::appendBox(b, m.positions, m.indices);
  return m;
}

// A height field of n x n cells (open surface, shared vertices).
inline TestMesh heightField(double x0, double z0, double size, int n, double y, double bump,
                            std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> h(-bump, bump);
  TestMesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) addVertex(m, x0 + size * i / n, y + h(rng), z0 + size * j / n);
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1,
                          c = a + std::uint32_t(n + 1), d = c + 1;
      m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
    }
  }
  return m;
}

// A wall of quads that share positions but not indices (each quad has its own four
// vertices, as the city's window bays do): the buffer must weld them.
inline TestMesh seamedWall(double x0, double y0, double z, double size, int n) {
  TestMesh m;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t base = vertexCount(m);
      const double xa = x0 + size * i / n, xb = x0 + size * (i + 1) / n;
      const double ya = y0 + size * j / n, yb = y0 + size * (j + 1) / n;
      addVertex(m, xa, ya, z);
      addVertex(m, xb, ya, z);
      addVertex(m, xb, yb, z);
      addVertex(m, xa, yb, z);
      m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
  return m;
}

// A fan of thin slivers around a centre: steep depth gradients and tiny areas.
inline TestMesh sliverFan(double cx, double cy, double cz, double r, int n) {
  TestMesh m;
  addVertex(m, cx, cy, cz);
  for (int i = 0; i <= n; ++i) {
    const double a = 0.3 + 0.02 * i;
    addVertex(m, cx + r * std::cos(a), cy + r * std::sin(a), cz - r * 0.7 * std::sin(3 * a));
  }
  for (int i = 0; i < n; ++i) {
    m.indices.insert(m.indices.end(), {0u, std::uint32_t(i + 1), std::uint32_t(i + 2)});
  }
  return m;
}

// Random triangles with no shared vertices.
inline TestMesh soup(std::uint32_t seed, int n, double spread) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> c(-spread, spread), d(-1.5, 1.5);
  TestMesh m;
  for (int i = 0; i < n; ++i) {
    const double x = c(rng), y = c(rng), z = c(rng);
    for (int k = 0; k < 3; ++k) addVertex(m, x + d(rng), y + d(rng), z + d(rng));
    const std::uint32_t b = vertexCount(m) - 3;
    m.indices.insert(m.indices.end(), {b, b + 1, b + 2});
  }
  return m;
}

// The meshes of a random test scene around the origin.
inline std::vector<TestMesh> randomScene(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> p(-4, 4), s(0.4, 2.5);
  std::vector<TestMesh> out;
  for (int i = 0; i < 3; ++i) {
    const double x = p(rng), y = p(rng), z = p(rng);
    out.push_back(box({{float(x), float(y), float(z)},
                       {float(x + s(rng)), float(y + s(rng)), float(z + s(rng))}}));
  }
  for (int i = 0; i < 2; ++i) {
    out.push_back(sphere(p(rng), p(rng), p(rng), s(rng), s(rng), s(rng), 7 + int(rng() % 12),
                         4 + int(rng() % 8)));
  }
  out.push_back(heightField(p(rng) - 3, p(rng) - 3, 6, 9, p(rng), 0.4, seed));
  out.push_back(seamedWall(p(rng) - 2, p(rng) - 2, p(rng), 4, 5));
  out.push_back(sliverFan(p(rng), p(rng), p(rng), 3, 12));
  out.push_back(soup(seed, 12, 4));
  // A wide ground that reaches behind the eye of most cameras (crossing the near plane).
  out.push_back(heightField(-40, -40, 80, 12, -4 + p(rng) * 0.5, 0.6, seed + 1));
  return out;
}

// A camera looking at the origin from a random direction (distance 6..14), or, with
// `ground`, from just above a ground plane at y = -5 that reaches behind the eye.
inline Camera randomCamera(std::uint32_t seed, std::uint32_t w, std::uint32_t h,
                           DepthConvention convention, ClipDepthRange range, DepthFormat format) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> a(0, 2 * M_PI), e(-1.2, 1.2), d(6, 14);
  Camera cam;
  cam.width = w;
  cam.height = h;
  cam.depth = {convention, range, format};
  const double yaw = a(rng), pitch = e(rng), dist = d(rng);
  const DVec3 eye{dist * std::cos(pitch) * std::cos(yaw), dist * std::sin(pitch),
                  dist * std::cos(pitch) * std::sin(yaw)};
  cam.view_projection = multiply(perspective(0.9, double(w) / h, 0.5, 60, cam.depth),
                                 lookAt(eye, {0, 0, 0}, {0, 1, 0}));
  cam.render_origin = eye;
  return cam;
}

// Moving objects: each object of a scene in its own coordinates (recentred on its box's
// centre), and a transform that turns it about that centre by a random rotation (a
// quarter of them mirrored) and puts it back there, and the vertices where that
// transform places them (in double, rounded to float) for the reference.
// `far` > 0: the object's own origin lies `far` from it on each axis (its coordinates
// about `far`, as a mesh modelled where it stands), and of the transforms not mirrored
// a third are scaled by 3.7 and a third flatten the local z axis (singular).
struct MovedScene {
  std::vector<TestMesh> local;
  std::vector<cpu::ObjectTransform> transforms;
  std::vector<TestMesh> placed;
};

inline MovedScene moveScene(const std::vector<TestMesh>& scene, std::mt19937& rng, double far = 0) {
  MovedScene out;
  std::normal_distribution<double> n(0, 1);
  for (std::size_t i = 0; i < scene.size(); ++i) {
    const TestMesh& m = scene[i];
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      lo[v % 3] = std::min(lo[v % 3], double(m.positions[v]));
      hi[v % 3] = std::max(hi[v % 3], double(m.positions[v]));
    }
    const double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    TestMesh local = m;
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      local.positions[v] = float(double(m.positions[v]) - c[v % 3] + far);
    }
    // A random unit quaternion's rotation, column-major.
    double q[4] = {n(rng), n(rng), n(rng), n(rng)};
    const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& e : q) e /= len;
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    cpu::ObjectTransform t;
    const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z),     2 * (x * z - w * y),
                         2 * (x * y - w * z),     1 - 2 * (x * x + z * z), 2 * (y * z + w * x),
                         2 * (x * z + w * y),     2 * (y * z - w * x),     1 - 2 * (x * x + y * y)};
    std::copy(r, r + 9, t.rotation);
    if (i % 4 == 3) {
      for (int k = 0; k < 3; ++k) t.rotation[k] = -t.rotation[k];  // mirrored in local x
    }
    if (far > 0 && i % 4 == 1) {
      for (double& e : t.rotation) e *= 3.7;
    } else if (far > 0 && i % 4 == 2) {
      for (int k = 6; k < 9; ++k) t.rotation[k] = 0;
    }
    // The origin (far, far, far) of the object's coordinates goes to its centre.
    double tr[3];
    for (int k = 0; k < 3; ++k) {
      tr[k] = c[k] - (t.rotation[k] + t.rotation[3 + k] + t.rotation[6 + k]) * far;
    }
    t.translation = {tr[0], tr[1], tr[2]};
    TestMesh placed = local;
    for (std::size_t v = 0; v < local.positions.size(); v += 3) {
      const double p[3] = {local.positions[v], local.positions[v + 1], local.positions[v + 2]};
      for (int k = 0; k < 3; ++k) {
        placed.positions[v + std::size_t(k)] = float(
            t.rotation[k] * p[0] + t.rotation[3 + k] * p[1] + t.rotation[6 + k] * p[2] + tr[k]);
      }
    }
    out.local.push_back(std::move(local));
    out.transforms.push_back(t);
    out.placed.push_back(std::move(placed));
  }
  return out;
}

}  // namespace logrid::test
