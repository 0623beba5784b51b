#pragma once
// The message of the exception a test expects:
//
//   EXPECT_EQ(error_message<ParseError>([&] { parse_path_csv("x\n", "p.csv"); }),
//             "p.csv:1:1: error: …");
//
// Returns "no error" if `f` returns normally; another exception type is a test failure (its
// message is returned, prefixed "wrong exception type: ").
#include <exception>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"

namespace motionmap::test {

template <class E = Error, class F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
    return std::string("wrong exception type: ") + e.what();
  }
  return "no error";
}

}  // namespace motionmap::test
