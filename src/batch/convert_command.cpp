#include "retarget/batch/convert_command.hpp"

#include "retarget/core/strings.hpp"

namespace rt {

namespace {

std::string number(double v) { return format("%.17g", v); }

std::string format_list(const std::vector<ReferenceFormat>& formats) {
  std::vector<std::string> names;
  for (ReferenceFormat f : formats) names.emplace_back(reference_format_name(f));
  return join(names, ",");
}

// The settings for one clip: the batch-wide ones with the manifest's overrides applied.
std::string output_file(const std::string& stem, const std::vector<ReferenceFormat>& formats) {
  return stem + "." + (formats.empty() ? "csv" : reference_format_name(formats.front()));
}

ConvertSettings effective(const BatchClip& clip, const ConvertSettings& s) {
  ConvertSettings e = s;
  const ClipOverrides& o = clip.overrides;
  if (o.source_units) e.source_units = o.source_units;
  if (o.source_fps) e.source_fps = o.source_fps;
  if (o.time_scale) e.time_scale = *o.time_scale;
  if (o.up_axis) e.up_axis = o.up_axis;
  if (o.profile) e.profile = *o.profile;
  return e;
}

}  // namespace

std::vector<std::string> convert_arguments(const BatchClip& clip, const ConvertSettings& settings,
                                           const std::string& robot, const std::string& output_stem,
                                           const std::string& report_dir) {
  const ConvertSettings s = effective(clip, settings);
  // "-o <stem>.<first format>": convert strips the extension to get the stem (the extension must
  // be one of --format) and never mistakes it for a folder (a folder of the same name may exist
  // for sub-folder clips).
  std::vector<std::string> a = {"convert", clip.input, "--robot", robot, "-o", output_file(output_stem, s.formats),
                                "--format", format_list(s.formats)};
  if (!s.npz_layout.empty()) a.insert(a.end(), {"--npz-layout", s.npz_layout});
  if (s.fps != 30.0) a.insert(a.end(), {"--fps", number(s.fps)});
  if (!s.passes.empty()) a.insert(a.end(), {"--passes", s.passes});
  for (const std::string& p : s.disabled_passes) a.push_back("--no-" + p);
  for (const std::string& p : s.enabled_passes) a.push_back("--" + p);
  if (s.time_scale != 1.0) a.insert(a.end(), {"--time-scale", number(s.time_scale)});
  if (s.max_joint_speed > 0) a.insert(a.end(), {"--max-joint-speed", number(s.max_joint_speed)});
  if (s.source_units) a.insert(a.end(), {"--source-units", *s.source_units});
  if (s.source_fps) a.insert(a.end(), {"--source-fps", number(*s.source_fps)});
  if (s.up_axis) a.insert(a.end(), {"--up-axis", *s.up_axis});
  if (!s.profile.empty()) a.insert(a.end(), {"--skeleton-profile", s.profile});
  if (s.keep_tpose) a.push_back("--keep-tpose");
  if (s.view) a.push_back("--view");
  for (const std::string& p : s.package_paths) a.insert(a.end(), {"--package-path", p});
  if (!report_dir.empty()) a.insert(a.end(), {"--check", "--report", report_dir});
  return a;
}

ConvertRequest convert_request_for(const BatchClip& clip, const ConvertSettings& settings, const std::string& output_stem) {
  const ConvertSettings s = effective(clip, settings);
  ConvertRequest r;
  r.clip_path = clip.input;
  r.output = output_file(output_stem, s.formats);
  r.formats = s.formats;
  r.npz_layout = s.npz_layout;
  r.fps = s.fps;
  r.time_scale = s.time_scale;
  r.max_joint_speed = s.max_joint_speed;
  r.passes = s.passes;
  r.disabled_passes = s.disabled_passes;
  r.enabled_passes = s.enabled_passes;
  r.motion.source_units = s.source_units;
  r.motion.source_fps = s.source_fps;
  r.motion.up_axis = s.up_axis;
  r.motion.profile_path = s.profile;
  r.motion.drop_tpose = !s.keep_tpose;
  return r;
}

}  // namespace rt
