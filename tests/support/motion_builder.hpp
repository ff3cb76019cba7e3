#pragma once
/// Building synthetic human motions in tests.

#include "retarget/motion/human_motion.hpp"

namespace rt::test {

/// Landmark `l` of `motion` made present: num_frames samples, all measured, positions zero (the
/// caller fills p_W).
inline LandmarkTrack& measured_track(HumanMotion& motion, Landmark l) {
  LandmarkTrack& t = motion[l];
  t.present = true;
  t.p_W.setZero(3, motion.num_frames);
  t.state.assign(static_cast<std::size_t>(motion.num_frames), SampleState::Measured);
  return t;
}

}  // namespace rt::test
