// An application's own depth source, without GL: the depth image of a Vulkan or
// Direct3D 12 renderer, copied into a host-visible read-back buffer when logrid needs it.
// What a renderer provides is one call, `CopyDepth`: record a copy of the depth image into
// the read-back buffer (vkCmdCopyImageToBuffer, CopyTextureRegion), submit it, wait for its
// fence, and return the mapped buffer (width * height 32-bit float window depths, row 0 at
// the bottom: flip rows if the API's origin is the top). logrid asks for it once per batch
// of reads: the source is asynchronous, so requests are gathered and the copy is waited for
// in collect(). Everything else — answering summaries and counts, rounding, counters — is
// logrid::PixelSource's (logrid/pixel_source.hpp).
//
// tests/unit/readback_source_test.cpp culls a box world through it with a CPU rasteriser
// standing in for the renderer, and finds no visible box missing.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include "logrid/error.hpp"
#include "logrid/pixel_source.hpp"

namespace example {

class ReadbackSource final : public logrid::PixelSource {
 public:
  using CopyDepth = std::function<const float*()>;

  ReadbackSource(std::uint32_t width, std::uint32_t height, logrid::DepthConvention convention,
                 CopyDepth copy)
      : width_(width), height_(height), convention_(convention), copy_(std::move(copy)) {}

  // Batched: submit() only gathers; collect() copies once and answers everything.
  logrid::DepthSourceTraits traits() const override { return {"readback", true, true}; }

  logrid::Status beginFrame(const logrid::Camera& camera) override {
    if (camera.width != width_ || camera.height != height_ ||
        camera.depth.convention != convention_ ||
        camera.depth.format != logrid::DepthFormat::D32F) {
      return logrid::Status(logrid::ErrorCode::InvalidArgument,
                            "ReadbackSource: the camera's viewport " +
                                std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                " or depth set-up differs from the read-back buffer's " +
                                std::to_string(width_) + "x" + std::to_string(height_) +
                                " (32-bit float); build the camera for this buffer");
    }
    encoding_ = {logrid::NativeDepth::Float32, convention_};
    return {};
  }

 protected:
  void fetch(const logrid::PixelRect* rects, std::size_t count, const void** data,
             std::size_t* strides) override {
    const float* image = copy_();  // one copy and one wait for the whole batch
    for (std::size_t i = 0; i < count; ++i) {
      data[i] = image + std::size_t(rects[i].y0) * width_ + std::size_t(rects[i].x0);
      strides[i] = width_;
    }
  }

 private:
  std::uint32_t width_, height_;
  logrid::DepthConvention convention_;
  CopyDepth copy_;
};

}  // namespace example
