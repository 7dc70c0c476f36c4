#include "logrid/zread/calibration.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "logrid/error.hpp"
#include "logrid/zread/box_query_source.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::zread {

namespace {

constexpr const char* kVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_vp;
void main() { gl_Position = u_vp * vec4(a_position, 1.0); }
)";
constexpr const char* kFragment = R"(#version 450 core
layout(location = 0) out vec4 o_color;
void main() { o_color = vec4(0.4, 0.6, 0.3, 1.0); }
)";

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// The bindings and state the measurement changes, restored at the end.
class SavedState {
 public:
  SavedState() {
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fb_);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb_);
    glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao_);
    glGetIntegerv(GL_VIEWPORT, viewport_);
    glGetIntegerv(GL_DEPTH_FUNC, &depth_func_);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
    glGetFloatv(GL_DEPTH_CLEAR_VALUE, &clear_depth_);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, clear_color_);
    depth_test_ = glIsEnabled(GL_DEPTH_TEST);
  }
  ~SavedState() {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_fb_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fb_));
    // A program the application deleted while current was freed when the measurement
    // used its own (GL 4.5 §7.3): rebinding its name would be GL_INVALID_VALUE, so it is
    // restored as 0, as GlStateGuard restores it. Deleting a bound framebuffer or vertex
    // array unbinds it, so those saved names still exist.
    glUseProgram(program_ != 0 && glIsProgram(GLuint(program_)) ? GLuint(program_) : 0);
    glBindVertexArray(GLuint(vao_));
    glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    glDepthFunc(GLenum(depth_func_));
    glDepthMask(depth_mask_);
    glClearDepthf(clear_depth_);
    glClearColor(clear_color_[0], clear_color_[1], clear_color_[2], clear_color_[3]);
    if (depth_test_) {
      glEnable(GL_DEPTH_TEST);
    } else {
      glDisable(GL_DEPTH_TEST);
    }
  }

 private:
  GLint draw_fb_ = 0, read_fb_ = 0, program_ = 0, vao_ = 0, viewport_[4] = {}, depth_func_ = 0;
  GLboolean depth_mask_ = GL_TRUE, depth_test_ = GL_FALSE;
  GLfloat clear_depth_ = 1, clear_color_[4] = {};
};

// A framebuffer, two meshes and the objects the measurement draws with.
class Bench {
 public:
  static Result<std::unique_ptr<Bench>> create(std::uint32_t size) {
    Result<std::unique_ptr<Program>> program = Program::create("calibration", kVertex, kFragment);
    if (!program) return program.status();
    std::unique_ptr<Bench> bench(new Bench(size, std::move(program).value()));
    if (glCheckNamedFramebufferStatus(bench->fbo_, GL_DRAW_FRAMEBUFFER) !=
        GL_FRAMEBUFFER_COMPLETE) {
      return Status(ErrorCode::Environment,
                    "calibration: the driver cannot render to an RGBA8 + 32F depth framebuffer "
                    "of " +
                        std::to_string(size) + " pixels square");
    }
    return bench;
  }

 private:
  Bench(std::uint32_t size, std::unique_ptr<Program> program)
      : size_(GLsizei(size)), program_(std::move(program)) {
    glCreateFramebuffers(1, &fbo_);
    glCreateRenderbuffers(1, &color_);
    glCreateRenderbuffers(1, &depth_);
    glNamedRenderbufferStorage(color_, GL_RGBA8, size_, size_);
    glNamedRenderbufferStorage(depth_, GL_DEPTH_COMPONENT32F, size_, size_);
    glNamedFramebufferRenderbuffer(fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
    glNamedFramebufferRenderbuffer(fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    // O-: one quad (two triangles) of side `pixel` in NDC at z = 0; O+: many triangles
    // inside one pixel, the same triangle over and over.
    const float px = 1.0f / float(size);
    std::vector<float> v = {-px, -px, 0,    px,  -px, 0,    px, px, 0,    -px, -px, 0,
                            px,  px,  0,    -px, px,  0,    -1, -1, 0.5f, 1,   -1,  0.5f,
                            1,   1,   0.5f, -1,  -1,  0.5f, 1,  1,  0.5f, -1,  1,   0.5f};
    for (int i = 0; i < kManyTriangles; ++i) {
      v.insert(v.end(), {-px, -px, 0, px, -px, 0, 0, px, 0});
    }
    glCreateBuffers(1, &buffer_);
    glNamedBufferStorage(buffer_, GLsizeiptr(v.size() * sizeof(float)), v.data(), 0);
    glCreateVertexArrays(1, &vao_);
    glVertexArrayVertexBuffer(vao_, 0, buffer_, 0, 3 * sizeof(float));
    glEnableVertexArrayAttrib(vao_, 0);
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_, 0, 0);
    queries_.resize(kQueries);
    glCreateQueries(GL_SAMPLES_PASSED, GLsizei(kQueries), queries_.data());
  }

 public:
  ~Bench() {
    glDeleteQueries(GLsizei(queries_.size()), queries_.data());
    glDeleteVertexArrays(1, &vao_);
    glDeleteBuffers(1, &buffer_);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteRenderbuffers(1, &color_);
    glDeleteRenderbuffers(1, &depth_);
  }

  static constexpr int kManyTriangles = 20000;
  static constexpr int kQueries = 2000;  // query objects: one per draw, never reused in flight
  GLuint framebuffer() const { return fbo_; }
  GLsizei size() const { return size_; }

  // Binds what the draws below use, clears, depth test on and `depth_func`.
  void prepare(GLenum depth_func) {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
    glViewport(0, 0, size_, size_);
    glClearDepthf(1.0f);
    glClearColor(0, 0, 0, 1);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(depth_func);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    program_->use();
    const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    glUniformMatrix4fv(program_->uniform("u_vp"), 1, GL_FALSE, identity);
    glBindVertexArray(vao_);
  }
  void pixelQuad() { glDrawArrays(GL_TRIANGLES, 0, 6); }
  void screenQuad() { glDrawArrays(GL_TRIANGLES, 6, 6); }
  void manyTriangles() { glDrawArrays(GL_TRIANGLES, 12, 3 * kManyTriangles); }
  GLuint query(int i) const { return queries_[std::size_t(i)]; }

 private:
  GLsizei size_;
  std::unique_ptr<Program> program_;
  GLuint fbo_ = 0, color_ = 0, depth_ = 0, buffer_ = 0, vao_ = 0;
  std::vector<GLuint> queries_;
};

// Median over `repeats` of (wall time of `work` between glFinish calls) / `per`.
double timed(std::uint32_t repeats, double per, const std::function<void()>& setup,
             const std::function<void()>& work) {
  std::vector<double> t;
  for (std::uint32_t r = 0; r < repeats; ++r) {
    setup();
    glFinish();
    const auto a = Clock::now();
    work();
    glFinish();
    t.push_back(seconds(a, Clock::now()) / per);
  }
  std::nth_element(t.begin(), t.begin() + std::ptrdiff_t(t.size() / 2), t.end());
  return t[t.size() / 2];
}

}  // namespace

std::string rendererName() {
  const GLubyte* r = glGetString(GL_RENDERER);
  return r ? reinterpret_cast<const char*>(r) : "unknown";
}

namespace {

constexpr int kCalls = 2000;  // draws (and queries around them) in a timed run

// Drawing: a call, a triangle, a fragment.
void measureDrawing(Bench& bench, std::uint32_t n, double pixels, HardwareParameters& p) {
  const auto prepare = [&] { bench.prepare(GL_LESS); };
  const auto prepare_always = [&] { bench.prepare(GL_ALWAYS); };
  p.render_setup = timed(n, kCalls, prepare, [&] {
    for (int i = 0; i < kCalls; ++i) bench.pixelQuad();
  });
  constexpr int kMeshes = 20;
  const double mesh = timed(n, kMeshes, prepare, [&] {
    for (int i = 0; i < kMeshes; ++i) bench.manyTriangles();
  });
  p.render_triangle = std::max(0.0, mesh - p.render_setup) / Bench::kManyTriangles;
  constexpr int kScreens = 40;
  const double screen = timed(n, kScreens, prepare_always, [&] {
    for (int i = 0; i < kScreens; ++i) bench.screenQuad();
  });
  p.render_fragment = std::max(0.0, screen - p.render_setup) / pixels;
}

// Occlusion query objects around draws: their overhead, and a poll's. After
// measureDrawing (render_setup).
void measureQueryObjects(Bench& bench, std::uint32_t n, HardwareParameters& p) {
  const auto prepare = [&] { bench.prepare(GL_LESS); };
  // A query around each draw (each its own query object) against the same draws without.
  static_assert(kCalls <= Bench::kQueries, "one query object per draw");
  const auto read_all = [&](int count) {
    GLuint samples = 0;
    for (int i = 0; i < count; ++i) glGetQueryObjectuiv(bench.query(i), GL_QUERY_RESULT, &samples);
  };
  const double with_query = timed(n, kCalls, prepare, [&] {
    for (int i = 0; i < kCalls; ++i) {
      glBeginQuery(GL_SAMPLES_PASSED, bench.query(i));
      bench.pixelQuad();
      glEndQuery(GL_SAMPLES_PASSED);
    }
    read_all(kCalls);
  });
  p.query_overhead = std::max(0.0, with_query - p.render_setup);
  // A poll of the query just issued around a draw (it has work pending), against the
  // queried draws without polls.
  constexpr int kPolls = 500;
  const double with_poll = timed(n, kPolls, prepare, [&] {
    GLuint available = 0;
    for (int i = 0; i < kPolls; ++i) {
      glBeginQuery(GL_SAMPLES_PASSED, bench.query(i));
      bench.pixelQuad();
      glEndQuery(GL_SAMPLES_PASSED);
      glGetQueryObjectuiv(bench.query(i), GL_QUERY_RESULT_AVAILABLE, &available);
    }
    read_all(kPolls);
  });
  p.poll = std::max(0.0, with_poll - with_query);
}

// Queries as the culler issues them (BoxQuerySource): a query's setup, a fragment's,
// and the latency from issue to answer.
Status measureBoxQueries(Bench& bench, std::uint32_t size, std::uint32_t n, HardwareParameters& p) {
  Camera camera;  // clip space = world space
  camera.width = size;
  camera.height = size;
  const float px = 1.0f / float(size);
  const QueryBox small{{{-px, -px, 0.0f}, {px, px, 0.1f}}, 0};
  const QueryBox large{{{-1, -1, 0.0f}, {1, 1, 0.1f}}, 0};
  BoxQuerySource queries(bench.framebuffer());
  std::vector<QueryHandle> handles;
  auto queryMany = [&](const QueryBox& box, int count) {
    handles.clear();
    for (int i = 0; i < count; ++i) handles.push_back(queries.issueBoxes(&box, 1));
    for (QueryHandle h : handles) queries.result(h);
  };
  // The query source is checked once; in the timed runs it serves the same camera.
  bench.prepare(GL_LESS);
  if (Status begun = queries.beginQueryFrame(camera); !begun) return begun;
  const auto prepare_queries = [&] {
    bench.prepare(GL_LESS);
    (void)queries.beginQueryFrame(camera);
  };
  constexpr int kQueries = 500;
  timed(1, 1, prepare_queries, [&] { queryMany(large, 4); });  // warm-up
  p.query_setup = timed(n, kQueries, prepare_queries, [&] { queryMany(small, kQueries); });
  constexpr int kLargeQueries = 40;
  const double large_query =
      timed(n, kLargeQueries, prepare_queries, [&] { queryMany(large, kLargeQueries); });
  p.query_fragment = std::max(0.0, large_query - p.query_setup) / (double(size) * size);
  // Latency: from issue to answer of one query on an idle pipeline. The paper takes the
  // largest; on a shared machine the largest of a few runs is a scheduling hiccup, so the
  // median is kept like every other time here.
  std::vector<double> latencies;
  for (std::uint32_t r = 0; r < std::max(n, 5u); ++r) {
    prepare_queries();
    glFinish();
    const auto a = Clock::now();
    const QueryHandle h = queries.issueBoxes(&small, 1);
    while (!queries.ready(h)) {
    }
    latencies.push_back(seconds(a, Clock::now()));
    queries.result(h);
  }
  std::nth_element(latencies.begin(), latencies.begin() + std::ptrdiff_t(latencies.size() / 2),
                   latencies.end());
  p.query_latency = latencies[latencies.size() / 2];
  if (Status ended = queries.endQueryFrame(); !ended) return ended;
  return queries.takeError();
}

}  // namespace

Result<HardwareParameters> tryMeasureHardwareParameters(const CalibrationDesc& desc) {
  if (desc.size < 16 || desc.size > 4096 || desc.repeats < 1) {
    return Status(ErrorCode::InvalidArgument,
                  "calibration: size " + std::to_string(desc.size) + " and repeats " +
                      std::to_string(desc.repeats) +
                      " are invalid; use a size from 16 to 4096 pixels and 1 or more repeats");
  }
  const SavedState saved;
  Result<std::unique_ptr<Bench>> made = Bench::create(desc.size);
  if (!made) return made.status();
  Bench& bench = **made;
  // Warm-up: llvmpipe compiles each new state on first use (docs/PLATFORM.md, "JIT warm-up").
  timed(
      1, 1, [&] { bench.prepare(GL_LESS); },
      [&] {
        bench.pixelQuad();
        bench.screenQuad();
        bench.manyTriangles();
      });
  HardwareParameters p;
  measureDrawing(bench, desc.repeats, double(desc.size) * desc.size, p);
  measureQueryObjects(bench, desc.repeats, p);
  if (Status queried = measureBoxQueries(bench, desc.size, desc.repeats, p); !queried) {
    return queried;
  }
  glFinish();
  return p;
}

Result<HardwareParameters> tryHardwareParameters() {
  static std::mutex mutex;
  static std::map<std::string, HardwareParameters> measured;
  const std::string renderer = rendererName();
  const std::lock_guard<std::mutex> lock(mutex);
  const auto it = measured.find(renderer);
  if (it != measured.end()) return it->second;
  const Result<HardwareParameters> p = tryMeasureHardwareParameters();
  if (p) measured.emplace(renderer, *p);
  return p;
}

}  // namespace logrid::zread
