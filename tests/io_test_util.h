// Helpers shared by the tests of readers, writers and the command line.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <initializer_list>
#include <string>

#include "io/input_error.h"

namespace clothfit {
namespace testing_util {

// A fresh, empty directory per test under CLOTHFIT_TEST_TMP (set by
// tests/CMakeLists.txt): <tmp>/<prefix><test name>.
inline std::filesystem::path FreshTestDir(const std::string& prefix) {
  const ::testing::TestInfo* info =
      ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::path(CLOTHFIT_TEST_TMP) / (prefix + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Runs `action` and returns the InputError message ("" if none).
template <typename Action>
std::string ErrorOf(Action action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// Expects a non-empty message holding every piece.
inline void ExpectHas(const std::string& message,
                      std::initializer_list<std::string> pieces) {
  ASSERT_FALSE(message.empty()) << "no error";
  for (const std::string& piece : pieces) {
    EXPECT_NE(message.find(piece), std::string::npos)
        << "'" << piece << "' not in: " << message;
  }
}

}  // namespace testing_util
}  // namespace clothfit
