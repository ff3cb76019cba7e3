#include "retarget/batch/clip_outputs.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/sha256.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/report/check_report.hpp"
#include "retarget/sim/violations.hpp"

namespace rt {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

constexpr std::uint64_t kMaxMetaBytes = 256ull << 20;
// The plots write_check_report writes, in its order.
const char* const kPlotNames[] = {"com_cop_y.svg", "com_cop_x.svg", "contacts.svg", "tracking.svg"};

bool is_file(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

bool mtime(const std::string& path, fs::file_time_type& t) {
  std::error_code ec;
  t = fs::last_write_time(path, ec);
  return !ec;
}

// Reads and parses a JSON file; null on any failure.
Json read_json(const std::string& path) {
  try {
    return Json::parse(read_file(path, kMaxMetaBytes));
  } catch (const std::exception&) {
    return Json();
  }
}

// j[a][b]... as a string, or "" when absent or not a string.
std::string json_string(const Json& j, std::initializer_list<const char*> keys) {
  const Json* p = &j;
  for (const char* k : keys) {
    if (!p->is_object() || !p->contains(k)) return "";
    p = &(*p)[k];
  }
  return p->is_string() ? p->get<std::string>() : "";
}

double json_number(const Json& j, std::initializer_list<const char*> keys, double fallback) {
  const Json* p = &j;
  for (const char* k : keys) {
    if (!p->is_object() || !p->contains(k)) return fallback;
    p = &(*p)[k];
  }
  if (!p->is_number()) return fallback;
  const double v = p->get<double>();
  return std::isfinite(v) ? v : fallback;
}

// "<base>.tmp.<digits>.<digits>": a temporary of write_file_atomic for <base>.
bool is_temporary_of(const std::string& name, const std::string& base) {
  const std::string prefix = base + ".tmp.";
  if (name.compare(0, prefix.size(), prefix) != 0) return false;
  const std::string rest = name.substr(prefix.size());
  const auto dot = rest.find('.');
  if (dot == 0 || dot == std::string::npos || dot + 1 == rest.size()) return false;
  return std::all_of(rest.begin(), rest.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '.'; });
}

std::string relative_to(const std::string& path, const std::string& folder) {
  std::error_code ec;
  const fs::path a = fs::absolute(path, ec).lexically_normal();
  const fs::path b = fs::absolute(folder.empty() ? "." : folder, ec).lexically_normal();
  const fs::path rel = a.lexically_relative(b);
  return rel.empty() ? a.generic_string() : rel.generic_string();
}

std::string main_violation(const CheckReportSummary& report) {
  const Violation* pick = nullptr;
  for (const Violation& v : report.violations)
    if (violation_fails_check(v.kind)) {
      pick = &v;
      break;
    }
  if (!pick && !report.violations.empty()) pick = &report.violations.front();
  if (!pick) return "";
  std::string s = format("%s at %.2f s", violation_name(pick->kind), pick->start_s);
  if (!pick->detail.empty()) s += ": " + pick->detail;
  return s;
}

// The files a complete clip has: data per format, meta, log and, with the check, the report folder.
std::vector<std::string> expected_outputs(const ClipOutputPaths& p, bool check) {
  std::vector<std::string> files = p.data;
  files.push_back(p.meta);
  files.push_back(p.log);
  if (check) {
    files.push_back(p.report);
    files.push_back(p.report_dir + "/report.txt");
    for (const char* plot : kPlotNames) files.push_back(p.report_dir + "/" + plot);
  }
  return files;
}

// Names in the marker are relative to the stem's folder ("walk01.csv", "walk01.report/report.json").
std::string marker_name(const ClipOutputPaths& p, const std::string& file) {
  return fs::path(file).lexically_relative(fs::path(p.stem).parent_path()).generic_string();
}

constexpr const char* kMarkerFormat = "retarget-clip-complete";

// "" when the marker matches the outputs on disk, else why not.
std::string check_completion_marker(const ClipOutputPaths& p, bool check) {
  const Json marker = read_json(p.complete);
  if (!marker.is_object() || json_string(marker, {"format"}) != kMarkerFormat) return "no completion marker";
  const Json& files = marker.contains("files") ? marker["files"] : Json();
  if (!files.is_object()) return "completion marker unreadable";
  for (const std::string& f : expected_outputs(p, check)) {
    const std::string name = marker_name(p, f);
    std::error_code ec;
    const auto size = fs::file_size(f, ec);
    if (ec || !is_file(f)) return name + " missing";
    if (!files.contains(name) || !files[name].is_number_unsigned() || files[name].get<std::uint64_t>() != size)
      return name + " incomplete (not as the completion marker recorded)";
  }
  std::string meta_hash;
  try {
    meta_hash = sha256_file(p.meta);
  } catch (const InputError&) {
    return "meta.json unreadable";
  }
  if (json_string(marker, {"meta_sha256"}) != meta_hash) return "meta.json changed after the completion marker";
  return "";
}

}  // namespace

void write_completion_marker(const ClipOutputPaths& p, bool check) {
  Json marker = Json::object();
  marker["format"] = kMarkerFormat;
  marker["format_version"] = 1;
  Json files = Json::object();
  for (const std::string& f : expected_outputs(p, check)) {
    std::error_code ec;
    const auto size = fs::file_size(f, ec);
    if (ec) throw InputError(f, "cannot record the completed output: " + ec.message());
    files[marker_name(p, f)] = static_cast<std::uint64_t>(size);
  }
  marker["files"] = std::move(files);
  marker["meta_sha256"] = sha256_file(p.meta);
  write_file_atomic(p.complete, marker.dump(1) + "\n");
}

void remove_completion_marker(const ClipOutputPaths& p) {
  std::error_code ec;
  fs::remove(p.complete, ec);
}

ClipOutputPaths clip_output_paths(const std::string& out_folder, const std::string& output_name,
                                  const std::vector<ReferenceFormat>& formats) {
  ClipOutputPaths p;
  p.stem = (fs::path(out_folder) / output_name).string();
  for (ReferenceFormat f : formats) p.data.push_back(p.stem + "." + reference_format_name(f));
  p.meta = p.stem + ".meta.json";
  p.log = p.stem + ".log";
  p.report_dir = p.stem + ".report";
  p.report = p.report_dir + "/report.json";
  p.complete = p.stem + ".complete";
  p.view = p.stem + ".html";
  return p;
}

UpToDate check_up_to_date(const std::string& input, const ClipOutputPaths& paths, const ExpectedHashes& expected,
                          bool check) {
  auto no = [](std::string why) { return UpToDate{false, std::move(why)}; };
  fs::file_time_type meta_time, input_time;
  if (!mtime(paths.meta, meta_time) || !is_file(paths.meta)) return no("no meta.json");
  if (expected.source_sha256.empty() || !mtime(input, input_time)) return no("input unreadable");
  if (meta_time < input_time) return no("input is newer than meta.json");
  const Json meta = read_json(paths.meta);
  if (!meta.is_object()) return no("meta.json unreadable");
  if (json_string(meta, {"source", "sha256"}) != expected.source_sha256) return no("input changed");
  if (json_string(meta, {"robot_config", "sha256"}) != expected.robot_config_sha256) return no("robot config changed");
  if (json_string(meta, {"urdf_sha256"}) != expected.urdf_sha256) return no("URDF changed");
  if (json_string(meta, {"options_sha256"}) != expected.options_sha256) return no("options changed");
  const Json files = meta.contains("files") ? meta["files"] : Json();
  for (const std::string& d : paths.data) {
    const std::string name = fs::path(d).filename().string();
    const bool listed = files.is_array() && std::find(files.begin(), files.end(), Json(name)) != files.end();
    if (!listed || !is_file(d)) return no(name + " missing");
  }
  if (check) {
    fs::file_time_type report_time;
    if (!mtime(paths.report, report_time) || !is_file(paths.report)) return no("no check report");
    if (report_time < meta_time) return no("check report older than meta.json");
    try {
      (void)read_check_report(paths.report);
    } catch (const std::exception&) {
      return no("check report unreadable");
    }
  }
  if (const std::string why = check_completion_marker(paths, check); !why.empty()) return no(why);
  return {true, "up to date"};
}

int remove_stale_temporaries(const ClipOutputPaths& paths) {
  // Temporaries live beside their target: the stem's folder and the report folder.
  std::vector<std::pair<fs::path, std::vector<std::string>>> folders;
  std::vector<std::string> bases;
  for (const std::string& d : paths.data) bases.push_back(fs::path(d).filename().string());
  bases.push_back(fs::path(paths.meta).filename().string());
  bases.push_back(fs::path(paths.complete).filename().string());
  folders.emplace_back(fs::path(paths.stem).parent_path(), bases);
  std::vector<std::string> report_bases = {"report.json", "report.txt"};
  for (const char* plot : kPlotNames) report_bases.emplace_back(plot);
  folders.emplace_back(fs::path(paths.report_dir), report_bases);
  int removed = 0;
  for (const auto& [folder, names] : folders) {
    std::error_code ec;
    fs::directory_iterator it(folder.empty() ? fs::path(".") : folder, ec), end;
    if (ec) continue;
    for (; it != end; it.increment(ec)) {
      if (ec) break;
      const std::string name = it->path().filename().string();
      if (name.find(".tmp.") == std::string::npos) continue;
      for (const std::string& base : names)
        if (is_temporary_of(name, base)) {
          std::error_code rm;
          if (fs::remove(it->path(), rm)) ++removed;
          break;
        }
    }
  }
  return removed;
}

std::string read_clip_outputs(ClipResult& r, const ClipOutputPaths& paths, const std::string& out_folder, bool check) {
  std::string problem;
  r.files = {};
  if (is_file(paths.log)) r.files.log = relative_to(paths.log, out_folder);
  const Json meta = is_file(paths.meta) ? read_json(paths.meta) : Json();
  if (meta.is_object()) {
    r.files.meta = relative_to(paths.meta, out_folder);
    for (const std::string& d : paths.data)
      if (is_file(d)) r.files.data.push_back(relative_to(d, out_folder));
    r.frames = static_cast<int>(json_number(meta, {"num_frames"}, -1));
    r.fps = json_number(meta, {"fps"}, 0);
    r.duration_s = json_number(meta, {"duration_s"}, -1);
    r.source_frames = static_cast<int>(json_number(meta, {"source", "frames"}, -1));
    r.landmark_error_median_m = json_number(meta, {"quality", "landmark_error_median_m"}, -1);
    r.landmark_error_p95_m = json_number(meta, {"quality", "landmark_error_p95_m"}, -1);
    r.foot_skating_p95_m = json_number(meta, {"quality", "foot_skating_p95_m"}, -1);
    r.penetration_max_m = json_number(meta, {"quality", "penetration_max_m"}, -1);
    if (r.files.data.size() != paths.data.size()) problem = "a data file is missing beside " + fs::path(paths.meta).filename().string();
  } else {
    problem = is_file(paths.meta) ? "meta.json is unreadable" : "no meta.json was written";
  }
  if (is_file(paths.view)) r.files.view = relative_to(paths.view, out_folder);
  if (check) {
    if (is_file(paths.report)) {
      try {
        const CheckReportSummary rep = read_check_report(paths.report);
        r.check = rep.passed ? CheckOutcome::Passed : CheckOutcome::Failed;
        r.violations = static_cast<int>(rep.violations.size());
        r.main_violation = main_violation(rep);
        r.files.report = relative_to(paths.report, out_folder);
      } catch (const std::exception& e) {
        if (problem.empty()) problem = std::string("check report unreadable: ") + e.what();
      }
      const std::string text = paths.report_dir + "/report.txt";
      if (is_file(text)) r.files.report_text = relative_to(text, out_folder);
      for (const char* plot : kPlotNames) {
        const std::string p = paths.report_dir + "/" + plot;
        if (is_file(p)) r.files.plots.push_back(relative_to(p, out_folder));
      }
    } else if (problem.empty()) {
      problem = "no check report was written";
    }
  }
  return problem;
}

}  // namespace rt
