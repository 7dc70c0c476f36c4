// Errors at logrid's API boundary.
//
// Programming errors (a broken invariant inside logrid) are asserts. Everything a
// user can cause — bad input, a missing driver, an unreadable file — is reported as
// a logrid::Error whose message says what failed, with which value, and what to do.
#pragma once

#include <stdexcept>
#include <string>

namespace logrid {

enum class ErrorCode {
  InvalidArgument,  // a value the caller passed is out of range, NaN, or inconsistent
  Unsupported,      // the platform lacks a feature (GL version, extension, format)
  Environment,      // the environment is missing something (EGL display, driver, file)
  BadInput,         // a file or data set is malformed
  Runtime,          // something failed while running (GL error, incomplete framebuffer)
};

class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

const char* toString(ErrorCode);

}  // namespace logrid
