// What the GL depth sources share about the framebuffer they read: the native read type
// of each depth format, and the check that the depth attachment is what the camera says.
#pragma once

#include <epoxy/gl.h>

#include <cstddef>

#include "logrid/camera.hpp"
#include "logrid/depth_kernels.hpp"
#include "logrid/error.hpp"

namespace logrid::zread::detail {

// The GL type a depth format is read in without conversion.
GLenum nativeType(DepthFormat format);
NativeDepth nativeDepth(DepthFormat format);
inline std::size_t bytesOf(GLenum type) { return type == GL_UNSIGNED_SHORT ? 2 : 4; }

// An error (InvalidArgument) unless the framebuffer's depth attachment has the format the
// camera says: the depth margin depends on it, so a mismatch would be silently wrong.
Status checkDepthAttachment(const char* who, GLuint framebuffer, const Camera& camera);

}  // namespace logrid::zread::detail
