#include "logrid/gl/framebuffer.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <sstream>
#include <string>

#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"

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

}  // namespace

Framebuffer::Framebuffer(const FramebufferDesc& desc) : desc_(desc) {
  GLint max_texture = 0, max_fb_w = 0, max_fb_h = 0, max_rb = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &max_fb_w);
  glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &max_fb_h);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
  const GLint max_w = std::min(max_texture, max_fb_w), max_h = std::min(max_texture, max_fb_h);
  if (desc.width < 1 || desc.height < 1 || GLint(desc.width) > max_w ||
      GLint(desc.height) > max_h || desc.width > kMaxViewportSide ||
      desc.height > kMaxViewportSide) {
    const std::uint32_t limit_w = std::min(std::uint32_t(std::max(max_w, 1)), kMaxViewportSide);
    const std::uint32_t limit_h = std::min(std::uint32_t(std::max(max_h, 1)), kMaxViewportSide);
    throw Error(ErrorCode::InvalidArgument,
                "framebuffer: size " + sizeText(desc.width, desc.height) +
                    " is not possible on this driver; each side must be between 1 and " +
                    sizeText(limit_w, limit_h) +
                    " (GL_MAX_TEXTURE_SIZE / GL_MAX_FRAMEBUFFER_*, and logrid's " +
                    std::to_string(kMaxViewportSide) + "). " +
                    (desc.width < 1 || desc.height < 1 ? "Pass the size in pixels, at least 1x1."
                                                       : "Choose a smaller size."));
  }
  const DepthSetup& d = desc.depth;
  if ((d.format != DepthFormat::D16 && d.format != DepthFormat::D24 &&
       d.format != DepthFormat::D32F) ||
      (d.convention != DepthConvention::Standard && d.convention != DepthConvention::Reversed) ||
      (d.clip_range != ClipDepthRange::NegativeOneToOne &&
       d.clip_range != ClipDepthRange::ZeroToOne)) {
    std::ostringstream out;
    out << "framebuffer: unknown depth set-up (format " << int(d.format) << ", convention "
        << int(d.convention) << ", clip range " << int(d.clip_range)
        << "); use the DepthFormat, DepthConvention and ClipDepthRange enumerators";
    throw Error(ErrorCode::InvalidArgument, out.str());
  }
  checkGlErrors("framebuffer: before creation");
  const GLsizei w = GLsizei(desc.width), h = GLsizei(desc.height);
  glCreateFramebuffers(1, &fbo_);
  glCreateTextures(GL_TEXTURE_2D, 1, &color_);
  glTextureStorage2D(color_, 1, GL_RGBA8, w, h);
  glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, color_, 0);
  if (desc.object_ids) {
    glCreateTextures(GL_TEXTURE_2D, 1, &ids_);
    glTextureStorage2D(ids_, 1, GL_R32UI, w, h);
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT1, ids_, 0);
  }
  glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
  glTextureStorage2D(depth_, 1, depthInternalFormat(desc.depth.format), w, h);
  glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
  const GLenum error = glGetError();
  if (error == GL_OUT_OF_MEMORY) {
    release();
    throw Error(ErrorCode::Runtime, "framebuffer: out of memory allocating " +
                                        sizeText(desc.width, desc.height) +
                                        " buffers; choose a smaller size");
  }
  if (error != GL_NO_ERROR) {
    release();
    std::ostringstream out;
    out << "framebuffer: GL error 0x" << std::hex << error << " creating a "
        << sizeText(desc.width, desc.height) << " framebuffer with depth format "
        << toString(desc.depth.format);
    throw Error(ErrorCode::Runtime, out.str());
  }
  const GLenum status = glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    release();
    throw Error(ErrorCode::Unsupported,
                std::string("framebuffer: incomplete (") + statusName(status) +
                    ") with depth "
                    "format " +
                    toString(desc.depth.format) +
                    "; the driver cannot render to this combination. Try depth format 32f.");
  }
  checkGlErrors("framebuffer: creation");
}

Framebuffer::~Framebuffer() { release(); }

void Framebuffer::release() {
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
// overflows GLsizei on very large framebuffers.
void readTexture(GLuint texture, std::uint32_t width, std::uint32_t height, GLenum format,
                 GLenum type, std::size_t pixel_bytes, void* dst) {
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  const std::size_t row_bytes = std::size_t(width) * pixel_bytes;
  const std::uint32_t band =
      std::uint32_t(std::max<std::size_t>(1, (std::size_t(1) << 30) / row_bytes));
  for (std::uint32_t y = 0; y < height; y += band) {
    const std::uint32_t rows = std::min(band, height - y);
    glGetTextureSubImage(texture, 0, 0, GLint(y), 0, GLsizei(width), GLsizei(rows), 1, format, type,
                         GLsizei(row_bytes * rows),
                         static_cast<std::uint8_t*>(dst) + row_bytes * y);
  }
}

}  // namespace

std::vector<std::uint8_t> Framebuffer::readColor() const {
  std::vector<std::uint8_t> out(std::size_t(desc_.width) * desc_.height * 4);
  readTexture(color_, desc_.width, desc_.height, GL_RGBA, GL_UNSIGNED_BYTE, 4, out.data());
  return out;
}

std::vector<float> Framebuffer::readDepth() const {
  std::vector<float> out(std::size_t(desc_.width) * desc_.height);
  readTexture(depth_, desc_.width, desc_.height, GL_DEPTH_COMPONENT, GL_FLOAT, 4, out.data());
  return out;
}

std::vector<std::uint32_t> Framebuffer::readObjectIds() const {
  if (!ids_) {
    throw Error(ErrorCode::InvalidArgument,
                "Framebuffer::readObjectIds: the framebuffer has no object-ID attachment");
  }
  std::vector<std::uint32_t> out(std::size_t(desc_.width) * desc_.height);
  readTexture(ids_, desc_.width, desc_.height, GL_RED_INTEGER, GL_UNSIGNED_INT, 4, out.data());
  return out;
}

}  // namespace logrid::gl
