// Draws DDO occluders (logrid/ddo/selector.hpp) into the depth buffer of the bound
// framebuffer before a culler runs: depth only, with the framebuffer's depth test and
// writes (Framebuffer::bind() sets them), colour writes off for the draw and restored
// after. The quads come in normalized device coordinates with w = 1, their depth already
// pushed back by the selector, so the draw uses no matrix: the GL pipeline only clips,
// maps to the viewport and rasterises them.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/ddo/selector.hpp"

namespace logrid::gl {

class OccluderRenderer {
 public:
  // Requires a current GL 4.5 context.
  OccluderRenderer();
  ~OccluderRenderer();
  OccluderRenderer(const OccluderRenderer&) = delete;
  OccluderRenderer& operator=(const OccluderRenderer&) = delete;

  // One draw call for all quads (two triangles each).
  void draw(const std::vector<ddo::Occluder>& occluders);

 private:
  struct Program;
  std::unique_ptr<Program> program_;
  std::uint32_t vao_ = 0;
  std::uint32_t buffer_ = 0;
  std::size_t capacity_ = 0;  // floats the buffer holds
  std::vector<float> vertices_;
};

}  // namespace logrid::gl
