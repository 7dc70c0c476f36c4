#include "logrid/zread/box_query_source.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "attachment.hpp"
#include "logrid/elapsed.hpp"
#include "logrid/error.hpp"

namespace logrid::zread {

namespace {

constexpr int kBoxesPerDraw = 64;

// Box faces from a uniform array of boxes (two vec4 each: min and bias, max): 36 vertices
// per instance, corners numbered by bits (x: 1, y: 2, z: 4).
constexpr const char* kBoxVertex = R"(#version 450 core
uniform mat4 u_vp;
uniform vec3 u_offset;
uniform vec4 u_boxes[128];
uniform float u_bias_scale;
const int kCorner[36] = int[36](0, 1, 3, 0, 3, 2,  4, 6, 7, 4, 7, 5,  0, 4, 5, 0, 5, 1,
                                2, 3, 7, 2, 7, 6,  0, 2, 6, 0, 6, 4,  1, 5, 7, 1, 7, 3);
void main() {
  vec4 lo = u_boxes[2 * gl_InstanceID];
  vec3 hi = u_boxes[2 * gl_InstanceID + 1].xyz;
  int c = kCorner[gl_VertexID];
  vec3 p = vec3((c & 1) != 0 ? hi.x : lo.x, (c & 2) != 0 ? hi.y : lo.y, (c & 4) != 0 ? hi.z : lo.z);
  vec4 clip = u_vp * vec4(p + u_offset, 1.0);
  clip.z += u_bias_scale * lo.w * clip.w;
  gl_Position = clip;
}
)";
constexpr const char* kEmptyFragment = R"(#version 450 core
void main() {}
)";

// A full-viewport triangle (scissored to the rectangle) at one window depth.
constexpr const char* kRectVertex = R"(#version 450 core
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;
  gl_Position = vec4(p, 0.0, 1.0);
}
)";
constexpr const char* kRectFragment = R"(#version 450 core
uniform float u_depth;
void main() { gl_FragDepth = u_depth; }
)";

// x rounded to the nearest float, in double arithmetic (as MeshRenderer rounds the render
// origin: the shader subtracts the float origin, the matrix is translated by the same).
double roundToFloat(double x) {
  if (x == 0 || !std::isfinite(x)) return x;
  int exponent = 0;
  std::frexp(x, &exponent);
  const double scale = std::ldexp(1.0, 24 - exponent);
  return std::nearbyint(x * scale) / scale;
}

}  // namespace

BoxQuerySource::BoxQuerySource(std::uint32_t framebuffer, QueryTarget target, GlStatePolicy state)
    : framebuffer_(framebuffer),
      target_(target == QueryTarget::SamplesPassed ? GL_SAMPLES_PASSED
                                                   : GL_ANY_SAMPLES_PASSED_CONSERVATIVE),
      guard_(state, &query_counters_.state_queries, &failure_) {
  Result<std::unique_ptr<Program>> boxes =
      Program::create("BoxQuerySource boxes", kBoxVertex, kEmptyFragment);
  Result<std::unique_ptr<Program>> rects =
      Program::create("BoxQuerySource rectangles", kRectVertex, kRectFragment);
  if (!boxes || !rects) {
    unusable_ = boxes ? rects.status() : boxes.status();
    return;
  }
  box_program_ = std::move(boxes).value();
  rect_program_ = std::move(rects).value();
  u_boxes_ = box_program_->uniform("u_boxes");
  u_depth_ = rect_program_->uniform("u_depth");
  glCreateVertexArrays(1, &vao_);
}

BoxQuerySource::~BoxQuerySource() {
  if (!pool_.empty()) glDeleteQueries(GLsizei(pool_.size()), pool_.data());
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

Status BoxQuerySource::beginQueryFrame(const Camera& camera) {
  if (!unusable_.ok()) return unusable_;
  if (Status format = detail::checkDepthAttachment("BoxQuerySource", framebuffer_, camera);
      !format) {
    return format;
  }
  if (inFlight() != 0) {
    return Status(ErrorCode::Runtime, "BoxQuerySource: queries of the last frame were never read");
  }
  camera_ = camera;
  const DVec3 origin{roundToFloat(camera.render_origin.x), roundToFloat(camera.render_origin.y),
                     roundToFloat(camera.render_origin.z)};
  const Mat4d vp = multiply(camera.view_projection, translation(origin));
  float m[16];
  for (int i = 0; i < 16; ++i) m[i] = static_cast<float>(vp.m[i]);
  const GLuint program = box_program_->handle();
  glProgramUniformMatrix4fv(program, box_program_->uniform("u_vp"), 1, GL_FALSE, m);
  glProgramUniform3f(program, box_program_->uniform("u_offset"), static_cast<float>(-origin.x),
                     static_cast<float>(-origin.y), static_cast<float>(-origin.z));
  const bool reversed = camera.depth.convention == DepthConvention::Reversed;
  const bool zero_to_one = camera.depth.clip_range == ClipDepthRange::ZeroToOne;
  // A key bias b moves window depth by -b (standard) or +b (reversed), i.e. clip z by
  // that over the depth scale (0.5 for the -1..1 range), times w.
  glProgramUniform1f(program, box_program_->uniform("u_bias_scale"),
                     float((reversed ? 1.0 : -1.0) / (zero_to_one ? 1.0 : 0.5)));
  depth_func_ = reversed ? GL_GEQUAL : GL_LEQUAL;
  clip_depth_mode_ = zero_to_one ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE;
  began_ = true;
  return {};
}

Status BoxQuerySource::endQueryFrame() {
  if (inFlight() != 0) {
    return Status(ErrorCode::Runtime, "BoxQuerySource: a query of this frame was never read");
  }
  return {};
}

bool BoxQuerySource::preparePass(GlStateGuard::Scope& scope, std::uint32_t program) {
  // Depth test with the convention's function, no writes; the boxes' clip space is the
  // camera's (lower-left origin, its depth mode). The scissor box is the whole viewport
  // until scissor() moves it.
  if (!scope.prepareDraw(framebuffer_, std::int32_t(camera_.width), std::int32_t(camera_.height),
                         depth_func_, false)) {
    return false;
  }
  scope.clipControl(GL_LOWER_LEFT, clip_depth_mode_);
  glUseProgram(program);
  glBindVertexArray(vao_);
  return true;
}

QueryHandle BoxQuerySource::failedQuery(Status error) {
  fail(std::move(error));
  const QueryHandle h = acquire();
  open_[h] = kFailedQuery;
  return h;
}

QueryHandle BoxQuerySource::acquire() {
  if (free_.empty()) {
    const std::size_t old = pool_.size();
    const std::size_t grown = std::max<std::size_t>(64, old * 2);
    pool_.resize(grown);
    // One query object per target (docs/PLATFORM.md, "Occlusion queries").
    glCreateQueries(target_, GLsizei(grown - old), pool_.data() + old);
    open_.resize(grown, 0);
    for (std::size_t i = grown; i-- > old;) free_.push_back(QueryHandle(i));
  }
  const QueryHandle h = free_.back();
  free_.pop_back();
  open_[h] = kOpenQuery;
  return h;
}

QueryHandle BoxQuerySource::issueBoxes(const QueryBox* boxes, std::size_t count) {
  if (!began_) {
    return failedQuery(
        Status(ErrorCode::InvalidArgument, "BoxQuerySource: call beginQueryFrame() first"));
  }
  const auto start = std::chrono::steady_clock::now();
  GlStateGuard::Scope scope(guard_, "BoxQuerySource::issueBoxes");
  const QueryHandle h = acquire();
  {
    if (!preparePass(scope, box_program_->handle())) {
      open_[h] = kFailedQuery;
      return h;
    }
    glBeginQuery(target_, pool_[h]);
    for (std::size_t first = 0; first < count; first += kBoxesPerDraw) {
      const std::size_t n = std::min<std::size_t>(kBoxesPerDraw, count - first);
      uniforms_.resize(n * 8);
      for (std::size_t i = 0; i < n; ++i) {
        const QueryBox& q = boxes[first + i];
        float* u = uniforms_.data() + i * 8;
        u[0] = q.box.min.x, u[1] = q.box.min.y, u[2] = q.box.min.z, u[3] = q.depth_bias;
        u[4] = q.box.max.x, u[5] = q.box.max.y, u[6] = q.box.max.z, u[7] = 0;
      }
      glUniform4fv(u_boxes_, GLsizei(2 * n), uniforms_.data());
      glDrawArraysInstanced(GL_TRIANGLES, 0, 36, GLsizei(n));
    }
    glEndQuery(target_);
    if (!scope.check("the box queries")) open_[h] = kFailedQuery;
  }
  pending_work_ = true;
  ++query_counters_.queries;
  query_counters_.boxes += count;
  query_counters_.seconds += secondsSince(start);
  return h;
}

QueryHandle BoxQuerySource::issueRects(const RectQuery* rects, std::size_t count) {
  if (!began_) {
    return failedQuery(
        Status(ErrorCode::InvalidArgument, "BoxQuerySource: call beginQueryFrame() first"));
  }
  const auto start = std::chrono::steady_clock::now();
  GlStateGuard::Scope scope(guard_, "BoxQuerySource::issueRects");
  const QueryHandle h = acquire();
  const bool reversed = camera_.depth.convention == DepthConvention::Reversed;
  const float far_key = clearKey(camera_.depth);
  {
    if (!preparePass(scope, rect_program_->handle())) {
      open_[h] = kFailedQuery;
      return h;
    }
    glBeginQuery(target_, pool_[h]);
    for (std::size_t i = 0; i < count; ++i) {
      const float t = rects[i].threshold;
      if (t > far_key) continue;  // nothing lies beyond the far plane: counts nothing
      // The window depth of the threshold, rounded so that a pixel stored exactly at the
      // threshold still passes; one at or before the near plane passes everywhere.
      const double d = reversed ? -double(t) : double(t);
      float depth = static_cast<float>(d);
      if (!reversed && depth > d) depth = std::nextafter(depth, -1.0f);
      if (reversed && depth < d) depth = std::nextafter(depth, 2.0f);
      glUniform1f(u_depth_, std::clamp(depth, 0.0f, 1.0f));
      scope.scissor(rects[i].rect);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glEndQuery(target_);
    if (!scope.check("the rectangle queries")) open_[h] = kFailedQuery;
  }
  pending_work_ = true;
  ++query_counters_.queries;
  query_counters_.boxes += count;
  query_counters_.seconds += secondsSince(start);
  return h;
}

void BoxQuerySource::syncCounted() {
  if (pending_work_) {
    ++query_counters_.flushes;
    pending_work_ = false;
  }
}

bool BoxQuerySource::ready(QueryHandle h) {
  if (h >= open_.size() || !open_[h]) {
    fail(Status(ErrorCode::InvalidArgument, "BoxQuerySource::ready: handle " + std::to_string(h) +
                                                " was not issued or was read already"));
    return true;
  }
  if (open_[h] == kFailedQuery) return true;
  const auto start = std::chrono::steady_clock::now();
  GLuint available = 0;
  glGetQueryObjectuiv(pool_[h], GL_QUERY_RESULT_AVAILABLE, &available);
  ++query_counters_.polls;
  syncCounted();
  query_counters_.seconds += secondsSince(start);
  return available != 0;
}

std::uint32_t BoxQuerySource::result(QueryHandle h) {
  constexpr std::uint32_t kVisible = std::numeric_limits<std::uint32_t>::max();
  if (h >= open_.size() || !open_[h]) {
    fail(Status(ErrorCode::InvalidArgument, "BoxQuerySource::result: handle " + std::to_string(h) +
                                                " was not issued or was read already"));
    return kVisible;
  }
  if (open_[h] == kFailedQuery) {  // its error is noted: "visible"
    open_[h] = 0;
    free_.push_back(h);
    return kVisible;
  }
  const auto start = std::chrono::steady_clock::now();
  GLuint available = 0;
  glGetQueryObjectuiv(pool_[h], GL_QUERY_RESULT_AVAILABLE, &available);
  if (!available) ++query_counters_.waits;
  GLuint samples = 0;
  glGetQueryObjectuiv(pool_[h], GL_QUERY_RESULT, &samples);
  syncCounted();
  open_[h] = 0;
  free_.push_back(h);
  query_counters_.seconds += secondsSince(start);
  return samples;
}

}  // namespace logrid::zread
