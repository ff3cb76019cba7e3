#include "retarget/batch/worker_process.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <system_error>
#include <thread>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

extern char** environ;

namespace rt {

namespace {

// Everything the child needs, prepared before fork(): between fork() and exec() only
// async-signal-safe calls are allowed (no allocation).
struct ChildSetup {
  std::vector<std::string> argv, env;
  std::vector<char*> argv_ptrs, env_ptrs;
  std::string exec_error;  // written to the log when exec fails
  std::string working_dir;
  std::uint64_t memory_limit_bytes = 0;
};

std::vector<std::string> merged_environment(const std::vector<std::string>& extra) {
  std::vector<std::string> env;
  for (char** e = environ; e && *e; ++e) {
    const std::string entry(*e);
    const std::string name = entry.substr(0, entry.find('='));
    bool overridden = false;
    for (const std::string& x : extra)
      if (x.compare(0, name.size() + 1, name + "=") == 0) overridden = true;
    if (!overridden) env.push_back(entry);
  }
  env.insert(env.end(), extra.begin(), extra.end());
  return env;
}

void write_all(int fd, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

[[noreturn]] void run_child(const ChildSetup& s, pid_t parent, int null_fd, int log_fd) {
  ::setpgid(0, 0);
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(126);  // the parent died before prctl took effect
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGCHLD, SIGUSR1, SIGUSR2}) ::sigaction(sig, &dfl, nullptr);
  ::dup2(null_fd, STDIN_FILENO);
  ::dup2(log_fd, STDOUT_FILENO);
  ::dup2(log_fd, STDERR_FILENO);
  if (!s.working_dir.empty() && ::chdir(s.working_dir.c_str()) != 0) {
    static const char msg[] = "cannot change to the working folder\n";
    write_all(STDERR_FILENO, msg, sizeof msg - 1);
    ::_exit(127);
  }
  if (s.memory_limit_bytes > 0) {
    struct rlimit lim {};
    lim.rlim_cur = lim.rlim_max = static_cast<rlim_t>(s.memory_limit_bytes);
    ::setrlimit(RLIMIT_AS, &lim);
  }
  ::execve(s.argv_ptrs[0], s.argv_ptrs.data(), s.env_ptrs.data());
  const int err = errno;
  write_all(STDERR_FILENO, s.exec_error.data(), s.exec_error.size());
  char num[16];
  int k = 0;
  for (int v = err; k == 0 || v > 0; v /= 10) num[k++] = static_cast<char>('0' + v % 10);
  while (k > 0) write_all(STDERR_FILENO, &num[--k], 1);
  write_all(STDERR_FILENO, ")\n", 2);
  ::_exit(127);
}

}  // namespace

WorkerProcess::WorkerProcess(const WorkerLaunch& launch) : timeout_s_(launch.timeout_s) {
  RT_DEMAND(!launch.argv.empty() && !launch.argv[0].empty(), "a worker needs an executable");
  ChildSetup s;
  s.argv = launch.argv;
  s.env = merged_environment(launch.extra_env);
  for (std::string& a : s.argv) s.argv_ptrs.push_back(a.data());
  s.argv_ptrs.push_back(nullptr);
  for (std::string& e : s.env) s.env_ptrs.push_back(e.data());
  s.env_ptrs.push_back(nullptr);
  s.exec_error = "error: cannot run " + launch.argv[0] + " (exec failed, errno ";
  s.working_dir = launch.working_dir;
  s.memory_limit_bytes = launch.memory_limit_bytes;

  const std::string log = launch.log_path.empty() ? std::string("/dev/null") : launch.log_path;
  // O_NOFOLLOW: a symlink planted at the log's name must not truncate the file it points to.
  const int log_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | (launch.log_path.empty() ? 0 : O_NOFOLLOW), 0644);
  if (log_fd < 0 && errno == ELOOP)
    throw InputError(log, "is a symlink; the worker log is not written through it");
  if (log_fd < 0) throw InputError(log, std::string("cannot create the worker log: ") + std::strerror(errno));
  const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (null_fd < 0) {
    const int err = errno;
    ::close(log_fd);
    throw std::system_error(err, std::generic_category(), "cannot open /dev/null");
  }
  const pid_t parent = ::getpid();
  start_ = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) run_child(s, parent, null_fd, log_fd);
  const int fork_errno = errno;
  ::close(log_fd);
  ::close(null_fd);
  if (pid < 0) throw std::system_error(fork_errno, std::generic_category(), "cannot start a worker process");
  ::setpgid(pid, pid);  // also in the parent, so the group exists before we may signal it
  pid_ = pid;
  running_ = true;
}

WorkerProcess::~WorkerProcess() {
  if (!running_) return;
  ::kill(-pid_, SIGKILL);
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
}

double WorkerProcess::elapsed_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void WorkerProcess::reap(int status, long max_rss_kb) {
  running_ = false;
  exit_.wall_s = elapsed_s();
  exit_.max_rss_mb = static_cast<double>(max_rss_kb) / 1024.0;
  if (WIFEXITED(status)) {
    exit_.exited = true;
    exit_.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    exit_.signal = WTERMSIG(status);
  }
}

bool WorkerProcess::poll() {
  if (!running_) return true;
  int status = 0;
  struct rusage ru {};
  const pid_t r = ::wait4(pid_, &status, WNOHANG, &ru);
  if (r == pid_) {
    reap(status, ru.ru_maxrss);
    return true;
  }
  if (r < 0 && errno != EINTR) {  // ECHILD: reaped by someone else (SIGCHLD ignored): status unknown
    running_ = false;
    exit_.wall_s = elapsed_s();
    return true;
  }
  if (timeout_s_ > 0 && !exit_.timed_out && elapsed_s() > timeout_s_) {
    exit_.timed_out = true;
    ::kill(-pid_, SIGKILL);
  }
  return false;
}

void WorkerProcess::terminate(int sig) {
  if (!running_) return;
  exit_.cancelled = true;
  ::kill(-pid_, sig);
}

const WorkerExit& WorkerProcess::wait(double poll_s) {
  while (!poll()) std::this_thread::sleep_for(std::chrono::duration<double>(poll_s));
  return exit_;
}

WorkerExit run_worker(const WorkerLaunch& launch) {
  WorkerProcess p(launch);
  return p.wait();
}

std::string signal_description(int sig) {
  const char* abbrev = ::sigabbrev_np(sig);
  const char* text = ::strsignal(sig);
  std::string out = abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
  if (text) out += std::string(" (") + text + ")";
  return out;
}

int available_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(0, sizeof set, &set) == 0) {
    const int n = CPU_COUNT(&set);
    if (n > 0) return n;
  }
  const unsigned n = std::thread::hardware_concurrency();
  return n > 0 ? static_cast<int>(n) : 1;
}

}  // namespace rt
