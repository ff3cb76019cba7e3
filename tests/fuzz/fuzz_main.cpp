// The seeded mutation driver: `rt_fuzz TARGET [options]` runs TARGET's seeds, then mutants of
// them until --seconds or --runs, from a fixed --seed (the same sequence every time; a shorter
// run is a prefix of a longer one). `rt_fuzz TARGET FILE...` replays saved inputs.
//
// A failure (exit 1) is: an exception other than rt::InputError, an InputError that is not one
// located line, a per-input timeout (--timeout-ms), a crash, or, in the sanitizer build, any
// ASan/UBSan report, including an allocation over 256 MB or a resident size over 2 GB (options
// below). The failing input is written to --artifacts (default: the working folder).

#include <fcntl.h>
#include <signal.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "fuzz_target.hpp"
#include "mutator.hpp"
#include "retarget/core/error.hpp"

// Sanitizer settings compiled in, so that ctest and a hand run behave alike (the environment's
// ASAN_OPTIONS / UBSAN_OPTIONS still override them).
extern "C" const char* __asan_default_options() {
  return "max_allocation_size_mb=256:allocator_may_return_null=0:hard_rss_limit_mb=2048:quarantine_size_mb=64:"
         "detect_leaks=1:handle_abort=1:print_summary=1";
}
extern "C" const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }
extern "C" void __sanitizer_set_death_callback(void (*)(void)) __attribute__((weak));

namespace rt::fuzz {
namespace {

std::vector<Target>& registry() {
  static std::vector<Target> r;
  return r;
}

// The input being run, for the artifact written on failure (also from signal handlers).
const std::string* g_input = nullptr;
char g_artifact[4096] = "fuzz-failure.input";
const char* g_target = "?";
long g_timeout_ms = 0;

void write_all(int fd, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w <= 0) return;
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

void say(const char* s) { write_all(2, s, std::strlen(s)); }

// Async-signal-safe.
void save_input() {
  if (!g_input) return;
  const int fd = ::open(g_artifact, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return;
  write_all(fd, g_input->data(), g_input->size());
  ::close(fd);
  say("rt_fuzz: failing input saved to ");
  say(g_artifact);
  say("\n");
}

void on_timeout(int) {
  say("rt_fuzz: FAILURE (");
  say(g_target);
  say("): an input ran past the per-input timeout (hang or quadratic work)\n");
  save_input();
  ::_exit(1);
}

void on_crash(int sig) {
  say("rt_fuzz: FAILURE: crashed on a signal\n");
  save_input();
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void arm_timer(bool on) {
  itimerval t{};
  if (on) {
    t.it_value.tv_sec = g_timeout_ms / 1000;
    t.it_value.tv_usec = (g_timeout_ms % 1000) * 1000;
  }
  ::setitimer(ITIMER_REAL, &t, nullptr);
}

struct Stats {
  long runs = 0, accepted = 0, rejected = 0;
};

void run_one(const Target& t, const std::string& input, Stats& stats) {
  g_input = &input;
  ++stats.runs;
  arm_timer(true);
  try {
    t.run(input);
    ++stats.accepted;
  } catch (const InputError& e) {
    const std::string what = e.what();
    check(!what.empty() && what.find('\n') == std::string::npos && what.find('\r') == std::string::npos,
          "InputError is not one line: " + what);
    check(!e.location().empty() || what.find("fuzz") != std::string::npos,
          "InputError without a location (file:line, file@offset or key): " + what);
    ++stats.rejected;
  } catch (const std::exception& e) {
    fail(std::string("exception other than InputError (") + typeid(e).name() + "): " + e.what());
  } catch (...) {
    fail("a non-std exception escaped");
  }
  arm_timer(false);
  g_input = nullptr;
}

int usage() {
  std::fprintf(stderr,
               "usage: rt_fuzz TARGET [--seconds S] [--runs N] [--seed N] [--timeout-ms T] [--source DIR]\n"
               "               [--shared DIR] [--artifacts DIR]   (mutation run)\n"
               "       rt_fuzz TARGET FILE...                     (replay inputs)\n"
               "       rt_fuzz --list\n");
  return 2;
}

}  // namespace

bool register_target(Target target) {
  registry().push_back(std::move(target));
  return true;
}

const std::vector<Target>& targets() { return registry(); }

void fail(const std::string& what) {
  std::fprintf(stderr, "rt_fuzz: FAILURE (%s): %s\n", g_target, what.c_str());
  save_input();
  std::fflush(stderr);
  std::_Exit(1);
}

std::string read_or_empty(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<Seed> seed_files(const std::string& dir, const std::vector<std::string>& extensions,
                             std::size_t max_bytes, bool recursive) {
  namespace fs = std::filesystem;
  std::vector<Seed> out;
  std::error_code ec;
  if (dir.empty() || !fs::is_directory(dir, ec)) return out;
  std::vector<std::string> paths;
  auto consider = [&](const fs::directory_entry& e) {
    if (!e.is_regular_file(ec)) return;
    const std::string p = e.path().string();
    bool ok = extensions.empty();
    for (const std::string& x : extensions)
      ok = ok || (p.size() >= x.size() && p.compare(p.size() - x.size(), x.size(), x) == 0);
    if (ok) paths.push_back(p);
  };
  if (recursive) {
    for (const auto& e : fs::recursive_directory_iterator(dir, ec)) consider(e);
  } else {
    for (const auto& e : fs::directory_iterator(dir, ec)) consider(e);
  }
  std::sort(paths.begin(), paths.end());
  for (const std::string& p : paths) {
    std::string bytes = read_or_empty(p);
    if (bytes.size() > max_bytes) bytes.resize(max_bytes);
    out.push_back({p, std::move(bytes)});
  }
  return out;
}

}  // namespace rt::fuzz

int main(int argc, char** argv) {
  using namespace rt::fuzz;
  namespace fs = std::filesystem;
  if (argc < 2) return usage();
  const std::string name = argv[1];
  if (name == "--list") {
    for (const Target& t : targets()) std::printf("%s\n", t.name.c_str());
    return 0;
  }
  const Target* target = nullptr;
  for (const Target& t : targets())
    if (t.name == name) target = &t;
  if (!target) {
    std::fprintf(stderr, "rt_fuzz: unknown target '%s' (--list shows them)\n", name.c_str());
    return 2;
  }
  double seconds = 10;
  long max_runs = -1;
  unsigned long long seed = 20261202;
  long timeout_ms = 5000;
  SeedDirs dirs{RT_FUZZ_SOURCE_DIR, RT_FUZZ_SOURCE_DIR "/../shared/data"};
  std::string artifacts = ".";
  std::vector<std::string> replay;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage();
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--seconds") seconds = std::atof(value().c_str());
    else if (a == "--runs") max_runs = std::atol(value().c_str());
    else if (a == "--seed") seed = std::strtoull(value().c_str(), nullptr, 10);
    else if (a == "--timeout-ms") timeout_ms = std::atol(value().c_str());
    else if (a == "--source") dirs.source = value();
    else if (a == "--shared") dirs.shared = value();
    else if (a == "--artifacts") artifacts = value();
    else if (a.rfind("--", 0) == 0) return usage();
    else replay.push_back(a);
  }
  std::error_code ec;
  if (!fs::is_directory(dirs.shared, ec)) dirs.shared.clear();
  fs::create_directories(artifacts, ec);
  g_target = target->name.c_str();
  g_timeout_ms = timeout_ms;
  std::snprintf(g_artifact, sizeof g_artifact, "%s/fuzz-%s-failure.input", artifacts.c_str(), target->name.c_str());

  struct sigaction sa {};
  sa.sa_handler = on_timeout;
  sigaction(SIGALRM, &sa, nullptr);
  if (__sanitizer_set_death_callback) {
    __sanitizer_set_death_callback(save_input);  // the sanitizers report crashes themselves
  } else {
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::signal(sig, on_crash);
  }

  const fs::path scratch = fs::temp_directory_path() / ("rt_fuzz_" + target->name + "_" + std::to_string(::getpid()));
  fs::create_directories(scratch);
  if (target->setup) target->setup(scratch.string());

  Stats stats;
  const auto t0 = std::chrono::steady_clock::now();
  if (!replay.empty()) {
    for (const std::string& p : replay) run_one(*target, read_or_empty(p), stats);
  } else {
    std::vector<Seed> corpus = target->seeds(dirs);
    if (corpus.empty()) {
      std::fprintf(stderr, "rt_fuzz: target %s has no seeds\n", target->name.c_str());
      return 1;
    }
    const std::size_t num_seeds = corpus.size();
    for (const Seed& s : corpus) run_one(*target, s.bytes, stats);
    // Mutants that parse join the corpus (bounded): they carry valid structure further in, where
    // a mutant of a mutant reaches deeper code than a mutant of a seed.
    constexpr std::size_t kMaxGrown = 256;
    Rng rng(seed);
    std::string input;
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    while ((max_runs < 0 || stats.runs < max_runs) && elapsed() < seconds) {
      input = corpus[static_cast<std::size_t>(rng() % corpus.size())].bytes;
      if (!(target->mutate && rng() % 2 && target->mutate(input, rng))) mutate(input, rng, *target, corpus);
      const long accepted_before = stats.accepted;
      run_one(*target, input, stats);
      if (stats.accepted > accepted_before && rng() % 8 == 0) {
        if (corpus.size() < num_seeds + kMaxGrown) corpus.push_back({"grown", input});
        else corpus[num_seeds + rng() % kMaxGrown] = {"grown", input};
      }
    }
    std::printf("rt_fuzz %s: %zu seeds, %ld inputs in %.1f s (seed %llu): %ld parsed, %ld rejected with a located error\n",
                target->name.c_str(), num_seeds, stats.runs, elapsed(), seed, stats.accepted, stats.rejected);
    if (stats.rejected == 0 || stats.runs < 2 * static_cast<long>(num_seeds)) {
      std::fprintf(stderr, "rt_fuzz: FAILURE (%s): the run reached too little (no input rejected, or fewer mutants than seeds)\n",
                   target->name.c_str());
      return 1;
    }
  }
  if (!replay.empty())
    std::printf("rt_fuzz %s: %ld inputs replayed: %ld parsed, %ld rejected\n", target->name.c_str(), stats.runs,
                stats.accepted, stats.rejected);
  fs::remove_all(scratch, ec);
  return 0;
}
