// For tests of GL-state independence: a snapshot of the context state that an
// application may set (written apart from zread's GlStateGuard, so that an item the guard
// forgets shows up as a difference), and random application state to set before a depth
// source runs.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace logrid::test {

// Item name -> values, e.g. "GL_VIEWPORT[0]" -> {x, y, w, h}.
using GlSnapshot = std::map<std::string, std::vector<double>>;

namespace detail {

inline void putInts(GlSnapshot& s, const std::string& name, GLenum e, int n = 1) {
  GLint v[16] = {};
  glGetIntegerv(e, v);
  s[name].assign(v, v + n);
}
inline void putFloats(GlSnapshot& s, const std::string& name, GLenum e, int n = 1) {
  GLdouble v[16] = {};
  glGetDoublev(e, v);
  s[name].assign(v, v + n);
}
inline void putEnabled(GlSnapshot& s, const std::string& name, GLenum e) {
  s[name] = {double(glIsEnabled(e))};
}

}  // namespace detail

#define LOGRID_PROBE_INT(e) detail::putInts(s, #e, e)
#define LOGRID_PROBE_INTS(e, n) detail::putInts(s, #e, e, n)
#define LOGRID_PROBE_FLOAT(e) detail::putFloats(s, #e, e)
#define LOGRID_PROBE_FLOATS(e, n) detail::putFloats(s, #e, e, n)
#define LOGRID_PROBE_ENABLED(e) detail::putEnabled(s, #e, e)

// The state of the current context, as glGet reports it. `textures` adds per-texture
// state (swizzle, depth-stencil mode, compare mode, filters) of those textures, and
// `framebuffers` their draw and read buffers.
inline GlSnapshot snapshotGlState(const std::vector<GLuint>& textures = {},
                                  const std::vector<GLuint>& framebuffers = {}) {
  GlSnapshot s;
  LOGRID_PROBE_ENABLED(GL_CULL_FACE);
  LOGRID_PROBE_ENABLED(GL_DEPTH_TEST);
  LOGRID_PROBE_ENABLED(GL_STENCIL_TEST);
  LOGRID_PROBE_ENABLED(GL_DEPTH_CLAMP);
  LOGRID_PROBE_ENABLED(GL_RASTERIZER_DISCARD);
  LOGRID_PROBE_ENABLED(GL_POLYGON_OFFSET_FILL);
  LOGRID_PROBE_ENABLED(GL_POLYGON_OFFSET_LINE);
  LOGRID_PROBE_ENABLED(GL_POLYGON_OFFSET_POINT);
  LOGRID_PROBE_ENABLED(GL_SAMPLE_MASK);
  LOGRID_PROBE_ENABLED(GL_SAMPLE_COVERAGE);
  LOGRID_PROBE_ENABLED(GL_SAMPLE_ALPHA_TO_COVERAGE);
  LOGRID_PROBE_ENABLED(GL_SAMPLE_ALPHA_TO_ONE);
  LOGRID_PROBE_ENABLED(GL_MULTISAMPLE);
  LOGRID_PROBE_ENABLED(GL_SAMPLE_SHADING);
  LOGRID_PROBE_ENABLED(GL_DITHER);
  LOGRID_PROBE_ENABLED(GL_COLOR_LOGIC_OP);
  LOGRID_PROBE_ENABLED(GL_PRIMITIVE_RESTART);
  LOGRID_PROBE_ENABLED(GL_PROGRAM_POINT_SIZE);
  LOGRID_PROBE_ENABLED(GL_FRAMEBUFFER_SRGB);
  LOGRID_PROBE_ENABLED(GL_LINE_SMOOTH);
  LOGRID_PROBE_ENABLED(GL_POLYGON_SMOOTH);
  if (epoxy_has_gl_extension("GL_EXT_depth_bounds_test")) {
    LOGRID_PROBE_ENABLED(GL_DEPTH_BOUNDS_TEST_EXT);
    LOGRID_PROBE_FLOATS(GL_DEPTH_BOUNDS_EXT, 2);
  }
  GLint viewports = 0, clip_distances = 0, draw_buffers = 0, mask_words = 0, units = 0;
  glGetIntegerv(GL_MAX_VIEWPORTS, &viewports);
  glGetIntegerv(GL_MAX_CLIP_DISTANCES, &clip_distances);
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &draw_buffers);
  glGetIntegerv(GL_MAX_SAMPLE_MASK_WORDS, &mask_words);
  glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &units);
  for (GLint i = 0; i < viewports; ++i) {
    const std::string at = "[" + std::to_string(i) + "]";
    s["GL_SCISSOR_TEST" + at] = {double(glIsEnabledi(GL_SCISSOR_TEST, GLuint(i)))};
    GLint box[4];
    glGetIntegeri_v(GL_SCISSOR_BOX, GLuint(i), box);
    s["GL_SCISSOR_BOX" + at].assign(box, box + 4);
    GLfloat vp[4];
    glGetFloati_v(GL_VIEWPORT, GLuint(i), vp);
    s["GL_VIEWPORT" + at].assign(vp, vp + 4);
    GLdouble range[2];
    glGetDoublei_v(GL_DEPTH_RANGE, GLuint(i), range);
    s["GL_DEPTH_RANGE" + at].assign(range, range + 2);
  }
  for (GLint i = 0; i < clip_distances; ++i) {
    s["GL_CLIP_DISTANCE" + std::to_string(i)] = {
        double(glIsEnabled(GLenum(GL_CLIP_DISTANCE0 + i)))};
  }
  for (GLint i = 0; i < draw_buffers; ++i) {
    const std::string at = "[" + std::to_string(i) + "]";
    GLboolean m[4];
    glGetBooleani_v(GL_COLOR_WRITEMASK, GLuint(i), m);
    s["GL_COLOR_WRITEMASK" + at].assign(m, m + 4);
    s["GL_BLEND" + at] = {double(glIsEnabledi(GL_BLEND, GLuint(i)))};
  }
  for (GLint i = 0; i < mask_words; ++i) {
    GLint w = 0;
    glGetIntegeri_v(GL_SAMPLE_MASK_VALUE, GLuint(i), &w);
    s["GL_SAMPLE_MASK_VALUE[" + std::to_string(i) + "]"] = {double(GLuint(w))};
  }
  LOGRID_PROBE_INT(GL_CULL_FACE_MODE);
  LOGRID_PROBE_INT(GL_FRONT_FACE);
  LOGRID_PROBE_INTS(GL_POLYGON_MODE, 2);
  LOGRID_PROBE_INT(GL_DEPTH_FUNC);
  LOGRID_PROBE_INT(GL_DEPTH_WRITEMASK);
  LOGRID_PROBE_INT(GL_STENCIL_FUNC);
  LOGRID_PROBE_INT(GL_STENCIL_REF);
  LOGRID_PROBE_INT(GL_STENCIL_VALUE_MASK);
  LOGRID_PROBE_INT(GL_STENCIL_FAIL);
  LOGRID_PROBE_INT(GL_STENCIL_PASS_DEPTH_FAIL);
  LOGRID_PROBE_INT(GL_STENCIL_PASS_DEPTH_PASS);
  LOGRID_PROBE_INT(GL_STENCIL_WRITEMASK);
  LOGRID_PROBE_INT(GL_STENCIL_BACK_FUNC);
  LOGRID_PROBE_INT(GL_STENCIL_BACK_WRITEMASK);
  LOGRID_PROBE_INT(GL_CLIP_ORIGIN);
  LOGRID_PROBE_INT(GL_CLIP_DEPTH_MODE);
  LOGRID_PROBE_INT(GL_SAMPLE_COVERAGE_INVERT);
  LOGRID_PROBE_FLOAT(GL_SAMPLE_COVERAGE_VALUE);
  LOGRID_PROBE_FLOAT(GL_POLYGON_OFFSET_FACTOR);
  LOGRID_PROBE_FLOAT(GL_POLYGON_OFFSET_UNITS);
  LOGRID_PROBE_FLOAT(GL_MIN_SAMPLE_SHADING_VALUE);
  LOGRID_PROBE_FLOAT(GL_LINE_WIDTH);
  LOGRID_PROBE_FLOAT(GL_POINT_SIZE);
  LOGRID_PROBE_FLOATS(GL_COLOR_CLEAR_VALUE, 4);
  LOGRID_PROBE_FLOAT(GL_DEPTH_CLEAR_VALUE);
  LOGRID_PROBE_INT(GL_STENCIL_CLEAR_VALUE);
  LOGRID_PROBE_FLOATS(GL_BLEND_COLOR, 4);
  LOGRID_PROBE_INT(GL_LOGIC_OP_MODE);
  LOGRID_PROBE_INT(GL_PROVOKING_VERTEX);
  LOGRID_PROBE_INT(GL_PRIMITIVE_RESTART_INDEX);
  LOGRID_PROBE_INT(GL_PATCH_VERTICES);
  LOGRID_PROBE_INT(GL_CLAMP_READ_COLOR);
  // Bindings.
  LOGRID_PROBE_INT(GL_READ_FRAMEBUFFER_BINDING);
  LOGRID_PROBE_INT(GL_DRAW_FRAMEBUFFER_BINDING);
  LOGRID_PROBE_INT(GL_RENDERBUFFER_BINDING);
  LOGRID_PROBE_INT(GL_CURRENT_PROGRAM);
  LOGRID_PROBE_INT(GL_PROGRAM_PIPELINE_BINDING);
  LOGRID_PROBE_INT(GL_VERTEX_ARRAY_BINDING);
  LOGRID_PROBE_INT(GL_ARRAY_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_PIXEL_PACK_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_PIXEL_UNPACK_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_COPY_READ_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_COPY_WRITE_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_DRAW_INDIRECT_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_DISPATCH_INDIRECT_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_QUERY_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_SHADER_STORAGE_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_UNIFORM_BUFFER_BINDING);
  LOGRID_PROBE_INT(GL_TRANSFORM_FEEDBACK_BINDING);
  LOGRID_PROBE_INT(GL_ACTIVE_TEXTURE);
  // Pixel storage.
  LOGRID_PROBE_INT(GL_PACK_ALIGNMENT);
  LOGRID_PROBE_INT(GL_PACK_ROW_LENGTH);
  LOGRID_PROBE_INT(GL_PACK_SKIP_PIXELS);
  LOGRID_PROBE_INT(GL_PACK_SKIP_ROWS);
  LOGRID_PROBE_INT(GL_PACK_IMAGE_HEIGHT);
  LOGRID_PROBE_INT(GL_PACK_SKIP_IMAGES);
  LOGRID_PROBE_INT(GL_PACK_SWAP_BYTES);
  LOGRID_PROBE_INT(GL_PACK_LSB_FIRST);
  LOGRID_PROBE_INT(GL_UNPACK_ALIGNMENT);
  LOGRID_PROBE_INT(GL_UNPACK_ROW_LENGTH);
  // Texture units: every unit's 2D and 2D-multisample binding and sampler. Switching
  // the active unit is undone before returning.
  GLint active = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  for (GLint u = 0; u < units; ++u) {
    glActiveTexture(GLenum(GL_TEXTURE0 + u));
    const std::string at = "[unit " + std::to_string(u) + "]";
    GLint t2d = 0, tms = 0, sampler = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &t2d);
    glGetIntegerv(GL_TEXTURE_BINDING_2D_MULTISAMPLE, &tms);
    glGetIntegerv(GL_SAMPLER_BINDING, &sampler);
    s["GL_TEXTURE_BINDING_2D" + at] = {double(t2d)};
    s["GL_TEXTURE_BINDING_2D_MULTISAMPLE" + at] = {double(tms)};
    s["GL_SAMPLER_BINDING" + at] = {double(sampler)};
  }
  glActiveTexture(GLenum(active));
  for (GLuint t : textures) {
    const std::string at = "[texture " + std::to_string(t) + "]";
    GLint swizzle[4] = {}, mode = 0, compare = 0, min_filter = 0, base = 0;
    glGetTextureParameteriv(t, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
    glGetTextureParameteriv(t, GL_DEPTH_STENCIL_TEXTURE_MODE, &mode);
    glGetTextureParameteriv(t, GL_TEXTURE_COMPARE_MODE, &compare);
    glGetTextureParameteriv(t, GL_TEXTURE_MIN_FILTER, &min_filter);
    glGetTextureParameteriv(t, GL_TEXTURE_BASE_LEVEL, &base);
    s["GL_TEXTURE_SWIZZLE_RGBA" + at].assign(swizzle, swizzle + 4);
    s["GL_DEPTH_STENCIL_TEXTURE_MODE" + at] = {double(mode)};
    s["GL_TEXTURE_COMPARE_MODE" + at] = {double(compare)};
    s["GL_TEXTURE_MIN_FILTER" + at] = {double(min_filter)};
    s["GL_TEXTURE_BASE_LEVEL" + at] = {double(base)};
  }
  // Draw and read buffers are framebuffer state, queried with the framebuffer bound (Mesa
  // does not answer them through glGetNamedFramebufferParameteriv); bindings are undone.
  GLint read_binding = 0, draw_binding = 0;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_binding);
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_binding);
  for (GLuint f : framebuffers) {
    const std::string at = "[framebuffer " + std::to_string(f) + "]";
    glBindFramebuffer(GL_FRAMEBUFFER, f);
    GLint read = 0, draw[4] = {};
    glGetIntegerv(GL_READ_BUFFER, &read);
    for (int i = 0; i < 4; ++i) glGetIntegerv(GLenum(GL_DRAW_BUFFER0 + i), &draw[i]);
    s["GL_READ_BUFFER" + at] = {double(read)};
    s["GL_DRAW_BUFFERi" + at].assign(draw, draw + 4);
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_binding));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_binding));
  return s;
}

#undef LOGRID_PROBE_INT
#undef LOGRID_PROBE_INTS
#undef LOGRID_PROBE_FLOAT
#undef LOGRID_PROBE_FLOATS
#undef LOGRID_PROBE_ENABLED

// The items that differ, one per line ("" when none).
inline std::string diffGlState(const GlSnapshot& before, const GlSnapshot& after) {
  std::ostringstream out;
  for (const auto& [name, values] : before) {
    const auto it = after.find(name);
    if (it == after.end()) {
      out << name << ": missing after\n";
    } else if (it->second != values) {
      out << name << ": {";
      for (double v : values) out << " " << v;
      out << " } became {";
      for (double v : it->second) out << " " << v;
      out << " }\n";
    }
  }
  return out.str();
}

// Objects an application might have bound: another framebuffer, a program, a program
// pipeline, a vertex array, a buffer on the pack target. Created on the current context.
struct AppObjects {
  GLuint framebuffer = 0, color = 0, program = 0, pipeline = 0, vertex_array = 0, buffer = 0;
  AppObjects() {
    glCreateFramebuffers(1, &framebuffer);
    glCreateTextures(GL_TEXTURE_2D, 1, &color);
    glTextureStorage2D(color, 1, GL_RGBA8, 8, 8);
    glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
    // A program whose vertices all land outside the clip volume.
    const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(4.0, 4.0, 4.0, 1.0); }\n";
    const char* fs = "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n";
    program = glCreateProgram();
    for (auto [stage, src] :
         {std::pair{GLenum(GL_VERTEX_SHADER), vs}, std::pair{GLenum(GL_FRAGMENT_SHADER), fs}}) {
      const GLuint sh = glCreateShader(stage);
      glShaderSource(sh, 1, &src, nullptr);
      glCompileShader(sh);
      glAttachShader(program, sh);
      glDeleteShader(sh);
    }
    glLinkProgram(program);
    glCreateProgramPipelines(1, &pipeline);
    glCreateVertexArrays(1, &vertex_array);
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, 1 << 20, nullptr, 0);
  }
  ~AppObjects() {
    // Unbound first: Mesa 22 keeps a program pipeline deleted while bound (with a program
    // current) as the current pipeline, and a later glUseProgram(0) then fails.
    glBindProgramPipeline(0);
    glUseProgram(0);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteTextures(1, &color);
    glDeleteProgram(program);
    glDeleteProgramPipelines(1, &pipeline);
    glDeleteVertexArrays(1, &vertex_array);
    glDeleteBuffers(1, &buffer);
  }
  AppObjects(const AppObjects&) = delete;
  AppObjects& operator=(const AppObjects&) = delete;
};

// Which parts of the state setRandomGlState() touches.
enum GlStateGroups : unsigned {
  // State that shapes what an application's own draws produce, and that an application
  // may legitimately draw its frame with: face culling and winding, stencil, sample mask,
  // sample coverage, alpha to coverage and to one, multisampling, rasterizer discard, the
  // scissor test and box (index 0).
  kDrawShaping = 1u << 0,
  // State an application must not draw its culled frame with (culler.hpp's contract:
  // the depth test keeps the nearer fragment, writes on, the camera's depth range and
  // projection), but may leave set between its draws: polygon mode, depth test, function
  // and mask, depth clamp and range, clip distances, polygon offset, viewport, colour
  // masks, depth bounds.
  kContractState = 1u << 1,
  kBindings = 1u << 2,    // framebuffers, program, pipeline, vertex array, pack buffer, texture
  kPixelStore = 1u << 3,  // pack parameters, read clamping
  kRasterState = kDrawShaping | kContractState,
  kAllGlState = kRasterState | kBindings | kPixelStore,
};

// Sets random values for the items in `groups`: what an application may have left on
// the context when it calls logrid. Boxes (scissor, viewport) lie in a `width` x `height`
// framebuffer; `app_framebuffer` is the application's own. Returns the items enabled,
// for messages. The same seed sets the same values.
inline std::string setRandomGlState(std::mt19937& rng, const AppObjects& objects,
                                    unsigned groups = kAllGlState, GLuint app_framebuffer = 0,
                                    int width = 8, int height = 8) {
  std::ostringstream what;
  auto coin = [&](double p = 0.5) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; };
  auto pick = [&](std::initializer_list<GLenum> v) {
    return *(v.begin() + std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng));
  };
  auto unit = [&] { return std::uniform_real_distribution<double>(0, 1)(rng); };
  auto below = [&](int n) { return n > 0 ? int(rng() % unsigned(n)) : 0; };
  auto set = [&](GLenum cap, bool on, const char* name) {
    on ? glEnable(cap) : glDisable(cap);
    if (on) what << name << " ";
  };
  if (groups & kDrawShaping) {
    set(GL_CULL_FACE, coin(), "cull");
    glCullFace(pick({GL_FRONT, GL_BACK, GL_FRONT_AND_BACK}));
    glFrontFace(pick({GL_CW, GL_CCW}));
    set(GL_STENCIL_TEST, coin(), "stencil");
    glStencilFunc(pick({GL_NEVER, GL_LESS, GL_EQUAL, GL_ALWAYS}), below(256), rng() % 256);
    glStencilOp(pick({GL_KEEP, GL_ZERO, GL_INVERT}), pick({GL_KEEP, GL_INCR}),
                pick({GL_KEEP, GL_REPLACE, GL_DECR}));
    // Sample masks and coverage leave samples unwritten, so the farthest sample of those
    // pixels stays cleared and nothing behind them is culled: rarer, to keep culling.
    set(GL_SAMPLE_MASK, coin(0.2), "sample-mask");
    glSampleMaski(0, GLbitfield(rng() & 0xF));
    set(GL_SAMPLE_COVERAGE, coin(0.2), "coverage");
    glSampleCoverage(float(unit()), coin() ? GL_TRUE : GL_FALSE);
    set(GL_SAMPLE_ALPHA_TO_COVERAGE, coin(), "alpha-to-coverage");
    set(GL_SAMPLE_ALPHA_TO_ONE, coin(), "alpha-to-one");
    set(GL_MULTISAMPLE, coin(0.7), "multisample");
    set(GL_RASTERIZER_DISCARD, coin(0.1), "discard");
    const bool scissor = coin();
    scissor ? glEnablei(GL_SCISSOR_TEST, 0) : glDisablei(GL_SCISSOR_TEST, 0);
    if (scissor) what << "scissor ";
    const int x0 = below(width / 2), y0 = below(height / 2);
    glScissorIndexed(0, x0, y0, 1 + below(width - x0), 1 + below(height - y0));
  }
  if (groups & kContractState) {
    const GLenum mode = pick({GL_FILL, GL_LINE, GL_POINT});
    glPolygonMode(GL_FRONT_AND_BACK, mode);
    if (mode != GL_FILL) what << (mode == GL_LINE ? "line " : "point ");
    set(GL_DEPTH_TEST, coin(), "depth-test");
    glDepthFunc(pick({GL_NEVER, GL_LESS, GL_EQUAL, GL_GREATER, GL_ALWAYS, GL_LEQUAL}));
    glDepthMask(coin() ? GL_TRUE : GL_FALSE);
    set(GL_DEPTH_CLAMP, coin(), "clamp");
    const double a = unit(), b = unit();
    glDepthRangeIndexed(0, a, b);
    for (int i = 0; i < 8; ++i) set(GLenum(GL_CLIP_DISTANCE0 + i), coin(0.2), "clip");
    set(GL_POLYGON_OFFSET_FILL, coin(), "offset");
    set(GL_POLYGON_OFFSET_LINE, coin(), "offset-line");
    set(GL_POLYGON_OFFSET_POINT, coin(), "offset-point");
    glPolygonOffset(float(unit() * 200 - 100), float(unit() * 2e5 - 1e5));
    glViewportIndexedf(0, float(below(width)), float(below(height)), float(below(width)),
                       float(below(height)));
    for (GLuint i = 0; i < 8; ++i) {
      glColorMaski(i, coin() ? GL_TRUE : GL_FALSE, coin() ? GL_TRUE : GL_FALSE,
                   coin() ? GL_TRUE : GL_FALSE, coin() ? GL_TRUE : GL_FALSE);
    }
    if (epoxy_has_gl_extension("GL_EXT_depth_bounds_test")) {
      set(GL_DEPTH_BOUNDS_TEST_EXT, coin(), "depth-bounds");
      glDepthBoundsEXT(0.4, 0.6);
    }
  }
  if (groups & kBindings) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, coin() ? objects.framebuffer : app_framebuffer);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, coin() ? objects.framebuffer : app_framebuffer);
    glBindProgramPipeline(coin() ? objects.pipeline : 0);
    glUseProgram(coin() ? objects.program : 0);
    glBindVertexArray(coin() ? objects.vertex_array : 0);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, coin() ? objects.buffer : 0);
    glActiveTexture(GLenum(GL_TEXTURE0 + rng() % 4));
    glBindTexture(GL_TEXTURE_2D, coin() ? objects.color : 0);
  }
  if (groups & kPixelStore) {
    glPixelStorei(GL_PACK_ALIGNMENT, int(pick({1, 2, 4, 8})));
    glPixelStorei(GL_PACK_ROW_LENGTH, int(rng() % 3) * 37);
    glPixelStorei(GL_PACK_SKIP_PIXELS, int(rng() % 5));
    glPixelStorei(GL_PACK_SKIP_ROWS, int(rng() % 5));
    glPixelStorei(GL_PACK_IMAGE_HEIGHT, int(rng() % 3));
    glPixelStorei(GL_PACK_SKIP_IMAGES, int(rng() % 3));
    glPixelStorei(GL_PACK_SWAP_BYTES, coin(0.3) ? GL_TRUE : GL_FALSE);
    glPixelStorei(GL_PACK_LSB_FIRST, coin() ? GL_TRUE : GL_FALSE);
    glClampColor(GL_CLAMP_READ_COLOR, pick({GL_TRUE, GL_FALSE, GL_FIXED_ONLY}));
  }
  return what.str();
}

// One piece of state that changes which fragments a depth source's draw produces or
// where it goes (each alone made an unguarded occlusion-query draw count wrong).
struct HostileState {
  const char* name;
  std::function<void()> set;
  // GL leaves the unguarded result undefined (it may happen to be right on a driver).
  bool undefined = false;
};

inline std::vector<HostileState> hostileGlStates() {
  return {
      {"cull front faces", [] { glEnable(GL_CULL_FACE), glCullFace(GL_FRONT); }},
      {"clockwise winding, cull back", [] { glEnable(GL_CULL_FACE), glFrontFace(GL_CW); }},
      {"cull front and back", [] { glEnable(GL_CULL_FACE), glCullFace(GL_FRONT_AND_BACK); }},
      {"polygon mode line", [] { glPolygonMode(GL_FRONT_AND_BACK, GL_LINE); }},
      {"polygon mode point", [] { glPolygonMode(GL_FRONT_AND_BACK, GL_POINT); }},
      {"stencil test failing everything",
       [] { glEnable(GL_STENCIL_TEST), glStencilFunc(GL_NEVER, 0, 0xFF); }},
      {"rasterizer discard", [] { glEnable(GL_RASTERIZER_DISCARD); }},
      {"depth clamp into a narrow depth range",
       [] { glEnable(GL_DEPTH_CLAMP), glDepthRangeIndexed(0, 0.0, 0.1); }},
      {"depth test off", [] { glDisable(GL_DEPTH_TEST); }},
      {"viewport of one pixel", [] { glViewportIndexedf(0, 0, 0, 1, 1); }},
      // The draw's shader writes no gl_ClipDistance: undefined (llvmpipe draws all).
      {"clip distances enabled",
       [] {
         for (int i = 0; i < 8; ++i) glEnable(GLenum(GL_CLIP_DISTANCE0 + i));
       },
       true},
      // The draw writes gl_FragDepth, which polygon offset does not move.
      {"polygon offset", [] { glEnable(GL_POLYGON_OFFSET_FILL), glPolygonOffset(0, -1e6f); }, true},
      {"pack row length, skips and alignment",
       [] {
         glPixelStorei(GL_PACK_ROW_LENGTH, 77);
         glPixelStorei(GL_PACK_SKIP_PIXELS, 3);
         glPixelStorei(GL_PACK_SKIP_ROWS, 2);
         glPixelStorei(GL_PACK_ALIGNMENT, 8);
       },
       true},
      {"read colour clamping", [] { glClampColor(GL_CLAMP_READ_COLOR, GL_TRUE); }, true},
  };
}

// GL's initial values for what setRandomGlState() sets, with the viewport and scissor
// box at `width` x `height` and nothing bound.
inline void setDefaultGlState(int width, int height) {
  glDisable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDisable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 0, 0xFF);
  glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  glDisable(GL_RASTERIZER_DISCARD);
  glDisable(GL_DEPTH_CLAMP);
  glDepthRangeIndexed(0, 0.0, 1.0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glViewportIndexedf(0, 0, 0, float(width), float(height));
  glDisablei(GL_SCISSOR_TEST, 0);
  glScissorIndexed(0, 0, 0, width, height);
  for (int i = 0; i < 8; ++i) glDisable(GLenum(GL_CLIP_DISTANCE0 + i));
  glDisable(GL_SAMPLE_MASK);
  glSampleMaski(0, ~0u);
  glDisable(GL_SAMPLE_COVERAGE);
  glSampleCoverage(1.0f, GL_FALSE);
  glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  glDisable(GL_SAMPLE_ALPHA_TO_ONE);
  glEnable(GL_MULTISAMPLE);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_POLYGON_OFFSET_LINE);
  glDisable(GL_POLYGON_OFFSET_POINT);
  glPolygonOffset(0, 0);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glUseProgram(0);
  glBindProgramPipeline(0);
  glBindVertexArray(0);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
  glPixelStorei(GL_PACK_SKIP_ROWS, 0);
  glPixelStorei(GL_PACK_IMAGE_HEIGHT, 0);
  glPixelStorei(GL_PACK_SKIP_IMAGES, 0);
  glPixelStorei(GL_PACK_SWAP_BYTES, GL_FALSE);
  glPixelStorei(GL_PACK_LSB_FIRST, GL_FALSE);
  glClampColor(GL_CLAMP_READ_COLOR, GL_FIXED_ONLY);
  if (epoxy_has_gl_extension("GL_EXT_depth_bounds_test")) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
}

}  // namespace logrid::test
