#include "retarget/batch/batch_summary.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/json_document.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

constexpr const char* kSummaryFormat = "retarget-batch-summary";
constexpr int kSummaryFormatVersion = 1;
constexpr std::uint64_t kMaxSummaryBytes = 1ull << 30;
constexpr int kMaxJsonDepth = 16;  // the schema nests 4 levels

const std::vector<std::pair<ClipStatus, const char*>>& status_names() {
  static const std::vector<std::pair<ClipStatus, const char*>> names = {
      {ClipStatus::Ok, "ok"},           {ClipStatus::CheckFailed, "check-failed"}, {ClipStatus::BadInput, "bad-input"},
      {ClipStatus::Crashed, "crashed"}, {ClipStatus::Timeout, "timeout"},         {ClipStatus::OutOfMemory, "out-of-memory"},
      {ClipStatus::Error, "error"},     {ClipStatus::Skipped, "skipped"},         {ClipStatus::Cancelled, "cancelled"}};
  return names;
}

// Rounds for compact, stable files: `digits` decimals.
double rounded(double v, int digits) {
  const double s = std::pow(10.0, digits);
  return std::round(v * s) / s;
}

Json number_or_null(double v, int digits) { return v < 0 || !std::isfinite(v) ? Json() : Json(rounded(v, digits)); }
Json int_or_null(int v) { return v < 0 ? Json() : Json(v); }
Json string_or_null(const std::string& s) { return s.empty() ? Json() : Json(s); }

Json clip_json(const ClipResult& c) {
  Json files = {{"data", c.files.data},
                {"meta", string_or_null(c.files.meta)},
                {"log", string_or_null(c.files.log)},
                {"report", string_or_null(c.files.report)},
                {"report_text", string_or_null(c.files.report_text)},
                {"plots", c.files.plots},
                {"view", string_or_null(c.files.view)}};
  return {{"name", c.name},
          {"input", c.input},
          {"input_bytes", c.input_bytes},
          {"status", clip_status_name(c.status)},
          {"error", string_or_null(c.error)},
          {"exit_code", int_or_null(c.exit_code)},
          {"signal", c.signal > 0 ? Json(c.signal) : Json()},
          {"time_s", rounded(c.time_s, 3)},
          {"peak_rss_mb", rounded(c.peak_rss_mb, 1)},
          {"frames", int_or_null(c.frames)},
          {"fps", c.fps > 0 ? Json(c.fps) : Json()},
          {"duration_s", number_or_null(c.duration_s, 6)},
          {"source_frames", int_or_null(c.source_frames)},
          {"landmark_error_median_m", number_or_null(c.landmark_error_median_m, 6)},
          {"landmark_error_p95_m", number_or_null(c.landmark_error_p95_m, 6)},
          {"foot_skating_p95_m", number_or_null(c.foot_skating_p95_m, 6)},
          {"penetration_max_m", number_or_null(c.penetration_max_m, 6)},
          {"check", check_outcome_name(c.check)},
          {"violations", int_or_null(c.violations)},
          {"main_violation", string_or_null(c.main_violation)},
          {"files", files}};
}

// ---- reading ------------------------------------------------------------------------------------

struct Reader {
  const std::string& file;
  [[noreturn]] void fail(const std::string& key, const std::string& msg) const {
    throw InputError(file + " [" + key + "]", msg);
  }
  const Json& at(const Json& j, const std::string& key, const std::string& path) const {
    if (!j.is_object() || !j.contains(key)) fail(path, "missing");
    return j.at(key);
  }
  std::string str(const Json& j, const std::string& key, const std::string& path, bool nullable = false) const {
    const Json& v = at(j, key, path);
    if (nullable && v.is_null()) return "";
    if (!v.is_string()) fail(path, nullable ? "expected a string or null" : "expected a string");
    return v.get<std::string>();
  }
  double num(const Json& j, const std::string& key, const std::string& path, bool nullable = false) const {
    const Json& v = at(j, key, path);
    if (nullable && v.is_null()) return -1;
    if (!v.is_number()) fail(path, nullable ? "expected a number or null" : "expected a number");
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < 0) fail(path, "expected a finite number >= 0");
    return d;
  }
  int integer(const Json& j, const std::string& key, const std::string& path, bool nullable = false) const {
    const Json& v = at(j, key, path);
    if (nullable && v.is_null()) return -1;
    if (!v.is_number_integer()) fail(path, nullable ? "expected an integer or null" : "expected an integer");
    const auto i = v.get<std::int64_t>();
    if (i < 0 || i > 2147483647) fail(path, "expected an integer in [0, 2^31)");
    return static_cast<int>(i);
  }
  bool boolean(const Json& j, const std::string& key, const std::string& path) const {
    const Json& v = at(j, key, path);
    if (!v.is_boolean()) fail(path, "expected true or false");
    return v.get<bool>();
  }
  std::vector<std::string> strings(const Json& j, const std::string& key, const std::string& path) const {
    const Json& v = at(j, key, path);
    if (!v.is_array()) fail(path, "expected a list of strings");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_string()) fail(path + "[" + std::to_string(i) + "]", "expected a string");
      out.push_back(v[i].get<std::string>());
    }
    return out;
  }
};

ClipResult parse_clip(const Reader& r, const Json& j, const std::string& p) {
  if (!j.is_object()) r.fail(p, "expected an object");
  ClipResult c;
  c.name = r.str(j, "name", p + ".name");
  if (c.name.empty()) r.fail(p + ".name", "expected a non-empty name");
  c.input = r.str(j, "input", p + ".input");
  const Json& bytes = r.at(j, "input_bytes", p + ".input_bytes");
  if (!bytes.is_number_unsigned()) r.fail(p + ".input_bytes", "expected a byte count");
  c.input_bytes = bytes.get<std::uint64_t>();
  c.status = parse_clip_status(r.str(j, "status", p + ".status"), r.file + " [" + p + ".status]");
  c.error = r.str(j, "error", p + ".error", true);
  c.exit_code = r.integer(j, "exit_code", p + ".exit_code", true);
  const int sig = r.integer(j, "signal", p + ".signal", true);
  c.signal = sig < 0 ? 0 : sig;
  c.time_s = r.num(j, "time_s", p + ".time_s");
  c.peak_rss_mb = r.num(j, "peak_rss_mb", p + ".peak_rss_mb");
  c.frames = r.integer(j, "frames", p + ".frames", true);
  const double fps = r.num(j, "fps", p + ".fps", true);
  c.fps = fps < 0 ? 0 : fps;
  c.duration_s = r.num(j, "duration_s", p + ".duration_s", true);
  c.source_frames = r.integer(j, "source_frames", p + ".source_frames", true);
  c.landmark_error_median_m = r.num(j, "landmark_error_median_m", p + ".landmark_error_median_m", true);
  c.landmark_error_p95_m = r.num(j, "landmark_error_p95_m", p + ".landmark_error_p95_m", true);
  c.foot_skating_p95_m = r.num(j, "foot_skating_p95_m", p + ".foot_skating_p95_m", true);
  c.penetration_max_m = r.num(j, "penetration_max_m", p + ".penetration_max_m", true);
  const std::string check = r.str(j, "check", p + ".check");
  if (check == "passed") c.check = CheckOutcome::Passed;
  else if (check == "failed") c.check = CheckOutcome::Failed;
  else if (check == "not-run") c.check = CheckOutcome::NotRun;
  else r.fail(p + ".check", "expected passed, failed or not-run, got '" + check + "'");
  c.violations = r.integer(j, "violations", p + ".violations", true);
  c.main_violation = r.str(j, "main_violation", p + ".main_violation", true);
  const Json& f = r.at(j, "files", p + ".files");
  const std::string fp = p + ".files";
  c.files.data = r.strings(f, "data", fp + ".data");
  c.files.meta = r.str(f, "meta", fp + ".meta", true);
  c.files.log = r.str(f, "log", fp + ".log", true);
  c.files.report = r.str(f, "report", fp + ".report", true);
  c.files.report_text = r.str(f, "report_text", fp + ".report_text", true);
  c.files.plots = r.strings(f, "plots", fp + ".plots");
  if (f.contains("view")) c.files.view = r.str(f, "view", fp + ".view", true);  // absent before the viewer
  return c;
}

// ---- text output helpers ------------------------------------------------------------------------

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string csv_number(double v, const char* fmt) { return v < 0 || !std::isfinite(v) ? "" : format(fmt, v); }
std::string csv_int(int v) { return v < 0 ? "" : std::to_string(v); }

std::string html_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

// Percent-encodes a relative path for an href (keeps '/' and unreserved characters).
std::string url_path(const std::string& path) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

std::string link(const std::string& path, const std::string& text) {
  if (path.empty()) return "";
  return "<a href=\"" + html_escape(url_path(path)) + "\">" + html_escape(text) + "</a>";
}

std::string cell_number(double v, const char* fmt) { return v < 0 || !std::isfinite(v) ? "&ndash;" : format(fmt, v); }

// Rewrites a path relative to `from` so it is relative to `to` (both absolute folders).
std::string rebase(const std::string& path, const fs::path& from, const fs::path& to) {
  if (path.empty()) return path;
  const fs::path abs = (from / path).lexically_normal();
  const fs::path rel = abs.lexically_relative(to);
  return rel.empty() ? abs.generic_string() : rel.generic_string();
}

fs::path absolute_folder(const std::string& folder) {
  std::error_code ec;
  const fs::path a = fs::absolute(folder.empty() ? fs::path(".") : fs::path(folder), ec);
  return (ec ? fs::path(folder) : a).lexically_normal();
}

}  // namespace

const char* clip_status_name(ClipStatus status) {
  for (const auto& [s, name] : status_names())
    if (s == status) return name;
  return "error";
}

ClipStatus parse_clip_status(const std::string& name, const std::string& where) {
  for (const auto& [s, n] : status_names())
    if (name == n) return s;
  std::vector<std::string> all;
  for (const auto& sn : status_names()) all.emplace_back(sn.second);
  throw InputError(where, "unknown clip status '" + name + "' (expected one of: " + join(all, ", ") + ")");
}

const std::vector<ClipStatus>& all_clip_statuses() {
  static const std::vector<ClipStatus> all = [] {
    std::vector<ClipStatus> v;
    for (const auto& sn : status_names()) v.push_back(sn.first);
    return v;
  }();
  return all;
}

const char* check_outcome_name(CheckOutcome outcome) {
  switch (outcome) {
    case CheckOutcome::Passed: return "passed";
    case CheckOutcome::Failed: return "failed";
    case CheckOutcome::NotRun: break;
  }
  return "not-run";
}

bool ClipResult::check_failed() const {
  return status == ClipStatus::CheckFailed || (status == ClipStatus::Skipped && check == CheckOutcome::Failed);
}

bool ClipResult::hard_failure() const {
  switch (status) {
    case ClipStatus::BadInput:
    case ClipStatus::Crashed:
    case ClipStatus::Timeout:
    case ClipStatus::OutOfMemory:
    case ClipStatus::Error:
    case ClipStatus::Cancelled: return true;
    default: return false;
  }
}

void BatchSummary::sort_clips() {
  std::sort(clips.begin(), clips.end(), [](const ClipResult& a, const ClipResult& b) { return a.name < b.name; });
}

int BatchSummary::count(ClipStatus status) const {
  return static_cast<int>(std::count_if(clips.begin(), clips.end(), [&](const ClipResult& c) { return c.status == status; }));
}

int batch_exit_status(const BatchSummary& summary) {
  bool check_failed = false;
  for (const ClipResult& c : summary.clips) {
    if (c.hard_failure()) return 2;
    check_failed = check_failed || c.check_failed();
  }
  return check_failed ? 1 : 0;
}

std::string summary_json(const BatchSummary& s) {
  Json counts = {{"total", s.clips.size()}};
  for (ClipStatus st : all_clip_statuses()) counts[clip_status_name(st)] = s.count(st);
  Json clips = Json::array();
  for (const ClipResult& c : s.clips) clips.push_back(clip_json(c));
  Json j = {{"format", kSummaryFormat},
            {"format_version", kSummaryFormatVersion},
            {"tool_version", s.tool_version},
            {"robot", s.robot},
            {"robot_config", s.robot_config},
            {"input", s.input},
            {"shard", string_or_null(s.shard)}};
  if (!s.merged_from.empty()) j["merged_from"] = s.merged_from;
  j["check"] = s.check;
  j["convert_options"] = s.convert_options;
  j["jobs"] = s.jobs;
  j["started_utc"] = s.started_utc;
  j["wall_s"] = rounded(s.wall_s, 3);
  j["stopped"] = string_or_null(s.stopped);
  j["exit_status"] = batch_exit_status(s);
  j["counts"] = counts;
  j["clips"] = clips;
  return j.dump(1) + "\n";
}

std::string summary_csv(const BatchSummary& s) {
  std::string out =
      "name,status,frames,fps,duration_s,time_s,peak_rss_mb,landmark_error_median_m,landmark_error_p95_m,"
      "foot_skating_p95_m,penetration_max_m,check,violations,main_violation,error,input,data,log,report\n";
  for (const ClipResult& c : s.clips) {
    const std::vector<std::string> row = {csv_field(c.name),
                                          clip_status_name(c.status),
                                          csv_int(c.frames),
                                          c.fps > 0 ? format("%g", c.fps) : "",
                                          csv_number(c.duration_s, "%.3f"),
                                          format("%.3f", c.time_s),
                                          format("%.1f", c.peak_rss_mb),
                                          csv_number(c.landmark_error_median_m, "%.6f"),
                                          csv_number(c.landmark_error_p95_m, "%.6f"),
                                          csv_number(c.foot_skating_p95_m, "%.6f"),
                                          csv_number(c.penetration_max_m, "%.6f"),
                                          check_outcome_name(c.check),
                                          csv_int(c.violations),
                                          csv_field(c.main_violation),
                                          csv_field(c.error),
                                          csv_field(c.input),
                                          csv_field(join(c.files.data, ";")),
                                          csv_field(c.files.log),
                                          csv_field(c.files.report)};
    out += join(row, ",") + "\n";
  }
  return out;
}

std::string summary_html(const BatchSummary& s) {
  const int exit_status = batch_exit_status(s);
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<title>retarget batch: " + html_escape(s.robot) + " (" + std::to_string(s.clips.size()) + " clips)</title>\n";
  h += "<style>\n"
       "body{font-family:system-ui,sans-serif;margin:1.5em;color:#222}\n"
       "table{border-collapse:collapse;font-size:0.9em}\n"
       "th,td{border:1px solid #ccc;padding:3px 6px;text-align:left;vertical-align:top}\n"
       "th{background:#f0f0f0;position:sticky;top:0}\n"
       "td.n{text-align:right;font-variant-numeric:tabular-nums}\n"
       ".st{font-weight:600;padding:1px 5px;border-radius:3px;white-space:nowrap}\n"
       ".ok,.skipped{background:#d8f0d8}.check-failed{background:#fbe8c0}\n"
       ".bad-input,.crashed,.timeout,.out-of-memory,.error{background:#f6cfcf}.cancelled{background:#e0e0e0}\n"
       ".passed{color:#161}.failed{color:#a11}\n"
       "td.err{max-width:40em;font-family:monospace;font-size:0.9em;word-break:break-word}\n"
       "</style>\n</head>\n<body>\n";
  h += "<h1>retarget batch on " + html_escape(s.robot) + "</h1>\n<p>";
  h += "Input <code>" + html_escape(s.input.empty() ? std::string("(several)") : s.input) + "</code>";
  if (!s.shard.empty()) h += ", shard " + html_escape(s.shard);
  if (!s.merged_from.empty()) h += format(", merged from %zu summaries", s.merged_from.size());
  h += ". Robot config <code>" + html_escape(s.robot_config) + "</code>. Convert options <code>" +
       html_escape(s.convert_options.empty() ? std::string("(defaults)") : s.convert_options) + "</code>" +
       (s.check ? ", with the dynamics check" : "") + ".<br>\n";
  h += "Started " + html_escape(s.started_utc) + format(", %.1f s wall time with %d worker(s)", s.wall_s, s.jobs) +
       ", tool version " + html_escape(s.tool_version) + ".";
  if (!s.stopped.empty()) h += " <b>Stopped early: " + html_escape(s.stopped) + ".</b>";
  h += "</p>\n<p>";
  h += format("<b>%zu clips</b>", s.clips.size());
  for (ClipStatus st : all_clip_statuses()) {
    const int n = s.count(st);
    if (n > 0) h += format(" &middot; <span class=\"st %s\">%s</span> %d", clip_status_name(st), clip_status_name(st), n);
  }
  h += format(" &middot; exit status %d</p>\n", exit_status);
  h += "<table>\n<thead><tr><th>clip</th><th>status</th><th>frames</th><th>duration [s]</th><th>time [s]</th>"
       "<th>landmark error median / p95 [m]</th><th>skating p95 [m]</th><th>check</th><th>main violation</th>"
       "<th>error</th><th>files</th></tr></thead>\n<tbody>\n";
  for (const ClipResult& c : s.clips) {
    const char* st = clip_status_name(c.status);
    h += "<tr><td>" + (c.files.data.empty() ? html_escape(c.name) : link(c.files.data.front(), c.name)) + "</td>";
    h += std::string("<td><span class=\"st ") + st + "\">" + st + "</span></td>";
    h += "<td class=\"n\">" + (c.frames < 0 ? std::string("&ndash;") : std::to_string(c.frames)) + "</td>";
    h += "<td class=\"n\">" + cell_number(c.duration_s, "%.2f") + "</td>";
    h += "<td class=\"n\">" + (c.status == ClipStatus::Skipped ? std::string("&ndash;") : format("%.1f", c.time_s)) + "</td>";
    h += "<td class=\"n\">" + cell_number(c.landmark_error_median_m, "%.3f") + " / " +
         cell_number(c.landmark_error_p95_m, "%.3f") + "</td>";
    h += "<td class=\"n\">" + cell_number(c.foot_skating_p95_m, "%.4f") + "</td>";
    const char* check = check_outcome_name(c.check);
    h += c.check == CheckOutcome::NotRun ? std::string("<td>&ndash;</td>")
                                         : std::string("<td class=\"") + check + "\">" + check + "</td>";
    h += "<td>" + html_escape(c.main_violation) + "</td>";
    h += "<td class=\"err\">" + html_escape(c.error) + "</td><td>";
    std::vector<std::string> links;
    if (!c.files.view.empty()) links.push_back(link(c.files.view, "view"));
    for (const std::string& d : c.files.data) links.push_back(link(d, fs::path(d).extension().string().substr(1)));
    if (!c.files.meta.empty()) links.push_back(link(c.files.meta, "meta"));
    if (!c.files.log.empty()) links.push_back(link(c.files.log, "log"));
    if (!c.files.report_text.empty()) links.push_back(link(c.files.report_text, "report"));
    if (!c.files.report.empty()) links.push_back(link(c.files.report, "json"));
    for (const std::string& p : c.files.plots) links.push_back(link(p, fs::path(p).stem().string()));
    h += join(links, " ") + "</td></tr>\n";
  }
  h += "</tbody>\n</table>\n</body>\n</html>\n";
  return h;
}

SummaryFileNames summary_file_names(const std::string& tag) {
  const std::string suffix = tag.empty() ? std::string() : "-" + tag;
  return {"summary" + suffix + ".json", "summary" + suffix + ".csv", "index" + suffix + ".html"};
}

std::vector<std::string> write_summary(const std::string& folder, const BatchSummary& summary, const std::string& tag) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw InputError(folder, "cannot create the output folder: " + ec.message());
  const SummaryFileNames names = summary_file_names(tag);
  const std::vector<std::pair<std::string, std::string>> files = {
      {(fs::path(folder) / names.json).string(), summary_json(summary)},
      {(fs::path(folder) / names.csv).string(), summary_csv(summary)},
      {(fs::path(folder) / names.html).string(), summary_html(summary)}};
  std::vector<std::string> written;
  for (const auto& [path, text] : files) {
    write_file_atomic(path, text);
    written.push_back(path);
  }
  return written;
}

BatchSummary parse_summary(const std::string& text, const std::string& file) {
  const Json j = parse_json_object(text, file, "a batch summary", kMaxJsonDepth);
  const Reader r{file};
  if (r.str(j, "format", "format") != kSummaryFormat)
    r.fail("format", std::string("not a batch summary (expected \"") + kSummaryFormat + "\")");
  const int version = r.integer(j, "format_version", "format_version");
  if (version != kSummaryFormatVersion)
    r.fail("format_version", format("version %d is not supported (this tool reads version %d)", version, kSummaryFormatVersion));
  BatchSummary s;
  s.tool_version = r.str(j, "tool_version", "tool_version");
  s.robot = r.str(j, "robot", "robot");
  s.robot_config = r.str(j, "robot_config", "robot_config");
  s.input = r.str(j, "input", "input");
  s.shard = r.str(j, "shard", "shard", true);
  if (j.contains("merged_from")) s.merged_from = r.strings(j, "merged_from", "merged_from");
  s.check = r.boolean(j, "check", "check");
  s.convert_options = r.str(j, "convert_options", "convert_options");
  s.jobs = r.integer(j, "jobs", "jobs");
  s.started_utc = r.str(j, "started_utc", "started_utc");
  s.wall_s = r.num(j, "wall_s", "wall_s");
  s.stopped = r.str(j, "stopped", "stopped", true);
  const Json& clips = r.at(j, "clips", "clips");
  if (!clips.is_array()) r.fail("clips", "expected a list");
  std::set<std::string> names;
  for (std::size_t i = 0; i < clips.size(); ++i) {
    const std::string p = "clips[" + std::to_string(i) + "]";
    ClipResult c = parse_clip(r, clips[i], p);
    if (!names.insert(c.name).second) r.fail(p + ".name", "clip '" + c.name + "' is listed twice");
    s.clips.push_back(std::move(c));
  }
  s.sort_clips();
  return s;
}

BatchSummary read_summary(const std::string& path) { return parse_summary(read_file(path, kMaxSummaryBytes), path); }

BatchSummary merge_summaries(const std::vector<std::string>& summary_paths, const std::string& out_folder) {
  if (summary_paths.empty()) throw InputError("merge-summaries", "no summaries to merge");
  const fs::path out = absolute_folder(out_folder);
  BatchSummary merged;
  std::map<std::string, std::string> clip_source;  // clip name -> summary it came from
  std::map<int, std::set<int>> shards;             // N -> the I seen
  bool same_input = true;
  for (std::size_t k = 0; k < summary_paths.size(); ++k) {
    const std::string& path = summary_paths[k];
    BatchSummary s = read_summary(path);
    const fs::path from = absolute_folder(fs::path(path).parent_path().string());
    if (k == 0) {
      merged.tool_version = s.tool_version;
      merged.robot = s.robot;
      merged.robot_config = s.robot_config;
      merged.input = s.input;
      merged.check = s.check;
      merged.convert_options = s.convert_options;
      merged.started_utc = s.started_utc;
    } else {
      if (s.robot != merged.robot)
        throw InputError(path, "robot '" + s.robot + "' differs from '" + merged.robot + "' of " + summary_paths[0]);
      if (s.check != merged.check)
        throw InputError(path, std::string("was run ") + (s.check ? "with" : "without") + " --check, unlike " + summary_paths[0]);
      if (s.convert_options != merged.convert_options)
        throw InputError(path, "convert options '" + s.convert_options + "' differ from '" + merged.convert_options + "' of " +
                                   summary_paths[0]);
      same_input = same_input && s.input == merged.input;
      if (!s.started_utc.empty() && (merged.started_utc.empty() || s.started_utc < merged.started_utc))
        merged.started_utc = s.started_utc;
    }
    if (!s.shard.empty()) {
      const auto slash = s.shard.find('/');
      if (slash != std::string::npos)
        shards[std::atoi(s.shard.c_str() + slash + 1)].insert(std::atoi(s.shard.substr(0, slash).c_str()));
    }
    merged.jobs += s.jobs;
    merged.wall_s = std::max(merged.wall_s, s.wall_s);
    if (!s.stopped.empty() && merged.stopped.empty()) merged.stopped = s.stopped + " (" + path + ")";
    merged.merged_from.push_back(rebase(fs::path(path).filename().string(), from, out));
    for (ClipResult& c : s.clips) {
      const auto [it, inserted] = clip_source.emplace(c.name, path);
      if (!inserted) throw InputError(path, "clip '" + c.name + "' is also in " + it->second);
      for (std::string& d : c.files.data) d = rebase(d, from, out);
      for (std::string& p : c.files.plots) p = rebase(p, from, out);
      for (std::string* f : {&c.files.meta, &c.files.log, &c.files.report, &c.files.report_text, &c.files.view}) *f = rebase(*f, from, out);
      merged.clips.push_back(std::move(c));
    }
  }
  for (const auto& [n, seen] : shards) {
    if (shards.size() > 1 || static_cast<int>(seen.size()) == n) continue;
    for (int i = 1; i <= n; ++i)
      if (!seen.count(i))
        throw InputError("merge-summaries", format("shard %d/%d is missing (merged %zu of %d shards)", i, n, seen.size(), n));
  }
  if (!same_input) merged.input.clear();
  merged.sort_clips();
  return merged;
}

}  // namespace rt
