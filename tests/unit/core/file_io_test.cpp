#include "retarget/core/file_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "retarget/core/error.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

TEST(FileIo, AtomicWriteReplacesAndLeavesNoTemporaries) {
  const std::string dir = test::scratch_dir();
  const std::string path = dir + "/out.txt";
  write_file_atomic(path, "first");
  write_file_atomic(path, "second");
  EXPECT_EQ(read_file(path), "second");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(FileIo, ErrorsNameThePath) {
  try {
    read_file("/nonexistent/file.bvh");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), "/nonexistent/file.bvh");
  }
  EXPECT_THROW(write_file_atomic("/nonexistent/dir/x.csv", "x"), InputError);
  const std::string dir = test::scratch_dir();
  write_file_atomic(dir + "/big", std::string(100, 'a'));
  EXPECT_THROW(read_file(dir + "/big", 10), InputError);
}

}  // namespace
}  // namespace rt
