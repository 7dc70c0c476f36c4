// Waiting for the fence behind an asynchronous read, as the GL depth sources do. Internal
// to logrid::zread.
#pragma once

#include <epoxy/gl.h>

#include <string>

#include "logrid/error.hpp"

namespace logrid::zread::detail {

inline constexpr GLuint64 kWaitNanoseconds = 10'000'000'000ull;  // 10 s: a hung renderer

// Waits for `fence` (a GLsync; nothing when null), deletes it and sets it to null. An
// error (Runtime) "<waiting_for> failed or took over 10 s" when the wait fails or times out.
inline Status waitFence(void*& fence, const std::string& waiting_for) {
  if (!fence) return {};
  const GLenum result = glClientWaitSync(static_cast<GLsync>(fence), 0, kWaitNanoseconds);
  glDeleteSync(static_cast<GLsync>(fence));
  fence = nullptr;
  if (result == GL_TIMEOUT_EXPIRED || result == GL_WAIT_FAILED) {
    return Status(ErrorCode::Runtime, waiting_for + " failed or took over 10 s");
  }
  return {};
}

}  // namespace logrid::zread::detail
