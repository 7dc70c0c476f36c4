#include "logrid/gl/framebuffer.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <utility>

#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"
#include "logrid/zread/gl_state.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::gl {

std::uint32_t depthInternalFormat(DepthFormat format) {
  switch (format) {
    case DepthFormat::D16: return GL_DEPTH_COMPONENT16;
    case DepthFormat::D24: return GL_DEPTH_COMPONENT24;
    case DepthFormat::D32F: return GL_DEPTH_COMPONENT32F;
  }
  return GL_DEPTH_COMPONENT32F;
}

void applyDepthState(const DepthSetup& depth) {
  const bool reversed = depth.convention == DepthConvention::Reversed;
  glClipControl(GL_LOWER_LEFT, depth.clip_range == ClipDepthRange::ZeroToOne
                                   ? GL_ZERO_TO_ONE
                                   : GL_NEGATIVE_ONE_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDepthFunc(reversed ? GL_GREATER : GL_LESS);
  glClearDepth(reversed ? 0.0 : 1.0);
}

namespace {

std::string sizeText(std::uint32_t w, std::uint32_t h) {
  std::ostringstream out;
  out << w << "x" << h;
  return out.str();
}

const char* statusName(GLenum status) {
  switch (status) {
    case GL_FRAMEBUFFER_UNDEFINED: return "GL_FRAMEBUFFER_UNDEFINED";
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
      return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    default: return "unknown status";
  }
}

GLint integer(GLenum name) {
  GLint value = 0;
  glGetIntegerv(name, &value);
  return value;
}

// The size against the driver's limits and logrid's.
Status checkSize(const FramebufferDesc& desc) {
  const GLint max_texture = integer(GL_MAX_TEXTURE_SIZE);
  const GLint max_w = std::min(max_texture, integer(GL_MAX_FRAMEBUFFER_WIDTH));
  const GLint max_h = std::min(max_texture, integer(GL_MAX_FRAMEBUFFER_HEIGHT));
  if (desc.width >= 1 && desc.height >= 1 && GLint(desc.width) <= max_w &&
      GLint(desc.height) <= max_h && desc.width <= kMaxViewportSide &&
      desc.height <= kMaxViewportSide) {
    return {};
  }
  const std::uint32_t limit_w = std::min(std::uint32_t(std::max(max_w, 1)), kMaxViewportSide);
  const std::uint32_t limit_h = std::min(std::uint32_t(std::max(max_h, 1)), kMaxViewportSide);
  return Status(ErrorCode::InvalidArgument,
                "framebuffer: size " + sizeText(desc.width, desc.height) +
                    " is not possible on this driver; each side must be between 1 and " +
                    sizeText(limit_w, limit_h) +
                    " (GL_MAX_TEXTURE_SIZE / GL_MAX_FRAMEBUFFER_*, and logrid's " +
                    std::to_string(kMaxViewportSide) + "). " +
                    (desc.width < 1 || desc.height < 1 ? "Pass the size in pixels, at least 1x1."
                                                       : "Choose a smaller size."));
}

Status checkDepthSetup(const DepthSetup& d) {
  if ((d.format == DepthFormat::D16 || d.format == DepthFormat::D24 ||
       d.format == DepthFormat::D32F) &&
      (d.convention == DepthConvention::Standard || d.convention == DepthConvention::Reversed) &&
      (d.clip_range == ClipDepthRange::NegativeOneToOne ||
       d.clip_range == ClipDepthRange::ZeroToOne)) {
    return {};
  }
  std::ostringstream out;
  out << "framebuffer: unknown depth set-up (format " << int(d.format) << ", convention "
      << int(d.convention) << ", clip range " << int(d.clip_range)
      << "); use the DepthFormat, DepthConvention and ClipDepthRange enumerators";
  return Status(ErrorCode::InvalidArgument, out.str());
}

// The samples per pixel against the driver's limits for these attachments.
Status checkSamples(const FramebufferDesc& desc) {
  GLint limit = std::min({integer(GL_MAX_SAMPLES), integer(GL_MAX_DEPTH_TEXTURE_SAMPLES),
                          integer(GL_MAX_COLOR_TEXTURE_SAMPLES)});
  if (desc.object_ids) limit = std::min(limit, integer(GL_MAX_INTEGER_SAMPLES));
  if (desc.samples <= 1 || GLint(desc.samples) <= limit) return {};
  return Status(ErrorCode::Unsupported,
                "framebuffer: " + std::to_string(desc.samples) +
                    " samples per pixel requested, but this driver allows at most " +
                    std::to_string(limit) +
                    " for these attachments (GL_MAX_SAMPLES, GL_MAX_DEPTH_TEXTURE_SAMPLES, "
                    "GL_MAX_COLOR_TEXTURE_SAMPLES" +
                    (desc.object_ids ? ", GL_MAX_INTEGER_SAMPLES" : "") +
                    "); ask for fewer, or 0 for a single-sampled framebuffer");
}

// What creating the attachments of `fbo` left: a GL error, or an incomplete framebuffer.
Status checkCreated(const FramebufferDesc& desc, GLuint fbo) {
  const GLenum error = glGetError();
  if (error == GL_OUT_OF_MEMORY) {
    return Status(ErrorCode::Runtime, "framebuffer: out of memory allocating " +
                                          sizeText(desc.width, desc.height) +
                                          " buffers; choose a smaller size");
  }
  if (error != GL_NO_ERROR) {
    std::ostringstream out;
    out << "framebuffer: GL error 0x" << std::hex << error << " creating a "
        << sizeText(desc.width, desc.height) << " framebuffer with depth format "
        << toString(desc.depth.format);
    return Status(ErrorCode::Runtime, out.str());
  }
  const GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    return Status(ErrorCode::Unsupported,
                  std::string("framebuffer: incomplete (") + statusName(status) +
                      ") with depth "
                      "format " +
                      toString(desc.depth.format) +
                      "; the driver cannot render to this combination. Try depth format 32f.");
  }
  return tryCheckGlErrors("framebuffer: creation");
}

}  // namespace

Framebuffer::Framebuffer(Unmade, const FramebufferDesc& desc) : desc_(desc) {}

Result<std::unique_ptr<Framebuffer>> Framebuffer::create(const FramebufferDesc& desc) {
  std::unique_ptr<Framebuffer> framebuffer(new Framebuffer(Unmade{}, desc));
  if (Status s = framebuffer->make(); !s) return s;
  return Result<std::unique_ptr<Framebuffer>>(std::move(framebuffer));
}

// Whatever fails leaves no GL object behind.
Status Framebuffer::make() {
  const FramebufferDesc& desc = desc_;
  if (Status s = checkSize(desc); !s) return s;
  if (Status s = checkDepthSetup(desc.depth); !s) return s;
  if (Status s = checkSamples(desc); !s) return s;
  if (Status s = tryCheckGlErrors("framebuffer: before creation"); !s) return s;
  const GLsizei w = GLsizei(desc.width), h = GLsizei(desc.height);
  const bool multi = desc.samples > 1;
  const GLenum target = multi ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D;
  auto storage = [&](GLuint texture, GLenum format) {
    if (multi) {
      glTextureStorage2DMultisample(texture, GLsizei(desc.samples), format, w, h, GL_TRUE);
    } else {
      glTextureStorage2D(texture, 1, format, w, h);
    }
  };
  guard_ = std::make_unique<zread::GlStateGuard>();
  glCreateFramebuffers(1, &fbo_);
  glCreateTextures(target, 1, &color_);
  storage(color_, GL_RGBA8);
  glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, color_, 0);
  if (desc.object_ids) {
    glCreateTextures(target, 1, &ids_);
    storage(ids_, GL_R32UI);
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT1, ids_, 0);
  }
  glCreateTextures(target, 1, &depth_);
  storage(depth_, depthInternalFormat(desc.depth.format));
  glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
  if (multi) {
    GLint given = 0;
    glGetTextureLevelParameteriv(depth_, 0, GL_TEXTURE_SAMPLES, &given);
    samples_ = std::uint32_t(std::max(given, 0));
  }
  if (Status s = checkCreated(desc, fbo_); !s) {
    release();
    return s;
  }
  return {};
}

Framebuffer::~Framebuffer() { release(); }

void Framebuffer::release() {
  sample_reader_.reset();
  guard_.reset();
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  GLuint textures[3] = {color_, ids_, depth_};
  glDeleteTextures(3, textures);
  fbo_ = color_ = ids_ = depth_ = 0;
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, GLsizei(desc_.width), GLsizei(desc_.height));
  selectIdPass(false);
  applyDepthState(desc_.depth);
}

void Framebuffer::unmask() const {
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void Framebuffer::selectIdPass(bool id_pass) const {
  const GLenum color_only[2] = {GL_COLOR_ATTACHMENT0, GL_NONE};
  const GLenum ids_only[2] = {GL_NONE, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(fbo_, ids_ ? 2 : 1, id_pass ? ids_only : color_only);
}

void Framebuffer::clear(const float rgba[4]) const {
  glClearNamedFramebufferfv(fbo_, GL_COLOR, 0, rgba);
  clearDepthAndIds();
}

void Framebuffer::clearDepthAndIds() const {
  const GLfloat depth = desc_.depth.convention == DepthConvention::Reversed ? 0.0f : 1.0f;
  if (ids_) {
    const GLuint none[4] = {kNoObject, 0, 0, 0};
    // Draw buffer 1 may be GL_NONE (colour pass): enable both while clearing.
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(fbo_, 2, both);
    glClearNamedFramebufferuiv(fbo_, GL_COLOR, 1, none);
    selectIdPass(false);
  }
  glDepthMask(GL_TRUE);
  glClearNamedFramebufferfv(fbo_, GL_DEPTH, 0, &depth);
}

namespace {

// Reads a whole texture level in bands of rows, so that no single call's byte count
// overflows GLsizei on very large framebuffers. Whatever pack state and pack buffer the
// application left are set aside for it and restored.
Status readTexture(zread::GlStateGuard& guard, GLuint texture, std::uint32_t width,
                   std::uint32_t height, GLenum format, GLenum type, std::size_t pixel_bytes,
                   void* dst) {
  zread::GlStateGuard::Scope scope(guard, "Framebuffer read-back");
  GLint read_framebuffer = 0;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_framebuffer);
  if (!scope.prepareRead(GLuint(read_framebuffer), 0)) return guard.takeError();
  const std::size_t row_bytes = std::size_t(width) * pixel_bytes;
  const std::uint32_t band =
      std::uint32_t(std::max<std::size_t>(1, (std::size_t(1) << 30) / row_bytes));
  for (std::uint32_t y = 0; y < height; y += band) {
    const std::uint32_t rows = std::min(band, height - y);
    glGetTextureSubImage(texture, 0, 0, GLint(y), 0, GLsizei(width), GLsizei(rows), 1, format, type,
                         GLsizei(row_bytes * rows),
                         static_cast<std::uint8_t*>(dst) + row_bytes * y);
  }
  if (!scope.check("glGetTextureSubImage")) return guard.takeError();
  return {};
}

// Multisampled textures cannot be read with glGetTextureSubImage: a compute shader copies
// every sample (depth as float bits, IDs) or the average of the samples (colour, packed
// RGBA8) into a buffer, a band of rows at a time.
enum class SampleKind : int { Depth = 0, Ids = 1, ColorAverage = 2 };

constexpr const char* kSampleCompute = R"(
layout(local_size_x = 8, local_size_y = 8) in;
#if KIND == 1
uniform usampler2DMS u_texture;
#else
uniform sampler2DMS u_texture;
#endif
uniform ivec2 u_size;  // width, rows in this band
uniform int u_first_row;
uniform int u_samples;
layout(std430, binding = 0) writeonly buffer Out { uint values[]; };
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= u_size.x || p.y >= u_size.y) return;
  ivec2 texel = ivec2(p.x, p.y + u_first_row);
  uint pixel = uint(p.y * u_size.x + p.x);
#if KIND == 2
  vec4 sum = vec4(0.0);
  for (int s = 0; s < u_samples; ++s) sum += texelFetch(u_texture, texel, s);
  values[pixel] = packUnorm4x8(sum / float(u_samples));
#else
  for (int s = 0; s < u_samples; ++s) {
#if KIND == 0
    values[pixel * uint(u_samples) + uint(s)] = floatBitsToUint(texelFetch(u_texture, texel, s).r);
#else
    values[pixel * uint(u_samples) + uint(s)] = texelFetch(u_texture, texel, s).r;
#endif
  }
#endif
}
)";

Result<std::unique_ptr<zread::Program>> computeProgram(SampleKind kind) {
  const std::string source =
      "#version 450 core\n#define KIND " + std::to_string(int(kind)) + "\n" + kSampleCompute;
  return zread::Program::create("framebuffer multisample read-back", source.c_str());
}

}  // namespace

struct Framebuffer::SampleReader {
  std::unique_ptr<zread::Program> programs[3];
  GLuint buffer = 0;
  std::size_t capacity = 0;
  ~SampleReader() {
    if (buffer) glDeleteBuffers(1, &buffer);
  }
};

// `values_per_pixel` 32-bit values per pixel into dst (rows bottom-up).
Status Framebuffer::readSamples(int kind, std::uint32_t texture, std::uint32_t values_per_pixel,
                                void* dst) const {
  if (!sample_reader_) sample_reader_ = std::make_unique<SampleReader>();
  SampleReader& r = *sample_reader_;
  if (!r.programs[kind]) {
    Result<std::unique_ptr<zread::Program>> built = computeProgram(SampleKind(kind));
    if (!built) return built.status();
    r.programs[kind] = std::move(built).value();
  }
  const GLuint program = r.programs[kind]->handle();
  const std::size_t row_values = std::size_t(desc_.width) * values_per_pixel;
  const std::uint32_t band =
      std::uint32_t(std::max<std::size_t>(1, (std::size_t(1) << 26) / row_values));
  const std::size_t bytes = row_values * std::min(band, desc_.height) * 4;
  if (bytes > r.capacity) {
    if (r.buffer) glDeleteBuffers(1, &r.buffer);
    glCreateBuffers(1, &r.buffer);
    glNamedBufferStorage(r.buffer, GLsizeiptr(bytes), nullptr, 0);
    r.capacity = bytes;
  }
  zread::GlStateGuard::Scope scope(*guard_, "Framebuffer read-back");
  if (!scope.prepareProgram() || !scope.bindTexture(0, GL_TEXTURE_2D_MULTISAMPLE, texture)) {
    return guard_->takeError();
  }
  // The storage-buffer binding point 0 and the generic binding, set aside and restored.
  GLint generic = 0, indexed = 0;
  GLint64 start = 0, size = 0;
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_BINDING, &generic);
  glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, 0, &indexed);
  glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, 0, &start);
  glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, 0, &size);
  glUseProgram(program);
  glProgramUniform1i(program, glGetUniformLocation(program, "u_texture"), 0);
  glProgramUniform1i(program, glGetUniformLocation(program, "u_samples"), GLint(samples_));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, r.buffer);
  for (std::uint32_t y = 0; y < desc_.height; y += band) {
    const std::uint32_t rows = std::min(band, desc_.height - y);
    glProgramUniform2i(program, glGetUniformLocation(program, "u_size"), GLint(desc_.width),
                       GLint(rows));
    glProgramUniform1i(program, glGetUniformLocation(program, "u_first_row"), GLint(y));
    glDispatchCompute((desc_.width + 7) / 8, (rows + 7) / 8, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(r.buffer, 0, GLsizeiptr(row_values * rows * 4),
                            static_cast<std::uint8_t*>(dst) + row_values * 4 * y);
  }
  if (size > 0) {
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, GLuint(indexed), start, size);
  } else {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, GLuint(indexed));
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, GLuint(generic));
  if (!scope.check("the multisample read-back")) return guard_->takeError();
  return {};
}

Result<std::vector<std::uint8_t>> Framebuffer::tryReadColor() const {
  std::vector<std::uint8_t> out(std::size_t(desc_.width) * desc_.height * 4);
  const Status read = samples_ ? readSamples(int(SampleKind::ColorAverage), color_, 1, out.data())
                               : readTexture(*guard_, color_, desc_.width, desc_.height, GL_RGBA,
                                             GL_UNSIGNED_BYTE, 4, out.data());
  if (!read) return read;
  return out;
}

Result<std::vector<float>> Framebuffer::tryReadDepth() const {
  const std::uint32_t per_pixel = std::max<std::uint32_t>(samples_, 1);
  std::vector<float> out(std::size_t(desc_.width) * desc_.height * per_pixel);
  const Status read = samples_ ? readSamples(int(SampleKind::Depth), depth_, per_pixel, out.data())
                               : readTexture(*guard_, depth_, desc_.width, desc_.height,
                                             GL_DEPTH_COMPONENT, GL_FLOAT, 4, out.data());
  if (!read) return read;
  return out;
}

Result<std::vector<std::uint32_t>> Framebuffer::tryReadObjectIds() const {
  if (!ids_) {
    return Status(ErrorCode::InvalidArgument,
                  "Framebuffer::readObjectIds: the framebuffer has no object-ID attachment");
  }
  const std::uint32_t per_pixel = std::max<std::uint32_t>(samples_, 1);
  std::vector<std::uint32_t> out(std::size_t(desc_.width) * desc_.height * per_pixel);
  const Status read = samples_ ? readSamples(int(SampleKind::Ids), ids_, per_pixel, out.data())
                               : readTexture(*guard_, ids_, desc_.width, desc_.height,
                                             GL_RED_INTEGER, GL_UNSIGNED_INT, 4, out.data());
  if (!read) return read;
  return out;
}

}  // namespace logrid::gl
