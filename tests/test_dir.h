// A fresh, empty directory per test under CLOTHFIT_TEST_TMP (set by
// tests/CMakeLists.txt): <tmp>/<prefix><test name>.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace clothfit {
namespace testing_util {

inline std::filesystem::path FreshTestDir(const std::string& prefix) {
  const ::testing::TestInfo* info =
      ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::path(CLOTHFIT_TEST_TMP) / (prefix + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace testing_util
}  // namespace clothfit
