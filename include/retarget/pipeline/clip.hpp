#pragma once
/// Clip: everything that flows through the pass pipeline for one input (design.md §2). Passes
/// read what earlier passes produced and fill their own part; nothing here is shared between clips.

#include <array>
#include <string>
#include <vector>

#include "retarget/core/diagnostics.hpp"
#include "retarget/core/types.hpp"
#include "retarget/motion/human_motion.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

/// Human landmarks scaled to the robot (output of `scale`), same layout as HumanMotion's tracks.
struct LandmarkTargets {
  std::array<LandmarkTrack, kLandmarkCount> tracks;  ///< W, metres, robot proportions
  /// Per-landmark scale factors actually applied (1 where not scaled), for the summary.
  std::array<double, kLandmarkCount> scale{};
  double height_scale = 1;  ///< root height scale (robot leg length / human leg length)
  const LandmarkTrack& operator[](Landmark l) const { return tracks[static_cast<std::size_t>(index(l))]; }
  LandmarkTrack& operator[](Landmark l) { return tracks[static_cast<std::size_t>(index(l))]; }
};

/// Robot motion at the source rate (output of `ik`, edited by later passes; com-plan puts it on the
/// export grid, clip_rate.hpp).
struct RobotMotion {
  double fps = 0;
  MatX q;                      ///< nq x T generalised positions (robot_model.hpp convention)
  VecX landmark_error_m;       ///< per frame: weighted RMS landmark position error after IK [m]
  std::vector<int> worst_landmark;  ///< per frame: landmark index with the largest error
  MatX q_per_frame_ik;         ///< copy of q right after per-frame IK (jitter baseline, design.md §6)
  int num_frames() const { return static_cast<int>(q.cols()); }
};

/// Contact schedule at the robot motion's rate: per foot (0 left, 1 right) per frame, 1 = in contact.
struct ContactSchedule {
  std::array<std::vector<std::uint8_t>, 2> in_contact;
  bool empty() const { return in_contact[0].empty(); }
};

struct Clip {
  std::string name;              ///< output stem (source file name without extension)
  HumanMotion human;             ///< normalised source motion (parse)
  LandmarkTargets targets;       ///< scaled landmarks (scale)
  RobotMotion motion;            ///< robot motion at the source rate (ik, flat-contact, refine, ground); at the export rate after com-plan
  ContactSchedule contacts;      ///< (label-contacts)
  VecX flat_contact_offset;      ///< joint-angle differences added by flat-contact (nu), empty if not run
  Mat3X com_replanned_W;         ///< re-planned COM at the robot motion's rate (com-replan, com-plan), empty if not run
  Eigen::Matrix2Xd cop_predicted_W;  ///< predicted COP / planned ZMP at the robot motion's rate (com-replan, com-plan)
  Reference reference;           ///< the output at the export rate (resample)
  /// Standing frames added before the source's first and after its last frame (robot motion's rate;
  /// com-plan's lead-in and lead-out, clip_ends.hpp): the source's time t is the robot motion's
  /// t + lead_in_frames / motion.fps.
  int lead_in_frames = 0;
  int lead_out_frames = 0;
  Diagnostics diagnostics;       ///< warnings from all passes
};

}  // namespace rt
