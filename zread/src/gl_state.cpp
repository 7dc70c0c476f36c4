#include "logrid/zread/gl_state.hpp"

#include <epoxy/gl.h>

#include <sstream>
#include <string>

#include "logrid/error.hpp"

namespace logrid::zread {
namespace {

std::string errorName(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    default: {
      std::ostringstream out;
      out << "0x" << std::hex << e;
      return out.str();
    }
  }
}

// Every error flag GL holds (an implementation may hold several), as one string.
std::string drainErrors(std::uint64_t& queries) {
  std::string errors;
  for (int i = 0; i < 16; ++i) {
    ++queries;
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    if (!errors.empty()) errors += ", ";
    errors += errorName(e);
  }
  return errors;
}

void setEnabled(GLenum cap, bool on) { on ? glEnable(cap) : glDisable(cap); }

}  // namespace

// Every GL query the guard makes (glGet*, glIsEnabled*, glIs*, glGetError) goes through
// LOGRID_STATE_QUERY, which counts it in GlStateGuard::stateQueries(): on a threaded
// driver each one waits for the driver's thread.
#define LOGRID_STATE_QUERY(call) (++*guard_.queries_, (call))

std::uint8_t GlStateGuard::Scope::enabled(std::uint32_t cap) {
  return LOGRID_STATE_QUERY(glIsEnabled(cap)) ? 1 : 0;
}
std::int32_t GlStateGuard::Scope::integer(std::uint32_t name) {
  GLint v = 0;
  LOGRID_STATE_QUERY(glGetIntegerv(name, &v));
  return v;
}

namespace {

// `name` if it still names an object (glIs* says so, counted in `queries`), else 0.
template <typename IsFunction>
GLuint exists(std::uint64_t& queries, IsFunction is, GLint name) {
  if (name == 0) return 0;
  ++queries;
  return is(GLuint(name)) ? GLuint(name) : 0;
}

GLenum textureBinding(GLenum target) {
  switch (target) {
    case GL_TEXTURE_2D: return GL_TEXTURE_BINDING_2D;
    case GL_TEXTURE_2D_ARRAY: return GL_TEXTURE_BINDING_2D_ARRAY;
    case GL_TEXTURE_2D_MULTISAMPLE: return GL_TEXTURE_BINDING_2D_MULTISAMPLE;
    case GL_TEXTURE_2D_MULTISAMPLE_ARRAY: return GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY;
    case GL_TEXTURE_RECTANGLE: return GL_TEXTURE_BINDING_RECTANGLE;
    case GL_TEXTURE_CUBE_MAP: return GL_TEXTURE_BINDING_CUBE_MAP;
    case GL_TEXTURE_CUBE_MAP_ARRAY: return GL_TEXTURE_BINDING_CUBE_MAP_ARRAY;
    case GL_TEXTURE_1D: return GL_TEXTURE_BINDING_1D;
    case GL_TEXTURE_1D_ARRAY: return GL_TEXTURE_BINDING_1D_ARRAY;
    case GL_TEXTURE_3D: return GL_TEXTURE_BINDING_3D;
    default: return 0;
  }
}

}  // namespace

namespace {
// The guard whose access window is open on this thread (GL contexts are per thread).
thread_local GlStateGuard* t_open_window = nullptr;
}  // namespace

GlStateGuard::GlStateGuard(GlStatePolicy policy, std::uint64_t* query_counter, FirstError* errors)
    : policy_(policy),
      queries_(query_counter ? query_counter : &own_queries_),
      errors_(errors ? errors : &own_errors_) {
  glGetIntegerv(GL_MAX_CLIP_DISTANCES, &clip_distances_);
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &draw_buffers_);
  glGetIntegerv(GL_MAX_SAMPLE_MASK_WORDS, &sample_mask_words_);
  if (clip_distances_ > kMaxClipDistances || draw_buffers_ > kMaxDrawBuffers ||
      sample_mask_words_ > kMaxSampleMaskWords) {
    std::ostringstream out;
    out << "GlStateGuard: the driver reports " << clip_distances_ << " clip distances, "
        << draw_buffers_ << " draw buffers and " << sample_mask_words_
        << " sample-mask words; logrid saves at most " << kMaxClipDistances << ", "
        << kMaxDrawBuffers << " and " << kMaxSampleMaskWords
        << " (raise GlStateGuard::kMax* and rebuild)";
    unusable_ = Status(ErrorCode::Unsupported, out.str());
    return;
  }
  depth_bounds_ = epoxy_has_gl_extension("GL_EXT_depth_bounds_test");
  representative_fragment_ = epoxy_has_gl_extension("GL_NV_representative_fragment_test");
  scissor_exclusive_ = epoxy_has_gl_extension("GL_NV_scissor_exclusive");
  glCreateQueries(GL_SAMPLES_PASSED, 1, &probe_query_);
  glCreateSamplers(1, &sampler_);
  glSamplerParameteri(sampler_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(sampler_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(sampler_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  glSamplerParameteri(sampler_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(sampler_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

GlStateGuard::~GlStateGuard() {
  access_ = false;
  closeWindow(false);
  if (probe_query_) glDeleteQueries(1, &probe_query_);
  if (sampler_) glDeleteSamplers(1, &sampler_);
}

// ---------------------------------------------------------------------------
// Scope
// ---------------------------------------------------------------------------

void GlStateGuard::beginAccess() { access_ = true; }

Status GlStateGuard::endAccess() {
  access_ = false;
  closeWindow(true);
  return takeError();
}

void GlStateGuard::closeWindow(bool check) {
  const std::unique_ptr<Scope> window = std::move(window_);  // restores when it goes
  if (t_open_window == this) t_open_window = nullptr;
  const std::string call = std::move(unchecked_);
  unchecked_.clear();
  if (!window || !check) return;
  const std::string errors = drainErrors(*queries_);
  if (!errors.empty()) {
    errors_->note(Status(ErrorCode::Runtime,
                         call + " (or a later GL call of logrid's in the same batch) failed with " +
                             errors +
                             "; the depth values could not be read (a debug context's messages "
                             "say more)"));
  }
}

// Closes the access window of a guard other than `guard`, so that saves and restores of
// two guards nest (gl_state.hpp).
void GlStateGuard::closeOtherWindow(GlStateGuard& guard) {
  if (t_open_window && t_open_window != &guard) {
    GlStateGuard* other = t_open_window;
    const bool access = other->inAccess();
    other->access_ = false;
    other->closeWindow(true);          // its errors wait for its own endAccess() or takeError()
    if (access) other->beginAccess();  // its next scope opens a new window
  }
}

GlStateGuard::Scope::Scope(GlStateGuard& guard, const char* who) : guard_(guard), who_(who) {
  closeOtherWindow(guard);
  if (guard.access_) {
    if (!guard.window_) {
      guard.window_.reset(new Scope(guard, who, Window{}));
      t_open_window = &guard;
    }
    window_ = guard.window_.get();
    return;
  }
  open();
}

GlStateGuard::Scope::Scope(GlStateGuard& guard, const char* who, Window)
    : guard_(guard), who_(who) {
  open();
}

void GlStateGuard::Scope::open() {
  if (!guard_.unusable_.ok()) return fail(guard_.unusable_);
  if (!saving()) return;  // ApplicationManaged: the application promises no pending error
  const std::string pending = drainErrors(*guard_.queries_);
  if (!pending.empty()) {
    fail(Status(ErrorCode::Runtime,
                std::string(who_) + ": a GL error (" + pending +
                    ") was pending before logrid's depth source ran, from an earlier GL call "
                    "of the application; find it with glGetError() or a debug context before "
                    "culling (logrid cannot tell it from its own errors)"));
  }
}

bool GlStateGuard::Scope::ok() const { return window_ ? window_->ok() : !failed_; }

void GlStateGuard::Scope::fail(Status error) {
  if (window_) return window_->fail(std::move(error));
  failed_ = true;
  guard_.errors_->note(std::move(error));
}

GlStateGuard::Scope::~Scope() {
  if (!window_) restore();
}

Result<bool> GlStateGuard::Scope::conditionalRenderingActive(std::uint32_t probe_query) {
  // GL has no query for conditional rendering, but BeginConditionalRender fails with
  // GL_INVALID_OPERATION while it is active (GL 4.5 §10.9) and otherwise begins it on
  // the probe, which is ended at once: nothing is drawn in between, so nothing changes.
  // The probe query is never in progress and was created for GL_SAMPLES_PASSED, so that
  // error has no other cause. Callers make sure no error is pending.
  glBeginConditionalRender(probe_query, GL_QUERY_NO_WAIT);
  const GLenum e = glGetError();
  if (e == GL_INVALID_OPERATION) return true;
  if (e != GL_NO_ERROR) {
    return Status(ErrorCode::Runtime, "GlStateGuard: the conditional-rendering probe failed with " +
                                          errorName(e) +
                                          "; the driver does not follow GL 4.5 here");
  }
  glEndConditionalRender();
  return false;
}

bool GlStateGuard::Scope::refuseUnsavable() {
  if (!saving()) return true;  // ApplicationManaged: the application promises neither
  // The probe needs no error pending: in a window, check the deferred ones first.
  if (!guard_.unchecked_.empty()) {
    const std::string errors = drainErrors(*guard_.queries_);
    if (!errors.empty()) {
      fail(Status(ErrorCode::Runtime, guard_.unchecked_ + " failed with " + errors +
                                          "; the depth values could not be read (a debug "
                                          "context's messages say more)"));
      return false;
    }
    guard_.unchecked_.clear();
  }
  ++*guard_.queries_;  // the probe's glGetError
  const Result<bool> conditional = conditionalRenderingActive(guard_.probe_query_);
  if (!conditional) {
    fail(conditional.status());
    return false;
  }
  if (*conditional) {
    fail(Status(ErrorCode::InvalidArgument,
                std::string(who_) +
                    ": conditional rendering is active (glBeginConditionalRender without "
                    "glEndConditionalRender), so the depth source's own draws could be "
                    "discarded and GL offers no way to save and restore it; end conditional "
                    "rendering before culling, or begin it only inside the draw callback "
                    "around the application's own draws"));
    return false;
  }
  GLint feedback = 0, active = 0, paused = 0;
  LOGRID_STATE_QUERY(glGetIntegerv(GL_TRANSFORM_FEEDBACK_BINDING, &feedback));
  LOGRID_STATE_QUERY(
      glGetTransformFeedbackiv(GLuint(feedback), GL_TRANSFORM_FEEDBACK_ACTIVE, &active));
  LOGRID_STATE_QUERY(
      glGetTransformFeedbackiv(GLuint(feedback), GL_TRANSFORM_FEEDBACK_PAUSED, &paused));
  if (active && !paused) {
    fail(Status(ErrorCode::InvalidArgument,
                std::string(who_) +
                    ": transform feedback is active and not paused, so GL forbids the depth "
                    "source to change programs; pause it (glPauseTransformFeedback) or end "
                    "it before culling"));
    return false;
  }
  return true;
}

bool GlStateGuard::Scope::prepareDraw(std::uint32_t framebuffer, std::int32_t width,
                                      std::int32_t height, std::uint32_t depth_func,
                                      bool depth_write, bool color_write) {
  if (window_)
    return window_->prepareDraw(framebuffer, width, height, depth_func, depth_write, color_write);
  if (failed_) return false;
  if (!draw_saved_ && saving()) {
    if (!refuseUnsavable()) return false;
    DrawState& s = draw_;
    s.cull_face = enabled(GL_CULL_FACE);
    s.depth_test = enabled(GL_DEPTH_TEST);
    s.stencil_test = enabled(GL_STENCIL_TEST);
    s.depth_clamp = enabled(GL_DEPTH_CLAMP);
    s.rasterizer_discard = enabled(GL_RASTERIZER_DISCARD);
    s.offset_fill = enabled(GL_POLYGON_OFFSET_FILL);
    s.offset_line = enabled(GL_POLYGON_OFFSET_LINE);
    s.offset_point = enabled(GL_POLYGON_OFFSET_POINT);
    s.scissor_test = LOGRID_STATE_QUERY(glIsEnabledi(GL_SCISSOR_TEST, 0)) ? 1 : 0;
    s.sample_mask = enabled(GL_SAMPLE_MASK);
    s.sample_coverage = enabled(GL_SAMPLE_COVERAGE);
    s.alpha_to_coverage = enabled(GL_SAMPLE_ALPHA_TO_COVERAGE);
    s.alpha_to_one = enabled(GL_SAMPLE_ALPHA_TO_ONE);
    s.multisample = enabled(GL_MULTISAMPLE);
    if (guard_.depth_bounds_) {
      s.depth_bounds = enabled(GL_DEPTH_BOUNDS_TEST_EXT);
      LOGRID_STATE_QUERY(glGetDoublev(GL_DEPTH_BOUNDS_EXT, s.depth_bounds_range));
    }
    if (guard_.representative_fragment_) {
      s.representative = enabled(GL_REPRESENTATIVE_FRAGMENT_TEST_NV);
    }
    if (guard_.scissor_exclusive_) s.scissor_exclusive = enabled(GL_SCISSOR_TEST_EXCLUSIVE_NV);
    GLboolean mask = GL_TRUE, invert = GL_FALSE;
    LOGRID_STATE_QUERY(glGetBooleanv(GL_DEPTH_WRITEMASK, &mask));
    LOGRID_STATE_QUERY(glGetBooleanv(GL_SAMPLE_COVERAGE_INVERT, &invert));
    s.depth_mask = mask ? 1 : 0;
    s.coverage_invert = invert ? 1 : 0;
    s.cull_mode = integer(GL_CULL_FACE_MODE);
    s.front_face = integer(GL_FRONT_FACE);
    GLint polygon_mode[2] = {GL_FILL, GL_FILL};  // core profile: front and back are equal
    LOGRID_STATE_QUERY(glGetIntegerv(GL_POLYGON_MODE, polygon_mode));
    s.polygon_mode = polygon_mode[0];
    s.depth_func = integer(GL_DEPTH_FUNC);
    LOGRID_STATE_QUERY(glGetDoublei_v(GL_DEPTH_RANGE, 0, s.depth_range));
    LOGRID_STATE_QUERY(glGetFloati_v(GL_VIEWPORT, 0, s.viewport));
    LOGRID_STATE_QUERY(glGetIntegeri_v(GL_SCISSOR_BOX, 0, s.scissor_box));
    LOGRID_STATE_QUERY(glGetFloatv(GL_SAMPLE_COVERAGE_VALUE, &s.coverage_value));
    LOGRID_STATE_QUERY(glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &s.offset_factor));
    LOGRID_STATE_QUERY(glGetFloatv(GL_POLYGON_OFFSET_UNITS, &s.offset_units));
    s.draw_framebuffer = integer(GL_DRAW_FRAMEBUFFER_BINDING);
    for (int i = 0; i < guard_.clip_distances_; ++i) {
      s.clip_distances[i] = enabled(GLenum(GL_CLIP_DISTANCE0 + i));
    }
    for (int i = 0; i < guard_.draw_buffers_; ++i) {
      GLboolean rgba[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
      LOGRID_STATE_QUERY(glGetBooleani_v(GL_COLOR_WRITEMASK, GLuint(i), rgba));
      for (int c = 0; c < 4; ++c) s.color_masks[4 * i + c] = rgba[c] ? 1 : 0;
    }
    for (int i = 0; i < guard_.sample_mask_words_; ++i) {
      LOGRID_STATE_QUERY(glGetIntegeri_v(GL_SAMPLE_MASK_VALUE, GLuint(i), &s.sample_mask_words[i]));
    }
    draw_saved_ = true;
  }
  if (!prepareProgram()) return false;

  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  glDisable(GL_CULL_FACE);
  glFrontFace(GL_CCW);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDisable(GL_STENCIL_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(depth_func);
  glDepthMask(depth_write ? GL_TRUE : GL_FALSE);
  glDisable(GL_DEPTH_CLAMP);
  glDepthRangeIndexed(0, 0.0, 1.0);
  glViewportIndexedf(0, 0.0f, 0.0f, float(width), float(height));
  glEnablei(GL_SCISSOR_TEST, 0);
  glScissorIndexed(0, 0, 0, width, height);
  for (int i = 0; i < guard_.clip_distances_; ++i) glDisable(GLenum(GL_CLIP_DISTANCE0 + i));
  glDisable(GL_SAMPLE_MASK);
  glDisable(GL_SAMPLE_COVERAGE);
  glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  glDisable(GL_SAMPLE_ALPHA_TO_ONE);
  glEnable(GL_MULTISAMPLE);
  glDisable(GL_RASTERIZER_DISCARD);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_POLYGON_OFFSET_LINE);
  glDisable(GL_POLYGON_OFFSET_POINT);
  if (guard_.depth_bounds_) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
  if (guard_.representative_fragment_) glDisable(GL_REPRESENTATIVE_FRAGMENT_TEST_NV);
  if (guard_.scissor_exclusive_) glDisable(GL_SCISSOR_TEST_EXCLUSIVE_NV);
  const GLboolean c = color_write ? GL_TRUE : GL_FALSE;
  for (int i = 0; i < guard_.draw_buffers_; ++i) glColorMaski(GLuint(i), c, c, c, c);
  return true;
}

void GlStateGuard::Scope::scissor(const PixelRect& rect) {
  if (window_) return window_->scissor(rect);
  if (failed_) return;
  glScissorIndexed(0, rect.x0, rect.y0, rect.x1 - rect.x0, rect.y1 - rect.y0);
}

void GlStateGuard::Scope::clipControl(std::uint32_t origin, std::uint32_t depth_mode) {
  if (window_) return window_->clipControl(origin, depth_mode);
  if (failed_) return;
  if (!clip_saved_ && saving()) {
    clip_origin_ = integer(GL_CLIP_ORIGIN);
    clip_depth_mode_ = integer(GL_CLIP_DEPTH_MODE);
    clip_saved_ = true;
  }
  glClipControl(origin, depth_mode);
}

bool GlStateGuard::Scope::prepareProgram() {
  if (window_) return window_->prepareProgram();
  if (failed_) return false;
  if (program_saved_ || !saving()) return true;
  if (!draw_saved_ && !refuseUnsavable()) return false;
  program_.program = integer(GL_CURRENT_PROGRAM);
  program_.pipeline = integer(GL_PROGRAM_PIPELINE_BINDING);
  program_.vertex_array = integer(GL_VERTEX_ARRAY_BINDING);
  program_saved_ = true;
  return true;
}

bool GlStateGuard::Scope::prepareRead(std::uint32_t framebuffer, std::uint32_t pack_buffer) {
  if (window_) return window_->prepareRead(framebuffer, pack_buffer);
  if (failed_) return false;
  if (!read_saved_ && saving()) {
    ReadState& s = read_;
    s.read_framebuffer = integer(GL_READ_FRAMEBUFFER_BINDING);
    s.pack_buffer = integer(GL_PIXEL_PACK_BUFFER_BINDING);
    s.alignment = integer(GL_PACK_ALIGNMENT);
    s.row_length = integer(GL_PACK_ROW_LENGTH);
    s.skip_pixels = integer(GL_PACK_SKIP_PIXELS);
    s.skip_rows = integer(GL_PACK_SKIP_ROWS);
    s.swap_bytes = integer(GL_PACK_SWAP_BYTES);
    read_saved_ = true;
  }
  // Only the pack state a two-dimensional read applies (GL 4.5 §18.2, §8.11.4): image
  // height and skipped images act on three-dimensional images only, LSB-first on bitmaps
  // (none in the core profile), read colour clamping on colour values of float buffers
  // only; logrid reads depth, integers and normalised colour. Each is a query the
  // application's state would cost otherwise (gl_state_fuzz_test sets them at random).
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, pack_buffer);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
  glPixelStorei(GL_PACK_SKIP_ROWS, 0);
  glPixelStorei(GL_PACK_SWAP_BYTES, GL_FALSE);
  return true;
}

bool GlStateGuard::Scope::bindTexture(std::uint32_t unit, std::uint32_t target,
                                      std::uint32_t texture) {
  if (window_) return window_->bindTexture(unit, target, texture);
  if (failed_) return false;
  const GLenum binding = textureBinding(target);
  bool unit_taken = false;
  for (int i = 0; i < textures_saved_; ++i) {
    const TextureState& t = textures_[i];
    if (t.unit == unit && t.target == target && t.texture == texture) return true;  // bound already
    unit_taken |= t.unit == unit;
  }
  if (binding == 0 || textures_saved_ == kMaxTextures || unit_taken) {
    fail(
        Status(ErrorCode::InvalidArgument,
               std::string(who_) + ": bindTexture: " +
                   (binding == 0 ? "unknown texture target " + errorName(target)
                    : unit_taken
                        ? "texture unit " + std::to_string(unit) + " is already bound in this scope"
                        : "more than " + std::to_string(kMaxTextures) + " textures in one scope")));
    return false;
  }
  TextureState unsaved;  // ApplicationManaged: nothing is saved
  TextureState& s = saving() ? textures_[textures_saved_] : unsaved;
  s.unit = unit;
  s.target = target;
  s.texture = texture;
  if (saving()) s.active = integer(GL_ACTIVE_TEXTURE);
  glActiveTexture(GL_TEXTURE0 + unit);
  if (saving()) {
    s.bound = integer(binding);
    s.sampler = integer(GL_SAMPLER_BINDING);
    LOGRID_STATE_QUERY(glGetTextureParameteriv(texture, GL_TEXTURE_SWIZZLE_RGBA, s.swizzle));
  }
  // Under either policy: whether the texture has a depth-stencil mode to set.
  GLint format = 0;
  LOGRID_STATE_QUERY(glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format));
  s.has_depth_stencil_mode = format == GL_DEPTH24_STENCIL8 || format == GL_DEPTH32F_STENCIL8;
  if (s.has_depth_stencil_mode && saving()) {
    LOGRID_STATE_QUERY(
        glGetTextureParameteriv(texture, GL_DEPTH_STENCIL_TEXTURE_MODE, &s.depth_stencil_mode));
  }
  s.has_levels = target != GL_TEXTURE_2D_MULTISAMPLE && target != GL_TEXTURE_2D_MULTISAMPLE_ARRAY &&
                 target != GL_TEXTURE_RECTANGLE;
  if (s.has_levels && saving()) {
    LOGRID_STATE_QUERY(glGetTextureParameteriv(texture, GL_TEXTURE_BASE_LEVEL, &s.base_level));
    LOGRID_STATE_QUERY(glGetTextureParameteriv(texture, GL_TEXTURE_MAX_LEVEL, &s.max_level));
  }
  if (saving()) ++textures_saved_;
  glBindTexture(target, texture);
  glBindSampler(unit, guard_.sampler_);
  const GLint identity[4] = {GL_RED, GL_GREEN, GL_BLUE, GL_ALPHA};
  glTextureParameteriv(texture, GL_TEXTURE_SWIZZLE_RGBA, identity);
  if (s.has_depth_stencil_mode) {
    glTextureParameteri(texture, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
  }
  if (s.has_levels) {
    glTextureParameteri(texture, GL_TEXTURE_BASE_LEVEL, 0);
    glTextureParameteri(texture, GL_TEXTURE_MAX_LEVEL, 1000);
  }
  return true;
}

bool GlStateGuard::Scope::bindStorageBuffer(std::uint32_t index, std::uint32_t buffer,
                                            std::int64_t offset, std::int64_t size) {
  if (window_) return window_->bindStorageBuffer(index, buffer, offset, size);
  if (failed_) return false;
  int slot = storage_saved_;
  for (int i = 0; i < storage_saved_; ++i) {
    if (storage_[i].index == index) slot = i;
  }
  if (slot == kMaxStorageBuffers) {
    fail(Status(ErrorCode::InvalidArgument, std::string(who_) + ": bindStorageBuffer: more than " +
                                                std::to_string(kMaxStorageBuffers) +
                                                " binding points in one scope"));
    return false;
  }
  if (slot == storage_saved_ && saving()) {
    StorageState& s = storage_[slot];
    s.index = index;
    s.generic = integer(GL_SHADER_STORAGE_BUFFER_BINDING);
    LOGRID_STATE_QUERY(glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, index, &s.buffer));
    LOGRID_STATE_QUERY(glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, index, &s.start));
    LOGRID_STATE_QUERY(glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, index, &s.size));
    ++storage_saved_;
  }
  if (size > 0) {
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, index, buffer, GLintptr(offset), GLsizeiptr(size));
  } else {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, index, buffer);
  }
  return true;
}

bool GlStateGuard::Scope::check(const char* call) {
  if (window_) {
    if (guard_.unchecked_.empty()) guard_.unchecked_ = std::string(who_) + ": " + call;
    return window_->ok();
  }
  if (failed_) return false;
  const std::string errors = drainErrors(*guard_.queries_);
  if (!errors.empty()) {
    fail(Status(ErrorCode::Runtime, std::string(who_) + ": " + call + " failed with " + errors +
                                        "; the depth values could not be read (a debug "
                                        "context's messages say more)"));
    return false;
  }
  return true;
}

void GlStateGuard::Scope::restore() {
  // Nothing here may throw; errors are left for the next check (there is none after
  // this, so a failed restore shows in the application's own glGetError).
  for (int i = storage_saved_ - 1; i >= 0; --i) {
    const StorageState& s = storage_[i];
    const GLuint buffer = exists(*guard_.queries_, glIsBuffer, s.buffer);
    if (buffer && s.size > 0) {
      glBindBufferRange(GL_SHADER_STORAGE_BUFFER, s.index, buffer, GLintptr(s.start),
                        GLsizeiptr(s.size));
    } else {
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, s.index, buffer);
    }
    // Binding an indexed point also sets the generic binding.
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, exists(*guard_.queries_, glIsBuffer, s.generic));
  }
  for (int i = textures_saved_ - 1; i >= 0; --i) {
    const TextureState& s = textures_[i];
    glTextureParameteriv(s.texture, GL_TEXTURE_SWIZZLE_RGBA, s.swizzle);
    if (s.has_depth_stencil_mode) {
      glTextureParameteri(s.texture, GL_DEPTH_STENCIL_TEXTURE_MODE, s.depth_stencil_mode);
    }
    if (s.has_levels) {
      glTextureParameteri(s.texture, GL_TEXTURE_BASE_LEVEL, s.base_level);
      glTextureParameteri(s.texture, GL_TEXTURE_MAX_LEVEL, s.max_level);
    }
    glBindSampler(s.unit, exists(*guard_.queries_, glIsSampler, s.sampler));
    glBindTexture(s.target, exists(*guard_.queries_, glIsTexture, s.bound));
    glActiveTexture(GLenum(s.active));
  }
  if (read_saved_) {
    const ReadState& s = read_;
    // Framebuffers are not shared between contexts, and deleting a bound one unbinds it:
    // a saved binding still names a framebuffer (no glIsFramebuffer query needed).
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(s.read_framebuffer));
    glBindBuffer(GL_PIXEL_PACK_BUFFER, exists(*guard_.queries_, glIsBuffer, s.pack_buffer));
    glPixelStorei(GL_PACK_ALIGNMENT, s.alignment);
    glPixelStorei(GL_PACK_ROW_LENGTH, s.row_length);
    glPixelStorei(GL_PACK_SKIP_PIXELS, s.skip_pixels);
    glPixelStorei(GL_PACK_SKIP_ROWS, s.skip_rows);
    glPixelStorei(GL_PACK_SWAP_BYTES, s.swap_bytes);
  }
  if (program_saved_) {
    const ProgramState& s = program_;
    // Names are rebound only if they still exist. A program deleted while current is
    // gone once another was used (see the header); and Mesa 22 keeps reporting a program
    // pipeline that was deleted while bound (with a program current) as bound, although
    // GL says deleting it unbinds it: rebinding that name would be an error.
    glBindVertexArray(exists(*guard_.queries_, glIsVertexArray, s.vertex_array));
    glBindProgramPipeline(exists(*guard_.queries_, glIsProgramPipeline, s.pipeline));
    glUseProgram(exists(*guard_.queries_, glIsProgram, s.program));
  }
  if (clip_saved_) glClipControl(GLenum(clip_origin_), GLenum(clip_depth_mode_));
  if (draw_saved_) {
    const DrawState& s = draw_;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(s.draw_framebuffer));  // as the read one
    setEnabled(GL_CULL_FACE, s.cull_face);
    glCullFace(GLenum(s.cull_mode));
    glFrontFace(GLenum(s.front_face));
    glPolygonMode(GL_FRONT_AND_BACK, GLenum(s.polygon_mode));
    setEnabled(GL_STENCIL_TEST, s.stencil_test);
    setEnabled(GL_DEPTH_TEST, s.depth_test);
    glDepthFunc(GLenum(s.depth_func));
    glDepthMask(s.depth_mask ? GL_TRUE : GL_FALSE);
    setEnabled(GL_DEPTH_CLAMP, s.depth_clamp);
    glDepthRangeIndexed(0, s.depth_range[0], s.depth_range[1]);
    glViewportIndexedfv(0, s.viewport);
    s.scissor_test ? glEnablei(GL_SCISSOR_TEST, 0) : glDisablei(GL_SCISSOR_TEST, 0);
    glScissorIndexedv(0, s.scissor_box);
    for (int i = 0; i < guard_.clip_distances_; ++i) {
      setEnabled(GLenum(GL_CLIP_DISTANCE0 + i), s.clip_distances[i]);
    }
    setEnabled(GL_SAMPLE_MASK, s.sample_mask);
    for (int i = 0; i < guard_.sample_mask_words_; ++i) {
      glSampleMaski(GLuint(i), GLbitfield(s.sample_mask_words[i]));
    }
    setEnabled(GL_SAMPLE_COVERAGE, s.sample_coverage);
    glSampleCoverage(s.coverage_value, s.coverage_invert ? GL_TRUE : GL_FALSE);
    setEnabled(GL_SAMPLE_ALPHA_TO_COVERAGE, s.alpha_to_coverage);
    setEnabled(GL_SAMPLE_ALPHA_TO_ONE, s.alpha_to_one);
    setEnabled(GL_MULTISAMPLE, s.multisample);
    setEnabled(GL_RASTERIZER_DISCARD, s.rasterizer_discard);
    setEnabled(GL_POLYGON_OFFSET_FILL, s.offset_fill);
    setEnabled(GL_POLYGON_OFFSET_LINE, s.offset_line);
    setEnabled(GL_POLYGON_OFFSET_POINT, s.offset_point);
    glPolygonOffset(s.offset_factor, s.offset_units);
    if (guard_.depth_bounds_) {
      setEnabled(GL_DEPTH_BOUNDS_TEST_EXT, s.depth_bounds);
      glDepthBoundsEXT(s.depth_bounds_range[0], s.depth_bounds_range[1]);
    }
    if (guard_.representative_fragment_) {
      setEnabled(GL_REPRESENTATIVE_FRAGMENT_TEST_NV, s.representative);
    }
    if (guard_.scissor_exclusive_) setEnabled(GL_SCISSOR_TEST_EXCLUSIVE_NV, s.scissor_exclusive);
    for (int i = 0; i < guard_.draw_buffers_; ++i) {
      const std::uint8_t* m = s.color_masks + 4 * i;
      glColorMaski(GLuint(i), m[0], m[1], m[2], m[3]);
    }
  }
}

}  // namespace logrid::zread
