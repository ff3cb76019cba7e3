#include "retarget/motion/bvh/bvh_motion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "formats/bvh/bvh_kinematics.hpp"
#include "formats/bvh/bvh_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/bvh/skeleton_profile.hpp"
#include "retarget/motion/normalize.hpp"

namespace rt {

namespace {

// [m] skeleton size (thigh + shank + pelvis-to-head segment lengths) of an adult with the
// built-in profiles' landmark choices; unit detection picks the unit that brings the clip's size
// closest to it (in log scale). The shared clips measure 1.28-1.60 m. Neighbouring candidate
// units differ by >= 2.2x, so sizes within ~1.49x of the reference (0.94-2.09 m, i.e. adults)
// are classified correctly; children or scaled rigs need --source-units.
constexpr double kReferenceSize_m = 1.40;

// Stature estimate: the head joint (skull base / top of the neck in every built-in convention)
// sits at about 0.87 of stature (head height ~0.13 H; Drillis, Contini & Bluestein 1964). Head End
// Sites are not used because several conventions have none or a zero-length one (Daz, Bandai,
// iClone) and CMU's stops short of the crown.
constexpr double kHeadJointStatureRatio = 0.87;

// [m] landmarks farther than this from the file origin are rejected: no capture volume is this
// large, and it keeps every later computation (norms, floor, alignment) far from overflow.
constexpr double kMaxCoordinate_m = 1e6;

// Synthetic T-pose detection (see is_tpose_like / count_synthetic_tpose_frames).
constexpr int kMaxTposeFrames = 10;           // longest synthetic lead-in we look for
constexpr double kTposeHoldJump_m = 0.01;     // frames of one T-pose hold differ by less than this
constexpr double kTposeMinJump_m = 0.15;      // the jump into the real data is at least this ...
constexpr double kTposeJumpFactor = 8.0;      // ... and this many times the clip's median motion

struct Track {
  bool present = false;
  Mat3X p;  // 3 x frames
};
using Tracks = std::array<Track, kLandmarkCount>;

const Track& at(const Tracks& t, Landmark l) { return t[static_cast<std::size_t>(index(l))]; }
Track& at(Tracks& t, Landmark l) { return t[static_cast<std::size_t>(index(l))]; }
Vec3 pos(const Tracks& t, Landmark l, int f) { return at(t, l).p.col(f); }

// Landmark positions of every frame, in the file's frame and units.
Tracks extract_landmarks(const BvhFile& file, const SkeletonBinding& binding) {
  std::vector<int> seeds;
  for (const LandmarkSource& s : binding.sources)
    if (s.available()) seeds.push_back(s.joint);
  const std::vector<char> mask = bvh_ancestor_closure(file, seeds);

  Tracks tracks;
  for (Landmark l : all_landmarks()) {
    Track& t = at(tracks, l);
    t.present = binding.has(l);
    if (t.present) t.p.resize(3, file.num_frames);
  }
  const auto L = [](Landmark l) { return static_cast<std::size_t>(index(l)); };
  BvhPose pose;
  for (int f = 0; f < file.num_frames; ++f) {
    bvh_forward_kinematics(file, f, pose, &mask);
    for (Landmark l : all_landmarks()) {
      Track& t = tracks[L(l)];
      if (!t.present || (l == Landmark::Pelvis && binding.pelvis_from_hips)) continue;
      const LandmarkSource& s = binding.sources[L(l)];
      switch (s.point) {
        case JointPoint::Joint: t.p.col(f) = pose.p_F_joint.col(s.joint); break;
        case JointPoint::EndSite: t.p.col(f) = pose.p_F_end_site.col(s.end_site); break;
        case JointPoint::Midpoint:
          t.p.col(f) = 0.5 * (pose.p_F_joint.col(s.joint) + pose.p_F_end_site.col(s.end_site));
          break;
      }
    }
    if (binding.pelvis_from_hips && at(tracks, Landmark::Pelvis).present)
      at(tracks, Landmark::Pelvis).p.col(f) =
          0.5 * (at(tracks, Landmark::LeftHip).p.col(f) + at(tracks, Landmark::RightHip).p.col(f));
  }

  // Finite channel values can still overflow in FK (e.g. positions of 1e308).
  for (Landmark l : all_landmarks()) {
    const Track& t = at(tracks, l);
    if (!t.present || t.p.allFinite()) continue;
    for (int f = 0; f < file.num_frames; ++f) {
      if (t.p.col(f).allFinite()) continue;
      const LandmarkSource& s = binding.sources[L(l)];
      const int j = s.available() ? s.joint : binding.sources[L(Landmark::LeftHip)].joint;
      throw InputError(file.name + " frame " + std::to_string(f) + " joint " + file.joints[static_cast<std::size_t>(j)].name,
                       "forward kinematics gives a non-finite position (channel values too large)");
    }
  }
  return tracks;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Pose-independent size of the skeleton [file units]: mean thigh + mean shank + pelvis-to-head.
double skeleton_size_at(const Tracks& t, int f) {
  using L = Landmark;
  const double legs = 0.5 * ((pos(t, L::LeftKnee, f) - pos(t, L::LeftHip, f)).norm() +
                             (pos(t, L::LeftAnkle, f) - pos(t, L::LeftKnee, f)).norm() +
                             (pos(t, L::RightKnee, f) - pos(t, L::RightHip, f)).norm() +
                             (pos(t, L::RightAnkle, f) - pos(t, L::RightKnee, f)).norm());
  return legs + (pos(t, L::Head, f) - pos(t, L::Pelvis, f)).norm();
}

// Median size over a few frames spread over the clip (position channels on non-root joints can
// make segment lengths vary).
double skeleton_size(const Tracks& t, int frames) {
  std::vector<double> sizes;
  const int samples = std::min(frames, 9);
  for (int i = 0; i < samples; ++i) sizes.push_back(skeleton_size_at(t, static_cast<int>((static_cast<long long>(i) * frames) / samples)));
  return median(std::move(sizes));
}

struct UnitGuess {
  std::string name;
  double metres_per_unit;
};

UnitGuess detect_units(double size_file_units) {
  static constexpr const char* kCandidates[] = {"m", "cm", "mm", "inch", "cmu"};
  UnitGuess best{"m", 1.0};
  double best_error = INFINITY;
  for (const char* c : kCandidates) {
    const double mpu = metres_per_unit(c);
    const double error = std::abs(std::log(size_file_units * mpu / kReferenceSize_m));
    if (error < best_error) best_error = error, best = {c, mpu};
  }
  return best;
}

struct UpGuess {
  char axis = 'y';
  bool negative = false;
  double confidence = 0;  // |component along the axis| / |mean direction|
};

// Up = the file axis closest to the mean direction from the ankles' midpoint to the head.
UpGuess detect_up_axis(const Tracks& t, int frames) {
  using L = Landmark;
  Vec3 sum = Vec3::Zero();
  for (int f = 0; f < frames; ++f) {
    const Vec3 d = pos(t, L::Head, f) - 0.5 * (pos(t, L::LeftAnkle, f) + pos(t, L::RightAnkle, f));
    const double n = d.norm();
    if (n > 0) sum += d / n;
  }
  UpGuess g;
  const double norm = sum.norm();
  if (!(norm > 0)) return g;
  Eigen::Index k = 0;
  sum.cwiseAbs().maxCoeff(&k);
  g.axis = static_cast<char>('x' + k);
  g.negative = sum[k] < 0;
  g.confidence = std::abs(sum[k]) / norm;
  return g;
}

// Arms straight and horizontal, pointing away from each other (metres, Z up).
bool is_tpose_like(const Tracks& t, int f) {
  using L = Landmark;
  double chain = (pos(t, L::LeftShoulder, f) - pos(t, L::RightShoulder, f)).norm();
  for (Landmark s : {L::LeftShoulder, L::RightShoulder}) {
    const Landmark e = s == L::LeftShoulder ? L::LeftElbow : L::RightElbow;
    const Landmark w = s == L::LeftShoulder ? L::LeftWrist : L::RightWrist;
    const double arm = (pos(t, e, f) - pos(t, s, f)).norm() + (pos(t, w, f) - pos(t, e, f)).norm();
    if (!(arm > 0)) return false;
    if (std::abs(pos(t, w, f).z() - pos(t, s, f).z()) > 0.3 * arm) return false;  // within ~17 deg of level
    chain += arm;
  }
  const double span = (pos(t, L::LeftWrist, f) - pos(t, L::RightWrist, f)).norm();
  return span > 0.9 * chain;
}

// Largest displacement of any root-relative landmark between frames f and f + 1.
double pose_jump(const Tracks& t, int f) {
  double jump = 0;
  const Vec3 root0 = pos(t, Landmark::Pelvis, f), root1 = pos(t, Landmark::Pelvis, f + 1);
  for (Landmark l : all_landmarks()) {
    const Track& tr = at(t, l);
    if (!tr.present || l == Landmark::Pelvis) continue;
    jump = std::max(jump, ((tr.p.col(f + 1) - root1) - (tr.p.col(f) - root0)).norm());
  }
  return jump;
}

struct TposeResult {
  int frames = 0;         // leading frames to drop
  double jump_m = 0;      // pose jump into the real data
  double typical_m = 0;   // median frame-to-frame pose change
};

TposeResult count_synthetic_tpose_frames(const Tracks& t, int frames) {
  TposeResult r;
  if (frames < 3 || !is_tpose_like(t, 0)) return r;
  std::vector<double> jumps;
  for (int f = 0; f + 1 < frames; ++f) jumps.push_back(pose_jump(t, f));
  r.typical_m = median(std::vector<double>(jumps.begin() + std::min<std::ptrdiff_t>(kMaxTposeFrames, static_cast<std::ptrdiff_t>(jumps.size()) - 1), jumps.end()));
  int last = 0;  // last frame of the T-pose hold
  while (last + 1 < frames - 1 && last + 1 < kMaxTposeFrames && jumps[static_cast<std::size_t>(last)] < kTposeHoldJump_m &&
         is_tpose_like(t, last + 1))
    ++last;
  r.jump_m = jumps[static_cast<std::size_t>(last)];
  if (r.jump_m >= kTposeMinJump_m && r.jump_m >= kTposeJumpFactor * r.typical_m) r.frames = last + 1;
  return r;
}

std::string fmt(double v) { return format("%.4g", v); }

}  // namespace

HumanMotion bvh_to_human_motion(const BvhFile& file, const MotionLoadOptions& options) {
  HumanMotion m;
  MotionSourceInfo& src = m.source;
  src.path = file.name;
  src.format = "bvh";
  src.file_frames = file.num_frames;
  src.file_fps = file.frame_time_s > 0 ? 1.0 / file.frame_time_s : 0.0;
  src.details["joints"] = std::to_string(file.joints.size());
  src.details["channels"] = std::to_string(file.num_channels);
  src.details["end_sites"] = std::to_string(file.end_sites.size());
  src.details["root"] = file.joints.empty() ? "" : file.joints.front().name;
  src.details["frame_time_s"] = format("%.9g", file.frame_time_s);
  src.details["declared_frames"] = std::to_string(file.declared_frames);

  if (file.num_frames == 0) throw InputError(file.name + ":" + std::to_string(file.frames_line), "the clip has no frames");

  // Frame rate.
  if (options.source_fps) {
    const double fps = *options.source_fps;
    check_frame_rate(fps, "--source-fps", "the source frame rate");
    m.fps = fps;
  } else {
    if (!(file.frame_time_s > 0) || !std::isfinite(src.file_fps))
      throw InputError(file.name + ":" + std::to_string(file.frame_time_line),
                       "'Frame Time: " + format("%g", file.frame_time_s) +
                           "' gives no frame rate; pass the rate with --source-fps");
    m.fps = src.file_fps;
    // Exporters write 1/fps rounded: "Frame Time: 0.033333" is 30.0003 Hz as written but 1/30 s to
    // its six decimals. Taken as written, the export grid drifts against the source frames (a 30 Hz
    // output of a 3,945-frame LAFAN1 clip interpolated every frame between two source frames, also
    // across touchdowns); so a frame time that is 1/n s for a whole n to its written precision is
    // read as n Hz.
    const double whole = std::round(src.file_fps);
    if (file.frame_time_decimals >= 0 && whole >= 1 && whole != src.file_fps &&
        std::abs(file.frame_time_s - 1 / whole) <= 0.5 * std::pow(10.0, -file.frame_time_decimals) * (1 + 1e-9)) {
      m.fps = whole;
      m.diagnostics.note(file.name + ":" + std::to_string(file.frame_time_line),
                         format("frame time %.9g s read as 1/%g s (%g Hz), its value to the %d decimals written", file.frame_time_s, whole,
                                whole, file.frame_time_decimals));
    }
    check_frame_rate(m.fps, file.name + ":" + std::to_string(file.frame_time_line),
                     "the frame rate ('Frame Time: " + format("%g", file.frame_time_s) + "')");
  }
  check_clip_duration(file.num_frames / m.fps,
                      options.source_fps ? std::string("--source-fps")
                                         : file.name + ":" + std::to_string(file.frame_time_line),
                      format("the clip (%d frames at %g Hz)", file.num_frames, m.fps));

  // Skeleton.
  SkeletonBinding binding;
  if (options.profile_path.empty()) {
    binding = recognise_skeleton(file);
  } else {
    const SkeletonProfile profile = load_skeleton_profile(options.profile_path);
    binding = bind_skeleton_profile(profile, file);
    if (!binding.missing_required.empty()) {
      std::vector<std::string> names;
      for (Landmark l : binding.missing_required) names.emplace_back(landmark_name(l));
      throw InputError(options.profile_path, "skeleton profile '" + profile.name + "' does not give the required landmarks " +
                                                 join(names, ", ") + " for " + file.name);
    }
  }
  src.profile = binding.profile;
  src.details["profile_origin"] = binding.origin;
  m.diagnostics.note(file.name, "skeleton profile '" + binding.profile + "' (" + binding.origin + ")");

  Tracks tracks = extract_landmarks(file, binding);
  const int frames = file.num_frames;

  // Units.
  const double size_units = skeleton_size(tracks, frames);
  std::string units_note;
  if (!(size_units > 0) || !std::isfinite(size_units))
    throw InputError(file.name, "the skeleton size (leg and trunk segment lengths) is " + format("%g", size_units) +
                                    ": cannot detect units or scale the motion");
  if (options.source_units) {
    src.metres_per_unit = metres_per_unit(*options.source_units);
    src.units = units_name(src.metres_per_unit);
    src.units_overridden = true;
  } else {
    const UnitGuess u = detect_units(size_units);
    src.metres_per_unit = u.metres_per_unit;
    src.units = u.name;
    units_note = "units detected: " + u.name + " (skeleton size " + fmt(size_units) + " units = " +
                 fmt(size_units * u.metres_per_unit) + " m";
  }
  src.details["skeleton_size_m"] = fmt(size_units * src.metres_per_unit);

  // Up axis.
  bool up_negative = false;
  if (options.up_axis) {
    const auto [axis, negative] = parse_up_axis(*options.up_axis);
    src.up_axis = axis;
    up_negative = negative;
    src.up_axis_overridden = true;
  } else {
    const UpGuess g = detect_up_axis(tracks, frames);
    src.up_axis = g.axis;
    up_negative = g.negative;
    src.details["up_axis_confidence"] = format("%.3f", g.confidence);
    const std::string axis = std::string(g.negative ? "-" : "") + g.axis;
    if (g.confidence < 0.8)
      m.diagnostics.warn(file.name, "up axis unclear (head-above-feet direction only " + format("%.0f", 100 * g.confidence) +
                                        "% along " + axis + "); assuming " + axis + ", override with --up-axis");
    else
      m.diagnostics.note(file.name, "up axis detected: " + axis + "; override with --up-axis");
  }
  src.details["up_axis"] = std::string(up_negative ? "-" : "") + src.up_axis;

  // To metres, Z up.
  const Mat3 R = src.metres_per_unit * up_axis_to_z_up(src.up_axis, up_negative);
  for (Landmark l : all_landmarks()) {
    Track& t = at(tracks, l);
    if (!t.present) continue;
    t.p = R * t.p;
    if (t.p.allFinite() && t.p.cwiseAbs().maxCoeff() <= kMaxCoordinate_m) continue;
    int f = 0;
    while (f + 1 < frames && t.p.col(f).allFinite() && t.p.col(f).cwiseAbs().maxCoeff() <= kMaxCoordinate_m) ++f;
    const LandmarkSource& s = binding.sources[static_cast<std::size_t>(index(l))];
    const int j = s.available() ? s.joint : binding.sources[static_cast<std::size_t>(index(Landmark::LeftHip))].joint;
    throw InputError(file.name + " frame " + std::to_string(f) + " joint " + file.joints[static_cast<std::size_t>(j)].name,
                     std::string(landmark_name(l)) + " is " + format("%.3g", t.p.col(f).norm()) +
                         " m from the origin (more than " + format("%g", kMaxCoordinate_m) + " m): values out of range");
  }

  // Synthetic T-pose lead-in.
  int first = 0;
  const TposeResult tpose = count_synthetic_tpose_frames(tracks, frames);
  if (tpose.frames > 0) {
    if (options.drop_tpose) {
      first = tpose.frames;
      src.dropped_leading_frames = first;
      m.diagnostics.note(file.name, "dropped " + std::to_string(first) + " synthetic T-pose frame" + (first == 1 ? "" : "s") +
                                        " at the start (pose jump " + fmt(tpose.jump_m) + " m vs typical " +
                                        fmt(tpose.typical_m) + " m per frame); keep them with drop_tpose = false");
    } else {
      m.diagnostics.note(file.name, "kept " + std::to_string(tpose.frames) + " synthetic T-pose frame(s) at the start");
    }
    src.details["tpose_frames"] = std::to_string(tpose.frames);
  }

  m.num_frames = frames - first;
  for (Landmark l : all_landmarks()) {
    const Track& t = at(tracks, l);
    LandmarkTrack& out = m[l];
    out.present = t.present;
    if (!t.present) continue;
    out.p_W = t.p.rightCols(m.num_frames);
    out.state.assign(static_cast<std::size_t>(m.num_frames), SampleState::Measured);
  }

  normalize_motion(m, options.normalize);

  // Stature estimate at the first kept frame (reported, and a plausibility check on the units).
  const int head_joint = binding.sources[static_cast<std::size_t>(index(Landmark::Head))].joint;
  BvhPose pose;
  const std::vector<char> head_mask = bvh_ancestor_closure(file, {head_joint});
  bvh_forward_kinematics(file, first, pose, &head_mask);
  const double head_height_m = (R * pose.p_F_joint.col(head_joint)).z() - src.floor_height_m;
  const double stature_m = head_height_m / kHeadJointStatureRatio;
  src.details["head_joint_height_m"] = fmt(head_height_m);
  src.details["stature_m"] = fmt(stature_m);
  if (!units_note.empty())
    m.diagnostics.note(file.name, units_note + ", stature about " + format("%.2f", stature_m) +
                                      " m); override with --source-units");
  if (!(stature_m > 1.0 && stature_m < 2.5))
    m.diagnostics.warn(file.name, "implausible stature " + format("%.2f", stature_m) + " m with units " + src.units +
                                      (src.units_overridden ? "" : " (detected)") + " and up axis " +
                                      src.details["up_axis"] + "; check --source-units and --up-axis");
  return m;
}

HumanMotion load_bvh_motion(const std::string& path, const MotionLoadOptions& options) {
  Diagnostics reader;
  const BvhFile file = read_bvh(path, &reader);
  HumanMotion m = bvh_to_human_motion(file, options);
  Diagnostics all = reader;
  all.append(m.diagnostics);
  m.diagnostics = std::move(all);
  return m;
}

}  // namespace rt
