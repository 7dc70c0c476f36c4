#include "logrid/cpu/software_depth.hpp"

#include <algorithm>
#include <sstream>

#include "logrid/error.hpp"

namespace logrid::cpu {

Status SoftwareDepthBuffer::checkSize(std::uint32_t width, std::uint32_t height) {
  if (width < 1 || height < 1 || width > kMaxViewportSide || height > kMaxViewportSide) {
    std::ostringstream out;
    out << "SoftwareDepthBuffer: size " << width << "x" << height
        << " is out of range; each side must be between 1 and " << kMaxViewportSide;
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  return {};
}

Result<std::unique_ptr<SoftwareDepthBuffer>> SoftwareDepthBuffer::create(
    std::uint32_t width, std::uint32_t height, DepthConvention convention) {
  if (Status size = checkSize(width, height); !size) return size;
  return std::unique_ptr<SoftwareDepthBuffer>(
      new SoftwareDepthBuffer(Checked{}, width, height, convention));
}

SoftwareDepthBuffer::SoftwareDepthBuffer(Checked, std::uint32_t width, std::uint32_t height,
                                         DepthConvention convention)
    : width_(width), height_(height) {
  encoding_ = {NativeDepth::Float32, convention};
  depth_.resize(std::size_t(width) * height);
  clear();
}

void SoftwareDepthBuffer::clear() {
  std::fill(depth_.begin(), depth_.end(),
            encoding_.convention == DepthConvention::Reversed ? 0.0f : 1.0f);
}

void SoftwareDepthBuffer::fillRect(const PixelRect& rect, float depth) {
  const bool reversed = encoding_.convention == DepthConvention::Reversed;
  const std::int32_t x0 = std::max(rect.x0, 0), x1 = std::min(rect.x1, std::int32_t(width_));
  const std::int32_t y0 = std::max(rect.y0, 0), y1 = std::min(rect.y1, std::int32_t(height_));
  for (std::int32_t y = y0; y < y1; ++y) {
    float* row = depth_.data() + std::size_t(y) * width_;
    for (std::int32_t x = x0; x < x1; ++x) {
      if (reversed ? depth > row[x] : depth < row[x]) row[x] = depth;
    }
  }
}

Status SoftwareDepthBuffer::beginFrame(const Camera& camera) {
  if (camera.width != width_ || camera.height != height_ ||
      camera.depth.convention != encoding_.convention) {
    std::ostringstream out;
    out << "SoftwareDepthBuffer: the camera is " << camera.width << "x" << camera.height << " "
        << toString(camera.depth.convention) << " but the buffer is " << width_ << "x" << height_
        << " " << toString(encoding_.convention) << "; create the buffer to match the camera";
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  return {};
}

void SoftwareDepthBuffer::fetch(const PixelRect* rects, std::size_t count, const void** data,
                                std::size_t* strides) {
  for (std::size_t i = 0; i < count; ++i) {
    strides[i] = width_;
    data[i] = depth_.data() + std::size_t(rects[i].y0) * width_ + std::size_t(rects[i].x0);
  }
}

}  // namespace logrid::cpu
