// The message of an expected std::invalid_argument, for tests of the checks that name a
// violated constraint (core options' validate(), the tools' readers).
#pragma once

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace asperity::test_support {

// Runs f, which must throw std::invalid_argument; returns its message (a failure, and an empty
// message, when nothing is thrown).
template <class F>
std::string invalid_argument_message(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::invalid_argument thrown";
  return {};
}

}  // namespace asperity::test_support
