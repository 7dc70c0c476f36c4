// What the margin tests share (tests/unit/margin_test.cpp in exact arithmetic,
// tests/gl/margin_gl_test.cpp on the GL rasteriser): a camera whose pixels are world units,
// the scene of the render-error term, and logrid's answer for one box, the zfar grid's test.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/depth_source.hpp"
#include "logrid/grid.hpp"
#include "logrid/projection.hpp"

namespace logrid::test {

// An orthographic w x h camera over [0, w] x [0, h] looking down -z, one world unit per
// pixel, near 0 and far 1: for the standard convention the window depth of z is exactly -z.
inline Camera pixelCamera(std::uint32_t w, std::uint32_t h, const DepthSetup& depth) {
  Camera cam;
  cam.width = w;
  cam.height = h;
  cam.depth = depth;
  cam.view_projection = orthographic(0, w, 0, h, 0, 1, depth);
  return cam;
}

// The render-error scene: a 128 x 128 perspective view in 32F standard depth, 64 walls at 64
// depths, each filling a 16 x 16 pixel block, and over each wall a coplanar duplicate
// covering its middle 8 x 8 pixels. Rendered camera-relative (render_origin = eye at the
// origin) or, with `world_space`, from an eye 1e4 units from the origin.
struct CoplanarWalls {
  Camera cam;
  std::vector<Aabb> walls;       // wall i is at distance 1 + 1.618 i
  std::vector<Aabb> duplicates;  // duplicate i lies in the plane of wall i
};

inline CoplanarWalls coplanarWalls(bool world_space) {
  const std::uint32_t w = 128, h = 128;
  CoplanarWalls scene;
  Camera& cam = scene.cam;
  cam.width = w;
  cam.height = h;
  cam.depth = {DepthConvention::Standard, ClipDepthRange::NegativeOneToOne, DepthFormat::D32F};
  const double eye_z = world_space ? 1e4 : 0.0, fovy = 1.0, f = 1.0 / std::tan(fovy / 2);
  cam.view_projection = multiply(perspective(fovy, 1.0, 0.5, 200, cam.depth),
                                 lookAt({0, 0, eye_z}, {0, 0, eye_z - 1}, {0, 1, 0}));
  cam.render_origin = world_space ? DVec3{} : DVec3{0, 0, eye_z};
  for (int i = 0; i < 64; ++i) {
    const double distance = 1.0 + 1.618 * i, x0 = 16 * (i % 8), y0 = 16 * (i / 8);
    // World coordinate of window coordinate px on the plane at `distance`.
    auto at = [&](double px) { return float((2 * px / w - 1) * distance / f); };
    const float z = float(eye_z - distance);
    scene.walls.push_back({{at(x0), at(y0), z}, {at(x0 + 16), at(y0 + 16), z}});
    scene.duplicates.push_back({{at(x0 + 4), at(y0 + 4), z}, {at(x0 + 12), at(y0 + 12), z}});
  }
  return scene;
}

// Is `box` culled by the zfar grid (log-zfar's test: threshold = nearest key - margin)
// over what `source` holds? A box that covers no pixel centre counts as culled.
inline bool zfarCulls(const Projector& projector, const Aabb& box, DepthSource& source) {
  const BoxProjection p = projector.project(box);
  if (p.cls == ProjectionClass::Outside) return true;
  if (p.cls != ProjectionClass::Inside) return false;
  const Camera& cam = projector.camera();
  OcclusionGrid grid({cam.width, cam.height, 8, GridVariant::Zfar});
  grid.reset(projector.clearKey());
  grid.markOutdated(projector.viewportRect());
  GridTestCounts counts;
  return grid.test(p.rect, p.occlusionThreshold(), source, counts) == Visibility::Occluded;
}

}  // namespace logrid::test
