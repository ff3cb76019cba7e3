#include "retarget/reference/reference_io.hpp"

#include <cmath>
#include <filesystem>
#include <set>

#include "formats/reference/reference_csv.hpp"
#include "formats/reference/reference_meta.hpp"
#include "formats/reference/reference_npz.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

// Lower-case extension of the file name ("walk.CSV" -> "csv"), "" when none.
std::string extension_of(const std::string& path) {
  const std::string name = base_name(path);
  const auto dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? std::string() : to_lower(name.substr(dot + 1));
}

bool is_file(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

std::string robot_label(const std::string& robot_name) {
  return robot_name.empty() ? "the robot" : "robot " + robot_name;
}

// The checks of ReferenceReadOptions that hold for every format.
void check_against_options(Reference& r, const ReferenceReadOptions& o, const std::string& file) {
  if (!o.robot_name.empty()) {
    if (!r.robot_name.empty() && r.robot_name != o.robot_name)
      throw InputError(file, "reference is for robot '" + r.robot_name + "', not '" + o.robot_name + "'");
    r.robot_name = o.robot_name;
  }
  if (!o.joint_names.empty()) {
    const std::set<std::string> robot(o.joint_names.begin(), o.joint_names.end());
    const std::set<std::string> ours(r.joint_names.begin(), r.joint_names.end());
    std::string first_missing;
    for (const std::string& n : o.joint_names)
      if (!ours.count(n)) {
        first_missing = n;
        break;
      }
    if (r.joint_names.size() != o.joint_names.size())
      throw InputError(file, format("reference has %zu joints but %s has %zu%s", r.joint_names.size(),
                                    robot_label(o.robot_name).c_str(), o.joint_names.size(),
                                    first_missing.empty() ? "" : (" (first missing: " + first_missing + ")").c_str()));
    for (const std::string& n : r.joint_names)
      if (!robot.count(n))
        throw InputError(file, "joint '" + n + "' is not a joint of " + robot_label(o.robot_name));
  }
  if (o.fps > 0 && std::fabs(r.fps - o.fps) > 1e-9 * o.fps)
    throw InputError(file, format("the file says %.9g fps but --fps %.9g was given", r.fps, o.fps));
}

}  // namespace

const char* reference_format_name(ReferenceFormat format) {
  return format == ReferenceFormat::Csv ? "csv" : "npz";
}

std::vector<ReferenceFormat> parse_reference_formats(std::string_view list) {
  std::vector<ReferenceFormat> out;
  for (const std::string& item : split(list, ",")) {
    const std::string name = to_lower(trim(item));
    if (name.empty()) continue;
    ReferenceFormat f;
    if (name == "csv") {
      f = ReferenceFormat::Csv;
    } else if (name == "npz") {
      f = ReferenceFormat::Npz;
    } else {
      throw InputError("--format", "unknown output format '" + name + "' (expected csv, npz)");
    }
    bool seen = false;
    for (ReferenceFormat g : out) seen = seen || g == f;
    if (!seen) out.push_back(f);
  }
  if (out.empty()) throw InputError("--format", "no output format given (expected csv, npz or csv,npz)");
  return out;
}

std::string meta_path_for(const std::string& data_path) {
  const auto slash = data_path.find_last_of('/');
  const auto dot = data_path.find_last_of('.');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  return (has_ext ? data_path.substr(0, dot) : data_path) + ".meta.json";
}

void check_reference(const Reference& r, const std::string& where) {
  check_frame_rate(r.fps, where, "the frame rate");
  const int T = r.num_frames();
  if (T < 1) throw InputError(where, "reference has no frames");
  check_clip_duration(T / r.fps, where, format("the reference (%d frames at %g Hz)", T, r.fps));
  const Eigen::Index J = static_cast<Eigen::Index>(r.joint_names.size());
  if (J < 1) throw InputError(where, "reference has no joints");
  std::set<std::string> names;
  for (const std::string& n : r.joint_names) {
    if (n.empty()) throw InputError(where, "empty joint name");
    if (!names.insert(n).second) throw InputError(where, "duplicate joint name '" + n + "'");
  }
  RT_DEMAND(r.root_quat_W.size() == static_cast<std::size_t>(T), "Reference: one root quaternion per frame");
  RT_DEMAND(r.joint_pos.rows() == J && r.joint_pos.cols() == T, "Reference: joint_pos is joints x frames");
  RT_DEMAND(r.contact[0].size() == r.contact[1].size(), "Reference: contacts for both feet or neither");
  RT_DEMAND(r.contact[0].empty() || r.contact[0].size() == static_cast<std::size_t>(T), "Reference: one contact flag per frame");
  RT_DEMAND(r.com_W.cols() == 0 || r.com_W.cols() == T, "Reference: com_W has 0 or T columns");
  RT_DEMAND(r.cop_W.cols() == 0 || r.cop_W.cols() == T, "Reference: cop_W has 0 or T columns");
  for (int t = 0; t < T; ++t) {
    const std::string frame = format("%s frame %d", where.c_str(), t);
    if (!r.root_pos_W.col(t).allFinite()) throw InputError(frame + " root position", "non-finite value");
    const Quat& q = r.root_quat_W[static_cast<std::size_t>(t)];
    if (!q.coeffs().allFinite()) throw InputError(frame + " root orientation", "non-finite value");
    if (!(std::fabs(q.norm() - 1.0) <= 1e-3))
      throw InputError(frame + " root orientation", format("quaternion norm %.9g is not 1", q.norm()));
    for (Eigen::Index j = 0; j < J; ++j)
      if (!std::isfinite(r.joint_pos(j, t)))
        throw InputError(frame + " joint " + r.joint_names[static_cast<std::size_t>(j)], "non-finite value");
    for (std::size_t foot = 0; foot < 2; ++foot)
      if (!r.contact[foot].empty() && r.contact[foot][static_cast<std::size_t>(t)] > 1)
        throw InputError(frame + (foot ? " right foot" : " left foot"), "contact flag is not 0 or 1");
    if (r.com_W.cols() > 0 && !r.com_W.col(t).allFinite()) throw InputError(frame + " COM", "non-finite value");
    if (r.cop_W.cols() > 0 && !r.cop_W.col(t).allFinite()) throw InputError(frame + " COP", "non-finite value");
  }
}

Reference read_reference(const std::string& path, const ReferenceReadOptions& o, NpzBodyArrays* bodies) {
  const std::string file = base_name(path);
  const std::string ext = extension_of(path);
  const std::string meta_path = meta_path_for(path);
  const std::string meta_file = base_name(meta_path);
  if (bodies) *bodies = NpzBodyArrays();
  Reference r;
  if (ext == "csv") {
    CsvReadOptions c;
    c.quat_norm_tolerance = o.quat_norm_tolerance;
    if (is_file(meta_path)) {
      ReferenceMeta meta = parse_reference_meta(read_file(meta_path, o.max_file_bytes), meta_file);
      c.joint_names = meta.joint_names;
      c.joints_source = "in " + meta_file;
      c.quat_wxyz = meta.quat_wxyz;
      r = parse_reference_csv(read_file(path, o.max_file_bytes), file, c);
      apply_reference_meta(std::move(meta), meta_file, file, MetaMerge::Fill, r);
    } else {
      if (o.joint_names.empty() || !(o.fps > 0))
        throw InputError(file, "no " + meta_file + " beside it: a plain Unitree-layout CSV needs --fps and a robot "
                               "(--robot) for its frame rate and joint order");
      c.joint_names = o.joint_names;
      c.joints_source = "of " + robot_label(o.robot_name);
      r = parse_reference_csv(read_file(path, o.max_file_bytes), file, c);
      r.fps = o.fps;
    }
  } else if (ext == "npz") {
    r = read_reference_npz(path, o, bodies);
    if (is_file(meta_path))
      apply_reference_meta(parse_reference_meta(read_file(meta_path, o.max_file_bytes), meta_file), meta_file, file,
                           MetaMerge::CrossCheck, r);
  } else {
    throw InputError(file, "unknown reference format '" + (ext.empty() ? std::string("(no extension)") : "." + ext) +
                               "' (expected .csv or .npz)");
  }
  check_reference(r, file);
  check_against_options(r, o, file);
  return r;
}

std::vector<std::string> write_reference(const std::string& path_stem, const Reference& reference,
                                         const std::vector<ReferenceFormat>& formats, const NpzBodyArrays* body_arrays) {
  if (formats.empty()) throw InputError(path_stem, "no output format requested (--format csv,npz)");
  // Encode everything first: an invalid reference must not leave a partial set of new files.
  std::vector<std::pair<std::string, std::string>> files;
  std::vector<std::string> names;
  const std::string stem_name = base_name(path_stem);
  for (ReferenceFormat f : formats) {
    const std::string ext = std::string(".") + reference_format_name(f);
    bool seen = false;
    for (const auto& done : files) seen = seen || done.first == path_stem + ext;
    if (seen) continue;
    files.emplace_back(path_stem + ext, f == ReferenceFormat::Csv ? format_reference_csv(reference)
                                                                  : encode_reference_npz(reference, body_arrays));
    names.push_back(stem_name + ext);
  }
  // The meta goes last and an old one is removed first: its presence marks a complete output
  // (a crash in between leaves data files without meta, never new data with an old meta).
  const std::string meta_path = path_stem + ".meta.json";
  files.emplace_back(meta_path, format_reference_meta(reference, names));
  std::error_code ec;
  std::filesystem::remove(meta_path, ec);  // absent is fine; a failure shows up when writing it
  std::vector<std::string> written;
  for (const auto& [path, content] : files) {
    write_file_atomic(path, content);
    written.push_back(path);
  }
  return written;
}

}  // namespace rt
