// Depth sources for tests: wrappers around a SoftwareDepthBuffer that behave like the
// other kinds of source — predicate-only (as hardware occlusion queries) or batching
// (as pixel-buffer objects) — so the grid's paths for each can be checked without GL.
#pragma once

#include <vector>

#include "logrid/cpu/software_depth.hpp"

namespace logrid::test {

// Answers only countAtOrBeyond(), like QuerySource.
class CountOnlySource : public DepthSource {
 public:
  explicit CountOnlySource(cpu::SoftwareDepthBuffer& buffer) : buffer_(buffer) {}
  DepthSourceTraits traits() const override { return {"count-only", false, true}; }
  void beginFrame(const Camera& camera) override { buffer_.beginFrame(camera); }
  void summarize(const PixelRect*, std::size_t, AreaDepth*) override {
    ADD_FAILURE() << "summarize() called on a predicate-only source";
  }
  void readKeys(const PixelRect&, float*) override {
    ADD_FAILURE() << "readKeys() called on a predicate-only source";
  }
  void countAtOrBeyond(const AreaQuery* q, std::size_t n, std::uint32_t* out) override {
    buffer_.countAtOrBeyond(q, n, out);
    counters_.queries += n;
  }

 private:
  cpu::SoftwareDepthBuffer& buffer_;
};

// Reads pixels like the software buffer, but asks to be given every read at once.
class BatchedSource : public DepthSource {
 public:
  explicit BatchedSource(cpu::SoftwareDepthBuffer& buffer) : buffer_(buffer) {}
  DepthSourceTraits traits() const override { return {"batched", true, true}; }
  void beginFrame(const Camera& camera) override { buffer_.beginFrame(camera); }
  void summarize(const PixelRect* r, std::size_t n, AreaDepth* out) override {
    buffer_.summarize(r, n, out);
    ++batches;
    sync();
  }
  void readKeys(const PixelRect& r, float* keys) override {
    buffer_.readKeys(r, keys);
    sync();
  }
  void countAtOrBeyond(const AreaQuery* q, std::size_t n, std::uint32_t* out) override {
    buffer_.countAtOrBeyond(q, n, out);
    ++batches;
    sync();
  }
  int batches = 0;

 private:
  void sync() { counters_ = buffer_.counters(); }
  cpu::SoftwareDepthBuffer& buffer_;
};

}  // namespace logrid::test
