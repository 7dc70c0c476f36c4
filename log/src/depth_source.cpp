#include "logrid/depth_source.hpp"

namespace logrid {

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
