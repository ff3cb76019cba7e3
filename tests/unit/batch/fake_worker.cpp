// A stand-in for the `retarget` binary in batch tests: run as `fake_worker convert CLIP ...` like a
// real worker. When CLIP's first line is a directive, it misbehaves as told; otherwise it execs the
// real retarget binary with the same arguments, so ordinary clips are converted for real.
//
// Directives (first line of the clip file):
//   FAKE-WORKER: crash                 dies from SIGSEGV
//   FAKE-WORKER: hang                  sleeps forever (for the timeout)
//   FAKE-WORKER: hang-with-child FILE  forks a child that sleeps forever, writes its pid to FILE,
//                                      then sleeps forever (the timeout must kill the whole group)
//   FAKE-WORKER: oom                   allocates until allocation fails (needs an address-space
//                                      limit), then reports it like retarget's main() does
//   FAKE-WORKER: sleep S               sleeps S seconds, then exits 0 without writing anything
//   FAKE-WORKER: exit N TEXT           prints "error: TEXT" to stderr and exits with status N

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

[[noreturn]] void sleep_forever() {
  while (true) ::pause();
}

int run_directive(const std::string& directive) {
  std::istringstream in(directive);
  std::string action;
  in >> action;
  if (action == "crash") {
    ::signal(SIGSEGV, SIG_DFL);  // bypass sanitizers' handlers: a real signal death
    ::raise(SIGSEGV);
    return 99;
  }
  if (action == "hang") sleep_forever();
  if (action == "hang-with-child") {
    std::string file;
    in >> file;
    const pid_t child = ::fork();
    if (child == 0) sleep_forever();
    std::ofstream(file) << child << "\n";
    sleep_forever();
  }
  if (action == "oom") {
    try {
      std::vector<std::unique_ptr<char[]>> blocks;
      for (int i = 0; i < 1 << 20; ++i) {  // at most 64 TiB: stops at the limit long before
        blocks.emplace_back(new char[64 << 20]);
        std::memset(blocks.back().get(), 1, 64 << 20);
      }
    } catch (const std::exception& e) {
      std::cerr << "internal error: " << e.what() << "\n";
      return 3;
    }
    return 0;
  }
  if (action == "sleep") {
    double s = 0;
    in >> s;
    std::this_thread::sleep_for(std::chrono::duration<double>(s));
    return 0;
  }
  if (action == "exit") {
    int code = 0;
    in >> code;
    std::string text;
    std::getline(in, text);
    std::cerr << "error:" << text << "\n";
    return code;
  }
  std::cerr << "fake_worker: unknown directive '" << directive << "'\n";
  return 64;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 3 && std::string(argv[1]) == "convert") {
    std::ifstream clip(argv[2]);
    std::string first;
    if (clip && std::getline(clip, first) && first.rfind("FAKE-WORKER:", 0) == 0) return run_directive(first.substr(12));
  }
  std::vector<char*> args(argv, argv + argc);
  args.push_back(nullptr);
  static char real[] = RT_REAL_RETARGET;
  args[0] = real;
  ::execv(real, args.data());
  std::perror("fake_worker: cannot exec the real retarget");
  return 127;
}
