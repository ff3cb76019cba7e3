#include "retarget/jobs/convert_job.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>

#include "retarget/core/error.hpp"
#include "retarget/core/sha256.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/core/version.hpp"
#include "retarget/reference/npz_layout.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/registry.hpp"

namespace rt {

namespace fs = std::filesystem;

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

nlohmann::json statistics_json(const Statistics& s) {
  nlohmann::json out = nlohmann::json::object();
  for (const Statistic& st : s.items()) {
    nlohmann::json v = {{"value", st.value}};
    if (!st.unit.empty()) v["unit"] = st.unit;
    if (!st.note.empty()) v["note"] = st.note;
    out[st.name] = v;
  }
  return out;
}

nlohmann::json quality_json(const QualityMetrics& q) {
  nlohmann::json per_landmark = nlohmann::json::object();
  for (const LandmarkErrorStat& e : q.landmark_errors) per_landmark[e.landmark] = {{"median_m", e.median_m}, {"p95_m", e.p95_m}};
  return {{"landmark_error_median_m", q.landmark_error_median_m},
          {"landmark_error_p95_m", q.landmark_error_p95_m},
          {"worst_landmark", q.worst_landmark},
          {"landmark_errors", per_landmark},
          {"foot_skating_p95_m", q.foot_skating_p95_m},
          {"foot_skating_max_m", q.foot_skating_max_m},
          {"worst_stance_foot", q.worst_stance_foot < 0 ? "none" : q.worst_stance_foot == 0 ? "left" : "right"},
          {"worst_stance_start_s", q.worst_stance_start_s},
          {"heel_skating_p95_m", q.heel_skating_p95_m},
          {"heel_skating_max_m", q.heel_skating_max_m},
          {"stance_yaw_drift_max_deg", q.stance_yaw_drift_max_deg},
          {"stance_tilt_max_deg", q.stance_tilt_max_deg},
          {"stance_height_max_m", q.stance_height_max_m},
          {"penetration_max_m", q.penetration_max_m},
          {"lowest_point_m", q.lowest_point_m},
          {"lowest_link", q.lowest_link},
          {"lowest_time_s", q.lowest_time_s},
          {"swing_clearance_min_m", q.swing_clearance_min_m},
          {"swing_frames_low", q.swing_frames_low},
          {"frames_without_stance", q.frames_without_stance},
          {"longest_flight_s", q.longest_flight_s},
          {"position_limit_violations", q.position_limit_violations},
          {"velocity_limit_violations", q.velocity_limit_violations},
          {"max_velocity_ratio", q.max_velocity_ratio},
          {"fastest_joint", q.fastest_joint},
          {"fastest_joint_speed", q.fastest_joint_speed},
          {"jitter_rad_s3", q.jitter_rad_s3},
          {"jitter_per_frame_ik_rad_s3", q.jitter_per_frame_ik_rad_s3},
          {"frame0_sole_tilt_deg", q.frame0_sole_tilt_deg},
          {"frame0_sole_height_m", q.frame0_sole_height_m},
          {"zmp_stance_frames", q.zmp_stance_frames},
          {"zmp_single_support_frames", q.zmp_single_support_frames},
          {"zmp_inside_fraction", q.zmp_inside_fraction},
          {"zmp_within_1cm_fraction", q.zmp_near_fraction},
          {"zmp_single_support_inside_fraction", q.zmp_single_inside_fraction},
          {"zmp_single_support_within_1cm_fraction", q.zmp_single_near_fraction},
          {"zmp_outside_max_m", q.zmp_outside_max_m},
          {"zmp_outside_time_s", q.zmp_outside_time_s},
          {"torque_demand_max_ratio", q.torque_demand_max_ratio},
          {"torque_demand_joint", q.torque_demand_joint},
          {"torque_demand_time_s", q.torque_demand_time_s},
          {"torque_demand_frames_over_limit", q.torque_demand_frames_over}};
}

// The pipeline run_convert runs for a request (the spec string records every option).
Pipeline make_pipeline(const ConvertRequest& request) {
  Pipeline pipeline = request.passes.empty() ? Pipeline::default_pipeline(builtin_passes(), request.disabled_passes, request.enabled_passes)
                                             : Pipeline::parse(request.passes, builtin_passes());
  if (request.passes.empty() || request.fps != 30.0) pipeline.set_option_everywhere("fps", format("%.17g", request.fps));
  if (request.time_scale != 1.0 && pipeline.set_option_everywhere("time_scale", format("%.17g", request.time_scale)) == 0)
    throw InputError("--time-scale", "the pipeline has no retime pass");
  if (request.max_joint_speed > 0 &&
      pipeline.set_option_everywhere("max_joint_speed", format("%.17g", request.max_joint_speed)) == 0)
    throw InputError("--max-joint-speed", "the pipeline has no refine pass");
  return pipeline;
}

NpzLayout npz_layout_for(const ConvertRequest& request, const RobotModel& model) {
  if (!request.npz_layout.empty()) return resolve_npz_layout(model, request.npz_layout, "--npz-layout");
  return resolve_npz_layout(model, model.config().npz_layout, model.config().where("npz_layout"));
}

std::string provenance_json(const ConvertRequest& request, const ConvertResult& r, const RobotModel& model) {
  const MotionSourceInfo& src = r.clip.human.source;
  nlohmann::json j;
  j["tool"] = {{"name", "retarget"}, {"version", kVersion}};
  j["source"] = {{"path", src.path},
                 {"sha256", sha256_file(request.clip_path)},
                 {"format", src.format},
                 {"profile", src.profile},
                 {"fps", r.clip.human.fps},
                 {"file_fps", src.file_fps},
                 {"frames", r.clip.human.num_frames},
                 {"units", src.units},
                 {"metres_per_unit", src.metres_per_unit},
                 {"up_axis", std::string(1, src.up_axis)},
                 {"dropped_leading_frames", src.dropped_leading_frames},
                 {"floor_height_m", src.floor_height_m}};
  if (r.clip.lead_in_frames > 0 || r.clip.lead_out_frames > 0) {
    // com-plan's standing lead-in / lead-out: the source's first frame is at t = lead_in_s.
    j["lead_in_s"] = r.clip.lead_in_frames / r.clip.motion.fps;
    j["lead_out_s"] = r.clip.lead_out_frames / r.clip.motion.fps;
  }
  j["robot_config"] = {{"path", model.config().config_path}, {"sha256", sha256_file(model.config().config_path)}};
  j["urdf_sha256"] = sha256_file(model.config().urdf_path);
  if (std::find(request.formats.begin(), request.formats.end(), ReferenceFormat::Npz) != request.formats.end())
    j["npz_layout"] = request.npz_layout.empty() ? model.config().npz_layout : request.npz_layout;
  j["pipeline"] = r.pipeline;
  j["options_sha256"] = convert_options_sha256(request);
  nlohmann::json passes = nlohmann::json::array();
  for (const PassRecord& p : r.passes)
    passes.push_back({{"name", p.name}, {"options", p.options}, {"time_ms", p.time_ms}, {"statistics", statistics_json(p.statistics)}});
  j["passes"] = passes;
  j["quality"] = quality_json(r.quality);
  nlohmann::json warnings = nlohmann::json::array();
  for (const Diagnostic& d : r.clip.diagnostics.items()) warnings.push_back(d.to_string());
  for (const Diagnostic& d : r.clip.human.diagnostics.items()) warnings.push_back(d.to_string());
  j["diagnostics"] = warnings;
  return j.dump();
}

}  // namespace

std::vector<ReferenceFormat> output_formats_for(const std::string& output,
                                                const std::optional<std::vector<ReferenceFormat>>& formats) {
  const std::vector<ReferenceFormat> listed = formats ? *formats : std::vector<ReferenceFormat>{ReferenceFormat::Csv};
  std::error_code ec;
  if (output.empty() || ends_with(output, "/") || fs::is_directory(output, ec)) return listed;
  const std::string ext = to_lower(fs::path(output).extension().string());
  if (ext.empty()) return listed;
  std::optional<ReferenceFormat> by_name;
  if (ext == ".csv") by_name = ReferenceFormat::Csv;
  if (ext == ".npz") by_name = ReferenceFormat::Npz;
  if (!by_name)
    throw InputError("-o " + output, "'" + ext + "' is not an output format: give a .csv or .npz file, a folder, "
                                                  "or a name without an extension (with --format csv,npz)");
  if (!formats) return {*by_name};
  if (std::find(formats->begin(), formats->end(), *by_name) == formats->end())
    throw InputError("-o " + output, std::string("the extension asks for ") + reference_format_name(*by_name) +
                                         " but --format does not include it");
  return *formats;
}

std::string output_stem_for(const ConvertRequest& request) {
  const std::string stem = fs::path(request.clip_path).stem().string();
  if (request.output.empty()) return (fs::path("out") / stem).string();
  const fs::path out(request.output);
  const std::string lower = to_lower(request.output);
  if (ends_with(lower, ".csv") || ends_with(lower, ".npz")) return (out.parent_path() / out.stem()).string();
  if (ends_with(request.output, "/") || fs::is_directory(out)) return (out / stem).string();
  return request.output;
}

std::string convert_options_sha256(const ConvertRequest& request) {
  const MotionLoadOptions& m = request.motion;
  std::string text = "retarget-convert-options 1\n";
  text += std::string("tool ") + kVersion + "\n";
  text += "pipeline " + make_pipeline(request).to_string() + "\n";
  text += "formats";
  for (ReferenceFormat f : request.formats) text += std::string(" ") + reference_format_name(f);
  text += "\n";
  // The layout by its content: the same file edited gives other outputs.
  if (!request.npz_layout.empty()) {
    const auto colon = request.npz_layout.find(':');
    text += "npz_layout " + (colon == std::string::npos ? request.npz_layout
                                                         : request.npz_layout.substr(0, colon) + ":" +
                                                               sha256_file(request.npz_layout.substr(colon + 1))) + "\n";
  }
  text += "source_units " + (m.source_units ? "=" + *m.source_units : std::string("auto")) + "\n";
  text += "source_fps " + (m.source_fps ? format("=%.17g", *m.source_fps) : std::string("auto")) + "\n";
  text += "up_axis " + (m.up_axis ? "=" + *m.up_axis : std::string("auto")) + "\n";
  text += "profile " + (m.profile_path.empty() ? std::string("none") : sha256_file(m.profile_path)) + "\n";
  if (!m.asf_path.empty()) text += "asf " + sha256_file(m.asf_path) + "\n";
  text += format("drop_tpose %d\nmax_gap_s %.17g\n", m.drop_tpose ? 1 : 0, m.max_gap_s);
  text += format("normalize %d %d %.17g\n", m.normalize.align_start ? 1 : 0, m.normalize.move_floor_to_zero ? 1 : 0,
                 m.normalize.floor_percentile);
  return sha256_hex(text);
}

ConvertResult run_convert(const ConvertRequest& request, const RobotModel& model) {
  const auto t0 = std::chrono::steady_clock::now();
  ConvertResult r;
  r.clip.name = fs::path(request.clip_path).stem().string();
  r.clip.human = load_motion(request.clip_path, request.motion);
  r.load_ms = ms_since(t0);

  Pipeline pipeline = make_pipeline(request);
  r.pipeline = pipeline.to_string();
  RobotData data(model);
  r.passes = pipeline.run(r.clip, &model, &data, request.on_pass);
  if (r.clip.motion.num_frames() > 0) r.quality = compute_quality(model, data, r.clip);

  r.output_stem = output_stem_for(request);
  if (request.write_outputs) {
    if (r.clip.reference.num_frames() == 0)
      throw InputError("--passes", "the pipeline produced no reference (it must end with the resample pass)");
    r.clip.reference.extra_meta_json = provenance_json(request, r, model);
    const fs::path dir = fs::path(r.output_stem).parent_path();
    if (!dir.empty()) {
      std::error_code ec;
      fs::create_directories(dir, ec);
      if (ec) throw InputError(dir.string(), "cannot create the output folder: " + ec.message());
    }
    const bool npz = std::find(request.formats.begin(), request.formats.end(), ReferenceFormat::Npz) != request.formats.end();
    NpzBodyArrays bodies;
    if (npz) bodies = compute_body_arrays(model, data, r.clip.reference, npz_layout_for(request, model));
    r.written = write_reference(r.output_stem, r.clip.reference, request.formats, npz ? &bodies : nullptr);
  }
  r.total_ms = ms_since(t0);
  return r;
}

}  // namespace rt
