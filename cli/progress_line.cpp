#include "cli/progress_line.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>

#include "retarget/batch/batch_progress.hpp"
#include "retarget/core/strings.hpp"

namespace rt::cli {

namespace {

constexpr auto kRedrawPeriod = std::chrono::milliseconds(250);
// The ETA is shown once this much of the work was measured since the first report: earlier
// estimates swing too far to help.
constexpr double kMinMeasuredFraction = 0.02;

int terminal_columns(int fd) {
  winsize w{};
  return ::ioctl(fd, TIOCGWINSZ, &w) == 0 ? static_cast<int>(w.ws_col) : 0;
}

void write_all(int fd, const std::string& s) {
  std::size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
    if (n <= 0) return;  // a closed terminal: the line is cosmetic
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

std::chrono::milliseconds progress_delay() {
  if (const char* v = std::getenv("RETARGET_PROGRESS_DELAY_MS")) {
    char* end = nullptr;
    const long ms = std::strtol(v, &end, 10);
    if (end != v && *end == '\0' && ms >= 0) return std::chrono::milliseconds(ms);
  }
  return std::chrono::milliseconds(2000);
}

std::string format_progress_line(const std::string& status, double elapsed_s, double eta_s, int width) {
  std::string line = status + "  " + format_duration(elapsed_s) + " elapsed";
  if (eta_s >= 0) line += ", ETA " + format_duration(eta_s);
  if (width > 1 && static_cast<int>(line.size()) >= width) line.resize(static_cast<std::size_t>(width - 1));
  return line;
}

ProgressLine::ProgressLine(std::chrono::milliseconds delay, int fd)
    : start_(std::chrono::steady_clock::now()), delay_(delay), fd_(fd), enabled_(::isatty(fd) == 1) {
  if (enabled_) thread_ = std::thread([this] { loop(); });
}

ProgressLine::~ProgressLine() { stop(); }

void ProgressLine::set(std::string status) {
  const std::lock_guard<std::mutex> lock(mutex_);
  status_ = std::move(status);
}

void ProgressLine::set(std::string status, double fraction_begin, double fraction_end) {
  const auto now = std::chrono::steady_clock::now();
  const std::lock_guard<std::mutex> lock(mutex_);
  status_ = std::move(status);
  fraction_begin = std::clamp(fraction_begin, 0.0, 1.0);
  if (first_ < 0 || fraction_begin < begin_) first_ = fraction_begin, first_time_ = now;
  begin_ = fraction_begin;
  end_ = std::clamp(fraction_end, fraction_begin, 1.0);
  begin_time_ = now;
}

double ProgressLine::eta_s_locked(std::chrono::steady_clock::time_point now) const {
  if (begin_ < 0 || begin_ - first_ < kMinMeasuredFraction) return -1;
  const double rate = (begin_ - first_) / std::chrono::duration<double>(begin_time_ - first_time_).count();  // [1/s]
  if (!(rate > 0)) return -1;
  // A step running past its predicted time has an unknown rest: take half the time already spent
  // in it (rather than 0 s) as the estimate.
  const double in_step_s = std::chrono::duration<double>(now - begin_time_).count();
  const double step_left_s = end_ > begin_ ? std::max((end_ - begin_) / rate - in_step_s, 0.5 * in_step_s) : 0.0;
  return step_left_s + (1 - end_) / rate;
}

void ProgressLine::stop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (shown_) write_all(fd_, "\r\033[K");
}

void ProgressLine::loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (wake_.wait_for(lock, delay_, [this] { return stopping_; })) return;
  while (!stopping_) {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    write_all(fd_, "\r\033[K" + format_progress_line(status_, elapsed, eta_s_locked(now), terminal_columns(fd_)));
    shown_ = true;
    wake_.wait_for(lock, kRedrawPeriod, [this] { return stopping_; });
  }
}

std::function<void(double, double)> simulation_progress(ProgressLine& line, std::string what) {
  return [&line, what = std::move(what)](double done_s, double total_s) {
    line.set(format("%s: %.1f/%.1f s of the clip simulated", what.c_str(), done_s, total_s), total_s > 0 ? done_s / total_s : 1.0);
  };
}

}  // namespace rt::cli
