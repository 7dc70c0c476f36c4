#include "logrid/zread/gl_sources.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "attachment.hpp"
#include "fence.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"

namespace logrid::zread {

using detail::bytesOf;
using detail::checkDepthAttachment;
using detail::nativeDepth;
using detail::nativeType;

namespace {

// The checks of beginFrame() common to every source; returns the depth attachment.
Result<DepthAttachment> checkFramebuffer(const char* who, GLuint framebuffer,
                                         const Camera& camera) {
  if (Status format = checkDepthAttachment(who, framebuffer, camera); !format) return format;
  Result<DepthAttachment> a = tryDescribeDepthAttachment(who, framebuffer);
  if (!a) return a;
  if (Status samples = tryCheckMultisample(who, *a, camera); !samples) return samples;
  return a;
}

// The format the pixel readers read: the buffer's own, or 32-bit float when they read
// the resolve of a multisampled buffer.
DepthFormat readFormat(const DepthAttachment& a, const Camera& camera) {
  return a.samples ? DepthFormat::D32F : camera.depth.format;
}

// The framebuffer to read `rects` from: the application's, or the resolve of its
// multisampled depth (the farthest sample of each pixel); nothing once the scope failed.
std::optional<GLuint> readableFramebuffer(GlStateGuard::Scope& scope,
                                          std::unique_ptr<MultisampleResolver>& r,
                                          const DepthAttachment& a, DepthConvention convention,
                                          const PixelRect* rects, std::size_t count) {
  if (!scope.ok()) return std::nullopt;
  if (a.samples == 0) return a.framebuffer;
  if (!r) {
    Result<std::unique_ptr<MultisampleResolver>> made = MultisampleResolver::create();
    if (!made) {
      scope.fail(made.status());
      return std::nullopt;
    }
    r = std::move(made).value();
  }
  return r->resolve(scope, a, convention, rects, count);
}

// The reads of `count` rectangles that failed: answered as if nothing were drawn.
void failAll(const void** data, std::size_t count) { std::fill_n(data, count, nullptr); }

}  // namespace

// ---------------------------------------------------------------------------
// glReadPixels
// ---------------------------------------------------------------------------

ReadPixelsSource::ReadPixelsSource(std::uint32_t framebuffer, GlStatePolicy state)
    : framebuffer_(framebuffer), guard_(state, &counters_.state_queries, &failure_) {}

Status ReadPixelsSource::beginFrame(const Camera& camera) {
  Result<DepthAttachment> a = checkFramebuffer("ReadPixelsSource", framebuffer_, camera);
  if (!a) return a.status();
  attachment_ = *a;
  encoding_ = {nativeDepth(readFormat(attachment_, camera)), camera.depth.convention};
  type_ = nativeType(readFormat(attachment_, camera));
  return {};
}

void ReadPixelsSource::fetch(const PixelRect* rects, std::size_t count, const void** data,
                             std::size_t* strides) {
  const std::size_t bytes = bytesOf(type_);
  std::size_t total = 0;
  for (std::size_t i = 0; i < count; ++i) total += std::size_t(rects[i].area()) * bytes;
  if (scratch_.size() < total) scratch_.resize(total);
  GlStateGuard::Scope scope(guard_, "ReadPixelsSource");
  const std::optional<GLuint> read =
      readableFramebuffer(scope, resolver_, attachment_, encoding_.convention, rects, count);
  if (!read || !scope.prepareRead(*read, 0)) return failAll(data, count);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const PixelRect& r = rects[i];
    glReadPixels(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0, GL_DEPTH_COMPONENT, type_,
                 scratch_.data() + offset);
    data[i] = scratch_.data() + offset;
    strides[i] = std::size_t(r.x1 - r.x0);
    offset += std::size_t(r.area()) * bytes;
  }
  if (!scope.check("glReadPixels")) failAll(data, count);
}

// ---------------------------------------------------------------------------
// A ring of persistently mapped pixel-buffer objects, one per batch in flight
// ---------------------------------------------------------------------------

namespace {

constexpr std::size_t kAlign = 16;
std::size_t aligned(std::size_t bytes) { return (bytes + kAlign - 1) & ~(kAlign - 1); }

}  // namespace

PboSource::PboSource(std::uint32_t framebuffer, GlStatePolicy state)
    : framebuffer_(framebuffer), guard_(state, &counters_.state_queries, &failure_) {}

PboSource::~PboSource() {
  for (Slot& s : slots_) release(s);
}

void PboSource::release(Slot& slot) {
  if (slot.fence) glDeleteSync(static_cast<GLsync>(slot.fence));
  if (slot.buffer) glDeleteBuffers(1, &slot.buffer);
  slot = {};
}

Status PboSource::beginFrame(const Camera& camera) {
  Result<DepthAttachment> a = checkFramebuffer("PboSource", framebuffer_, camera);
  if (!a) return a.status();
  attachment_ = *a;
  encoding_ = {nativeDepth(readFormat(attachment_, camera)), camera.depth.convention};
  type_ = nativeType(readFormat(attachment_, camera));
  return {};
}

Status PboSource::endFrame() {
  // Nothing may stay in flight across frames (the culler collects every batch).
  for (const Slot& s : slots_) {
    if (s.fence) return Status(ErrorCode::Runtime, "PboSource: a batch was never collected");
  }
  return {};
}

PboSource::Slot* PboSource::freeSlot(std::size_t bytes) {
  // Slots are handed out in turn; one still in flight is skipped and the ring grows.
  std::size_t index = slots_.size();
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    const std::size_t i = (next_slot_ + k) % slots_.size();
    if (!slots_[i].fence) {
      index = i;
      break;
    }
  }
  if (index == slots_.size()) slots_.emplace_back();
  next_slot_ = (index + 1) % slots_.size();
  Slot& slot = slots_[index];
  if (slot.capacity < bytes) {
    release(slot);
    slot.capacity = std::max<std::size_t>(aligned(bytes), 1 << 16);
    glCreateBuffers(1, &slot.buffer);
    const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glNamedBufferStorage(slot.buffer, GLsizeiptr(slot.capacity), nullptr, flags);
    slot.mapped = static_cast<const unsigned char*>(
        glMapNamedBufferRange(slot.buffer, 0, GLsizeiptr(slot.capacity), flags));
    if (!slot.mapped) {
      const std::size_t capacity = slot.capacity;
      release(slot);
      fail(Status(ErrorCode::Runtime, "PboSource: could not map a pixel-buffer object of " +
                                          std::to_string(capacity) + " bytes"));
      return nullptr;
    }
  }
  return &slot;
}

void PboSource::issue(const PixelRect* rects, std::size_t count) {
  const std::size_t bytes = bytesOf(type_);
  std::size_t total = 0;
  for (std::size_t i = 0; i < count; ++i) total += aligned(std::size_t(rects[i].area()) * bytes);
  Slot* free = freeSlot(total);
  GlStateGuard::Scope scope(guard_, "PboSource");
  const std::optional<GLuint> read =
      free ? readableFramebuffer(scope, resolver_, attachment_, encoding_.convention, rects, count)
           : std::nullopt;
  if (!read || !scope.prepareRead(*read, free->buffer)) {
    issued_.insert(issued_.end(), count, Issued{kFailed, 0});
    return;
  }
  Slot& slot = *free;
  const std::size_t slot_index = std::size_t(&slot - slots_.data());
  std::size_t offset = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const PixelRect& r = rects[i];
    glReadPixels(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0, GL_DEPTH_COMPONENT, type_,
                 reinterpret_cast<void*>(offset));
    issued_.push_back({slot_index, offset});
    offset += aligned(std::size_t(r.area()) * bytes);
  }
  if (!scope.check("glReadPixels into a pixel-buffer object")) {
    for (std::size_t i = issued_.size() - count; i < issued_.size(); ++i) issued_[i].slot = kFailed;
  }
  slot.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();  // the fence must reach the renderer, or waiting on it could wait forever
}

void PboSource::fetch(const PixelRect* rects, std::size_t count, const void** data,
                      std::size_t* strides) {
  if (issued_.size() != count) {
    fail(Status(ErrorCode::Runtime, "PboSource: fetch of rectangles that were not issued"));
    issued_.clear();
    return failAll(data, count);
  }
  GlStateGuard::Scope scope(guard_, "PboSource");
  for (Slot& slot : slots_) {
    Status waited = detail::waitFence(slot.fence, "PboSource: waiting for depth reads");
    if (!waited) scope.fail(std::move(waited));
  }
  const bool waited = scope.check("glClientWaitSync");
  for (std::size_t i = 0; i < count; ++i) {
    const Issued& at = issued_[i];
    data[i] = waited && at.slot != kFailed ? slots_[at.slot].mapped + at.offset : nullptr;
    strides[i] = std::size_t(rects[i].x1 - rects[i].x0);
  }
  issued_.clear();
}

// ---------------------------------------------------------------------------
// Hardware occlusion queries
// ---------------------------------------------------------------------------

namespace {

// A scissored full-viewport triangle whose fragments all get the depth `u_depth`:
// writing gl_FragDepth makes the compared depth exactly the uniform, whatever the clip
// range, so the threshold can be placed exactly.
constexpr const char* kQueryVertex = R"(#version 450 core
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;
  gl_Position = vec4(p, 0.0, 1.0);
}
)";
constexpr const char* kQueryFragment = R"(#version 450 core
uniform float u_depth;
void main() { gl_FragDepth = u_depth; }
)";

}  // namespace

QuerySource::QuerySource(std::uint32_t framebuffer, GlStatePolicy state)
    : framebuffer_(framebuffer), guard_(state, &counters_.state_queries, &failure_) {
  Result<std::unique_ptr<Program>> program =
      Program::create("QuerySource", kQueryVertex, kQueryFragment);
  if (!program) {
    unusable_ = program.status();
    return;
  }
  program_ = std::move(program).value();
  depth_uniform_ = program_->uniform("u_depth");
  glCreateVertexArrays(1, &vao_);
}

QuerySource::~QuerySource() {
  if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

Status QuerySource::beginFrame(const Camera& camera) {
  if (!unusable_.ok()) return unusable_;
  if (Result<DepthAttachment> a = checkFramebuffer("QuerySource", framebuffer_, camera); !a) {
    return a.status();
  }
  depth_ = camera.depth;
  width_ = std::int32_t(camera.width);
  height_ = std::int32_t(camera.height);
  if (!pending_.empty())
    return Status(ErrorCode::Runtime, "QuerySource: a batch was never collected");
  return {};
}

void QuerySource::answerConservatively(const AreaRequest* requests, std::size_t count,
                                       AreaAnswer* answers) {
  for (std::size_t i = 0; i < count; ++i) answers[i] = conservativeAnswer(requests[i]);
}

void QuerySource::submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) {
  if (count == 0) return;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < count; ++i) {
    if (requests[i].ask != AreaAsk::Count) {
      fail(Status(ErrorCode::Unsupported,
                  "QuerySource: occlusion queries cannot read depth values; use a "
                  "pixel-reading source (readpixels, pbo, reduce, software) for this method"));
      return answerConservatively(requests, count, answers);
    }
  }
  if (!unusable_.ok()) {
    fail(unusable_);
    return answerConservatively(requests, count, answers);
  }
  const std::size_t first_free = pending_.size();
  if (queries_.size() < first_free + count) {
    const std::size_t old = queries_.size();
    queries_.resize(first_free + count);
    // One query object per target (docs/PLATFORM.md, "Occlusion queries"): SAMPLES_PASSED.
    glCreateQueries(GL_SAMPLES_PASSED, GLsizei(queries_.size() - old), queries_.data() + old);
  }
  GLint active = 0;
  glGetQueryiv(GL_SAMPLES_PASSED, GL_CURRENT_QUERY, &active);
  if (active) {
    fail(Status(ErrorCode::InvalidArgument,
                "QuerySource: the application's GL_SAMPLES_PASSED query " + std::to_string(active) +
                    " is active, and GL allows one per target; end it before culling, or use "
                    "another reader"));
    return answerConservatively(requests, count, answers);
  }
  const bool reversed = depth_.convention == DepthConvention::Reversed;
  const float far_key = clearKey(depth_), near_key = nearPlaneKey(depth_);
  GlStateGuard::Scope scope(guard_, "QuerySource");
  // Pass where the stored key >= threshold: standard stored >= d, reversed stored <= d.
  if (!scope.prepareDraw(framebuffer_, width_, height_, reversed ? GL_GEQUAL : GL_LEQUAL, false)) {
    return answerConservatively(requests, count, answers);
  }
  program_->use();
  glBindVertexArray(vao_);
  std::size_t issued = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const PixelRect& r = requests[i].rect;
    const float t = requests[i].threshold;
    // Thresholds outside the depth range need no query: nothing lies beyond the far
    // plane, everything lies beyond the near plane.
    if (t > far_key) {
      answers[i].count = 0;
      continue;
    }
    if (t <= near_key) {
      answers[i].count = std::uint32_t(r.area());
      continue;
    }
    // Round the depth so that every pixel exactly at the threshold still passes.
    const double d = reversed ? -double(t) : double(t);
    float depth = static_cast<float>(d);
    if (!reversed && depth > d) depth = std::nextafter(depth, -1.0f);
    if (reversed && depth < d) depth = std::nextafter(depth, 2.0f);
    depth = std::clamp(depth, 0.0f, 1.0f);
    glUniform1f(depth_uniform_, depth);
    scope.scissor(r);
    const std::uint32_t q = std::uint32_t(first_free + issued);
    glBeginQuery(GL_SAMPLES_PASSED, queries_[q]);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEndQuery(GL_SAMPLES_PASSED);
    pending_.push_back({q, answers + i});
    ++issued;
  }

  if (!scope.check("the occlusion queries")) {
    pending_.resize(first_free);
    answerConservatively(requests, count, answers);
  }

  counters_.queries += issued;
  counters_.reads += count;
  ++counters_.batches;
  counters_.seconds += secondsSince(start);
}

void QuerySource::collect() {
  if (pending_.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  GlStateGuard::Scope scope(guard_, "QuerySource");
  for (const Pending& p : pending_) {
    GLuint samples = 0;
    if (scope.ok()) glGetQueryObjectuiv(queries_[p.query], GL_QUERY_RESULT, &samples);
    p.answer->count = samples;
  }
  if (!scope.check("glGetQueryObjectuiv")) {
    // Every pixel of the rectangle counted: never "hidden".
    for (const Pending& p : pending_) p.answer->count = std::numeric_limits<std::uint32_t>::max();
  }
  counters_.bytes += pending_.size() * sizeof(GLuint);
  pending_.clear();
  if (drawn_since_query_) {
    ++counters_.flushes;
    drawn_since_query_ = false;
  }
  counters_.seconds += secondsSince(start);
}

}  // namespace logrid::zread
