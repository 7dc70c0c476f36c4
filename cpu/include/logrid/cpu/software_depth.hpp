// A depth buffer in memory: a test aid (random buffers, the software rasteriser of the
// tests) and the depth source of renderers that are not GL. Stores window depth as
// float, rows bottom-up; reads are zero-copy.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "logrid/camera.hpp"
#include "logrid/error.hpp"
#include "logrid/pixel_source.hpp"

namespace logrid::cpu {

class SoftwareDepthBuffer : public PixelSource {
 public:
  // An error (InvalidArgument) for a size outside [1, kMaxViewportSide]; both forms
  // (logrid/error.hpp).
  static Result<std::unique_ptr<SoftwareDepthBuffer>> create(std::uint32_t width,
                                                             std::uint32_t height,
                                                             DepthConvention convention);
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
  // An error if the camera's size or convention differ from the buffer's.
  Status beginFrame(const Camera& camera) override;

 protected:
  void fetch(const PixelRect* rects, std::size_t count, const void** data,
             std::size_t* strides) override;

 private:
  struct Checked {};  // the size was checked
  static Status checkSize(std::uint32_t width, std::uint32_t height);
  static Checked checkedOrThrow(std::uint32_t width, std::uint32_t height);
  SoftwareDepthBuffer(Checked, std::uint32_t width, std::uint32_t height,
                      DepthConvention convention);

  std::uint32_t width_;
  std::uint32_t height_;
  std::vector<float> depth_;
};

#if LOGRID_HAS_EXCEPTIONS
inline SoftwareDepthBuffer::Checked SoftwareDepthBuffer::checkedOrThrow(std::uint32_t width,
                                                                        std::uint32_t height) {
  orThrow(checkSize(width, height));
  return {};
}
inline SoftwareDepthBuffer::SoftwareDepthBuffer(std::uint32_t width, std::uint32_t height,
                                                DepthConvention convention)
    : SoftwareDepthBuffer(checkedOrThrow(width, height), width, height, convention) {}
#endif

}  // namespace logrid::cpu
