#pragma once
/// A live status line on stderr for long commands: shown only when stderr is a terminal and the
/// work has run longer than a delay, redrawn in place, erased when the work ends.

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace rt::cli {

class ProgressLine {
 public:
  /// `delay`: nothing is shown for work that ends sooner.
  explicit ProgressLine(std::chrono::milliseconds delay = std::chrono::milliseconds(2000));
  ~ProgressLine();  ///< stop()
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  /// The text after the elapsed time ("pass 4/9 ik").
  void set(std::string status);
  /// Erases the line (if shown) and ends the redraw thread; idempotent.
  void stop();

 private:
  void loop();

  std::chrono::steady_clock::time_point start_;
  std::chrono::milliseconds delay_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string status_;
  bool stopping_ = false, shown_ = false, enabled_ = false;
  std::thread thread_;
};

}  // namespace rt::cli
