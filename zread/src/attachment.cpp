#include "attachment.hpp"

#include <sstream>
#include <string>

#include "logrid/error.hpp"

namespace logrid::zread::detail {

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

Status checkDepthAttachment(const char* who, GLuint framebuffer, const Camera& camera) {
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
    return Status(ErrorCode::InvalidArgument, out.str());
  }
  return {};
}

}  // namespace logrid::zread::detail
