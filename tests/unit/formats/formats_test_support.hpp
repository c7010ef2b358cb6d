// Helpers shared by the formats tests: fixture paths and checks of data-error messages.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "m2mlat/core/error.hpp"

namespace m2mlat::formats::test {

inline std::string fixture(const std::string& name) { return std::string(M2MLAT_TEST_DATA) + "/" + name; }

// Runs `action`, which must throw core::Error of kind data whose message contains every one of
// `parts` (e.g. "results.csv:3:" and "field vehicle_ns"). Returns the message for further checks.
inline std::string expect_data_error(const std::function<void()>& action,
                                     std::initializer_list<std::string> parts) {
  try {
    action();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data) << e.what();
    const std::string message = e.what();
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
    return message;
  }
  ADD_FAILURE() << "no core::Error thrown";
  return {};
}

}  // namespace m2mlat::formats::test
