#include "retarget/batch/clip_discovery.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <system_error>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/core/yaml_view.hpp"
#include "retarget/motion/load_motion.hpp"

namespace rt {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kMaxManifestBytes = 64ull << 20;
constexpr std::size_t kMaxOutputNameLength = 1024;

// Canonical form for the escape check: symlinks resolved where the path exists.
fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : r;
}

bool is_within(const fs::path& root, const fs::path& p) {
  const fs::path rel = p.lexically_relative(root);
  if (rel.empty()) return false;
  const std::string first = rel.begin()->string();
  return first != ".." && !rel.is_absolute();
}

std::uint64_t file_size_or_zero(const fs::path& p) {
  std::error_code ec;
  const auto n = fs::file_size(p, ec);
  return ec ? 0 : static_cast<std::uint64_t>(n);
}

// Output name of a clip path: relative to the root without its extension when inside the root,
// else the file name without its extension.
std::string default_output_name(const fs::path& root, const fs::path& clip) {
  const fs::path rel = clip.lexically_relative(root);
  if (!rel.empty() && is_within(root, clip)) return (rel.parent_path() / rel.stem()).generic_string();
  return clip.stem().string();
}

// Per-clip entry of a manifest before paths are resolved.
struct ManifestEntry {
  std::string where;  // file:line
  std::string path;
  std::string output;
  ClipOverrides overrides;
  std::string profile_raw;
};

// The checks both manifest formats share for override values; `fail` throws at the value.
template <class Fail>
void check_overrides(const ClipOverrides& o, Fail fail) {
  if (o.source_units && o.source_units->empty()) fail("source_units", "expected a units name or number");
  if (o.up_axis && o.up_axis->empty()) fail("up_axis", "expected x, y or z");
  if (o.source_units) {
    try {
      (void)metres_per_unit(*o.source_units);
    } catch (const InputError& e) {
      fail("source_units", e.message());
    }
  }
  if (o.up_axis) {
    try {
      (void)parse_up_axis(*o.up_axis);
    } catch (const InputError& e) {
      fail("up_axis", e.message());
    }
  }
  if (o.source_fps && !(*o.source_fps > 0)) fail("source_fps", "expected a positive frame rate [Hz]");
  if (o.time_scale && !(*o.time_scale >= 0.05 && *o.time_scale <= 20.0))
    fail("time_scale", "expected a time scale in [0.05, 20]");
}

std::vector<ManifestEntry> parse_yaml_manifest(const std::string& text, const std::string& file) {
  const YamlView root = YamlView::load_string(text, file);
  root.expect_map();
  root.check_keys({"clips"});
  const YamlView clips = root.at("clips");
  clips.expect_sequence();
  std::vector<ManifestEntry> out;
  for (std::size_t i = 0; i < clips.size(); ++i) {
    const YamlView item = clips.at(i);
    ManifestEntry e;
    e.where = item.location();
    if (item.is_scalar()) {
      e.path = item.as_string();
    } else {
      item.expect_map();
      item.check_keys({"path", "output", "source_units", "source_fps", "time_scale", "up_axis", "profile"});
      e.path = item.at("path").as_string();
      e.output = item.get("output", "");
      if (auto v = item.find("source_units")) e.overrides.source_units = v->as_string();
      if (auto v = item.find("source_fps")) e.overrides.source_fps = v->as_double();
      if (auto v = item.find("time_scale")) e.overrides.time_scale = v->as_double();
      if (auto v = item.find("up_axis")) e.overrides.up_axis = v->as_string();
      if (auto v = item.find("profile")) e.profile_raw = v->as_string();
      check_overrides(e.overrides, [&](const std::string& key, const std::string& msg) { item.at(key).fail(msg); });
      if (item.has("output") && e.output.empty()) item.at("output").fail("expected a non-empty output name");
    }
    if (e.path.empty()) item.fail("expected a clip path");
    out.push_back(std::move(e));
  }
  return out;
}

// One CSV record split into fields (RFC 4180 quoting within a line). `where` is file:line.
std::vector<std::string> split_csv_record(const std::string& line, const std::string& where) {
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false, was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < line.size() && line[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        field += c;
      }
    } else if (c == '"') {
      if (!trim(field).empty()) throw InputError(where + ":" + std::to_string(i + 1), "a quote inside an unquoted field");
      field.clear();
      quoted = was_quoted = true;
    } else if (c == ',') {
      fields.push_back(was_quoted ? field : std::string(trim(field)));
      field.clear();
      was_quoted = false;
    } else if (was_quoted) {
      if (c != ' ' && c != '\t') throw InputError(where + ":" + std::to_string(i + 1), "text after a closing quote");
    } else {
      field += c;
    }
  }
  if (quoted) throw InputError(where, "unterminated quoted field (fields cannot span lines)");
  fields.push_back(was_quoted ? field : std::string(trim(field)));
  return fields;
}

double parse_csv_number(const std::string& cell, const std::string& where, const std::string& column) {
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(v))
    throw InputError(where, "column " + column + ": expected a number, got '" + cell + "'");
  return v;
}

std::vector<ManifestEntry> parse_csv_manifest(const std::string& text, const std::string& file) {
  static const std::vector<std::string> kColumns = {"path",    "output",     "source_units", "source_fps",
                                                    "time_scale", "up_axis", "profile"};
  std::vector<ManifestEntry> out;
  std::vector<std::string> header;
  std::size_t pos = 0;
  int line_no = 0;
  while (pos <= text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no == 1 && starts_with(line, "\xEF\xBB\xBF")) line.erase(0, 3);  // UTF-8 byte-order mark
    const std::string where = file + ":" + std::to_string(line_no);
    const std::string_view t = trim(line);
    if (t.empty() || t.front() == '#') {
      if (pos > text.size()) break;
      continue;
    }
    std::vector<std::string> cells = split_csv_record(line, where);
    if (header.empty()) {
      for (std::string& c : cells) {
        c = to_lower(c);
        if (std::find(kColumns.begin(), kColumns.end(), c) == kColumns.end())
          throw InputError(where, "unknown column '" + c + "' (allowed: " + join(kColumns, ", ") +
                                      "; the first row must name the columns)");
        if (std::count(cells.begin(), cells.end(), c) > 1) throw InputError(where, "column '" + c + "' appears twice");
      }
      if (std::find(cells.begin(), cells.end(), "path") == cells.end())
        throw InputError(where, "the header row has no 'path' column");
      header = cells;
      continue;
    }
    if (cells.size() != header.size())
      throw InputError(where, format("expected %zu fields (as in the header), got %zu", header.size(), cells.size()));
    ManifestEntry e;
    e.where = where;
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const std::string& col = header[k];
      const std::string& v = cells[k];
      if (v.empty()) continue;
      if (col == "path") e.path = v;
      else if (col == "output") e.output = v;
      else if (col == "source_units") e.overrides.source_units = v;
      else if (col == "source_fps") e.overrides.source_fps = parse_csv_number(v, where, col);
      else if (col == "time_scale") e.overrides.time_scale = parse_csv_number(v, where, col);
      else if (col == "up_axis") e.overrides.up_axis = v;
      else if (col == "profile") e.profile_raw = v;
    }
    if (e.path.empty()) throw InputError(where, "column path: expected a clip path");
    check_overrides(e.overrides,
                    [&](const std::string& key, const std::string& msg) { throw InputError(where, "column " + key + ": " + msg); });
    out.push_back(std::move(e));
    if (pos > text.size()) break;
  }
  if (header.empty()) throw InputError(file, "empty manifest: expected a header row naming the columns (path, ...)");
  return out;
}

fs::path absolute_normal(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  return (ec ? p : a).lexically_normal();
}

std::vector<BatchClip> clips_from_entries(const std::vector<ManifestEntry>& entries, const fs::path& manifest_dir,
                                          const ClipDiscoveryOptions& options) {
  const fs::path root = absolute_normal(manifest_dir);
  const fs::path root_resolved = resolved(root);
  std::vector<BatchClip> clips;
  for (const ManifestEntry& e : entries) {
    fs::path p(e.path);
    if (p.is_relative()) p = root / p;
    p = p.lexically_normal();
    if (!options.allow_outside && !is_within(root_resolved, resolved(p)))
      throw InputError(e.where, "clip path '" + e.path + "' is outside the manifest's folder " + root.string() +
                                    " (pass --allow-outside to accept it)");
    BatchClip c;
    c.input = p.string();
    if (!options.allow_outside) c.input_root = root_resolved.string();
    c.input_bytes = file_size_or_zero(p);
    c.origin = e.where;
    c.overrides = e.overrides;
    if (!e.profile_raw.empty()) {
      fs::path prof(e.profile_raw);
      if (prof.is_relative()) prof = root / prof;
      prof = prof.lexically_normal();
      // Under the same rule as the clips: otherwise any readable file could be opened (and its
      // first line echoed in the error) through a manifest.
      if (!options.allow_outside && !is_within(root_resolved, resolved(prof)))
        throw InputError(e.where, "profile '" + e.profile_raw + "' is outside the manifest's folder " + root.string() +
                                      " (pass --allow-outside to accept it)");
      std::error_code ec;
      if (!fs::is_regular_file(prof, ec))
        throw InputError(e.where, "profile '" + e.profile_raw + "' not found (looked for " + prof.string() + ")");
      c.overrides.profile = prof.string();
    }
    c.output_name = e.output.empty() ? default_output_name(root, p) : e.output;
    check_output_name(c.output_name, e.where);
    clips.push_back(std::move(c));
  }
  if (clips.empty()) throw InputError(entries.empty() ? manifest_dir.string() : entries.front().where, "the manifest lists no clips");
  return clips;
}

std::vector<BatchClip> discover_folder(const fs::path& folder, const ClipDiscoveryOptions& options) {
  const fs::path root = absolute_normal(folder);
  const fs::path root_resolved = resolved(root);
  std::vector<BatchClip> clips;
  std::error_code ec;
  fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end;
  if (ec) throw InputError(folder.string(), "cannot list the folder: " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) throw InputError(folder.string(), "cannot list the folder: " + ec.message());
    const fs::path& p = it->path();
    const std::string name = p.filename().string();
    if (!name.empty() && name.front() == '.') {  // hidden files and folders (.git, editors' temporaries)
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (!is_motion_file(name) || !it->is_regular_file(ec)) continue;
    const fs::path abs = p.lexically_normal();
    if (!options.allow_outside && !is_within(root_resolved, resolved(abs)))
      throw InputError(abs.string(), "a symlink to a file outside the input folder " + root.string() +
                                         " (pass --allow-outside to accept it)");
    BatchClip c;
    c.input = abs.string();
    if (!options.allow_outside) c.input_root = root_resolved.string();
    c.input_bytes = file_size_or_zero(abs);
    c.origin = root.string();
    c.output_name = default_output_name(root, abs);
    check_output_name(c.output_name, abs.string());
    clips.push_back(std::move(c));
  }
  std::sort(clips.begin(), clips.end(), [](const BatchClip& a, const BatchClip& b) { return a.input < b.input; });
  if (clips.empty()) throw InputError(folder.string(), "no .bvh, .c3d or .amc files in this folder (searched recursively)");
  return clips;
}

}  // namespace

bool is_motion_file(const std::string& path) {
  const std::string lower = to_lower(path);
  return ends_with(lower, ".bvh") || ends_with(lower, ".c3d") || ends_with(lower, ".amc");
}

bool is_manifest_path(const std::string& input) {
  const std::string lower = to_lower(input);
  return ends_with(lower, ".yaml") || ends_with(lower, ".yml") || ends_with(lower, ".csv");
}

void check_output_name(const std::string& name, const std::string& where) {
  auto fail = [&](const std::string& why) { throw InputError(where, "output name '" + name + "' " + why); };
  if (name.empty()) fail("is empty");
  if (name.size() > kMaxOutputNameLength) fail("is too long");
  if (name.front() == '/') fail("must be relative to the output folder");
  for (const char c : name) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) fail("contains a control character");
    if (c == '\\') fail("contains a backslash (use '/' between folders)");
  }
  if (name.back() == '/' || name.find("//") != std::string::npos) fail("has an empty folder component");
  for (const std::string& part : split(name, "/"))
    if (part == "." || part == "..") fail("must not contain '.' or '..' components");
  if (name == "summary" || starts_with(name, "summary-shard-") || starts_with(name, ".retarget-batch"))
    fail("is reserved for the batch's summary files");
}

void check_unique_output_names(const std::vector<BatchClip>& clips) {
  std::map<std::string, const BatchClip*> seen;
  for (const BatchClip& c : clips) {
    const auto [it, inserted] = seen.emplace(c.output_name, &c);
    if (!inserted) {
      const BatchClip& first = *it->second;
      throw InputError(c.origin, "output name '" + c.output_name + "' of " + c.input + " is already used by " +
                                     first.input + (first.origin != c.origin ? " (" + first.origin + ")" : std::string()) +
                                     "; give one of them another name (a manifest's `output`)");
    }
  }
}

std::vector<BatchClip> parse_manifest(const std::string& text, const std::string& manifest_path, bool csv,
                                      const ClipDiscoveryOptions& options) {
  const std::vector<ManifestEntry> entries =
      csv ? parse_csv_manifest(text, manifest_path) : parse_yaml_manifest(text, manifest_path);
  fs::path dir = fs::path(manifest_path).parent_path();
  if (dir.empty()) dir = ".";
  std::vector<BatchClip> clips = clips_from_entries(entries, dir, options);
  check_unique_output_names(clips);
  return clips;
}

std::vector<BatchClip> discover_clips(const std::string& input, const ClipDiscoveryOptions& options) {
  std::error_code ec;
  if (input.empty()) throw InputError("batch", "no input given (a folder or a manifest)");
  if (fs::is_directory(input, ec)) {
    std::vector<BatchClip> clips = discover_folder(input, options);
    check_unique_output_names(clips);
    return clips;
  }
  if (!fs::exists(input, ec)) throw InputError(input, "no such file or folder");
  if (!is_manifest_path(input))
    throw InputError(input, "expected a folder of clips or a manifest (.yaml, .yml or .csv); to convert one clip, use "
                            "'retarget convert'");
  const std::string lower = to_lower(input);
  return parse_manifest(read_file(input, kMaxManifestBytes), input, ends_with(lower, ".csv"), options);
}

}  // namespace rt
