#include "retarget/core/file_io.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

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

// Issue 18 item 8: a FIFO blocked every reader forever; /dev/zero read as an "empty file"; a folder.
// Each is refused at once, saying what it is.
TEST(FileIo, NonRegularFilesAreRefusedWithoutBlocking) {
  const std::string dir = test::scratch_dir();
  const std::string fifo = dir + "/clip.bvh";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  auto message = [](const std::string& path) {
    try {
      read_file(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(fifo), fifo + ": is a FIFO (named pipe), expected a regular file");
  EXPECT_EQ(message("/dev/zero"), "/dev/zero: is a character device, expected a regular file");
  EXPECT_EQ(message(dir), dir + ": is a folder, expected a file");
  EXPECT_THROW(require_regular_file(fifo), InputError);
  EXPECT_THROW(require_regular_file("/dev/null"), InputError);
  // "cannot open" carries the reason.
  EXPECT_EQ(message(dir + "/missing.bvh"), dir + "/missing.bvh: cannot open: No such file or directory");
  write_file_atomic(dir + "/ok.txt", "ok");
  EXPECT_NO_THROW(require_regular_file(dir + "/ok.txt"));
}

}  // namespace
}  // namespace rt
