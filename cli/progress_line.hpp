#pragma once
/// A live status line on stderr for long commands (README "Progress"): shown only when stderr is a
/// terminal and the work has run longer than a delay, redrawn in place at most 4 times a second
/// with the elapsed time and, once the work reports how far it is, an ETA; erased when the work
/// ends. Library code never prints: it reports through callbacks that the commands forward here.

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace rt::cli {

/// [ms] Delay before the line appears: 2000, or $RETARGET_PROGRESS_DELAY_MS when set to a number.
std::chrono::milliseconds progress_delay();

/// One drawing of the line: "<status>  <elapsed> elapsed, ETA <eta>" (no ETA while `eta_s` < 0),
/// cut to `width` columns when `width` > 0 so that the terminal never wraps it.
std::string format_progress_line(const std::string& status, double elapsed_s, double eta_s, int width);

class ProgressLine {
 public:
  /// `delay`: nothing is shown for work that ends sooner. `fd`: where the line goes (stderr); it
  /// is drawn only when `fd` is a terminal.
  explicit ProgressLine(std::chrono::milliseconds delay = progress_delay(), int fd = 2);
  ~ProgressLine();  ///< stop()
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  /// The status text ("converting walk.bvh: pass 4/9 ik"); the fraction done is unknown.
  void set(std::string status);
  /// The status text and the fraction of the whole work done so far, in [0, 1] (simulated clip
  /// time / clip duration): the ETA assumes the rest goes at the rate measured since the first
  /// fraction reported. A fraction below the previous one starts a new measurement.
  void set(std::string status, double fraction_done) { set(std::move(status), fraction_done, fraction_done); }
  /// A step that starts now and takes the whole work from `fraction_begin` to `fraction_end` (a
  /// pipeline pass, weighted by its usual cost): the ETA counts the step down at the rate measured
  /// before it (once it runs past that, half the time spent in it), then the rest at that rate.
  void set(std::string status, double fraction_begin, double fraction_end);
  /// Erases the line (if shown) and ends the redraw thread; idempotent.
  void stop();

 private:
  void loop();
  double eta_s_locked(std::chrono::steady_clock::time_point now) const;

  std::chrono::steady_clock::time_point start_;
  std::chrono::milliseconds delay_;
  int fd_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string status_;
  // The current step [begin_, end_] of the whole and when it started; the rate is measured from
  // the first report (first_, first_time_) to the current step's start. begin_ < 0: no report yet.
  double begin_ = -1, end_ = -1, first_ = -1;
  std::chrono::steady_clock::time_point begin_time_, first_time_;
  bool stopping_ = false, shown_ = false, enabled_ = false;
  std::thread thread_;
};

/// A DynamicsCheckOptions::progress callback that shows "<what>: 3.2/10.0 s of the clip simulated"
/// on `line` (which must outlive the check).
std::function<void(double done_s, double total_s)> simulation_progress(ProgressLine& line, std::string what);

}  // namespace rt::cli
