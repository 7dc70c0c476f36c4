#include "logrid/zread/multisample.hpp"

#include <epoxy/gl.h>

#include <sstream>
#include <string>

#include "logrid/error.hpp"
#include "logrid/zread/program.hpp"

namespace logrid::zread {
namespace {

// A full-viewport triangle (scissored to each rectangle) whose fragments take the
// farthest of the pixel's samples. gl_FragCoord.xy is the pixel centre, so its integer
// part is the texel.
constexpr const char* kResolveVertex = R"(#version 450 core
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;
  gl_Position = vec4(p, 0.0, 1.0);
}
)";
constexpr const char* kResolveFragment = R"(#version 450 core
uniform sampler2DMS u_depth;
uniform int u_samples;
uniform bool u_farthest_is_largest;
void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  float d = texelFetch(u_depth, texel, 0).r;
  for (int s = 1; s < u_samples; ++s) {
    float v = texelFetch(u_depth, texel, s).r;
    d = u_farthest_is_largest ? max(d, v) : min(d, v);
  }
  gl_FragDepth = d;
}
)";

constexpr GLuint kTextureUnit = 0;

std::string hex(GLenum e) {
  std::ostringstream out;
  out << "0x" << std::hex << e;
  return out.str();
}

}  // namespace

Result<DepthAttachment> tryDescribeDepthAttachment(const char* who, std::uint32_t framebuffer) {
  DepthAttachment a;
  a.framebuffer = framebuffer;
  const GLenum point = framebuffer ? GL_DEPTH_ATTACHMENT : GL_DEPTH;
  GLint type = GL_NONE;
  glGetNamedFramebufferAttachmentParameteriv(framebuffer, point,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
  a.object_type = GLenum(type);
  if (type == GL_NONE) {
    return Status(ErrorCode::InvalidArgument,
                  std::string(who) + ": framebuffer " + std::to_string(framebuffer) +
                      " has no depth attachment; logrid reads the depth buffer the application "
                      "draws into, so attach one (depth texture or renderbuffer)");
  }
  if (type == GL_FRAMEBUFFER_DEFAULT) {
    GLint samples = 0;
    glGetNamedFramebufferParameteriv(0, GL_SAMPLES, &samples);
    a.samples = samples > 1 ? samples : 0;
    return a;
  }
  GLint name = 0;
  glGetNamedFramebufferAttachmentParameteriv(framebuffer, point,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
  a.name = GLuint(name);
  GLint samples = 0, format = 0, width = 0, height = 0;
  if (type == GL_RENDERBUFFER) {
    glGetNamedRenderbufferParameteriv(a.name, GL_RENDERBUFFER_SAMPLES, &samples);
    glGetNamedRenderbufferParameteriv(a.name, GL_RENDERBUFFER_INTERNAL_FORMAT, &format);
    glGetNamedRenderbufferParameteriv(a.name, GL_RENDERBUFFER_WIDTH, &width);
    glGetNamedRenderbufferParameteriv(a.name, GL_RENDERBUFFER_HEIGHT, &height);
  } else {
    GLint target = 0, level = 0, layer = 0;
    glGetTextureParameteriv(a.name, GL_TEXTURE_TARGET, &target);
    glGetNamedFramebufferAttachmentParameteriv(framebuffer, point,
                                               GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL, &level);
    glGetNamedFramebufferAttachmentParameteriv(framebuffer, point,
                                               GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LAYER, &layer);
    a.target = GLenum(target);
    a.layer = layer;
    glGetTextureLevelParameteriv(a.name, level, GL_TEXTURE_SAMPLES, &samples);
    glGetTextureLevelParameteriv(a.name, level, GL_TEXTURE_INTERNAL_FORMAT, &format);
    glGetTextureLevelParameteriv(a.name, level, GL_TEXTURE_WIDTH, &width);
    glGetTextureLevelParameteriv(a.name, level, GL_TEXTURE_HEIGHT, &height);
  }
  a.samples = samples > 1 ? samples : 0;
  a.internal_format = GLenum(format);
  a.width = width;
  a.height = height;
  return a;
}

Status tryCheckMultisample(const char* who, const DepthAttachment& a, const Camera& camera) {
  if (a.samples == 0) return {};
  if (a.object_type == GL_FRAMEBUFFER_DEFAULT) {
    return Status(ErrorCode::Unsupported,
                  std::string(who) + ": the default framebuffer is multisampled (" +
                      std::to_string(a.samples) +
                      " samples); its samples cannot be read one by one, so logrid cannot take "
                      "the farthest of them. Render into a framebuffer object with a "
                      "multisampled depth texture or renderbuffer, and resolve colour to the "
                      "window afterwards");
  }
  if (!camera.multisample) {
    return Status(ErrorCode::InvalidArgument,
                  std::string(who) + ": framebuffer " + std::to_string(a.framebuffer) + " has " +
                      std::to_string(a.samples) +
                      " depth samples per pixel but Camera::multisample is false; set it, so "
                      "that a box counts every pixel it touches (samples lie away from pixel "
                      "centres)");
  }
  return {};
}

struct MultisampleResolver::Impl {
  std::unique_ptr<Program> program;
  GLint samples_uniform = -1;
  GLint largest_uniform = -1;
  GLuint vao = 0;
  // The resolved depth.
  GLuint fbo = 0, resolved = 0;
  GLint width = 0, height = 0;
  // The copy of a renderbuffer or array layer, as a multisampled texture.
  GLuint copy = 0;
  GLenum copy_format = 0;
  GLint copy_samples = 0, copy_width = 0, copy_height = 0;

  explicit Impl(std::unique_ptr<Program> resolve) : program(std::move(resolve)) {
    samples_uniform = program->uniform("u_samples");
    largest_uniform = program->uniform("u_farthest_is_largest");
    glCreateVertexArrays(1, &vao);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferDrawBuffer(fbo, GL_NONE);
    glNamedFramebufferReadBuffer(fbo, GL_NONE);
    glProgramUniform1i(program->handle(), program->uniform("u_depth"), GLint(kTextureUnit));
  }
  ~Impl() {
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    if (resolved) glDeleteTextures(1, &resolved);
    if (copy) glDeleteTextures(1, &copy);
  }

  void size(GLint w, GLint h) {
    if (resolved && w == width && h == height) return;
    if (resolved) glDeleteTextures(1, &resolved);
    glCreateTextures(GL_TEXTURE_2D, 1, &resolved);
    glTextureStorage2D(resolved, 1, GL_DEPTH_COMPONENT32F, w, h);
    glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, resolved, 0);
    width = w;
    height = h;
  }

  // The multisampled texture to fetch from: the attachment itself, or a copy of the
  // rectangles of a renderbuffer or array layer.
  GLuint source(const DepthAttachment& a, const PixelRect* rects, std::size_t count) {
    if (a.object_type == GL_TEXTURE && a.target == GL_TEXTURE_2D_MULTISAMPLE) return a.name;
    if (!copy || copy_format != a.internal_format || copy_samples != a.samples ||
        copy_width != a.width || copy_height != a.height) {
      if (copy) glDeleteTextures(1, &copy);
      glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &copy);
      glTextureStorage2DMultisample(copy, a.samples, a.internal_format, a.width, a.height, GL_TRUE);
      copy_format = a.internal_format;
      copy_samples = a.samples;
      copy_width = a.width;
      copy_height = a.height;
    }
    const GLenum target = a.object_type == GL_RENDERBUFFER ? GLenum(GL_RENDERBUFFER) : a.target;
    for (std::size_t i = 0; i < count; ++i) {
      const PixelRect& r = rects[i];
      glCopyImageSubData(a.name, target, 0, r.x0, r.y0, a.layer, copy, GL_TEXTURE_2D_MULTISAMPLE, 0,
                         r.x0, r.y0, 0, r.x1 - r.x0, r.y1 - r.y0, 1);
    }
    return copy;
  }
};

Result<std::unique_ptr<MultisampleResolver>> MultisampleResolver::create() {
  std::unique_ptr<MultisampleResolver> resolver(new MultisampleResolver(Unbuilt{}));
  if (Status built = resolver->build(); !built) return built;
  return resolver;
}

Status MultisampleResolver::build() {
  Result<std::unique_ptr<Program>> program =
      Program::create("MultisampleResolver", kResolveVertex, kResolveFragment);
  if (!program) return program.status();
  impl_ = std::make_unique<Impl>(std::move(program).value());
  return {};
}

MultisampleResolver::MultisampleResolver(Unbuilt) {}
MultisampleResolver::~MultisampleResolver() = default;

std::uint32_t MultisampleResolver::depthTexture() const { return impl_ ? impl_->resolved : 0; }

std::optional<std::uint32_t> MultisampleResolver::resolve(GlStateGuard::Scope& scope,
                                                          const DepthAttachment& a,
                                                          DepthConvention convention,
                                                          const PixelRect* rects,
                                                          std::size_t count) {
  Impl& s = *impl_;
  if (a.samples == 0 || a.object_type == GL_FRAMEBUFFER_DEFAULT ||
      (a.object_type == GL_TEXTURE && a.target != GL_TEXTURE_2D_MULTISAMPLE &&
       a.target != GL_TEXTURE_2D_MULTISAMPLE_ARRAY)) {
    scope.fail(Status(ErrorCode::Unsupported,
                      "MultisampleResolver: cannot resolve a depth attachment of object type " +
                          hex(a.object_type) + ", target " + hex(a.target) + " and " +
                          std::to_string(a.samples) +
                          " samples; attach a multisampled depth texture or renderbuffer"));
    return std::nullopt;
  }
  if (!scope.ok()) return std::nullopt;
  s.size(a.width, a.height);
  const GLuint texture = s.source(a, rects, count);
  if (!scope.check("glCopyImageSubData (multisampled depth to texture)") ||
      !scope.prepareDraw(s.fbo, a.width, a.height, GL_ALWAYS, true) ||
      !scope.bindTexture(kTextureUnit, GL_TEXTURE_2D_MULTISAMPLE, texture)) {
    return std::nullopt;
  }
  s.program->use();
  glBindVertexArray(s.vao);
  glProgramUniform1i(s.program->handle(), s.samples_uniform, a.samples);
  glProgramUniform1i(s.program->handle(), s.largest_uniform,
                     convention == DepthConvention::Standard ? 1 : 0);
  for (std::size_t i = 0; i < count; ++i) {
    scope.scissor(rects[i]);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  if (!scope.check("the multisample depth resolve")) return std::nullopt;
  return s.fbo;
}

}  // namespace logrid::zread
