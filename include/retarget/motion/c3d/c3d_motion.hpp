#pragma once
/// C3D marker files -> HumanMotion (design.md §3.1).
///
/// Steps: decode the file (formats/c3d), scale markers to metres (POINT:UNITS, default mm, or
/// options.source_units), recognise the marker set and compute the landmarks
/// (marker_set_profiles.hpp, or the user's marker map in options.profile_path), rotate the file's
/// up axis to +Z (detected from the head/trunk-to-feet direction, or options.up_axis), trim the
/// leading and trailing frames where the pelvis or a leg joint is not in view, interpolate gaps of
/// up to options.max_gap_s (longer gaps stay Missing and are reported with their file frame
/// numbers), and finally rt::normalize_motion. Everything noteworthy goes to
/// HumanMotion::diagnostics; MotionSourceInfo::details holds the file facts ("markers",
/// "analog_channels", "first_frame", "events", "processor", "trimmed_leading_frames", ...).

#include <string>

#include "formats/c3d/c3d_file.hpp"
#include "retarget/motion/human_motion.hpp"
#include "retarget/motion/load_motion.hpp"

namespace rt {

/// Loads a C3D file. Throws InputError (with a `file@0xOFFSET [GROUP:PARAM]` location for
/// malformed files) when the file cannot be decoded or its markers give no pelvis and feet.
HumanMotion load_c3d_motion(const std::string& path, const MotionLoadOptions& options);

/// The same conversion from an already decoded file; `reader_diagnostics` (the reader's
/// warnings) are copied into the result first.
HumanMotion c3d_to_motion(const c3d::C3dFile& file, const MotionLoadOptions& options,
                          const Diagnostics& reader_diagnostics = {});

}  // namespace rt
