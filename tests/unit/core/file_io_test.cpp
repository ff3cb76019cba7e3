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

// Issue 18 item 9: batch paths are checked where they are opened. A confined read of a symlink
// that leads outside the root is refused (checked on the opened descriptor, so a link changed
// after any earlier check is still caught); unlisted paths and links inside the root are read.
TEST(FileIo, ConfinedReadsMustResolveInsideTheRoot) {
  namespace fs = std::filesystem;
  const std::string dir = test::scratch_dir();
  fs::create_directories(dir + "/root/sub");
  fs::create_directories(dir + "/elsewhere");
  write_file_atomic(dir + "/elsewhere/secret.bvh", "secret\n");
  write_file_atomic(dir + "/root/sub/clip.bvh", "clip\n");
  fs::create_symlink(dir + "/elsewhere/secret.bvh", dir + "/root/escape.bvh");
  fs::create_symlink("sub/clip.bvh", dir + "/root/inside.bvh");
  fs::create_symlink(dir + "/elsewhere", dir + "/root/linked");  // a folder link on the way
  PathConfinement c;
  c.read_root = dir + "/root";
  c.confined_reads = {dir + "/root/escape.bvh", dir + "/root/inside.bvh", dir + "/root/linked/secret.bvh"};
  {
    const ScopedPathConfinement scope(c);
    for (const std::string& p : {dir + "/root/escape.bvh", dir + "/root/linked/secret.bvh"}) {
      try {
        read_file(p);
        ADD_FAILURE() << p << " was read";
      } catch (const InputError& e) {
        EXPECT_EQ(e.location(), p);
        EXPECT_NE(e.message().find("resolves outside the input root"), std::string::npos) << e.what();
        EXPECT_NE(e.message().find("secret.bvh"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find("secret\n"), std::string::npos);  // the content is never echoed
      }
      EXPECT_THROW(read_file_prefix(p, 16), InputError);
    }
    EXPECT_EQ(read_file(dir + "/root/inside.bvh"), "clip\n");
    EXPECT_EQ(read_file(dir + "/elsewhere/secret.bvh"), "secret\n");  // not a confined path
  }
  EXPECT_EQ(read_file(dir + "/root/escape.bvh"), "secret\n");  // the scope ended
}

// Outputs: an atomic write into a folder that is (or passes through) a symlink leading outside
// the write root is refused before anything is created there; inside, writes work as before.
TEST(FileIo, ConfinedWritesStayInsideTheOutputFolder) {
  namespace fs = std::filesystem;
  const std::string dir = test::scratch_dir();
  fs::create_directories(dir + "/out/walks");
  fs::create_directories(dir + "/elsewhere");
  fs::create_symlink(dir + "/elsewhere", dir + "/out/linked");
  fs::create_symlink(dir + "/elsewhere/planted", dir + "/out/walks/planted.csv");  // a link at the file's name
  PathConfinement c;
  c.write_root = dir + "/out";
  const ScopedPathConfinement scope(c);
  try {
    write_file_atomic(dir + "/out/linked/walk.csv", "x");
    FAIL() << "written through the symlink";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), dir + "/out/linked/walk.csv");
    EXPECT_NE(e.message().find("leads outside the output folder"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir + "/elsewhere"));
  write_file_atomic(dir + "/out/walks/walk.csv", "y");
  EXPECT_EQ(read_file(dir + "/out/walks/walk.csv"), "y");
  // rename() replaces a link planted at the file's name; its target is never created or written.
  write_file_atomic(dir + "/out/walks/planted.csv", "z");
  EXPECT_FALSE(fs::is_symlink(dir + "/out/walks/planted.csv"));
  EXPECT_FALSE(fs::exists(dir + "/elsewhere/planted"));
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir + "/out/walks")) ++entries;
  EXPECT_EQ(entries, 2);  // no temporaries left
}

}  // namespace
}  // namespace rt
