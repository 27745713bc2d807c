#pragma once
// Paths to the source tree's fixtures and a fresh scratch directory per test.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace ppohdem::test {

inline std::filesystem::path fixture(const std::string& relative) {
  return std::filesystem::path(PPOHDEM_SOURCE_DIR) / "fixtures" / relative;
}

/// An empty directory unique to the running test (removed and re-made on each call).
inline std::filesystem::path scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  auto dir = std::filesystem::path(PPOHDEM_BINARY_DIR) / "test-scratch" /
             (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace ppohdem::test
