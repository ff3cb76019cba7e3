#pragma once
/// Reading and writing robot references (design.md §5): the entry points that `convert`,
/// `validate` and tests use. The format details live in formats/reference/ (reference_csv.hpp,
/// reference_meta.hpp, reference_npz.hpp); this header picks the format and checks the result
/// against the robot the caller expects.
///
/// Files of one output, for a path stem `out/walk`:
///   out/walk.csv        Unitree/LAFAN1 layout, no header (reference_csv.hpp)
///   out/walk.npz        BeyondMimic-style arrays (reference_npz.hpp)
///   out/walk.meta.json  everything else: robot, fps, joint order, contacts, COM/COP, provenance
///                       (reference_meta.hpp); written last, so its presence means the outputs
///                       listed in it are complete.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "retarget/reference/npz_body_arrays.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

enum class ReferenceFormat { Csv, Npz };

/// "csv" or "npz".
const char* reference_format_name(ReferenceFormat format);

/// Parses a `--format` list such as "csv,npz" (case-insensitive, comma-separated, duplicates
/// dropped, order kept). InputError naming the bad item when one is unknown or the list is empty.
std::vector<ReferenceFormat> parse_reference_formats(std::string_view list);

struct ReferenceReadOptions {
  /// The robot the caller expects (robot.yaml `name`), "" = any. A file that names another robot
  /// is an error; a file that names none gets this name. Also used in messages.
  std::string robot_name;
  /// The robot's export joint order. Required for a plain CSV (no meta.json beside it). When the
  /// file names its joints, they must be the same set (any order), else an InputError names the
  /// first joint that differs. Empty = no check.
  std::vector<std::string> joint_names;
  /// The joint order of an NPZ without `joint_names`, as the user states it (`validate
  /// --joint-order`); empty = such an NPZ is refused (the robot's order is never guessed).
  std::vector<std::string> npz_joint_order;
  /// [Hz] Frame rate for files that do not state one (a plain CSV: the CLI's `--fps`); 0 = none.
  /// When the file states a rate too, the two must agree (relative 1e-9), else InputError.
  double fps = 0;
  /// A root quaternion whose norm differs from 1 by more than this is an error; smaller
  /// deviations are normalised (see kQuatKeepNormTolerance in reference_csv.hpp). Default 1e-3.
  double quat_norm_tolerance = 1e-3;
  /// Files larger than this are rejected before reading (protects against absurd inputs).
  std::uint64_t max_file_bytes = std::uint64_t{1} << 31;
};

/// Reads a reference, choosing the format by extension (case-insensitive):
///   .csv  with `<stem>.meta.json` beside it: CSV + meta (the meta gives joint names, fps, ...)
///   .csv  without meta: plain third-party CSV; needs options.joint_names and options.fps, else
///         an InputError saying that `--fps` and a robot are required
///   .npz  read_reference_npz (reference_npz.hpp); a `<stem>.meta.json` beside it, when present,
///         adds the robot and provenance and must agree with the NPZ (fps, joint names, frames)
/// The result passes check_reference and the robot checks of `options`; its root quaternions are
/// unit within 1e-8 (kQuatKeepNormTolerance: that close to unit they are kept bit-exact as
/// stored). When `bodies` is given and the file is an NPZ with body arrays, they are filled in
/// (else cleared).
Reference read_reference(const std::string& path, const ReferenceReadOptions& options = {},
                         NpzBodyArrays* bodies = nullptr);

/// Writes `reference` as `<path_stem>.csv` and/or `<path_stem>.npz` (one per requested format)
/// and then `<path_stem>.meta.json`, each atomically (rt::write_file_atomic: temporary file +
/// rename). Everything is encoded before the first file is written, so an invalid reference
/// leaves existing files untouched. An existing meta is removed before the data files are
/// replaced, so a crash in between never pairs new data with an old meta. `body_arrays` (optional) go into the NPZ only. Returns the
/// paths written, meta last. InputError when `formats` is empty or a file cannot be written.
std::vector<std::string> write_reference(const std::string& path_stem, const Reference& reference,
                                         const std::vector<ReferenceFormat>& formats,
                                         const NpzBodyArrays* body_arrays = nullptr);

/// `<stem>.meta.json` for a data file path (`out/walk.csv` -> `out/walk.meta.json`); the stem is
/// the path without its last extension.
std::string meta_path_for(const std::string& data_path);

/// Checks a reference's internal consistency before it is written or after it is read:
/// fps finite and > 0; T >= 1 frames; J >= 1 unique non-empty joint names; every array sized
/// for T frames (contacts both or neither, COM and COP 0 or T columns); contact flags 0/1; all
/// values finite; root quaternions unit within 1e-3. `where` names the reference in messages
/// (a file name, or "reference"); errors are InputError "<where> frame N joint J: ...".
void check_reference(const Reference& reference, const std::string& where);

}  // namespace rt
