// expectStatus and expectBothForms: the checks of the result forms (logrid/error.hpp),
// beside expectError (expect_error.hpp) for the throwing forms.
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "logrid/error.hpp"

namespace logrid::test {

inline const Status& statusOf(const Status& status) { return status; }
template <typename T>
const Status& statusOf(const Result<T>& result) {
  return result.status();
}

// Expects `status` to be an error with `code` whose message contains every part.
inline void expectStatus(const Status& status, ErrorCode code,
                         std::initializer_list<std::string> parts) {
  ASSERT_FALSE(status.ok()) << "no error; expected one containing '" << *parts.begin() << "'";
  EXPECT_EQ(status.code(), code) << toString(status.code()) << ": " << status.message();
  for (const std::string& part : parts) {
    EXPECT_NE(status.message().find(part), std::string::npos)
        << "message '" << status.message() << "' lacks '" << part << "'";
  }
}

// Expects the result form `try_form` (returning a Status or a Result) to fail with `code`
// and a message containing every part, and the throwing form `throw_form` to throw a
// logrid::Error with the same code and the same message.
template <typename TryForm, typename ThrowForm>
void expectBothForms(TryForm&& try_form, ThrowForm&& throw_form, ErrorCode code,
                     std::initializer_list<std::string> parts) {
  const auto result = try_form();
  const Status& status = statusOf(result);
  expectStatus(status, code, parts);
  try {
    throw_form();
    ADD_FAILURE() << "the throwing form did not throw; the result form gave '" << status.message()
                  << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), status.code());
    EXPECT_EQ(std::string(e.what()), status.message());
  }
}

}  // namespace logrid::test
