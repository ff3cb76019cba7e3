#pragma once
/// Paths for tests: the shared real data (may be absent) and a per-test scratch folder.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace rt::test {

/// Folder of the shared real test data (../shared/data beside the project root).
inline std::string shared_data_dir() { return RT_SHARED_DATA_DIR; }

/// Path of a file in the shared data, or "" when the shared data is absent.
inline std::string shared_data(const std::string& relative) {
  const std::string p = shared_data_dir() + "/" + relative;
  return std::filesystem::exists(p) ? p : std::string();
}

/// Project source folder (for robots/, examples/, tests/data/).
inline std::string source_dir() { return RT_SOURCE_DIR; }
inline std::string source_path(const std::string& relative) { return source_dir() + "/" + relative; }

/// A fresh empty scratch folder for the current test.
inline std::string scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const char* root = std::getenv("RT_TEST_TMPDIR");
  std::filesystem::path dir = std::filesystem::path(root ? root : "/tmp/retarget-tests") /
                              (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace rt::test

/// Skips the current test with a clear message when a shared data file is absent.
#define RT_REQUIRE_SHARED(var, relative)                                                    \
  const std::string var = ::rt::test::shared_data(relative);                                \
  if (var.empty()) GTEST_SKIP() << "shared test data not found: " << ::rt::test::shared_data_dir() \
                                << "/" << (relative) << " (tests that need it are skipped)"
