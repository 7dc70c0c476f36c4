// Depth sources for tests: wrappers around a SoftwareDepthBuffer that behave like the
// other kinds of source — count-only (as hardware occlusion queries) and asynchronous
// (as pixel-buffer objects or the compute reduction) — so the grid's paths for each can
// be checked without GL. Both answer only in collect(): submit() writes answers that
// would cull everything (a count of 0, keys of -infinity), so a caller that reads an
// answer before collect() culls visible boxes and the tests see misses.
#pragma once

#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "logrid/cpu/software_depth.hpp"

namespace logrid::test {

class DeferredSource : public DepthSource, public KeyReader {
 public:
  DeferredSource(cpu::SoftwareDepthBuffer& buffer, bool reads_depth)
      : buffer_(buffer), reads_depth_(reads_depth) {}
  DepthSourceTraits traits() const override {
    return {reads_depth_ ? "batched" : "count-only", reads_depth_, true};
  }
  Status beginFrame(const Camera& camera) override {
    EXPECT_TRUE(requests_.empty()) << "a batch was never collected";
    return buffer_.beginFrame(camera);
  }
  void submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) override {
    constexpr float kNear = -std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < count; ++i) {
      if (!reads_depth_ && requests[i].ask == AreaAsk::Summary) {
        ADD_FAILURE() << "a Summary request to a count-only source";
      }
      requests_.push_back(requests[i]);
      answers_.push_back(answers + i);
      answers[i] = {{kNear, kNear, 0}, 0};  // culls everything if read too early
    }
    if (count > 0) ++batches;
    counters_.queries += reads_depth_ ? 0 : count;
  }
  void collect() override {
    std::vector<AreaAnswer> real(requests_.size());
    buffer_.submit(requests_.data(), requests_.size(), real.data());
    buffer_.collect();
    for (std::size_t i = 0; i < real.size(); ++i) *answers_[i] = real[i];
    requests_.clear();
    answers_.clear();
    const std::uint64_t queries = counters_.queries;
    counters_ = buffer_.counters();
    counters_.queries = queries;
  }
  void readKeys(const PixelRect& r, float* keys) override {
    if (!reads_depth_) ADD_FAILURE() << "readKeys() called on a count-only source";
    buffer_.readKeys(r, keys);
  }
  int batches = 0;

 private:
  cpu::SoftwareDepthBuffer& buffer_;
  bool reads_depth_;
  std::vector<AreaRequest> requests_;
  std::vector<AreaAnswer*> answers_;
};

// Answers only Count requests, like QuerySource.
class CountOnlySource : public DeferredSource {
 public:
  explicit CountOnlySource(cpu::SoftwareDepthBuffer& buffer) : DeferredSource(buffer, false) {}
};

// Reads pixels like the software buffer, but asynchronously, like the PBO ring.
class BatchedSource : public DeferredSource {
 public:
  explicit BatchedSource(cpu::SoftwareDepthBuffer& buffer) : DeferredSource(buffer, true) {}
};

}  // namespace logrid::test
