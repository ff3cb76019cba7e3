// core/limits.hpp: the bounds on rates and durations, and their messages (issue 18).

#include <gtest/gtest.h>

#include <limits>

#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"

namespace rt {
namespace {

std::string message_of(double rate) {
  try {
    check_frame_rate(rate, "clip.bvh:7", "the frame rate");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Limits, FrameRateRangeInWords) {
  EXPECT_EQ(message_of(30), "");
  EXPECT_EQ(message_of(1), "");
  EXPECT_EQ(message_of(10000), "");
  EXPECT_EQ(message_of(0.001), "clip.bvh:7: the frame rate is 0.001 Hz, not between 1 and 10000 Hz");
  // A huge value is short, not a 309-digit number.
  EXPECT_EQ(message_of(1e300), "clip.bvh:7: the frame rate is 1e+300 Hz, not between 1 and 10000 Hz");
  for (double bad : {-1.0, 0.0, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()})
    EXPECT_FALSE(message_of(bad).empty()) << bad;
  EXPECT_THROW(check_frame_rate(2000, "--fps", "the output rate", kMinFrameRate_hz, kMaxOutputFrameRate_hz), InputError);
}

TEST(Limits, ClipDuration) {
  EXPECT_NO_THROW(check_clip_duration(3600, "x", "the clip"));
  EXPECT_THROW(check_clip_duration(3600.5, "x", "the clip"), InputError);
  EXPECT_THROW(check_clip_duration(std::numeric_limits<double>::infinity(), "x", "the clip"), InputError);
  EXPECT_THROW(check_clip_duration(std::numeric_limits<double>::quiet_NaN(), "x", "the clip"), InputError);
}

}  // namespace
}  // namespace rt
