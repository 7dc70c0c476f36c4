#include "cli/images.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/ext/matrix_double4x4.hpp>
#include <glm/ext/vector_double4.hpp>

#include "logrid/grid.hpp"
#include "logrid/error.hpp"
#include "logrid/glm_camera.hpp"

namespace logrid::samples {

void writePng(const std::string& path, const std::vector<std::uint8_t>& rgba, std::uint32_t width,
              std::uint32_t height) {
  auto out = OIIO::ImageOutput::create(path);
  const OIIO::ImageSpec spec(int(width), int(height), 4, OIIO::TypeDesc::UINT8);
  const auto row = OIIO::stride_t(width) * 4;
  // GL rows are bottom-up: start at the last row and step backwards.
  if (!out || !out->open(path, spec) ||
      !out->write_image(OIIO::TypeDesc::UINT8,
                        rgba.data() + std::size_t(height - 1) * std::size_t(row), OIIO::AutoStride,
                        -row) ||
      !out->close()) {
    throw Error(ErrorCode::Environment, "cannot write image '" + path +
                                            "': " + (out ? out->geterror() : OIIO::geterror()) +
                                            " (check that the folder exists and is writable)");
  }
}

namespace {

class Canvas {
 public:
  Canvas(std::vector<std::uint8_t>& rgba, std::int32_t w, std::int32_t h)
      : px_(rgba), w_(w), h_(h) {}

  void blend(std::int32_t x, std::int32_t y, const std::uint8_t c[3], float a) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    std::uint8_t* p = &px_[(std::size_t(y) * std::size_t(w_) + std::size_t(x)) * 4];
    for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(float(p[k]) * (1 - a) + float(c[k]) * a + 0.5f);
  }
  void fill(const PixelRect& r, const std::uint8_t c[3], float a) {
    for (std::int32_t y = std::max(r.y0, 0); y < std::min(r.y1, h_); ++y) {
      for (std::int32_t x = std::max(r.x0, 0); x < std::min(r.x1, w_); ++x) blend(x, y, c, a);
    }
  }
  void outline(const PixelRect& r, const std::uint8_t c[3]) {
    for (std::int32_t x = r.x0; x < r.x1; ++x) blend(x, r.y0, c, 1), blend(x, r.y1 - 1, c, 1);
    for (std::int32_t y = r.y0; y < r.y1; ++y) blend(r.x0, y, c, 1), blend(r.x1 - 1, y, c, 1);
  }
  void line(double x0, double y0, double x1, double y1, const std::uint8_t c[3]) {
    const double steps = std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)));
    if (!(steps < 1e5)) return;  // off-screen or degenerate
    for (double i = 0; i <= steps; ++i) {
      const double t = steps > 0 ? i / steps : 0;
      blend(std::int32_t(std::floor(x0 + t * (x1 - x0))),
            std::int32_t(std::floor(y0 + t * (y1 - y0))), c, 1);
    }
  }

 private:
  std::vector<std::uint8_t>& px_;
  std::int32_t w_, h_;
};

constexpr std::uint8_t kRed[3] = {230, 40, 40}, kYellow[3] = {240, 210, 40},
                       kBlue[3] = {40, 110, 240}, kGreen[3] = {40, 220, 60},
                       kDark[3] = {60, 60, 60}, kLight[3] = {200, 200, 200},
                       kCyan[3] = {40, 220, 230};

// m: camera.view_projection, converted once per picture.
void wireBox(Canvas& canvas, const Camera& camera, const glm::dmat4& m, const Aabb& box) {
  glm::dvec4 clip[8];
  for (int i = 0; i < 8; ++i) {
    clip[i] = m * glm::dvec4((i & 1) ? box.max.x : box.min.x, (i & 2) ? box.max.y : box.min.y,
                             (i & 4) ? box.max.z : box.min.z, 1.0);
  }
  static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                   {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (const auto& e : edges) {
    glm::dvec4 a = clip[e[0]], b = clip[e[1]];
    // Clip against w > small, so lines behind the eye are not drawn.
    constexpr double kW = 1e-3;
    if (a.w < kW && b.w < kW) continue;
    if (a.w < kW || b.w < kW) {
      glm::dvec4& in = a.w < kW ? b : a;
      glm::dvec4& out = a.w < kW ? a : b;
      out = glm::mix(in, out, (in.w - kW) / (in.w - out.w));
    }
    auto sx = [&](const glm::dvec4& c) { return (c.x / c.w * 0.5 + 0.5) * camera.width; };
    auto sy = [&](const glm::dvec4& c) { return (c.y / c.w * 0.5 + 0.5) * camera.height; };
    canvas.line(sx(a), sy(a), sx(b), sy(b), kGreen);
  }
}

}  // namespace

std::vector<std::uint8_t> drawOverlay(const std::vector<std::uint8_t>& rgba, const Camera& camera,
                                      const OverlayData& data) {
  std::vector<std::uint8_t> out = rgba;
  for (std::size_t i = 0; i < out.size(); i += 4) {
    for (int k = 0; k < 3; ++k)
      out[i + std::size_t(k)] = std::uint8_t(out[i + std::size_t(k)] * 0.55);
  }
  Canvas canvas(out, std::int32_t(camera.width), std::int32_t(camera.height));
  if (const OcclusionGrid* grid = data.grid) {
    const float clear = clearKey(camera.depth);
    // Zfar shade: the range of the covered tiles' far keys, nearest white, farthest blue.
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (std::uint32_t ty = 0; ty < grid->tilesY(); ++ty) {
      for (std::uint32_t tx = 0; tx < grid->tilesX(); ++tx) {
        const float f = grid->tile(tx, ty).far_key;
        if (f < clear) lo = std::min(lo, f), hi = std::max(hi, f);
      }
    }
    for (std::uint32_t ty = 0; ty < grid->tilesY(); ++ty) {
      for (std::uint32_t tx = 0; tx < grid->tilesX(); ++tx) {
        const TileRecord t = grid->tile(tx, ty);
        const PixelRect r = grid->tileRect(tx, ty);
        if (data.shade == TileShade::Zfar) {
          if (t.far_key < clear) {
            const float u = hi > lo ? (t.far_key - lo) / (hi - lo) : 0.0f;
            const std::uint8_t c[3] = {std::uint8_t(250 - 210 * u), std::uint8_t(250 - 150 * u),
                                       250};
            canvas.fill(r, c, 0.45f);
          }
        } else if (t.far_key < clear) {
          canvas.fill(r, kRed, 0.30f);
        } else if (t.near_key < clear) {
          canvas.fill(r, kYellow, 0.25f);
        }
        if (t.outdated) {  // a diagonal hatch
          for (std::int32_t y = r.y0; y < r.y1; ++y) {
            for (std::int32_t x = r.x0; x < r.x1; ++x) {
              if ((x + y) % 6 == 0) canvas.blend(x, y, kBlue, 0.7f);
            }
          }
        }
      }
    }
    // Figure 1: internal and border tiles of the largest occluded box.
    const BoxProjection* largest = nullptr;
    for (const BoxProjection& p : data.occluded) {
      if (!largest || p.rect.area() > largest->rect.area()) largest = &p;
    }
    if (largest) {
      for (std::uint32_t ty = 0; ty < grid->tilesY(); ++ty) {
        for (std::uint32_t tx = 0; tx < grid->tilesX(); ++tx) {
          const PixelRect t = grid->tileRect(tx, ty);
          const PixelRect& r = largest->rect;
          if (t.x1 <= r.x0 || t.x0 >= r.x1 || t.y1 <= r.y0 || t.y0 >= r.y1) continue;
          const bool internal = t.x0 >= r.x0 && t.x1 <= r.x1 && t.y0 >= r.y0 && t.y1 <= r.y1;
          canvas.fill(t, internal ? kDark : kLight, 0.5f);
        }
      }
    }
  }
  if (data.outline_visible) {
    for (const BoxProjection& p : data.tested_visible) canvas.outline(p.rect, kCyan);
  }
  for (const BoxProjection& p : data.occluded) canvas.outline(p.rect, kRed);
  const glm::dmat4 view_projection = toGlm(camera.view_projection);
  for (const Aabb& box : data.drawn_boxes) wireBox(canvas, camera, view_projection, box);
  return out;
}

}  // namespace logrid::samples
