#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <thread>

#include "batch_test_util.hpp"
#include "retarget/batch/worker_process.hpp"

namespace rt {
namespace {

using test::read_text;
using test::scratch_dir;
using test::write_text;

// Alive and not a zombie (a container's init may be slow to reap orphans).
bool process_alive(pid_t pid) {
  const std::string stat = read_text("/proc/" + std::to_string(pid) + "/stat");
  const auto paren = stat.rfind(')');
  return paren != std::string::npos && paren + 2 < stat.size() && stat[paren + 2] != 'Z' && stat[paren + 2] != 'X';
}

TEST(WorkerProcess, CapturesOutputAndExitCode) {
  const std::string dir = scratch_dir();
  WorkerLaunch l;
  l.argv = {"/bin/sh", "-c", "echo out; echo err >&2; echo \"$RT_X $PWD\"; exit 7"};
  l.extra_env = {"RT_X=hello"};
  l.log_path = dir + "/w.log";
  l.working_dir = dir;
  const WorkerExit x = run_worker(l);
  EXPECT_TRUE(x.exited);
  EXPECT_EQ(x.exit_code, 7);
  EXPECT_EQ(x.signal, 0);
  EXPECT_FALSE(x.timed_out);
  EXPECT_GT(x.max_rss_mb, 0.0);
  EXPECT_EQ(read_text(dir + "/w.log"), "out\nerr\nhello " + dir + "\n");
}

TEST(WorkerProcess, MissingExecutableIsExit127WithTheReason) {
  const std::string dir = scratch_dir();
  WorkerLaunch l;
  l.argv = {dir + "/no-such-program", "x"};
  l.log_path = dir + "/w.log";
  const WorkerExit x = run_worker(l);
  EXPECT_EQ(x.exit_code, 127);
  EXPECT_NE(read_text(dir + "/w.log").find("cannot run " + dir + "/no-such-program"), std::string::npos);
}

TEST(WorkerProcess, SignalDeathIsReported) {
  WorkerLaunch l;
  l.argv = {"/bin/sh", "-c", "kill -SEGV $$"};
  const WorkerExit x = run_worker(l);
  EXPECT_FALSE(x.exited);
  EXPECT_EQ(x.signal, SIGSEGV);
  EXPECT_EQ(signal_description(SIGSEGV), "SIGSEGV (Segmentation fault)");
}

TEST(WorkerProcess, TimeoutKillsTheWholeProcessGroup) {
  const std::string dir = scratch_dir();
  write_text(dir + "/hang.bvh", "FAKE-WORKER: hang-with-child " + dir + "/child.pid\n");
  WorkerLaunch l;
  l.argv = {test::fake_worker(), "convert", dir + "/hang.bvh"};
  l.timeout_s = 0.5;
  const auto t0 = std::chrono::steady_clock::now();
  const WorkerExit x = run_worker(l);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(x.timed_out);
  EXPECT_EQ(x.signal, SIGKILL);
  EXPECT_LT(wall, 5.0);
  const pid_t child = static_cast<pid_t>(std::stol(read_text(dir + "/child.pid")));
  // The grandchild was in the group: it is gone (reaped by init) shortly after.
  for (int i = 0; i < 200 && process_alive(child); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_FALSE(process_alive(child));
}

TEST(WorkerProcess, TerminateMarksCancelled) {
  WorkerLaunch l;
  l.argv = {"/bin/sleep", "30"};
  WorkerProcess p(l);
  EXPECT_TRUE(p.running());
  EXPECT_FALSE(p.poll());
  p.terminate(SIGTERM);
  const WorkerExit& x = p.wait();
  EXPECT_TRUE(x.cancelled);
  EXPECT_EQ(x.signal, SIGTERM);
  EXPECT_FALSE(p.running());
}

TEST(WorkerProcess, SignalMaskIsNotInherited) {
  // The batch CLI blocks SIGINT/SIGTERM while it runs; its workers must still die from SIGTERM.
  sigset_t set, old;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, &old);
  WorkerLaunch l;
  l.argv = {"/bin/sleep", "30"};
  WorkerProcess p(l);
  p.terminate(SIGTERM);
  const WorkerExit& x = p.wait();
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  EXPECT_EQ(x.signal, SIGTERM);
}

TEST(WorkerProcess, MemoryLimitMakesAllocationFail) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: RLIMIT_AS cannot be tested under it";
#endif
  const std::string dir = scratch_dir();
  write_text(dir + "/oom.bvh", "FAKE-WORKER: oom\n");
  WorkerLaunch l;
  l.argv = {test::fake_worker(), "convert", dir + "/oom.bvh"};
  l.log_path = dir + "/w.log";
  l.memory_limit_bytes = 256ull << 20;
  const WorkerExit x = run_worker(l);
  EXPECT_EQ(x.exit_code, 3);
  EXPECT_NE(read_text(dir + "/w.log").find("bad_alloc"), std::string::npos);
  EXPECT_LT(x.max_rss_mb, 300.0);
}

TEST(WorkerProcess, DestructorKillsARunningWorker) {
  pid_t pid = -1;
  {
    WorkerLaunch l;
    l.argv = {"/bin/sleep", "30"};
    WorkerProcess p(l);
    pid = p.pid();
    EXPECT_TRUE(process_alive(pid));
  }
  EXPECT_FALSE(process_alive(pid));  // killed and reaped
}

TEST(WorkerProcess, AvailableCpus) { EXPECT_GE(available_cpus(), 1); }

}  // namespace
}  // namespace rt
