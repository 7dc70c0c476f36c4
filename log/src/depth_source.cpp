#include "logrid/depth_source.hpp"

#include <limits>

namespace logrid {

AreaAnswer DepthSource::conservativeAnswer(const AreaRequest& request) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const auto pixels = static_cast<std::uint32_t>(request.rect.area());
  AreaAnswer answer;
  answer.depth = {-kInf, kInf, pixels};
  answer.count = pixels;
  return answer;
}

void DepthSource::summarize(const PixelRect* rects, std::size_t count, AreaDepth* out) {
  scratch_requests_.resize(count);
  scratch_answers_.resize(count);
  for (std::size_t i = 0; i < count; ++i) scratch_requests_[i] = {rects[i], AreaAsk::Summary, 0};
  submit(scratch_requests_.data(), count, scratch_answers_.data());
  collect();
  for (std::size_t i = 0; i < count; ++i) out[i] = scratch_answers_[i].depth;
}

void DepthSource::countAtOrBeyond(const PixelRect* rects, std::size_t count, float threshold,
                                  std::uint32_t* out) {
  scratch_requests_.resize(count);
  scratch_answers_.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    scratch_requests_[i] = {rects[i], AreaAsk::Count, threshold};
  }
  submit(scratch_requests_.data(), count, scratch_answers_.data());
  collect();
  for (std::size_t i = 0; i < count; ++i) out[i] = scratch_answers_[i].count;
}

}  // namespace logrid
