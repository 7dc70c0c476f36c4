#include "logrid/zread/gl_sources.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>

#include "logrid/error.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::zread {
namespace {

// The GL type a depth format is read in without conversion.
GLenum nativeType(DepthFormat format) {
  switch (format) {
    case DepthFormat::D16: return GL_UNSIGNED_SHORT;
    case DepthFormat::D24: return GL_UNSIGNED_INT;
    case DepthFormat::D32F: return GL_FLOAT;
  }
  return GL_FLOAT;
}

NativeDepth nativeDepth(DepthFormat format) {
  switch (format) {
    case DepthFormat::D16: return NativeDepth::Unorm16;
    case DepthFormat::D24: return NativeDepth::Unorm32;
    case DepthFormat::D32F: return NativeDepth::Float32;
  }
  return NativeDepth::Float32;
}

// Throws unless the framebuffer's depth attachment is what the camera says it is: the
// depth margin depends on the format, so a mismatch would be silently wrong.
void checkDepthAttachment(const char* who, GLuint framebuffer, const Camera& camera) {
  const GLenum attachment = framebuffer ? GL_DEPTH_ATTACHMENT : GL_DEPTH;
  GLint bits = 0, type = 0;
  glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment,
                                             GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &bits);
  glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment,
                                             GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE, &type);
  const DepthFormat want = camera.depth.format;
  const bool ok = (want == DepthFormat::D32F && type == GL_FLOAT && bits == 32) ||
                  (want == DepthFormat::D24 && type == GL_UNSIGNED_NORMALIZED && bits == 24) ||
                  (want == DepthFormat::D16 && type == GL_UNSIGNED_NORMALIZED && bits == 16);
  if (!ok) {
    std::ostringstream out;
    out << who << ": the camera says depth format " << toString(want) << " but framebuffer "
        << framebuffer << " has a " << bits << "-bit "
        << (type == GL_FLOAT                 ? "float"
            : type == GL_UNSIGNED_NORMALIZED ? "unorm"
                                             : "unknown")
        << " depth attachment; set Camera::depth.format to match the buffer";
    throw Error(ErrorCode::InvalidArgument, out.str());
  }
}

std::size_t bytesOf(GLenum type) { return type == GL_UNSIGNED_SHORT ? 2 : 4; }

// The checks of beginFrame() common to the pixel readers; returns the attachment.
DepthAttachment checkFramebuffer(const char* who, GLuint framebuffer, const Camera& camera) {
  checkDepthAttachment(who, framebuffer, camera);
  const DepthAttachment a = describeDepthAttachment(who, framebuffer);
  checkMultisample(who, a, camera);
  return a;
}

// The framebuffer to read: the application's, or the resolve of its multisampled depth.
GLuint readableFramebuffer(GlStateGuard::Scope& scope, std::unique_ptr<MultisampleResolver>& r,
                           const DepthAttachment& a, const DepthSetup& depth,
                           const PixelRect* rects, std::size_t count) {
  if (a.samples == 0) return a.framebuffer;
  if (!r) r = std::make_unique<MultisampleResolver>();
  return r->resolve(scope, a, depth.convention, rects, count);
}

}  // namespace

// ---------------------------------------------------------------------------
// glReadPixels
// ---------------------------------------------------------------------------

ReadPixelsSource::ReadPixelsSource(std::uint32_t framebuffer) : framebuffer_(framebuffer) {}

void ReadPixelsSource::beginFrame(const Camera& camera) {
  attachment_ = checkFramebuffer("ReadPixelsSource", framebuffer_, camera);
  depth_ = camera.depth;
  // The resolve of a multisampled buffer is 32-bit float whatever the format.
  const DepthFormat read = attachment_.samples ? DepthFormat::D32F : camera.depth.format;
  encoding_ = {nativeDepth(read), camera.depth.convention};
  type_ = nativeType(read);
}

void ReadPixelsSource::fetch(const PixelRect* rects, std::size_t count, const void** data,
                             std::size_t* strides) {
  const std::size_t bytes = bytesOf(type_);
  std::size_t total = 0;
  for (std::size_t i = 0; i < count; ++i) total += std::size_t(rects[i].area()) * bytes;
  if (scratch_.size() < total) scratch_.resize(total);
  GlStateGuard::Scope scope(guard_, "ReadPixelsSource");
  scope.prepareRead(readableFramebuffer(scope, resolver_, attachment_, depth_, rects, count), 0);
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
// Pixel-buffer objects, persistently mapped
// ---------------------------------------------------------------------------

PboSource::PboSource(std::uint32_t framebuffer) : framebuffer_(framebuffer) {}

PboSource::~PboSource() {
  if (buffer_) glDeleteBuffers(1, &buffer_);
}

void PboSource::beginFrame(const Camera& camera) {
  attachment_ = checkFramebuffer("PboSource", framebuffer_, camera);
  depth_ = camera.depth;
  const DepthFormat read = attachment_.samples ? DepthFormat::D32F : camera.depth.format;
  encoding_ = {nativeDepth(read), camera.depth.convention};
  type_ = nativeType(read);
}

void PboSource::reserve(std::size_t bytes) {
  if (bytes <= capacity_) return;
  if (buffer_) glDeleteBuffers(1, &buffer_);
  capacity_ = std::max<std::size_t>(bytes, std::max<std::size_t>(capacity_ * 2, 1 << 16));
  glCreateBuffers(1, &buffer_);
  const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  glNamedBufferStorage(buffer_, GLsizeiptr(capacity_), nullptr, flags);
  mapped_ = static_cast<const unsigned char*>(
      glMapNamedBufferRange(buffer_, 0, GLsizeiptr(capacity_), flags));
  if (!mapped_) {
    throw Error(ErrorCode::Runtime, "PboSource: could not map a pixel-buffer object of " +
                                        std::to_string(capacity_) + " bytes");
  }
}

void PboSource::fetch(const PixelRect* rects, std::size_t count, const void** data,
                      std::size_t* strides) {
  const std::size_t bytes = bytesOf(type_);
  std::size_t total = 0;
  for (std::size_t i = 0; i < count; ++i) {
    total += (std::size_t(rects[i].area()) * bytes + 15) & ~std::size_t(15);
  }
  reserve(total);
  GlStateGuard::Scope scope(guard_, "PboSource");
  scope.prepareRead(readableFramebuffer(scope, resolver_, attachment_, depth_, rects, count),
                    buffer_);
  // Issue every read, then wait once.
  std::size_t offset = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const PixelRect& r = rects[i];
    glReadPixels(r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0, GL_DEPTH_COMPONENT, type_,
                 reinterpret_cast<void*>(offset));
    data[i] = mapped_ + offset;
    strides[i] = std::size_t(r.x1 - r.x0);
    offset += (std::size_t(r.area()) * bytes + 15) & ~std::size_t(15);
  }
  scope.check("glReadPixels into a pixel-buffer object");
  GLsync fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  const GLenum result = glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 10'000'000'000ull);
  glDeleteSync(fence);
  if (result == GL_TIMEOUT_EXPIRED || result == GL_WAIT_FAILED) {
    throw Error(ErrorCode::Runtime, "PboSource: waiting for depth reads failed or took over 10 s");
  }
  scope.check("glClientWaitSync");
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

QuerySource::QuerySource(std::uint32_t framebuffer)
    : framebuffer_(framebuffer),
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
}

void QuerySource::summarize(const PixelRect*, std::size_t, AreaDepth*) {
  throw Error(ErrorCode::Unsupported,
              "QuerySource::summarize: occlusion queries cannot read depth values; use a "
              "pixel-reading source (readpixels, pbo, software) for this method");
}

void QuerySource::readKeys(const PixelRect&, float*) { summarize(nullptr, 0, nullptr); }

void QuerySource::countAtOrBeyond(const AreaQuery* queries, std::size_t count, std::uint32_t* out) {
  const auto start = std::chrono::steady_clock::now();
  if (queries_.size() < count) {
    const std::size_t old = queries_.size();
    queries_.resize(count);
    // One query object per target (PLATFORM.md pitfall 4): created for SAMPLES_PASSED.
    glCreateQueries(GL_SAMPLES_PASSED, GLsizei(count - old), queries_.data() + old);
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
    const PixelRect& r = queries[i].rect;
    // Thresholds outside the depth range need no query: nothing lies beyond the far
    // plane, everything lies beyond the near plane.
    if (queries[i].threshold > far_key || queries[i].threshold <= near_key) continue;
    ++issued;
    // Round the depth so that every pixel exactly at the threshold still passes.
    double d = reversed ? -double(queries[i].threshold) : double(queries[i].threshold);
    float depth = static_cast<float>(d);
    if (!reversed && depth > d) depth = std::nextafter(depth, -1.0f);
    if (reversed && depth < d) depth = std::nextafter(depth, 2.0f);
    depth = std::clamp(depth, 0.0f, 1.0f);
    glUniform1f(depth_uniform_, depth);
    scope.scissor(r);
    glBeginQuery(GL_SAMPLES_PASSED, queries_[i]);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEndQuery(GL_SAMPLES_PASSED);
  }
  for (std::size_t i = 0; i < count; ++i) {
    const float t = queries[i].threshold;
    if (t > far_key) {
      out[i] = 0;
    } else if (t <= near_key) {
      out[i] = std::uint32_t(queries[i].rect.area());
    } else {
      GLuint samples = 0;
      glGetQueryObjectuiv(queries_[i], GL_QUERY_RESULT, &samples);
      out[i] = samples;
    }
  }

  scope.check("the occlusion queries");

  counters_.queries += issued;
  if (drawn_since_query_) {
    ++counters_.flushes;
    drawn_since_query_ = false;
  }
  counters_.seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace logrid::zread
