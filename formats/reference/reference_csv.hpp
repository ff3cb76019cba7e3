#pragma once
/// The reference CSV in the Unitree/LAFAN1 layout (design.md §5), as Unitree's LAFAN1 retargeting
/// dataset and the g1-moves clips use it:
///
///   no header; one row per frame; comma-separated; '\n' line ends (the reader also takes "\r\n")
///   columns 1-3   root position x y z in W [m]
///   columns 4-7   root orientation quaternion x y z w (w last)
///   columns 8...  joint positions [rad, or m for prismatic joints] in the export joint order
///
/// Number format (writer): every value as printf "%.9g" (9 significant digits, shortest of fixed
/// or exponent notation, e.g. "0.782845", "-5.1e-05", "1.57079633"), produced with std::to_chars
/// so the C locale never matters. Reading a value gives the double nearest to its decimal, and
/// %.9g of that double gives the same decimal back, so write -> read -> write is byte-identical.
///
/// The CSV carries neither the frame rate nor the joint names: they come from the meta.json beside
/// it (reference_meta.hpp) or, for a plain third-party CSV, from the robot and `--fps`.

#include <string>
#include <string_view>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

/// Significant digits of every CSV value (printf "%.9g").
constexpr int kCsvSignificantDigits = 9;

/// Root quaternions whose norm is within this of 1 are kept exactly as stored; others (within the
/// reader's tolerance) are normalised. 1e-8 is above the norm error of a unit quaternion rounded
/// to 9 significant digits (< 5e-9), so our own files are never touched (bit-exact round trips)
/// while e.g. 6-decimal third-party files are normalised.
constexpr double kQuatKeepNormTolerance = 1e-8;

/// `q` unchanged when | |q| - 1 | <= kQuatKeepNormTolerance, else q / |q|.
Quat canonical_unit_quat(const Quat& q);

/// The CSV text of a reference (after check_reference, InputError on an invalid reference).
std::string format_reference_csv(const Reference& reference);

struct CsvReadOptions {
  /// Joint names in column order (columns 8...). Every row must have 7 + size() columns.
  std::vector<std::string> joint_names;
  /// Where the joint list comes from, for the column-count message "expected 36 columns (7 root +
  /// 29 joints <joints_source>), got 35": e.g. "of robot g1", "in walk.meta.json".
  std::string joints_source;
  /// Columns 4-7 hold w x y z instead of x y z w (a meta.json "quaternion_order": "wxyz").
  bool quat_wxyz = false;
  /// | |q| - 1 | beyond this is an error; see kQuatKeepNormTolerance for what happens below it.
  double quat_norm_tolerance = 1e-3;
};

/// Parses CSV text strictly: an empty file, a header row, a row whose column count is not
/// 7 + joints, an empty row between rows, an empty or non-numeric cell, NaN or infinity, and a
/// root quaternion that is not unit within the tolerance are each an InputError located
/// "<file>:<line>[:<column>]" (1-based, column = character position of the cell). Fills
/// root_pos_W, root_quat_W, joint_pos and joint_names; fps stays 0 (the caller knows it).
Reference parse_reference_csv(std::string_view text, const std::string& file, const CsvReadOptions& options);

/// Reads a plain third-party CSV (no meta.json): joint names from the robot, rate from the user
/// (`--fps`). `robot_name` is used in messages and stored in the result. InputError when fps is
/// not finite and > 0 or joint_names is empty.
Reference read_plain_csv(const std::string& path, const std::vector<std::string>& joint_names, double fps,
                         const std::string& robot_name = "");

}  // namespace rt
