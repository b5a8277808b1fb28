// Checks shared by the C++ tests.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "bdinterp/types.h"

namespace bdinterp::testing {

// Expects InvalidInput whose message contains `needle`.
template <typename Fn>
void expect_invalid(Fn fn, const std::string& needle) {
  try {
    fn();
    FAIL() << "no exception, expected one mentioning '" << needle << "'";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

}  // namespace bdinterp::testing
