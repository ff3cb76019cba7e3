#include "cli/progress_line.hpp"

#include <unistd.h>

#include <cstdio>

namespace rt::cli {

ProgressLine::ProgressLine(std::chrono::milliseconds delay)
    : start_(std::chrono::steady_clock::now()), delay_(delay), enabled_(isatty(STDERR_FILENO) == 1) {
  if (enabled_) thread_ = std::thread([this] { loop(); });
}

ProgressLine::~ProgressLine() { stop(); }

void ProgressLine::set(std::string status) {
  const std::lock_guard<std::mutex> lock(mutex_);
  status_ = std::move(status);
}

void ProgressLine::stop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (shown_) std::fputs("\r\033[K", stderr);
}

void ProgressLine::loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (wake_.wait_for(lock, delay_, [this] { return stopping_; })) return;
  while (!stopping_) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::fprintf(stderr, "\r\033[K%.0f s  %s", elapsed, status_.c_str());
    std::fflush(stderr);
    shown_ = true;
    wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stopping_; });
  }
}

}  // namespace rt::cli
