// A small software rasteriser for tests: triangles through a float vertex transform
// (as a GPU does it), clipped against the near and far planes, sampled at pixel centres,
// depth interpolated linearly in screen space, depth-tested per convention. It writes a
// SoftwareDepthBuffer and, optionally, an object-ID buffer: with it the whole culler can
// be checked against an ID-pass oracle without GL.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/zread/software_depth.hpp"

namespace logrid::test {

inline constexpr std::uint32_t kNoId = 0xFFFFFFFFu;

class SoftRasterizer {
 public:
  SoftRasterizer(const Camera& camera, zread::SoftwareDepthBuffer& depth,
                 std::vector<std::uint32_t>* ids);

  // positions: xyz per vertex, world space; indices: three per triangle.
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
  zread::SoftwareDepthBuffer& depth_;
  std::vector<std::uint32_t>* ids_;
  float near_plane_[4];
  float far_plane_[4];
  float depth_scale_, depth_offset_;
};

// Appends the 12 triangles of a box.
void appendBox(const Aabb& box, std::vector<float>& positions,
               std::vector<std::uint32_t>& indices);

}  // namespace logrid::test
