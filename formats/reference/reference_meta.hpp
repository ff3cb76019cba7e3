#pragma once
/// `<name>.meta.json`: everything needed to interpret a reference CSV/NPZ beside it (design.md §5).
///
/// Schema (format "retarget-reference", version 1). Keys the project writes, in this order:
///
///   format               "retarget-reference"
///   format_version       1 (a reader refuses a newer version)
///   robot                robot.yaml name (omitted when unknown)
///   fps                  [Hz] frame rate, > 0; frame k is at t = k / fps             (required)
///   num_frames           T, the CSV row count / NPZ first dimension
///   duration_s           (T - 1) / fps, informational
///   files                data files written with this meta (["walk.csv", "walk.npz"])
///   joint_names          joint names in CSV column order (columns 8...)               (required)
///   quaternion_order     "xyzw": order of the CSV root quaternion columns 4-7 ("wxyz" is read too)
///   npz_quaternion_order "wxyz": order of root_quat_w / body_quat_w in the NPZ, informational
///   csv                  {"header": false, "columns": 7 + J, "number_format": "%.9g", "layout": [...]}
///   units                {"length": "m", "angle": "rad", "time": "s", ...}; other units are refused
///   world_frame          "z up, floor at z = 0", informational
///   contacts             {"encoding": ..., "left": [[b, e], ...], "right": [[b, e], ...]}: stance
///                        intervals [begin, end) in frames per foot, ordered, inside [0, T)
///   com_pos_w            [[x, y, z], ...] planned COM per frame [m] (when present)
///   zmp_w                [[x, y], ...] planned ZMP per frame [m], the COP to realise (when present)
///   cop_ref_w            the same as zmp_w (design.md's name); read when zmp_w is absent
///   <extra keys>         Reference::extra_meta_json merged in (provenance: tool version, source
///                        file and hash, urdf_sha256, passes with options; quality metrics)
///
/// Also read when present: `time_s` ([t0, t1, ...], T time stamps [s]; must increase strictly with
/// a uniform step 1/fps within 1 %). Every other key is kept verbatim (order included) in
/// Reference::extra_meta_json, so read -> write loses nothing. Numbers are written with the
/// shortest decimal that reads back to the same double, so COM/COP survive bit-exactly.
///
/// Example (G1, 3 frames, abridged):
///   {
///     "format": "retarget-reference",
///     "format_version": 1,
///     "robot": "g1",
///     "fps": 30.0,
///     "num_frames": 3,
///     "duration_s": 0.06666666666666667,
///     "files": ["walk.csv","walk.npz"],
///     "joint_names": [ "left_hip_pitch_joint", ... ],
///     "quaternion_order": "xyzw",
///     "npz_quaternion_order": "wxyz",
///     "csv": {"header":false,"columns":36,"number_format":"%.9g","layout":[...]},
///     "units": {"length":"m","angle":"rad","time":"s","joint_pos":"rad (revolute), m (prismatic)"},
///     "world_frame": "z up, floor at z = 0",
///     "contacts": {"encoding":"[begin_frame, end_frame) stance intervals per foot","left":[[0,3]],"right":[[0,2]]},
///     "com_pos_w": [[0.01,0.0,0.68],[0.011,0.0,0.68],[0.012,0.0,0.68]],
///     "urdf_sha256": "9f2c...",
///     "provenance": {"tool": "retarget 0.1.0", "source": "walk.bvh", ...}
///   }
///
/// Errors are InputError located "<file>:<line>:<column>" for JSON syntax and "<file> [<key path>]"
/// (e.g. "walk.meta.json [contacts.left[2]]") for content.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/reference/contact_intervals.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

constexpr const char* kMetaFormat = "retarget-reference";
constexpr int kMetaFormatVersion = 1;

/// A parsed meta.json, checked on its own (types, names, rates); the checks against the frame
/// count happen in apply_reference_meta.
struct ReferenceMeta {
  std::string robot_name;                          ///< "" when absent
  double fps = 0;                                  ///< [Hz]
  std::vector<std::string> joint_names;            ///< column order, unique
  int num_frames = -1;                             ///< -1 when absent
  bool quat_wxyz = false;                          ///< "quaternion_order": "wxyz"
  bool has_contacts = false;
  std::array<std::vector<FrameInterval>, 2> stance;  ///< [0 left, 1 right] as stored (unchecked)
  Mat3X com_W;                                     ///< 3 x n, n = 0 when absent
  Eigen::Matrix2Xd cop_W;                          ///< 2 x n, n = 0 when absent
  std::vector<double> time_s;                      ///< empty when absent
  std::string extra_json = "{}";                   ///< the other keys, a JSON object
};

/// The meta.json text for `reference` (after check_reference). `data_files` lists the data file
/// names written with it (for "files"). InternalError when Reference::extra_meta_json is not a
/// JSON object, nests deeper than 64 levels, or uses a key this writer owns.
std::string format_reference_meta(const Reference& reference, const std::vector<std::string>& data_files);

/// Parses meta.json text; `file` names it in errors.
ReferenceMeta parse_reference_meta(std::string_view text, const std::string& file);

/// How apply_reference_meta combines the meta with what the data file already gave.
enum class MetaMerge {
  Fill,        ///< CSV: the meta is the only source of fps, contacts, COM and COP
  CrossCheck,  ///< NPZ: fps and joint names must agree; contacts/COM/COP only fill what is missing
};

/// Checks `meta` against `reference` (read from `data_file`, T frames): num_frames equals T,
/// contact intervals ordered and inside [0, T), COM/COP have T columns, time stamps (if any) T
/// strictly increasing uniform values; then moves the meta's content into `reference` (robot,
/// fps, contacts, COM, COP, extra_meta_json). Errors are InputError located in `meta_file`.
void apply_reference_meta(ReferenceMeta meta, const std::string& meta_file, const std::string& data_file,
                          MetaMerge merge, Reference& reference);

/// Time stamps [s] must be finite, strictly increasing, and uniform with step 1/fps within 1 % of
/// a frame period. InputError "<where>: ..." naming the first bad index otherwise.
void check_time_stamps(const std::vector<double>& t_s, double fps, const std::string& where);

}  // namespace rt
