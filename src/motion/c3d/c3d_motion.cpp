#include "retarget/motion/c3d/c3d_motion.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>

#include "formats/c3d/c3d_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/c3d/landmark_gaps.hpp"
#include "retarget/motion/c3d/marker_map.hpp"
#include "retarget/motion/c3d/marker_set_profiles.hpp"
#include "retarget/motion/c3d/marker_trajectories.hpp"
#include "retarget/motion/normalize.hpp"

namespace rt {

namespace {

// POINT:UNITS is a fixed-width text and some writers cut it: 'mete' is "meters" (c3d.org FP1).
// A prefix of at least three letters of a unit's full name stands for that unit.
std::string untruncated_units(const std::string& units) {
  const std::string u = to_lower(trim(units));
  if (u.size() < 3) return units;
  static const std::pair<const char*, const char*> kFull[] = {
      {"meters", "m"}, {"metres", "m"}, {"millimeters", "mm"}, {"millimetres", "mm"},
      {"centimeters", "cm"}, {"centimetres", "cm"}, {"inches", "inch"}};
  for (const auto& [full, unit] : kFull)
    if (std::string_view(full).substr(0, u.size()) == u && u.size() < std::string_view(full).size()) return unit;
  return units;
}

// Landmarks whose absence at the start or end of a trial means the subject is not (fully) in view.
const std::vector<Landmark>& core_landmarks() {
  static const std::vector<Landmark> kCore = {Landmark::Pelvis,   Landmark::LeftHip,    Landmark::RightHip,
                                              Landmark::LeftKnee, Landmark::RightKnee,  Landmark::LeftAnkle,
                                              Landmark::RightAnkle};
  return kCore;
}

struct DetectedUp {
  char axis = 'z';
  bool negative = false;
  double confidence = 0;  ///< |dominant component| / |mean direction|
};

// Up direction = mean over frames of (highest available trunk landmark - mean of the valid foot
// landmarks), in the file frame.
std::optional<DetectedUp> detect_up(const MarkerLandmarks& ml, int frames) {
  const Landmark tops[] = {Landmark::Head, Landmark::Neck, Landmark::Chest, Landmark::Spine, Landmark::Pelvis};
  const Landmark feet[] = {Landmark::LeftAnkle, Landmark::LeftToe,  Landmark::LeftHeel,
                           Landmark::RightAnkle, Landmark::RightToe, Landmark::RightHeel};
  Vec3 sum = Vec3::Zero();
  int n = 0;
  for (int f = 0; f < frames; ++f) {
    const LandmarkTrack* top = nullptr;
    for (Landmark l : tops) {
      const LandmarkTrack& t = ml.tracks[static_cast<std::size_t>(index(l))];
      if (t.present && t.state[static_cast<std::size_t>(f)] != SampleState::Missing) {
        top = &t;
        break;
      }
    }
    if (!top) continue;
    Vec3 foot = Vec3::Zero();
    int k = 0;
    for (Landmark l : feet) {
      const LandmarkTrack& t = ml.tracks[static_cast<std::size_t>(index(l))];
      if (t.present && t.state[static_cast<std::size_t>(f)] != SampleState::Missing) foot += t.p_W.col(f), ++k;
    }
    if (k == 0) continue;
    const Vec3 d = top->p_W.col(f) - foot / k;
    const double len = d.norm();
    if (len > 1e-3) sum += d / len, ++n;
  }
  if (n == 0) return std::nullopt;
  const Vec3 mean = sum / n;
  Eigen::Index axis = 0;
  mean.cwiseAbs().maxCoeff(&axis);
  DetectedUp up;
  up.axis = static_cast<char>('x' + axis);
  up.negative = mean[axis] < 0;
  up.confidence = std::abs(mean[axis]) / std::max(mean.norm(), 1e-12);
  return up;
}

std::string frame_range(int first_file_frame, int begin, int end) {
  return end - begin == 1 ? format("%d", first_file_frame + begin)
                          : format("%d-%d", first_file_frame + begin, first_file_frame + end - 1);
}

std::string axis_text(char axis, bool negative) { return std::string(negative ? "-" : "+") + axis; }

}  // namespace

HumanMotion c3d_to_motion(const c3d::C3dFile& file, const MotionLoadOptions& options, const Diagnostics& reader_diagnostics) {
  HumanMotion m;
  m.diagnostics.append(reader_diagnostics);
  const std::string& path = file.name;
  MotionSourceInfo& src = m.source;
  src.path = path;
  src.format = "c3d";

  const c3d::Parameter* labels_param = file.find("POINT", "LABELS");
  // Recognition errors point at POINT:LABELS, or at the parameter section when it is absent.
  const std::size_t parameter_section =
      file.header.parameter_block > 0 ? (static_cast<std::size_t>(file.header.parameter_block) - 1) * 512 : 0;
  const std::string labels_location =
      c3d::c3d_location(path, labels_param ? labels_param->offset : parameter_section, "POINT:LABELS");
  const c3d::Parameter* rate_param = file.find("POINT", "RATE");
  const std::string rate_location = c3d::c3d_location(path, rate_param ? rate_param->offset : 20, rate_param ? "POINT:RATE" : "");

  // ---- units and rate ----
  double mpu = 0.001;
  if (options.source_units) {
    mpu = metres_per_unit(*options.source_units);
    src.units_overridden = true;
  } else if (!file.point_units.empty()) {
    try {
      const std::string units = untruncated_units(file.point_units);
      if (units != file.point_units) {
        const c3d::Parameter* u = file.find("POINT", "UNITS");
        m.diagnostics.note(c3d::c3d_location(path, u ? u->offset : 0, "POINT:UNITS"),
                           "'" + file.point_units + "' read as " + units + " (a truncated unit name)");
      }
      mpu = metres_per_unit(units);
    } catch (const InputError&) {
      const c3d::Parameter* u = file.find("POINT", "UNITS");
      m.diagnostics.warn(c3d::c3d_location(path, u ? u->offset : 0, "POINT:UNITS"),
                         "unknown units '" + file.point_units + "'; assuming millimetres (override with --source-units)");
    }
  } else {
    m.diagnostics.note(path, "no POINT:UNITS parameter; assuming millimetres (override with --source-units)");
  }
  src.units = units_name(mpu);
  src.metres_per_unit = mpu;

  double fps = file.point_rate;
  src.file_fps = file.point_rate;
  if (options.source_fps) {
    fps = *options.source_fps;
    check_frame_rate(fps, "--source-fps", "the source frame rate");
    if (file.point_rate > 0 && std::abs(fps - file.point_rate) > 1e-9)
      m.diagnostics.note(path, format("frame rate overridden: %g Hz (the file says %g Hz)", fps, file.point_rate));
  } else if (!(fps > 0)) {
    throw InputError(rate_location, "the file states no frame rate (POINT:RATE and header word 11 are 0); give --source-fps");
  }
  if (!options.source_fps) check_frame_rate(fps, rate_location, "the point rate");
  src.file_frames = file.points.num_frames;
  if (file.points.num_frames == 0) throw InputError(c3d::c3d_location(path, file.data_offset), "the file holds no frames");
  check_clip_duration(file.points.num_frames / fps, options.source_fps ? "--source-fps" : rate_location,
                      format("the clip (%d frames at %g Hz)", file.points.num_frames, fps));

  // ---- markers and landmarks (file frame F) ----
  MarkerTrajectories markers = marker_trajectories(file, mpu);
  if (markers.implausible_samples > 0)
    m.diagnostics.warn(path, format("%d marker samples lie more than %g km from the origin; treated as missing",
                                    markers.implausible_samples, kMaxMarkerDistance_m / 1000));
  MarkerMap map;
  if (!options.profile_path.empty()) map = load_marker_map(options.profile_path);
  const SubjectMeasurements subject = subject_measurements(file);
  const MarkerLandmarks ml =
      compute_marker_landmarks(markers, subject, options.profile_path.empty() ? nullptr : &map, labels_location);
  src.profile = ml.profile;
  for (const std::string& how : ml.methods) m.diagnostics.note(path, "landmark " + how);
  for (const std::string& w : ml.warnings) m.diagnostics.warn(path, w);
  if (ml.rigid_filled_samples > 0)
    m.diagnostics.note(path, format("%d marker samples filled from the other markers of their segment (rigid cluster)",
                                    ml.rigid_filled_samples));

  // ---- up axis ----
  char up_axis = 'z';
  bool up_negative = false;
  const c3d::Parameter* y_screen = file.find("POINT", "Y_SCREEN");
  std::optional<std::pair<char, bool>> screen_up;
  if (y_screen && !y_screen->strings.empty()) {
    try {
      screen_up = parse_up_axis(y_screen->strings[0]);
    } catch (const InputError&) {
    }
  }
  if (options.up_axis) {
    std::tie(up_axis, up_negative) = parse_up_axis(*options.up_axis);
    src.up_axis_overridden = true;
  } else if (const auto up = detect_up(ml, file.points.num_frames); up && up->confidence > 0.7) {
    up_axis = up->axis;
    up_negative = up->negative;
    if (screen_up && (screen_up->first != up_axis || screen_up->second != up_negative))
      m.diagnostics.note(c3d::c3d_location(path, y_screen->offset, "POINT:Y_SCREEN"),
                         "says '" + y_screen->strings[0] + "' but the subject's feet-to-head direction is " +
                             axis_text(up_axis, up_negative) + "; using " + axis_text(up_axis, up_negative));
  } else {
    if (screen_up) std::tie(up_axis, up_negative) = *screen_up;
    m.diagnostics.warn(path, "cannot tell the up axis from the landmarks; using " + axis_text(up_axis, up_negative) +
                                 (screen_up ? " from POINT:Y_SCREEN" : " (default)") + " (override with --up-axis)");
  }
  src.up_axis = up_axis;
  const Mat3 R_W_F = up_axis_to_z_up(up_axis, up_negative);

  // ---- HumanMotion in W (metres, Z up) ----
  m.fps = fps;
  m.num_frames = file.points.num_frames;
  for (Landmark l : all_landmarks()) {
    const LandmarkTrack& in = ml.tracks[static_cast<std::size_t>(index(l))];
    if (!in.present) continue;
    LandmarkTrack& out = m[l];
    out.present = true;
    out.p_W = R_W_F * in.p_W;
    out.state = in.state;
  }

  // ---- trim to the span where the subject is in view ----
  const FrameGap span = common_valid_span(m, core_landmarks());
  if (span.begin >= span.end)
    throw InputError(labels_location, "the pelvis and leg joint centres are never in view together in any frame");
  const int first_file_frame = file.first_frame;
  if (span.begin > 0 || span.end < m.num_frames) {
    m.diagnostics.note(path, format("kept frames %s of %s: the pelvis and legs are not all in view in the %d leading "
                                    "and %d trailing frames",
                                    frame_range(first_file_frame, span.begin, span.end).c_str(),
                                    frame_range(first_file_frame, 0, m.num_frames).c_str(), span.begin,
                                    m.num_frames - span.end));
    trim_frames(m, span.begin, span.end);
  }

  // ---- gaps ----
  if (!std::isfinite(options.max_gap_s) || options.max_gap_s < 0)
    throw InputError(format("maximum gap %g s is not a valid duration", options.max_gap_s));
  const int max_gap_frames = static_cast<int>(std::floor(std::min(options.max_gap_s * fps, 1e9) + 1e-9));
  const int kept_first = first_file_frame + span.begin;
  int interpolated_gaps = 0, long_gaps = 0;
  std::vector<Landmark> unavailable;
  for (Landmark l : all_landmarks()) {
    LandmarkTrack& t = m[l];
    if (!t.present) {
      unavailable.push_back(l);
      continue;
    }
    const GapReport r = fill_gaps(t, max_gap_frames);
    if (!r.has_valid) {
      t = LandmarkTrack{};
      unavailable.push_back(l);
      m.diagnostics.warn(path, std::string(landmark_name(l)) + ": no valid sample in the kept frames; dropped");
      continue;
    }
    interpolated_gaps += r.filled_gaps;
    std::vector<std::string> ranges;
    std::vector<std::pair<FrameGap, const char*>> missing;
    if (r.leading.length() > 0) missing.emplace_back(r.leading, " (start)");
    for (const FrameGap& g : r.long_gaps) missing.emplace_back(g, "");
    if (r.trailing.length() > 0) missing.emplace_back(r.trailing, " (end)");
    long_gaps += static_cast<int>(missing.size());
    for (std::size_t k = 0; k < missing.size() && k < 6; ++k)
      ranges.push_back(frame_range(kept_first, missing[k].first.begin, missing[k].first.end) + missing[k].second);
    if (missing.size() > 6) ranges.push_back(format("and %zu more", missing.size() - 6));
    if (!missing.empty())
      m.diagnostics.warn(path, format("%s: missing in file frames %s; not interpolated (longer than %.3g s, or at an "
                                      "end of the kept frames): the nearest valid position is held",
                                      std::string(landmark_name(l)).c_str(), join(ranges, ", ").c_str(), options.max_gap_s));
  }
  if (!unavailable.empty()) {
    std::vector<std::string> names;
    for (Landmark l : unavailable) names.emplace_back(landmark_name(l));
    m.diagnostics.warn(path, "landmarks not available from the " + ml.profile + " markers: " + join(names, ", "));
  }

  // ---- source facts ----
  auto& d = src.details;
  d["markers"] = std::to_string(file.marker_count());
  d["points"] = std::to_string(file.points.num_points);
  d["analog_channels"] = std::to_string(file.analog_channels);
  d["analog_rate_hz"] = format("%g", file.analog_rate);
  d["first_frame"] = std::to_string(file.first_frame);
  d["last_frame"] = std::to_string(file.first_frame + file.points.num_frames - 1);
  d["kept_first_frame"] = std::to_string(kept_first);
  d["kept_last_frame"] = std::to_string(kept_first + m.num_frames - 1);
  d["trimmed_leading_frames"] = std::to_string(span.begin);
  d["trimmed_trailing_frames"] = std::to_string(file.points.num_frames - span.end);
  d["events"] = std::to_string(file.events.size());
  d["processor"] = c3d::processor_name(file.processor);
  d["storage"] = file.float_storage ? "float" : "int16";
  d["rigid_filled_samples"] = std::to_string(ml.rigid_filled_samples);
  d["interpolated_gaps"] = std::to_string(interpolated_gaps);
  d["missing_gaps"] = std::to_string(long_gaps);

  normalize_motion(m, options.normalize);
  return m;
}

HumanMotion load_c3d_motion(const std::string& path, const MotionLoadOptions& options) {
  Diagnostics reader;
  const c3d::C3dFile file = c3d::read_c3d(path, &reader);
  return c3d_to_motion(file, options, reader);
}

}  // namespace rt
