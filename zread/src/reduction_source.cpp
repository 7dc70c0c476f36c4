#include "logrid/zread/reduction_source.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>

#include "attachment.hpp"
#include "fence.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"
#include "logrid/zread/gl_sources.hpp"

namespace logrid::zread {
namespace {

// The layouts of the two buffers (std430).
struct GpuRequest {
  std::int32_t rect[4];       // x0, y0, x1, y1
  float threshold;            // window depth the count compares against
  std::uint32_t count_below;  // 1: count depth <= threshold (reversed), 0: depth >= threshold
  std::uint32_t pad[2];
};
struct GpuAnswer {
  float lo;  // nearest window depth (standard) / smallest stored value
  float hi;
  std::uint32_t free_pixels;
  std::uint32_t count;
};
static_assert(sizeof(GpuRequest) == 32 && sizeof(GpuAnswer) == 16, "std430 layouts");

// Shared by both kernels: the declarations, with the binding points filled in.
std::string header(int requests_binding, int answers_binding, const char* layout) {
  std::ostringstream s;
  s << "#version 450 core\n"
    << layout << "\n"
    << "uniform sampler2D u_depth;\n"
       "uniform uint u_count;\n"
       "uniform float u_clear;\n"
       "uniform int u_level;\n"
       "struct Request { ivec4 rect; float threshold; uint count_below; uint pad0; uint pad1; };\n"
    << "layout(std430, binding = " << requests_binding
    << ") readonly buffer Requests { Request requests[]; };\n"
       "struct Answer { float lo; float hi; uint free_pixels; uint count; };\n"
    << "layout(std430, binding = " << answers_binding
    << ") writeonly buffer Answers { Answer answers[]; };\n"
       "void accumulate(Request r, int x, int y, inout float lo, inout float hi,\n"
       "                inout uint free_px, inout uint n) {\n"
       "  float d = texelFetch(u_depth, ivec2(x, y), u_level).r;\n"
       "  lo = min(lo, d);\n"
       "  hi = max(hi, d);\n"
       "  free_px += uint(d == u_clear);\n"
       "  n += uint(r.count_below != 0u ? d <= r.threshold : d >= r.threshold);\n"
       "}\n";
  return s.str();
}

std::string perRequestKernel(int rb, int ab) {
  return header(rb, ab, "layout(local_size_x = 32) in;") +
         "void main() {\n"
         "  uint i = gl_GlobalInvocationID.x;\n"
         "  if (i >= u_count) return;\n"
         "  Request r = requests[i];\n"
         "  float lo = 3.0, hi = -3.0;\n"
         "  uint free_px = 0u, n = 0u;\n"
         "  for (int y = r.rect.y; y < r.rect.w; ++y)\n"
         "    for (int x = r.rect.x; x < r.rect.z; ++x) accumulate(r, x, y, lo, hi, free_px, n);\n"
         "  answers[i] = Answer(lo, hi, free_px, n);\n"
         "}\n";
}

std::string perWorkgroupKernel(int rb, int ab) {
  return header(rb, ab, "layout(local_size_x = 16, local_size_y = 16) in;") +
         "shared float s_lo[256];\n"
         "shared float s_hi[256];\n"
         "shared uint s_free[256];\n"
         "shared uint s_n[256];\n"
         "void main() {\n"
         "  uint i = gl_WorkGroupID.x + gl_WorkGroupID.y * 65535u;\n"
         "  if (i >= u_count) return;\n"  // the whole workgroup returns together
         "  Request r = requests[i];\n"
         "  float lo = 3.0, hi = -3.0;\n"
         "  uint free_px = 0u, n = 0u;\n"
         "  ivec2 l = ivec2(gl_LocalInvocationID.xy);\n"
         "  for (int y = r.rect.y + l.y; y < r.rect.w; y += 16)\n"
         "    for (int x = r.rect.x + l.x; x < r.rect.z; x += 16)\n"
         "      accumulate(r, x, y, lo, hi, free_px, n);\n"
         "  uint k = gl_LocalInvocationIndex;\n"
         "  s_lo[k] = lo; s_hi[k] = hi; s_free[k] = free_px; s_n[k] = n;\n"
         "  barrier();\n"
         "  for (uint s = 128u; s > 0u; s >>= 1) {\n"
         "    if (k < s) {\n"
         "      s_lo[k] = min(s_lo[k], s_lo[k + s]);\n"
         "      s_hi[k] = max(s_hi[k], s_hi[k + s]);\n"
         "      s_free[k] += s_free[k + s];\n"
         "      s_n[k] += s_n[k + s];\n"
         "    }\n"
         "    barrier();\n"
         "  }\n"
         "  if (k == 0u) answers[i] = Answer(s_lo[0], s_hi[0], s_free[0], s_n[0]);\n"
         "}\n";
}

float down(float v) { return std::nextafter(v, -std::numeric_limits<float>::infinity()); }
float up(float v) { return std::nextafter(v, std::numeric_limits<float>::infinity()); }

// Binding points and the texture unit used, from the top of their ranges so that an
// application's usual low bindings are not touched (they are restored anyway).
struct Bindings {
  GLuint unit;
  GLuint requests;
  GLuint answers;
};

Bindings bindings() {
  GLint units = 0, ssbos = 0;
  glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &units);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &ssbos);
  return {GLuint(std::max(units, 1) - 1), GLuint(std::max(ssbos, 2) - 2),
          GLuint(std::max(ssbos, 2) - 1)};
}

}  // namespace

ReductionSource::ReductionSource(std::uint32_t framebuffer, Kernel kernel, GlStatePolicy state)
    : framebuffer_(framebuffer),
      kernel_(kernel),
      guard_(state, &counters_.state_queries, &failure_) {
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 43) {
    unusable_ = Status(ErrorCode::Unsupported,
                       "ReductionSource: compute shaders need OpenGL 4.3, the context has " +
                           std::to_string(major) + "." + std::to_string(minor) +
                           "; use the readpixels or pbo source");
    return;
  }
  if (kernel_ == Kernel::Auto) {
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string name = renderer ? renderer : "";
    const bool software = name.find("llvmpipe") != std::string::npos ||
                          name.find("softpipe") != std::string::npos ||
                          name.find("SwiftShader") != std::string::npos;
    kernel_ = software ? Kernel::PerRequest : Kernel::PerWorkgroup;
  }
  const Bindings b = bindings();
  const std::string source = kernel_ == Kernel::PerRequest
                                 ? perRequestKernel(int(b.requests), int(b.answers))
                                 : perWorkgroupKernel(int(b.requests), int(b.answers));
  Result<std::unique_ptr<Program>> program = Program::create("ReductionSource", source.c_str());
  if (!program) {
    unusable_ = program.status();
    return;
  }
  program_ = std::move(program).value();
  glProgramUniform1i(program_->handle(), program_->uniform("u_depth"), GLint(b.unit));
}

ReductionSource::~ReductionSource() {
  for (Slot& s : slots_) release(s);
}

void ReductionSource::release(Slot& slot) {
  if (slot.fence) glDeleteSync(static_cast<GLsync>(slot.fence));
  if (slot.requests) glDeleteBuffers(1, &slot.requests);
  if (slot.answers) glDeleteBuffers(1, &slot.answers);
  slot = {};
}

Status ReductionSource::beginFrame(const Camera& camera) {
  if (!unusable_.ok()) return unusable_;
  if (Status format = detail::checkDepthAttachment("ReductionSource", framebuffer_, camera);
      !format) {
    return format;
  }
  Result<DepthAttachment> attachment = tryDescribeDepthAttachment("ReductionSource", framebuffer_);
  if (!attachment) return attachment.status();
  attachment_ = *attachment;
  if (Status samples = tryCheckMultisample("ReductionSource", attachment_, camera); !samples) {
    return samples;
  }
  const DepthAttachment& a = attachment_;
  GLint level = 0, layered = 0;
  if (framebuffer_ != 0 && a.object_type == GL_TEXTURE) {
    glGetNamedFramebufferAttachmentParameteriv(framebuffer_, GL_DEPTH_ATTACHMENT,
                                               GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL, &level);
    glGetNamedFramebufferAttachmentParameteriv(framebuffer_, GL_DEPTH_ATTACHMENT,
                                               GL_FRAMEBUFFER_ATTACHMENT_LAYERED, &layered);
  }
  // A multisampled attachment is read through its resolve, a single-sample 2D texture.
  const bool readable =
      a.samples > 0 || (a.object_type == GL_TEXTURE && a.target == GL_TEXTURE_2D && !layered);
  if (!readable) {
    std::ostringstream out;
    out << "ReductionSource: framebuffer " << framebuffer_
        << " has no 2D depth texture attached (a compute shader cannot read "
        << (framebuffer_ == 0                  ? "the default framebuffer's depth"
            : a.object_type == GL_RENDERBUFFER ? "a single-sample renderbuffer"
                                               : "this attachment")
        << "); attach a GL_TEXTURE_2D depth texture or use the readpixels or pbo source";
    return Status(ErrorCode::Unsupported, out.str());
  }
  texture_ = a.samples ? 0 : a.name;
  texture_level_ = a.samples ? 0 : level;
  depth_ = camera.depth;
  width_ = camera.width;
  height_ = camera.height;
  return endFrame();
}

Status ReductionSource::endFrame() {
  for (const Slot& s : slots_) {
    if (s.fence) return Status(ErrorCode::Runtime, "ReductionSource: a batch was never collected");
  }
  return {};
}

ReductionSource::Slot* ReductionSource::freeSlot(std::size_t count) {
  Slot* slot = nullptr;
  for (Slot& s : slots_) {
    if (!s.fence) {
      slot = &s;
      break;
    }
  }
  if (!slot) slot = &slots_.emplace_back();
  if (slot->capacity < count) {
    release(*slot);
    slot->capacity = std::max<std::size_t>(count, 256);
    glCreateBuffers(1, &slot->requests);
    glNamedBufferStorage(slot->requests, GLsizeiptr(slot->capacity * sizeof(GpuRequest)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    glCreateBuffers(1, &slot->answers);
    const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glNamedBufferStorage(slot->answers, GLsizeiptr(slot->capacity * sizeof(GpuAnswer)), nullptr,
                         flags);
    slot->mapped = static_cast<const unsigned char*>(glMapNamedBufferRange(
        slot->answers, 0, GLsizeiptr(slot->capacity * sizeof(GpuAnswer)), flags));
    if (!slot->mapped) {
      release(*slot);
      fail(Status(ErrorCode::Runtime, "ReductionSource: could not map the answer buffer"));
      return nullptr;
    }
  }
  return slot;
}

void ReductionSource::submit(const AreaRequest* requests, std::size_t count, AreaAnswer* answers) {
  if (count == 0) return;
  const auto start = std::chrono::steady_clock::now();
  if (!unusable_.ok()) fail(unusable_);
  Slot* free = unusable_.ok() ? freeSlot(count) : nullptr;
  if (!free) {
    for (std::size_t i = 0; i < count; ++i) answers[i] = conservativeAnswer(requests[i]);
    return;
  }
  Slot& slot = *free;
  const bool reversed = depth_.convention == DepthConvention::Reversed;
  const bool exact = depth_.format == DepthFormat::D32F;
  upload_.resize(count * sizeof(GpuRequest));
  slot.out.clear();
  slot.asked.assign(requests, requests + count);
  for (std::size_t i = 0; i < count; ++i) {
    const AreaRequest& q = requests[i];
    GpuRequest g{};
    g.rect[0] = q.rect.x0, g.rect[1] = q.rect.y0, g.rect[2] = q.rect.x1, g.rect[3] = q.rect.y1;
    // key >= t  <=>  depth >= t (standard) or depth <= -t (reversed); for unorm formats
    // the comparison moves one float step towards counting more.
    const float t = reversed ? -q.threshold : q.threshold;
    g.threshold = exact ? t : (reversed ? up(t) : down(t));
    g.count_below = reversed ? 1u : 0u;
    std::memcpy(upload_.data() + i * sizeof(GpuRequest), &g, sizeof g);
    slot.out.push_back(answers + i);
    counters_.pixels += std::uint64_t(q.rect.area());
  }
  glNamedBufferSubData(slot.requests, 0, GLsizeiptr(upload_.size()), upload_.data());
  if (!dispatch(slot, requests, count)) {
    for (std::size_t i = 0; i < count; ++i) answers[i] = conservativeAnswer(requests[i]);
    slot.out.clear();
  }
  ++counters_.batches;
  counters_.reads += count;
  if (drawn_since_read_) {
    ++counters_.flushes;
    drawn_since_read_ = false;
  }
  counters_.seconds += secondsSince(start);
}

bool ReductionSource::dispatch(Slot& slot, const AreaRequest* requests, std::size_t count) {
  const Bindings b = bindings();
  {
    GlStateGuard::Scope scope(guard_, "ReductionSource");
    // A multisampled buffer: resolve the requested rectangles (farthest sample) first.
    GLuint texture = texture_;
    GLint level = texture_level_;
    if (attachment_.samples && scope.ok()) {
      rects_.clear();
      for (std::size_t i = 0; i < count; ++i) rects_.push_back(requests[i].rect);
      if (!resolver_) {
        Result<std::unique_ptr<MultisampleResolver>> made = MultisampleResolver::create();
        if (!made) scope.fail(made.status());
        if (made) resolver_ = std::move(made).value();
      }
      if (resolver_ && !resolver_->resolve(scope, attachment_, depth_.convention, rects_.data(),
                                           rects_.size())) {
        return false;
      }
      texture = resolver_ ? resolver_->depthTexture() : 0;
      level = 0;
    }
    if (!scope.prepareProgram() || !scope.bindTexture(b.unit, GL_TEXTURE_2D, texture) ||
        !scope.bindStorageBuffer(b.requests, slot.requests, 0,
                                 GLsizeiptr(count * sizeof(GpuRequest))) ||
        !scope.bindStorageBuffer(b.answers, slot.answers, 0,
                                 GLsizeiptr(count * sizeof(GpuAnswer)))) {
      return false;
    }
    program_->use();
    glProgramUniform1ui(program_->handle(), program_->uniform("u_count"), GLuint(count));
    glProgramUniform1f(program_->handle(), program_->uniform("u_clear"),
                       depth_.convention == DepthConvention::Reversed ? 0.0f : 1.0f);
    glProgramUniform1i(program_->handle(), program_->uniform("u_level"), level);
    if (kernel_ == Kernel::PerRequest) {
      glDispatchCompute(GLuint((count + 31) / 32), 1, 1);
    } else {
      const std::size_t x = std::min<std::size_t>(count, 65535);
      glDispatchCompute(GLuint(x), GLuint((count + 65534) / 65535), 1);
    }
    glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
    if (!scope.check("glDispatchCompute")) return false;
  }
  slot.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();  // the fence must reach the renderer, or waiting on it could wait forever
  return true;
}

void ReductionSource::collect() {
  const auto start = std::chrono::steady_clock::now();
  const bool reversed = depth_.convention == DepthConvention::Reversed;
  const bool exact = depth_.format == DepthFormat::D32F;
  for (Slot& slot : slots_) {
    if (!slot.fence) continue;
    Status waited = detail::waitFence(slot.fence, "ReductionSource: waiting for the reduction");
    if (!waited) fail(std::move(waited));
    for (std::size_t i = 0; i < slot.out.size(); ++i) {
      GpuAnswer g;
      std::memcpy(&g, slot.mapped + i * sizeof(GpuAnswer), sizeof g);
      AreaAnswer& a = *slot.out[i];
      if (failure_.failed()) {
        a = conservativeAnswer(slot.asked[i]);
      } else if (slot.asked[i].ask == AreaAsk::Summary) {
        float lo = reversed ? -g.hi : g.lo, hi = reversed ? -g.lo : g.hi;
        if (!exact) lo = down(lo), hi = up(hi);
        a.depth = {lo, hi, g.free_pixels};
      } else {
        a.count = g.count;
      }
    }
    counters_.bytes += slot.out.size() * sizeof(GpuAnswer);
    slot.out.clear();
  }
  counters_.seconds += secondsSince(start);
}

void ReductionSource::readKeys(const PixelRect& rect, float* keys) {
  ReadPixelsSource pixels(framebuffer_);
  Camera camera;
  camera.width = width_;
  camera.height = height_;
  camera.depth = depth_;
  camera.multisample = attachment_.samples > 0;
  if (Status begun = pixels.beginFrame(camera); !begun) {
    fail(std::move(begun));
    std::fill_n(keys, std::size_t(rect.area()), std::numeric_limits<float>::infinity());
    return;
  }
  pixels.readKeys(rect, keys);
  if (Status read = pixels.takeError(); !read) fail(std::move(read));
  const ReadCounters& c = pixels.counters();
  counters_.reads += c.reads;
  counters_.pixels += c.pixels;
  counters_.bytes += c.bytes;
  counters_.batches += c.batches;
  counters_.seconds += c.seconds;
  if (drawn_since_read_) {
    ++counters_.flushes;
    drawn_since_read_ = false;
  }
}

}  // namespace logrid::zread
