// expectError: the check of the bad-input tests (tests/unit/bad_input_test.cpp,
// tests/gl/bad_input_gl_test.cpp) that a call fails with a given logrid::Error.
#pragma once

#include <gtest/gtest.h>

#include <exception>
#include <initializer_list>
#include <string>

#include "logrid/error.hpp"

namespace logrid::test {

// Expects `f` to throw a logrid::Error with `code` whose message contains every part.
template <typename F>
void expectError(F&& f, ErrorCode code, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no logrid::Error thrown; expected one containing '" << *parts.begin() << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << toString(e.code()) << ": " << e.what();
    for (const std::string& part : parts) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' lacks '" << part << "'";
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a logrid::Error: " << e.what();
  }
}

}  // namespace logrid::test
