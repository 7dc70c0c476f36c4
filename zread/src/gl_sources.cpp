#include "logrid/zread/gl_sources.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
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
DepthAttachment checkFramebuffer(const char* who, GLuint framebuffer, const Camera& camera) {
  checkDepthAttachment(who, framebuffer, camera);
  const DepthAttachment a = describeDepthAttachment(who, framebuffer);
  checkMultisample(who, a, camera);
  return a;
}

// The format the pixel readers read: the buffer's own, or 32-bit float when they read
// the resolve of a multisampled buffer.
DepthFormat readFormat(const DepthAttachment& a, const Camera& camera) {
  return a.samples ? DepthFormat::D32F : camera.depth.format;
}

// The framebuffer to read `rects` from: the application's, or the resolve of its
// multisampled depth (the farthest sample of each pixel).
GLuint readableFramebuffer(GlStateGuard::Scope& scope, std::unique_ptr<MultisampleResolver>& r,
                           const DepthAttachment& a, DepthConvention convention,
                           const PixelRect* rects, std::size_t count) {
  if (a.samples == 0) return a.framebuffer;
  if (!r) r = std::make_unique<MultisampleResolver>();
  return r->resolve(scope, a, convention, rects, count);
}

}  // namespace

// ---------------------------------------------------------------------------
// glReadPixels
// ---------------------------------------------------------------------------

ReadPixelsSource::ReadPixelsSource(std::uint32_t framebuffer, GlStatePolicy state)
    : framebuffer_(framebuffer), guard_(state, &counters_.state_queries) {}

void ReadPixelsSource::beginFrame(const Camera& camera) {
  attachment_ = checkFramebuffer("ReadPixelsSource", framebuffer_, camera);
  encoding_ = {nativeDepth(readFormat(attachment_, camera)), camera.depth.convention};
  type_ = nativeType(readFormat(attachment_, camera));
}

void ReadPixelsSource::fetch(const PixelRect* rects, std::size_t count, const void** data,
                             std::size_t* strides) {
  const std::size_t bytes = bytesOf(type_);
  std::size_t total = 0;
  for (std::size_t i = 0; i < count; ++i) total += std::size_t(rects[i].area()) * bytes;
  if (scratch_.size() < total) scratch_.resize(total);
  GlStateGuard::Scope scope(guard_, "ReadPixelsSource");
  scope.prepareRead(
      readableFramebuffer(scope, resolver_, attachment_, encoding_.convention, rects, count), 0);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const PixelRect& r = rects[i];
    glReadPixels(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0, GL_DEPTH_COMPONENT, type_,
                 scratch_.data() + offset);
    data[i] = scratch_.data() + offset;
    strides[i] = std::size_t(r.x1 - r.x0);
    offset += std::size_t(r.area()) * bytes;
  }
  scope.check("glReadPixels");
}

// ---------------------------------------------------------------------------
// A ring of persistently mapped pixel-buffer objects, one per batch in flight
// ---------------------------------------------------------------------------

namespace {

constexpr std::size_t kAlign = 16;
std::size_t aligned(std::size_t bytes) { return (bytes + kAlign - 1) & ~(kAlign - 1); }

}  // namespace

PboSource::PboSource(std::uint32_t framebuffer, GlStatePolicy state)
    : framebuffer_(framebuffer), guard_(state, &counters_.state_queries) {}

PboSource::~PboSource() {
  for (Slot& s : slots_) release(s);
}

void PboSource::release(Slot& slot) {
  if (slot.fence) glDeleteSync(static_cast<GLsync>(slot.fence));
  if (slot.buffer) glDeleteBuffers(1, &slot.buffer);
  slot = {};
}

void PboSource::beginFrame(const Camera& camera) {
  attachment_ = checkFramebuffer("PboSource", framebuffer_, camera);
  encoding_ = {nativeDepth(readFormat(attachment_, camera)), camera.depth.convention};
  type_ = nativeType(readFormat(attachment_, camera));
}

void PboSource::endFrame() {
  // Nothing may stay in flight across frames (the culler collects every batch).
  for (const Slot& s : slots_) {
    if (s.fence) throw Error(ErrorCode::Runtime, "PboSource: a batch was never collected");
  }
}

PboSource::Slot& PboSource::freeSlot(std::size_t bytes) {
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
      throw Error(ErrorCode::Runtime, "PboSource: could not map a pixel-buffer object of " +
                                          std::to_string(capacity) + " bytes");
    }
  }
  return slot;
}

void PboSource::issue(const PixelRect* rects, std::size_t count) {
  const std::size_t bytes = bytesOf(type_);
  std::size_t total = 0;
  for (std::size_t i = 0; i < count; ++i) total += aligned(std::size_t(rects[i].area()) * bytes);
  Slot& slot = freeSlot(total);
  const std::size_t slot_index = std::size_t(&slot - slots_.data());
  GlStateGuard::Scope scope(guard_, "PboSource");
  scope.prepareRead(
      readableFramebuffer(scope, resolver_, attachment_, encoding_.convention, rects, count),
      slot.buffer);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const PixelRect& r = rects[i];
    glReadPixels(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0, GL_DEPTH_COMPONENT, type_,
                 reinterpret_cast<void*>(offset));
    issued_.push_back({slot_index, offset});
    offset += aligned(std::size_t(r.area()) * bytes);
  }
  scope.check("glReadPixels into a pixel-buffer object");
  slot.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();  // the fence must reach the renderer, or waiting on it could wait forever
}

void PboSource::fetch(const PixelRect* rects, std::size_t count, const void** data,
                      std::size_t* strides) {
  if (issued_.size() != count) {
    throw Error(ErrorCode::Runtime, "PboSource: fetch of rectangles that were not issued");
  }
  GlStateGuard::Scope scope(guard_, "PboSource");
  for (Slot& slot : slots_) detail::waitFence(slot.fence, "PboSource: waiting for depth reads");
  scope.check("glClientWaitSync");
  for (std::size_t i = 0; i < count; ++i) {
    data[i] = slots_[issued_[i].slot].mapped + issued_[i].offset;
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
    : framebuffer_(framebuffer),
      guard_(state, &counters_.state_queries),
      program_(std::make_unique<Program>("QuerySource", kQueryVertex, kQueryFragment)),
      depth_uniform_(program_->uniform("u_depth")) {
  glCreateVertexArrays(1, &vao_);
}

QuerySource::~QuerySource() {
  if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
  glDeleteVertexArrays(1, &vao_);
}

void QuerySource::beginFrame(const Camera& camera) {
  checkFramebuffer("QuerySource", framebuffer_, camera);
  depth_ = camera.depth;
  width_ = std::int32_t(camera.width);
  height_ = std::int32_t(camera.height);
  if (!pending_.empty())
    throw Error(ErrorCode::Runtime, "QuerySource: a batch was never collected");
}

namespace {
[[noreturn]] void refuseDepthValues() {
  throw Error(ErrorCode::Unsupported,
              "QuerySource: occlusion queries cannot read depth values; use a pixel-reading "
              "source (readpixels, pbo, reduce, software) for this method");
}
}  // namespace

void QuerySource::submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) {
  if (count == 0) return;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < count; ++i) {
    if (requests[i].ask != AreaAsk::Count) refuseDepthValues();
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
    throw Error(ErrorCode::InvalidArgument,
                "QuerySource: the application's GL_SAMPLES_PASSED query " + std::to_string(active) +
                    " is active, and GL allows one per target; end it before culling, or use "
                    "another reader");
  }
  const bool reversed = depth_.convention == DepthConvention::Reversed;
  const float far_key = clearKey(depth_), near_key = nearPlaneKey(depth_);
  GlStateGuard::Scope scope(guard_, "QuerySource");
  // Pass where the stored key >= threshold: standard stored >= d, reversed stored <= d.
  scope.prepareDraw(framebuffer_, width_, height_, reversed ? GL_GEQUAL : GL_LEQUAL, false);
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

  scope.check("the occlusion queries");

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
    glGetQueryObjectuiv(queries_[p.query], GL_QUERY_RESULT, &samples);
    p.answer->count = samples;
  }
  scope.check("glGetQueryObjectuiv");
  counters_.bytes += pending_.size() * sizeof(GLuint);
  pending_.clear();
  if (drawn_since_query_) {
    ++counters_.flushes;
    drawn_since_query_ = false;
  }
  counters_.seconds += secondsSince(start);
}

}  // namespace logrid::zread
