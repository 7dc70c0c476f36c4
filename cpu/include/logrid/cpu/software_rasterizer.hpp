// A small software rasteriser: triangles through a float vertex transform (as a GPU
// does it, camera-relative like mesh_renderer.hpp), clipped against the near and far
// planes, sampled at pixel centres, depth interpolated linearly in screen space and
// depth-tested per convention. It writes a SoftwareDepthBuffer and, optionally, an
// object-ID buffer. Two uses: the depth source of a renderer that is not GL (draw what
// the culler draws into it, `--reader software`), and the tests, where it lets the whole
// culler be checked against an ID-pass oracle without GL. Scalar and simple: about
// 10-20 M pixels per second, fine for the few objects a culled frame draws.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/cpu/software_depth.hpp"

namespace logrid::cpu {

inline constexpr std::uint32_t kNoId = 0xFFFFFFFFu;  // an ID-buffer pixel with nothing drawn

// Which pixel centres a triangle covers.
enum class Coverage : std::uint8_t {
  // Every centre inside or on an edge: at least what any GL rasteriser covers. Right for
  // an ID-pass oracle, which must not miss a pixel GL could draw.
  Inclusive,
  // Only centres farther inside every edge than snapping can move it (one 1/16-pixel
  // step per axis, GL's minimum of 4 sub-pixel bits with truncation, plus float
  // rounding): at most what any GL rasteriser covers (GL leaves out centres on right and
  // top edges, and snapping moves edges). Right for a depth source standing in for a GL
  // depth buffer, which must never hold depth where GL drew nothing.
  Inner,
};

class SoftwareRasterizer {
 public:
  SoftwareRasterizer(const Camera& camera, SoftwareDepthBuffer& depth,
                     std::vector<std::uint32_t>* ids, Coverage coverage = Coverage::Inclusive);

  // positions: xyz per vertex in the camera's coordinates; indices: three per triangle.
  void draw(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices,
            std::uint32_t id);
  void drawTriangle(const float* a, const float* b, const float* c, std::uint32_t id);

 private:
  struct V {
    float c[4];
  };
  void rasterize(const V& a, const V& b, const V& c, std::uint32_t id);

  Camera camera_;
  float m_[16];  // world (minus render origin) to clip, float
  SoftwareDepthBuffer& depth_;
  std::vector<std::uint32_t>* ids_;
  float near_plane_[4];
  float far_plane_[4];
  float depth_scale_, depth_offset_;
  Coverage coverage_;
};

// Appends the 12 triangles of a box.
void appendBox(const Aabb& box, std::vector<float>& positions, std::vector<std::uint32_t>& indices);

}  // namespace logrid::cpu
