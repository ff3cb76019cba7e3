#pragma once
/// Progress of a running batch, and its one-line renderings for a terminal (live bar) and for
/// logs (plain lines). The library only formats; the CLI prints.

#include <string>

#include "retarget/batch/batch_summary.hpp"

namespace rt {

struct BatchProgress {
  int total = 0;      ///< clips in this batch (shard)
  int done = 0;       ///< finished successfully (ok) or skipped
  int skipped = 0;    ///< of `done`, skipped as up to date
  int failed = 0;     ///< finished with any failure (check-failed included)
  int running = 0;    ///< workers running now
  double elapsed_s = 0;  ///< [s] since the batch started
  /// [s] estimated time left; < 0 when unknown yet (nothing converted). Estimated from the input
  /// bytes still to convert at the rate (bytes per second of wall time) seen so far.
  double eta_s = -1;

  int remaining() const { return total - done - failed; }
};

/// "1h02m", "3m12s", "45s"; "?" for negative values.
std::string format_duration(double seconds);

/// Live bar for a terminal of `width` columns (no newline):
///   "[#########.........] 12/40  ok 10 (skipped 3)  failed 2  left 28  running 2  ETA 3m12s"
std::string format_progress_bar(const BatchProgress& progress, int width);

/// Plain line for a finished clip (no newline):
///   "[12/40] ok          walks/walk01  3.2 s"
///   "[13/40] bad-input   broken  broken.bvh:3:1: expected HIERARCHY"
std::string format_clip_line(const ClipResult& clip, int finished, int total);

}  // namespace rt
