#include "retarget/core/limits.hpp"

#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

std::string range_in_words(double lo, double hi, const std::string& unit) {
  const std::string u = unit.empty() ? "" : " " + unit;
  return format("between %.10g and %.10g%s", lo, hi, u.c_str());
}

void check_frame_rate(double rate_hz, const std::string& location, const std::string& what, double lo_hz,
                      double hi_hz) {
  if (std::isfinite(rate_hz) && rate_hz >= lo_hz && rate_hz <= hi_hz) return;
  throw InputError(location, format("%s is %.6g Hz, not %s", what.c_str(), rate_hz,
                                    range_in_words(lo_hz, hi_hz, "Hz").c_str()));
}

void check_clip_duration(double duration_s, const std::string& location, const std::string& what) {
  if (std::isfinite(duration_s) && duration_s <= kMaxClipDuration_s) return;
  throw InputError(location, format("%s lasts %.6g s, more than the limit of %g s (1 hour)", what.c_str(), duration_s,
                                    kMaxClipDuration_s));
}

}  // namespace rt
