#pragma once
/// Progress of a running batch, and its one-line renderings for a terminal (live bar) and for
/// logs (plain lines). The library only formats; the CLI prints.

#include <cstdint>
#include <string>
#include <vector>

#include "retarget/batch/batch_clip.hpp"
#include "retarget/batch/batch_summary.hpp"

namespace rt {

/// Source frame count of a motion file from its header only, for progress estimates: the
/// "Frames:" line after MOTION of a BVH file, or last - first + 1 from a C3D header (byte order
/// from the processor byte of the parameter section). 0 when unknown (unreadable, malformed, a
/// C3D whose 16-bit last-frame word saturated, another format): the worker reports bad input,
/// this only estimates.
std::int64_t probe_source_frames(const std::string& path);

/// The progress weight of each clip, in source frames: `probed[k]` where > 0; otherwise its input
/// bytes times the frames per byte of the clips that were probed (or plain bytes when none was).
/// Every weight is >= 1.
std::vector<double> source_frame_weights(const std::vector<BatchClip>& clips, const std::vector<std::int64_t>& probed);

struct BatchProgress {
  int total = 0;      ///< clips in this batch (shard)
  int done = 0;       ///< finished successfully (ok) or skipped
  int skipped = 0;    ///< of `done`, skipped as up to date
  int failed = 0;     ///< finished with any failure (check-failed included)
  int running = 0;    ///< workers running now
  double elapsed_s = 0;  ///< [s] since the batch started
  /// Source frames (source_frame_weights) of the clips to convert (not the skipped ones), and of
  /// those finished so far, failed or not.
  double frames_total = 0, frames_done = 0;
  /// Clips converted (finished, not skipped or cancelled) per minute of wall time since the first
  /// worker started; < 0 before the first one finished.
  double clips_per_min = -1;
  /// [s] estimated time left; < 0 when unknown yet (nothing converted). The source frames still to
  /// convert (running clips in full) at the rate (source frames per second of wall time) seen so far.
  double eta_s = -1;

  int remaining() const { return total - done - failed; }
};

/// "1h02m", "3m12s", "45s"; "?" for negative values.
std::string format_duration(double seconds);

/// "3.4 clips/min" (one decimal below 10, none above); "? clips/min" for negative values.
std::string format_clip_rate(double clips_per_min);

/// Live bar for a terminal of `width` columns (no newline):
///   "[####......] 12/40  ok 10 (skipped 3)  failed 2  left 28  running 2  3.4 clips/min  ETA 3m12s"
std::string format_progress_bar(const BatchProgress& progress, int width);

/// Plain line for a finished clip (no newline):
///   "[12/40] ok          walks/walk01  3.2 s"
///   "[13/40] bad-input   broken  broken.bvh:3:1: expected HIERARCHY"
std::string format_clip_line(const ClipResult& clip, int finished, int total);

/// format_clip_line for a log (not a terminal), with the running ETA after it:
///   "[12/40] ok          walks/walk01  3.2 s  check passed  ETA 3m12s"
/// ("ETA ?" before the first conversion finished, "ETA 0s" for the last clip).
std::string format_clip_log_line(const ClipResult& clip, const BatchProgress& progress);

}  // namespace rt
