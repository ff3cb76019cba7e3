#include "formats/reference/reference_meta.hpp"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "formats/reference/reference_csv.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/json_document.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/reference/reference_io.hpp"

namespace rt {

namespace {

// ordered_json keeps key order, so a written file reads like the schema and extra keys keep theirs.
using Json = nlohmann::ordered_json;

constexpr int kMaxJsonDepth = 64;
constexpr const char* kFootKeys[2] = {"left", "right"};

// Keys this module writes or interprets; everything else is the caller's (extra_meta_json).
const std::set<std::string>& reserved_keys() {
  static const std::set<std::string> keys = {
      "format",    "format_version", "robot", "fps",         "num_frames", "duration_s",
      "files",     "joint_names",    "quaternion_order",     "npz_quaternion_order",
      "csv",       "units",          "world_frame",          "contacts",   "com_pos_w",
      "cop_ref_w", "zmp_w",          "time_s"};
  return keys;
}

std::string dump_compact(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

// Small values on one line, large objects one key per line, large arrays one element per line:
// readable without putting every COM coordinate on a line of its own.
void dump_pretty(const Json& j, int indent, std::string& out) {
  const std::string compact = dump_compact(j);
  if (!j.is_structured() || j.empty() || (indent > 0 && compact.size() + static_cast<std::size_t>(indent) <= 100)) {
    out += compact;
    return;
  }
  const bool object = j.is_object();
  out += object ? "{\n" : "[\n";
  std::size_t i = 0;
  for (auto it = j.begin(); it != j.end(); ++it, ++i) {
    out.append(static_cast<std::size_t>(indent) + 2, ' ');
    if (object) {
      out += dump_compact(Json(it.key()));
      out += ": ";
    }
    dump_pretty(*it, indent + 2, out);
    if (i + 1 < j.size()) out.push_back(',');
    out.push_back('\n');
  }
  out.append(static_cast<std::size_t>(indent), ' ');
  out.push_back(object ? '}' : ']');
}

std::string key_loc(const std::string& file, const std::string& path) { return file + " [" + path + "]"; }

class MetaReader {
 public:
  explicit MetaReader(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw InputError(key_loc(file_, path), what);
  }

  double number(const Json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "expected a number, got " + json_type_phrase(j));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "expected a finite number");
    return v;
  }
  long long integer(const Json& j, const std::string& path, long long lo, long long hi) const {
    if (!j.is_number_integer()) fail(path, "expected an integer, got " + json_type_phrase(j));
    if (j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(hi))
      fail(path, format("%s is out of range [%lld, %lld]", dump_compact(j).c_str(), lo, hi));
    const long long v = j.get<long long>();
    if (v < lo || v > hi) fail(path, format("%lld is out of range [%lld, %lld]", v, lo, hi));
    return v;
  }
  std::string string(const Json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string, got " + json_type_phrase(j));
    return j.get<std::string>();
  }
  const Json& array(const Json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, "expected an array, got " + json_type_phrase(j));
    return j;
  }
  // [[a, b, ...], ...] with `width` numbers per row -> width x n matrix.
  MatX rows(const Json& j, const std::string& path, int width) const {
    array(j, path);
    MatX m(width, static_cast<Eigen::Index>(j.size()));
    for (std::size_t k = 0; k < j.size(); ++k) {
      const std::string p = format("%s[%zu]", path.c_str(), k);
      const Json& row = j[k];
      if (!row.is_array() || row.size() != static_cast<std::size_t>(width))
        fail(p, format("expected an array of %d numbers", width));
      for (int i = 0; i < width; ++i) m(i, static_cast<Eigen::Index>(k)) = number(row[static_cast<std::size_t>(i)], p);
    }
    return m;
  }

 private:
  const std::string& file_;
};

}  // namespace

void check_time_stamps(const std::vector<double>& t, double fps, const std::string& where) {
  const double dt = 1.0 / fps;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (!std::isfinite(t[k])) throw InputError(where, format("time stamp %zu is not finite", k));
    if (k == 0) continue;
    const double step = t[k] - t[k - 1];
    if (!(step > 0))
      throw InputError(where, format("time stamps are not increasing at index %zu (%.9g s after %.9g s)", k, t[k],
                                     t[k - 1]));
    if (std::fabs(step - dt) > 0.01 * dt)
      throw InputError(where, format("non-uniform time step at index %zu: %.9g s, expected 1/fps = %.9g s", k, step,
                                     dt));
  }
}

std::string format_reference_meta(const Reference& r, const std::vector<std::string>& data_files) {
  check_reference(r, "reference");
  Json extra;
  try {
    extra = Json::parse(r.extra_meta_json);
  } catch (const Json::exception& e) {
    throw InternalError(std::string("Reference::extra_meta_json is not valid JSON: ") + e.what());
  }
  RT_DEMAND(extra.is_object(), "Reference::extra_meta_json must be a JSON object");
  RT_DEMAND(json_depth(extra, kMaxJsonDepth + 1) <= kMaxJsonDepth, "Reference::extra_meta_json nests too deep");
  for (const auto& item : extra.items())
    RT_DEMAND(reserved_keys().count(item.key()) == 0,
              "Reference::extra_meta_json uses the key '" + item.key() + "' that the meta writer owns");

  const int T = r.num_frames();
  const int J = static_cast<int>(r.joint_names.size());
  Json m;
  m["format"] = kMetaFormat;
  m["format_version"] = kMetaFormatVersion;
  if (!r.robot_name.empty()) m["robot"] = r.robot_name;
  m["fps"] = r.fps;
  m["num_frames"] = T;
  m["duration_s"] = r.duration_s();
  m["files"] = data_files;
  m["joint_names"] = r.joint_names;
  m["quaternion_order"] = "xyzw";
  m["npz_quaternion_order"] = "wxyz";
  m["csv"] = Json{{"header", false},
                  {"columns", 7 + J},
                  {"number_format", "%.9g"},
                  {"layout", {"root_pos_w x y z [m]", "root_quat_w x y z w", "joint_pos in joint_names order"}}};
  m["units"] = Json{{"length", "m"}, {"angle", "rad"}, {"time", "s"}, {"joint_pos", "rad (revolute), m (prismatic)"}};
  m["world_frame"] = "z up, floor at z = 0";
  if (r.has_contacts()) {
    Json contacts;
    contacts["encoding"] = "[begin_frame, end_frame) stance intervals per foot";
    for (int foot = 0; foot < 2; ++foot) {
      Json list = Json::array();
      for (const FrameInterval& iv : contact_intervals(r.contact[static_cast<std::size_t>(foot)]))
        list.push_back(Json::array({iv.begin, iv.end}));
      contacts[kFootKeys[foot]] = std::move(list);
    }
    m["contacts"] = std::move(contacts);
  }
  if (r.com_W.cols() > 0) {
    Json rows = Json::array();
    for (Eigen::Index t = 0; t < r.com_W.cols(); ++t) rows.push_back({r.com_W(0, t), r.com_W(1, t), r.com_W(2, t)});
    m["com_pos_w"] = std::move(rows);
  }
  if (r.cop_W.cols() > 0) {
    Json rows = Json::array();
    for (Eigen::Index t = 0; t < r.cop_W.cols(); ++t) rows.push_back({r.cop_W(0, t), r.cop_W(1, t)});
    m["zmp_w"] = rows;  // the issue-14 name; cop_ref_w (design.md) kept for readers of the first format
    m["cop_ref_w"] = std::move(rows);
  }
  for (auto& item : extra.items()) m[item.key()] = item.value();

  std::string out;
  dump_pretty(m, 0, out);
  out.push_back('\n');
  return out;
}

ReferenceMeta parse_reference_meta(std::string_view text, const std::string& file) {
  const Json j = parse_json_object(text, file, "meta.json", kMaxJsonDepth);
  MetaReader in(file);

  ReferenceMeta m;
  Json extra = Json::object();
  long long csv_columns = -1;
  for (auto& item : j.items()) {
    const std::string& key = item.key();
    const Json& v = item.value();
    if (key == "format") {
      if (in.string(v, key) != kMetaFormat)
        in.fail(key, "unknown format '" + one_line(v.get<std::string>()).substr(0, 60) + "', expected '" + kMetaFormat + "'");
    } else if (key == "format_version") {
      const long long version = in.integer(v, key, 1, std::numeric_limits<int>::max());
      if (version > kMetaFormatVersion)
        in.fail(key, format("format version %lld is newer than this reader (%d); update retarget", version,
                            kMetaFormatVersion));
    } else if (key == "robot") {
      m.robot_name = in.string(v, key);
    } else if (key == "fps") {
      m.fps = in.number(v, key);
      if (!(m.fps >= kMinFrameRate_hz && m.fps <= kMaxFrameRate_hz))
        in.fail(key, format("the frame rate is %.6g Hz, not %s", m.fps, range_in_words(kMinFrameRate_hz, kMaxFrameRate_hz, "Hz").c_str()));
    } else if (key == "num_frames") {
      m.num_frames = static_cast<int>(in.integer(v, key, 1, std::numeric_limits<int>::max()));
    } else if (key == "joint_names") {
      in.array(v, key);
      std::set<std::string> seen;
      for (std::size_t i = 0; i < v.size(); ++i) {
        const std::string p = format("joint_names[%zu]", i);
        std::string name = in.string(v[i], p);
        if (name.empty()) in.fail(p, "empty joint name");
        if (!seen.insert(name).second) in.fail(p, "duplicate joint name '" + one_line(name) + "'");
        m.joint_names.push_back(std::move(name));
      }
    } else if (key == "quaternion_order") {
      const std::string order = in.string(v, key);
      if (order != "xyzw" && order != "wxyz")
        in.fail(key, "quaternion order '" + one_line(order).substr(0, 20) + "' is not \"xyzw\" or \"wxyz\"");
      m.quat_wxyz = order == "wxyz";
    } else if (key == "units") {
      if (!v.is_object()) in.fail(key, "expected an object");
      static const std::pair<const char*, const char*> kUnits[] = {{"length", "m"}, {"angle", "rad"}, {"time", "s"}};
      for (const auto& [unit, expected] : kUnits) {
        if (!v.contains(unit)) continue;
        const std::string got = in.string(v[unit], std::string("units.") + unit);
        if (got != expected)
          in.fail(std::string("units.") + unit, "unit '" + one_line(got).substr(0, 20) + "' is not supported (only '" +
                                                    expected + "')");
      }
    } else if (key == "csv") {
      if (!v.is_object()) in.fail(key, "expected an object");
      if (v.contains("header") && !(v["header"].is_boolean() && !v["header"].get<bool>()))
        in.fail("csv.header", "reference CSVs have no header row (expected false)");
      if (v.contains("columns")) {
        const long long cols = in.integer(v["columns"], "csv.columns", 0, std::numeric_limits<int>::max());
        csv_columns = cols;  // checked against joint_names once all keys are read
      }
    } else if (key == "contacts") {
      if (!v.is_object()) in.fail(key, "expected an object");
      m.has_contacts = true;
      for (int foot = 0; foot < 2; ++foot) {
        const std::string p = std::string("contacts.") + kFootKeys[foot];
        if (!v.contains(kFootKeys[foot])) in.fail(p, "missing (contacts need both feet)");
        const Json& list = in.array(v[kFootKeys[foot]], p);
        for (std::size_t k = 0; k < list.size(); ++k) {
          const std::string pk = format("%s[%zu]", p.c_str(), k);
          if (!list[k].is_array() || list[k].size() != 2) in.fail(pk, "expected [begin_frame, end_frame]");
          FrameInterval iv;
          iv.begin = static_cast<int>(in.integer(list[k][0], pk, 0, std::numeric_limits<int>::max()));
          iv.end = static_cast<int>(in.integer(list[k][1], pk, 0, std::numeric_limits<int>::max()));
          m.stance[static_cast<std::size_t>(foot)].push_back(iv);
        }
      }
    } else if (key == "com_pos_w") {
      m.com_W = in.rows(v, key, 3);
    } else if (key == "zmp_w" || key == "cop_ref_w") {
      // The same plan under both names; zmp_w wins where a file has both.
      if (key == "zmp_w" || m.cop_W.cols() == 0) m.cop_W = in.rows(v, key, 2);
    } else if (key == "time_s") {
      in.array(v, key);
      for (std::size_t k = 0; k < v.size(); ++k) m.time_s.push_back(in.number(v[k], format("time_s[%zu]", k)));
    } else if (reserved_keys().count(key) != 0) {
      // Informational keys the writer regenerates (duration_s, files, world_frame, ...).
    } else {
      extra[key] = v;
    }
  }
  if (m.fps == 0) throw InputError(file, "missing required key 'fps'");
  if (m.joint_names.empty()) throw InputError(file, "missing required key 'joint_names' (or it is empty)");
  if (csv_columns >= 0 && csv_columns != 7 + static_cast<long long>(m.joint_names.size()))
    throw InputError(key_loc(file, "csv.columns"),
                     format("%lld columns disagree with the %zu joint_names (7 root + %zu joints = %zu)",
                            csv_columns, m.joint_names.size(), m.joint_names.size(), 7 + m.joint_names.size()));
  m.extra_json = dump_compact(extra);
  return m;
}

void apply_reference_meta(ReferenceMeta meta, const std::string& meta_file, const std::string& data_file,
                          MetaMerge merge, Reference& r) {
  const int T = r.num_frames();
  if (meta.num_frames >= 0 && meta.num_frames != T)
    throw InputError(key_loc(meta_file, "num_frames"),
                     format("meta says %d frames but %s has %d", meta.num_frames, data_file.c_str(), T));
  if (merge == MetaMerge::CrossCheck) {
    if (std::fabs(meta.fps - r.fps) > 1e-6 * meta.fps)
      throw InputError(key_loc(meta_file, "fps"),
                       format("meta says %.9g fps but %s says %.9g", meta.fps, data_file.c_str(), r.fps));
    // The same joints; the order may differ (an NPZ in a simulator's order beside the CSV's meta).
    if (std::set<std::string>(meta.joint_names.begin(), meta.joint_names.end()) !=
            std::set<std::string>(r.joint_names.begin(), r.joint_names.end()) ||
        meta.joint_names.size() != r.joint_names.size())
      throw InputError(key_loc(meta_file, "joint_names"),
                       format("the %zu joint names differ from the %zu of %s", meta.joint_names.size(),
                              r.joint_names.size(), data_file.c_str()));
  } else {
    r.fps = meta.fps;
    r.joint_names = meta.joint_names;
  }
  if (!meta.time_s.empty()) {
    if (meta.time_s.size() != static_cast<std::size_t>(T))
      throw InputError(key_loc(meta_file, "time_s"),
                       format("%zu time stamps for %d frames of %s", meta.time_s.size(), T, data_file.c_str()));
    check_time_stamps(meta.time_s, meta.fps, key_loc(meta_file, "time_s"));
  }
  if (meta.has_contacts) {
    for (std::size_t foot = 0; foot < 2; ++foot) {
      int previous_end = 0;
      for (std::size_t k = 0; k < meta.stance[foot].size(); ++k) {
        const FrameInterval& iv = meta.stance[foot][k];
        const std::string where = key_loc(meta_file, format("contacts.%s[%zu]", kFootKeys[foot], k));
        if (iv.begin >= iv.end)
          throw InputError(where, format("stance interval [%d, %d) is empty or reversed", iv.begin, iv.end));
        if (iv.end > T)
          throw InputError(where, format("stance interval [%d, %d) ends after the clip's %d frames", iv.begin, iv.end, T));
        if (iv.begin < previous_end)
          throw InputError(where, format("stance interval [%d, %d) overlaps or precedes the one ending at %d",
                                         iv.begin, iv.end, previous_end));
        previous_end = iv.end;
      }
    }
    if (merge == MetaMerge::Fill || !r.has_contacts())
      for (std::size_t foot = 0; foot < 2; ++foot) r.contact[foot] = contact_flags(meta.stance[foot], T);
  }
  if (meta.com_W.cols() > 0) {
    if (meta.com_W.cols() != T)
      throw InputError(key_loc(meta_file, "com_pos_w"),
                       format("%lld rows for %d frames of %s", static_cast<long long>(meta.com_W.cols()), T, data_file.c_str()));
    if (merge == MetaMerge::Fill || r.com_W.cols() == 0) r.com_W = std::move(meta.com_W);
  }
  if (meta.cop_W.cols() > 0) {
    if (meta.cop_W.cols() != T)
      throw InputError(key_loc(meta_file, "cop_ref_w"),
                       format("%lld rows for %d frames of %s", static_cast<long long>(meta.cop_W.cols()), T, data_file.c_str()));
    if (merge == MetaMerge::Fill || r.cop_W.cols() == 0) r.cop_W = std::move(meta.cop_W);
  }
  if (!meta.robot_name.empty()) r.robot_name = std::move(meta.robot_name);
  r.extra_meta_json = std::move(meta.extra_json);
}

}  // namespace rt
