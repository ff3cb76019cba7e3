// The CLI's progress line (cli/progress_line.hpp): the drawn text, the ETA from reported
// fractions, and silence when the output is not a terminal.

#include <gtest/gtest.h>

#include <fcntl.h>
#include <pty.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include "cli/progress_line.hpp"

namespace rt::cli {
namespace {

std::string drain(int fd) {
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  return out;
}

TEST(ProgressLine, TextWithElapsedAndEtaCutToTheTerminal) {
  EXPECT_EQ(format_progress_line("converting walk.bvh: pass 4/8 ik", 12.4, -1, 0), "converting walk.bvh: pass 4/8 ik  12s elapsed");
  EXPECT_EQ(format_progress_line("checking a.csv: 3.2/10.0 s of the clip simulated", 75, 30, 0),
            "checking a.csv: 3.2/10.0 s of the clip simulated  1m15s elapsed, ETA 30s");
  EXPECT_EQ(format_progress_line("checking a.csv", 1, 2, 10).size(), 9u);  // never wraps a 10-column terminal
}

TEST(ProgressLine, NothingOnAPipe) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  {
    ProgressLine line(std::chrono::milliseconds(0), fds[1]);
    line.set("working", 0.5);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  ::close(fds[1]);
  EXPECT_EQ(drain(fds[0]), "");
  ::close(fds[0]);
}

TEST(ProgressLine, OnATerminalRedrawsInPlaceWithAnEta) {
  int master = -1, slave = -1;
  if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) GTEST_SKIP() << "no pseudo-terminal";
  {
    ProgressLine line(std::chrono::milliseconds(0), slave);
    for (int k = 0; k <= 10; ++k) {  // a tenth of the work every 60 ms
      line.set("checking x: " + std::to_string(k) + "/10 s", k / 10.0);
      std::this_thread::sleep_for(std::chrono::milliseconds(60));
    }
  }
  ::close(slave);
  ::fcntl(master, F_SETFL, O_NONBLOCK);
  const std::string out = drain(master);
  ::close(master);
  EXPECT_EQ(out.rfind("\r\033[K"), out.size() - 4) << out;  // erased at the end
  EXPECT_NE(out.find("\r\033[Kchecking x: "), std::string::npos) << out;
  EXPECT_NE(out.find(" elapsed, ETA "), std::string::npos) << out;
  EXPECT_EQ(out.find('\n'), std::string::npos) << out;  // in place: never a new line
}

}  // namespace
}  // namespace rt::cli
