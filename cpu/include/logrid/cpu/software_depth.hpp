// A depth buffer in memory: a test aid (random buffers, the software rasteriser of the
// tests) and the depth source of renderers that are not GL. Stores window depth as
// float, rows bottom-up; reads are zero-copy.
#pragma once

#include <cstdint>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/pixel_source.hpp"

namespace logrid::cpu {

class SoftwareDepthBuffer : public PixelSource {
 public:
  // Throws logrid::Error for a size outside [1, kMaxViewportSide].
  SoftwareDepthBuffer(std::uint32_t width, std::uint32_t height, DepthConvention convention);

  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  DepthConvention convention() const { return encoding_.convention; }

  // Window depths, width * height, row 0 at the bottom.
  float* data() { return depth_.data(); }
  const float* data() const { return depth_.data(); }
  float at(std::uint32_t x, std::uint32_t y) const { return depth_[std::size_t(y) * width_ + x]; }

  // Clears to the convention's far value (1 standard, 0 reversed).
  void clear();
  // Writes `depth` into `rect` wherever it is nearer than what is stored (the depth test).
  void fillRect(const PixelRect& rect, float depth);

  DepthSourceTraits traits() const override { return {"software", true, false}; }
  // Throws logrid::Error if the camera's size or convention differ from the buffer's.
  void beginFrame(const Camera& camera) override;

 protected:
  void fetch(const PixelRect* rects, std::size_t count, const void** data,
             std::size_t* strides) override;

 private:
  std::uint32_t width_;
  std::uint32_t height_;
  std::vector<float> depth_;
};

}  // namespace logrid::cpu
