// The CPU occlusion buffer's triangle set-up (cpu/src/triangle_setup.hpp) in groups of
// four (AVX2: a still object's vertices transformed and the triangles in front of the
// near plane set up four at a time) against the scalar set-up, one vertex and one
// triangle at a time, which stays the reference: on random and adversarial triangles
// (degenerate, sub-pixel, huge, behind the eye, at and across the near plane, beyond the
// far plane, closed surfaces either way round, still and moving objects) every triangle
// the two write must be the same, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "logrid/cpu/occluder_mesh.hpp"
#include "triangle_setup.hpp"

namespace logrid {
namespace {

using cpu::OccluderMeshes;
using cpu::detail::RasterTriangle;
using cpu::detail::SetupFrame;
using cpu::detail::SetupObject;
using cpu::detail::TriangleSetup;

// A GL perspective camera at the origin looking down -z (column-major), near 0.1, far 100.
SetupFrame frameOf(int width, int height, int scale, bool multisample, bool reversed) {
  SetupFrame f;
  const double near = 0.1, far = 100, t = 1 / std::tan(0.5), aspect = double(width) / height;
  f.m[0] = t / aspect;
  f.m[5] = t;
  f.m[10] = (far + near) / (near - far);
  f.m[11] = -1;
  f.m[14] = 2 * far * near / (near - far);
  for (int i = 0; i < 16; ++i) f.render_abs[i] = std::fabs(f.m[i]);
  for (int r = 0; r < 4; ++r) {
    f.clip_abs[r] = std::fabs(f.m[r]) + std::fabs(f.m[4 + r]) + std::fabs(f.m[8 + r]);
  }
  f.render_k = 4.0 / 16777216.0;
  f.quantisation = 1.0 / 16777215.0;
  f.snap = 1.0 / 256;
  f.half_w = 0.5 * width;
  f.half_h = 0.5 * height;
  const double sign = reversed ? -1.0 : 1.0;
  f.key_scale = 0.5 * sign;
  f.key_offset = 0.5 * sign;
  f.near_key = reversed ? -1.0 : 0.0;
  f.clear_key = reversed ? 0.0 : 1.0;
  f.scale = scale;
  f.inv_scale = 1.0 / scale;
  f.radius = 0.5 * (scale - 1) + (multisample ? 0.5 : 0.0);
  f.buffer_w = (width + scale - 1) / scale;
  f.buffer_h = (height + scale - 1) / scale;
  return f;
}

// Objects of every kind of triangle the set-up meets. Each is in its own coordinates
// and drawn where SetupObject places it (still ones at their own coordinates).
OccluderMeshes adversarialMeshes(std::mt19937& rng) {
  OccluderMeshes meshes;
  std::uniform_real_distribution<double> u(0, 1);
  const auto add = [&](const std::vector<float>& p, const std::vector<std::uint32_t>& i) {
    meshes.addObject(p.data(), p.size() / 3, i.data(), i.size());
  };
  // A jittered height-field patch at a depth (shared edges, neighbours, folds).
  const auto patch = [&](double cx, double cy, double cz, double size, double jitter, int n) {
    std::vector<float> p;
    std::vector<std::uint32_t> idx;
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        p.push_back(float(cx + size * (double(i) / n - 0.5) + jitter * (u(rng) - 0.5)));
        p.push_back(float(cy + size * (double(j) / n - 0.5) + jitter * (u(rng) - 0.5)));
        p.push_back(float(cz + jitter * (u(rng) - 0.5)));
      }
    }
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1,
                            c = a + std::uint32_t(n + 1), d = c + 1;
        idx.insert(idx.end(), {a, b, d, a, d, c});
      }
    }
    add(p, idx);
  };
  // A closed box (counter-clockwise from outside, or clockwise).
  const auto box = [&](double cx, double cy, double cz, double h, bool clockwise) {
    std::vector<float> p;
    for (int k = 0; k < 8; ++k) {
      p.push_back(float(cx + (k & 1 ? h : -h)));
      p.push_back(float(cy + (k & 2 ? h : -h)));
      p.push_back(float(cz + (k & 4 ? h : -h)));
    }
    std::vector<std::uint32_t> idx = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                      2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    if (clockwise) {
      for (std::size_t t = 0; t < idx.size(); t += 3) std::swap(idx[t + 1], idx[t + 2]);
    }
    add(p, idx);
  };
  // A soup of random triangles in a region (x, y, z ranges).
  const auto soup = [&](double x0, double x1, double y0, double y1, double z0, double z1,
                        double size, int n) {
    std::vector<float> p;
    std::vector<std::uint32_t> idx;
    for (int t = 0; t < n; ++t) {
      const double cx = x0 + (x1 - x0) * u(rng), cy = y0 + (y1 - y0) * u(rng),
                   cz = z0 + (z1 - z0) * u(rng);
      for (int k = 0; k < 3; ++k) {
        p.push_back(float(cx + size * (u(rng) - 0.5)));
        p.push_back(float(cy + size * (u(rng) - 0.5)));
        p.push_back(float(cz + size * (u(rng) - 0.5)));
        idx.push_back(std::uint32_t(3 * t + k));
      }
    }
    add(p, idx);
  };
  for (int i = 0; i < 6; ++i) {
    patch(40 * (u(rng) - 0.5), 30 * (u(rng) - 0.5), -2 - 60 * u(rng), 2 + 20 * u(rng), 0.5 * u(rng),
          3 + int(9 * u(rng)));
  }
  for (int i = 0; i < 12; ++i) {
    box(20 * (u(rng) - 0.5), 16 * (u(rng) - 0.5), -1 - 40 * u(rng), 0.05 + 3 * u(rng), i % 2 == 1);
  }
  box(0, 0, -0.3, 0.25, false);                   // across the near plane
  box(0, 0, 0, 1, true);                          // around the eye
  soup(-40, 40, -30, 30, -80, -0.5, 4, 301);      // in view, mostly
  soup(-5, 5, -4, 4, -30, -1, 1e-4, 203);         // sub-pixel
  soup(-5, 5, -4, 4, -0.2, 0.05, 0.3, 157);       // at, across and behind the near plane
  soup(-60, 60, -60, 60, 0.5, 30, 10, 97);        // behind the eye
  soup(-300, 300, -300, 300, -150, -90, 40, 99);  // at and beyond the far plane
  soup(-2e6, 2e6, -2e6, 2e6, -2, -1, 5e5, 61);    // huge: beyond the guard band
  // Across the view, up to about the guard band and beyond it.
  for (const double size : {1e6, 4e4, 3e4, 2e4, 1.5e4}) patch(0, 0, -1.5, size, 0.2, 5);
  soup(-1e-3, 1e-3, -1e-3, 1e-3, -0.11, -0.09, 1e-3, 51);  // close to the eye on the axis
  // Degenerate: repeated corners, collinear corners, and a sliver.
  add({0,  0, -5, 0,  0, -5, 1,  1, -5, 0,  0, -5,    1, 1,
       -5, 2, 2,  -5, 0, 0,  -5, 3, 0,  -5, 6, 1e-6f, -5},
      {0, 1, 2, 3, 4, 5, 6, 7, 8, 0, 2, 1, 3, 5, 4});
  // On the far and near planes (z = -100, -0.1) and the view's axis planes.
  for (const float z : {-100.0f, -0.1f}) {
    std::vector<float> p;
    std::vector<std::uint32_t> idx;
    for (int t = 0; t < 40; ++t) {
      const float s = -z * float(0.01 + 0.5 * u(rng)), x = -z * float(u(rng) - 0.5);
      p.insert(p.end(), {x, 0, z, x + s, 0, z, x, s, z});
      idx.insert(idx.end(),
                 {std::uint32_t(3 * t), std::uint32_t(3 * t + 1), std::uint32_t(3 * t + 2)});
    }
    add(p, idx);
  }
  // The edge of the view, and exactly on the pixel grid's half-pixel lines.
  soup(-0.7, 0.7, -0.5, 0.5, -1.01, -0.99, 0.4, 131);
  return meshes;
}

// The usable triangles of every object, set up by one setup, as bytes.
std::vector<RasterTriangle> setUpAll(TriangleSetup& setup, const SetupFrame& f,
                                     const OccluderMeshes& meshes, const SetupObject* objects,
                                     std::size_t& looked_at) {
  std::vector<RasterTriangle> out;
  std::size_t count = 0;
  looked_at = 0;
  for (std::uint32_t i = 0; i < meshes.objectCount(); ++i) {
    looked_at += setup.run(f, meshes, objects[i], out, count);
  }
  out.resize(count);
  return out;
}

TEST(TriangleSetupTest, GroupsSetUpAsOneAtATime) {
  TriangleSetup probe;
  if (!probe.useGroups(true)) GTEST_SKIP() << "no AVX2 on this CPU";
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(0, 1);
  std::size_t usable = 0, looked_at = 0, cases = 0;
  for (int round = 0; round < 24; ++round) {
    const OccluderMeshes meshes = adversarialMeshes(rng);
    const int scale = 1 << (round % 3);
    const SetupFrame f = frameOf(640, 480, scale, round % 4 == 3, round % 5 == 4);
    std::vector<SetupObject> objects(meshes.objectCount());
    for (std::uint32_t i = 0; i < objects.size(); ++i) {
      SetupObject& o = objects[i];
      o.occluder = i;
      o.s_x = f.snap * u(rng) + (i % 3 == 0 ? 2 * u(rng) : 0.0);
      o.s_y = i % 7 == 5 ? 1e7 : f.snap * u(rng);  // some beyond what the set-up can bound
      o.margin = i % 2 == 0 ? 1e-7 * u(rng) : 0.0;
      if ((i + std::uint32_t(round)) % 4 == 1) {  // moving: turned about y, some mirrored
        const double a = 6.283 * u(rng), c = std::cos(a), s = std::sin(a);
        const double m = i % 8 == 1 ? -1.0 : 1.0;
        const double r[9] = {m * c, 0, -s, 0, 1, 0, m * s, 0, c};
        o.moved = true;
        std::memcpy(o.rotation, r, sizeof r);
        o.translation[0] = 2 * (u(rng) - 0.5);
        o.translation[2] = -2 * u(rng);
        o.pad = 1e-5 * u(rng);
        o.orientation = int(m);
      }
    }
    TriangleSetup one_at_a_time, groups;
    EXPECT_FALSE(one_at_a_time.useGroups(false));
    ASSERT_TRUE(groups.useGroups(true));
    std::size_t looked_one = 0, looked_groups = 0;
    const auto want = setUpAll(one_at_a_time, f, meshes, objects.data(), looked_one);
    // Twice: the second run reuses the stores the first one left.
    for (int pass = 0; pass < 2; ++pass) {
      const auto got = setUpAll(groups, f, meshes, objects.data(), looked_groups);
      ASSERT_EQ(looked_one, looked_groups);
      ASSERT_EQ(want.size(), got.size()) << "round " << round;
      for (std::size_t t = 0; t < want.size(); ++t) {
        ASSERT_EQ(0, std::memcmp(&want[t], &got[t], sizeof(RasterTriangle)))
            << "round " << round << ", triangle " << t << " (x0 " << want[t].x0 << " vs "
            << got[t].x0 << ", zc " << want[t].zc << " vs " << got[t].zc << ", ec[0] "
            << want[t].ec[0] << " vs " << got[t].ec[0] << ")";
      }
    }
    usable += want.size();
    looked_at += looked_one;
    ++cases;
  }
  // Most triangles are left out (behind, beyond, outside, facing away), many are not.
  EXPECT_GT(usable, 5000u);
  EXPECT_GT(looked_at, 2 * usable);
  EXPECT_EQ(cases, 24u);
}

}  // namespace
}  // namespace logrid
