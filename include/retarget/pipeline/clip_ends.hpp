#pragma once
/// Held ends of a clip: a standing lead-in before its first frame and a lead-out after its last,
/// each a copy of that end's frame (robot pose, contact labels, landmark targets), for a pass that
/// must bring a clip which starts or ends moving to rest (com-plan, issue 14). Every per-frame
/// array at the robot motion's rate that later passes read grows alike; the source motion
/// (`human`) is left as parsed.

#include "retarget/pipeline/clip.hpp"

namespace rt {

/// Prepends `before` copies of frame 0 and appends `after` copies of the last frame to the robot
/// motion, the contact schedule, the landmark targets and (when present) the re-planned COM and
/// predicted COP, and adds them to Clip::lead_in_frames / lead_out_frames.
void hold_clip_ends(Clip& clip, int before, int after);

}  // namespace rt
