// One headless GL context per test binary. GL tests call requireGl() first: without a
// usable EGL/GL 4.5 they are skipped (with the reason), unless LOGRID_REQUIRE_GL=1 is
// set, as in the project's test command, where they fail instead.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "logrid/error.hpp"
#include "logrid/gl/context.hpp"

namespace logrid::test {

inline logrid::gl::Context* sharedContext(std::string* why = nullptr) {
  static std::unique_ptr<logrid::gl::Context> context;
  static std::string failure;
  static bool tried = false;
  if (!tried) {
    tried = true;
    try {
      logrid::gl::ContextDesc desc;
      desc.debug = true;  // every GL error is caught in tests, in every build type
      context = std::make_unique<logrid::gl::Context>(desc);
    } catch (const logrid::Error& e) {
      failure = e.what();
    }
  }
  if (why) *why = failure;
  return context.get();
}

inline bool glRequired() {
  const char* v = std::getenv("LOGRID_REQUIRE_GL");
  return v && std::string(v) == "1";
}

}  // namespace logrid::test

#define LOGRID_REQUIRE_GL()                                                  \
  do {                                                                       \
    std::string why_;                                                        \
    if (!::logrid::test::sharedContext(&why_)) {                             \
      if (::logrid::test::glRequired()) FAIL() << "no GL context: " << why_; \
      GTEST_SKIP() << "no GL context: " << why_;                             \
    }                                                                        \
  } while (0)
