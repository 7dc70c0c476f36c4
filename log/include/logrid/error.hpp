// Errors at logrid's API boundary.
//
// Programming errors (a broken invariant inside logrid) are asserts. Everything a
// user can cause — bad input, a missing driver, an unreadable file — is reported with
// an ErrorCode and a message that says what failed, with which value, and what to do.
//
// Two forms of every call that can fail, the same checks and the same messages:
//   * the result form, which never throws: it returns a Status (or a Result<T>, a value
//     or a Status) — Culler::create(), Culler::tryBeginFrame(), parseCullerConfig(), ...
//     The libraries are written in it alone, so that they build with -fno-exceptions
//     (the CMake option LOGRID_EXCEPTIONS=OFF; docs/DESIGN.md, "Errors").
//   * the throwing form, which throws logrid::Error with the same code and message —
//     the Culler constructor, Culler::beginFrame(), ... Each is an inline function in
//     its header over the result form, declared only where exceptions are enabled
//     (LOGRID_HAS_EXCEPTIONS), so that it is compiled into the application, not into
//     the library. logrid::orThrow() turns any result form into the throwing one.
#pragma once

#include <cassert>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
#define LOGRID_HAS_EXCEPTIONS 1
#else
#define LOGRID_HAS_EXCEPTIONS 0
#endif

namespace logrid {

enum class ErrorCode {
  InvalidArgument,  // a value the caller passed is out of range, NaN, or inconsistent
  Unsupported,      // the platform lacks a feature (GL version, extension, format)
  Environment,      // the environment is missing something (EGL display, driver, file)
  BadInput,         // a file or data set is malformed
  Runtime,          // something failed while running (GL error, incomplete framebuffer)
};

const char* toString(ErrorCode);

// Success, or an error: its code and its message.
class [[nodiscard]] Status {
 public:
  Status() = default;  // success
  Status(ErrorCode code, std::string message)
      : failed_(true), code_(code), message_(std::move(message)) {}

  bool ok() const noexcept { return !failed_; }
  explicit operator bool() const noexcept { return !failed_; }
  ErrorCode code() const noexcept { return code_; }  // an error's only
  const std::string& message() const noexcept { return message_; }

 private:
  bool failed_ = false;
  ErrorCode code_ = ErrorCode::Runtime;
  std::string message_;
};

// A value, or the Status of the error that left none.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}       // NOLINT: a value converts
  Result(Status error) : status_(std::move(error)) {  // NOLINT: so does an error
    assert(!status_.ok() && "Result: an ok Status carries no value");
  }

  bool ok() const noexcept { return value_.has_value(); }
  explicit operator bool() const noexcept { return ok(); }
  const Status& status() const noexcept { return status_; }  // ok() when there is a value

  // Preconditions: ok().
  T& value() & { return assert(ok()), *value_; }
  const T& value() const& { return assert(ok()), *value_; }
  T&& value() && { return assert(ok()), std::move(*value_); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::optional<T> value_;
  Status status_;
};

// The first error of calls that cannot return one (a depth source's requests: they are
// answered conservatively, and the error is reported later), kept until it is taken.
class FirstError {
 public:
  void note(Status error) {
    if (first_.ok()) first_ = std::move(error);
  }
  bool failed() const noexcept { return !first_.ok(); }
  Status take() { return std::exchange(first_, Status{}); }

 private:
  Status first_;
};

#if LOGRID_HAS_EXCEPTIONS
// The throwing form's exception.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

// The throwing forms over the result forms, and for an application's own use of a
// result form (a depth source's Status, say): throws its error as logrid::Error.
inline void orThrow(const Status& status) {
  if (!status.ok()) throw Error(status.code(), status.message());
}
template <typename T>
T orThrow(Result<T>&& result) {
  orThrow(result.status());
  return std::move(result).value();
}
#endif

}  // namespace logrid
