#pragma once
/// Bounds on the rates and durations that a clip, a reference or an option may claim
/// (design.md Sec. 8: no hang, no huge allocation). Everything sized from a rate or a duration —
/// resampled frames, smoothing kernels, simulated steps — is checked against these first, so a
/// hostile `Frame Time: 1000` or `"fps": 0.001` is a located one-line error, not gigabytes.

#include <string>

namespace rt {

/// [Hz] Frame rates of motion capture and references: 1 Hz to 10 kHz (mocap is 24-2000 Hz).
inline constexpr double kMinFrameRate_hz = 1.0;
inline constexpr double kMaxFrameRate_hz = 10000.0;

/// [Hz] The output rate of a reference (the resample pass, `--fps`): up to the simulation's 1 kHz.
inline constexpr double kMaxOutputFrameRate_hz = 1000.0;

/// [s] The longest clip or reference: one hour (clips, played at any time scale, and references).
inline constexpr double kMaxClipDuration_s = 3600.0;

/// "between 1 and 10000 Hz" for a range [lo, hi] with a unit: how messages and --help state a range.
std::string range_in_words(double lo, double hi, const std::string& unit);

/// Throws InputError(location, "<what> is <rate> Hz, not between <lo> and <hi> Hz")
/// unless `rate_hz` is finite and within [lo_hz, hi_hz].
void check_frame_rate(double rate_hz, const std::string& location, const std::string& what,
                      double lo_hz = kMinFrameRate_hz, double hi_hz = kMaxFrameRate_hz);

/// Throws InputError(location, "<what> lasts <d> s, more than the limit of 3600 s (1 hour)";
/// `what` names the clip with its frames and rate, e.g. "the clip (105 frames at 0.01 Hz)"))
/// unless `duration_s` is finite and at most kMaxClipDuration_s.
void check_clip_duration(double duration_s, const std::string& location, const std::string& what);

}  // namespace rt
