#include "formats/reference/reference_csv.hpp"

#include <charconv>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/reference/reference_io.hpp"

namespace rt {

namespace {

constexpr int kRootColumns = 7;

void append_number(std::string& out, double v) {
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::general, kCsvSignificantDigits);
  RT_DEMAND(r.ec == std::errc(), "to_chars failed");
  out.append(buf, r.ptr);
}

enum class Cell { Ok, Empty, NotNumber, NotFinite };

Cell parse_cell(std::string_view s, double& v) {
  if (s.empty()) return Cell::Empty;
  // from_chars takes no leading '+'; accept one in front of a digit or '.' as strtod would.
  if (s[0] == '+' && s.size() > 1 && (std::isdigit(static_cast<unsigned char>(s[1])) || s[1] == '.'))
    s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::general);
  if (r.ptr != s.data() + s.size()) return Cell::NotNumber;
  if (r.ec == std::errc::result_out_of_range) return Cell::NotFinite;  // e.g. 1e999
  if (r.ec != std::errc()) return Cell::NotNumber;
  return std::isfinite(v) ? Cell::Ok : Cell::NotFinite;
}

std::string_view trim_blanks(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Quoted, single-line, bounded excerpt of a cell for messages.
std::string excerpt(std::string_view s) {
  std::string out = "'";
  for (char c : s.substr(0, 40)) out.push_back(static_cast<unsigned char>(c) >= 0x20 && c != 0x7F ? c : '?');
  if (s.size() > 40) out += "...";
  return out + "'";
}

}  // namespace

Quat canonical_unit_quat(const Quat& q) {
  const double n = q.norm();
  return std::fabs(n - 1.0) <= kQuatKeepNormTolerance ? q : Quat(q.coeffs() / n);
}

std::string format_reference_csv(const Reference& r) {
  check_reference(r, "reference");
  const int T = r.num_frames();
  const int J = static_cast<int>(r.joint_names.size());
  std::string out;
  out.reserve(static_cast<std::size_t>(T) * static_cast<std::size_t>(kRootColumns + J) * 12);
  for (int t = 0; t < T; ++t) {
    const Quat q = canonical_unit_quat(r.root_quat_W[static_cast<std::size_t>(t)]);
    const double row_root[kRootColumns] = {r.root_pos_W(0, t), r.root_pos_W(1, t), r.root_pos_W(2, t),
                                           q.x(), q.y(), q.z(), q.w()};
    for (int c = 0; c < kRootColumns; ++c) {
      if (c > 0) out.push_back(',');
      append_number(out, row_root[c]);
    }
    for (int j = 0; j < J; ++j) {
      out.push_back(',');
      append_number(out, r.joint_pos(j, t));
    }
    out.push_back('\n');
  }
  return out;
}

Reference parse_reference_csv(std::string_view text, const std::string& file, const CsvReadOptions& o) {
  const std::size_t joints = o.joint_names.size();
  const std::size_t expected = kRootColumns + joints;
  static const char* const kRootNames[2][kRootColumns] = {
      {"root_x", "root_y", "root_z", "root_qx", "root_qy", "root_qz", "root_qw"},
      {"root_x", "root_y", "root_z", "root_qw", "root_qx", "root_qy", "root_qz"}};
  auto column_name = [&](std::size_t c) -> std::string {
    return c < kRootColumns ? kRootNames[o.quat_wxyz ? 1 : 0][c] : o.joint_names[c - kRootColumns];
  };
  auto at = [&](std::size_t line, std::size_t col = 0) {
    return col == 0 ? format("%s:%zu", file.c_str(), line) : format("%s:%zu:%zu", file.c_str(), line, col);
  };

  // A UTF-8 byte order mark (spreadsheet exports) is not data.
  if (starts_with(text, "\xEF\xBB\xBF")) text.remove_prefix(3);
  if (trim(text).empty()) throw InputError(at(1), "empty file: expected one row of numbers per frame, no header");

  std::vector<double> values;
  std::vector<std::string_view> cells;
  std::size_t rows = 0;
  std::size_t line_no = 0;
  std::size_t blank_line = 0;  // first blank line seen since the last data row
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (trim(line).empty()) {
      if (blank_line == 0) blank_line = line_no;
      continue;
    }
    if (blank_line != 0)
      throw InputError(at(blank_line), "empty row between data rows (one row per frame expected)");

    cells.clear();
    for (std::size_t b = 0;;) {
      const std::size_t comma = line.find(',', b);
      cells.push_back(line.substr(b, comma == std::string_view::npos ? std::string_view::npos : comma - b));
      if (comma == std::string_view::npos) break;
      b = comma + 1;
    }
    auto col_of = [&](std::size_t c) {
      const std::string_view cell = trim_blanks(cells[c]);
      return static_cast<std::size_t>((cell.empty() ? cells[c].data() : cell.data()) - line.data()) + 1;
    };
    if (rows == 0) {
      // A header row is the commonest mistake with third-party CSVs: say so instead of
      // "not a number".
      for (std::size_t c = 0; c < cells.size(); ++c) {
        double v;
        const std::string_view cell = trim_blanks(cells[c]);
        const Cell kind = parse_cell(cell, v);
        if (kind == Cell::NotNumber && !cell.empty() && std::isalpha(static_cast<unsigned char>(cell[0])))
          throw InputError(at(line_no, col_of(c)),
                           "header row found (" + excerpt(cell) +
                               "): the Unitree/LAFAN1 CSV layout has no header, only one row of numbers per frame");
      }
    }
    if (cells.size() != expected)
      throw InputError(at(line_no), format("expected %zu columns (7 root + %zu joints%s%s), got %zu", expected,
                                           joints, o.joints_source.empty() ? "" : " ",
                                           o.joints_source.c_str(), cells.size()));
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string_view cell = trim_blanks(cells[c]);
      double v = 0;
      switch (parse_cell(cell, v)) {
        case Cell::Ok:
          break;
        case Cell::Empty:
          throw InputError(at(line_no, col_of(c)), format("column %zu (%s) is empty", c + 1, column_name(c).c_str()));
        case Cell::NotNumber:
          throw InputError(at(line_no, col_of(c)), format("column %zu (%s): %s is not a number", c + 1,
                                                          column_name(c).c_str(), excerpt(cell).c_str()));
        case Cell::NotFinite:
          throw InputError(at(line_no, col_of(c)),
                           format("column %zu (%s): %s is not a finite number (NaN and infinity are not allowed)",
                                  c + 1, column_name(c).c_str(), excerpt(cell).c_str()));
      }
      values.push_back(v);
    }
    const double* q = values.data() + rows * expected + 3;
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::fabs(norm - 1.0) <= o.quat_norm_tolerance))
      throw InputError(at(line_no, col_of(3)),
                       format("root quaternion (columns 4-7, %s) has norm %.9g; expected a unit quaternion "
                              "(tolerance %g)", o.quat_wxyz ? "w x y z" : "x y z w", norm, o.quat_norm_tolerance));
    ++rows;
  }

  Reference r;
  r.joint_names = o.joint_names;
  const auto T = static_cast<Eigen::Index>(rows);
  r.root_pos_W.resize(3, T);
  r.root_quat_W.resize(rows);
  r.joint_pos.resize(static_cast<Eigen::Index>(joints), T);
  for (std::size_t t = 0; t < rows; ++t) {
    const double* v = values.data() + t * expected;
    const auto ti = static_cast<Eigen::Index>(t);
    r.root_pos_W.col(ti) << v[0], v[1], v[2];
    const Quat q = o.quat_wxyz ? Quat(v[3], v[4], v[5], v[6]) : Quat(v[6], v[3], v[4], v[5]);  // Quat(w, x, y, z)
    r.root_quat_W[t] = canonical_unit_quat(q);
    for (std::size_t j = 0; j < joints; ++j) r.joint_pos(static_cast<Eigen::Index>(j), ti) = v[kRootColumns + j];
  }
  return r;
}

Reference read_plain_csv(const std::string& path, const std::vector<std::string>& joint_names, double fps,
                         const std::string& robot_name) {
  const std::string file = base_name(path);
  check_frame_rate(fps, file, "the frame rate (--fps)");
  if (joint_names.empty())
    throw InputError(file, "a plain CSV needs the robot's joint order (--robot)");
  CsvReadOptions o;
  o.joint_names = joint_names;
  o.joints_source = robot_name.empty() ? "of the robot" : "of robot " + robot_name;
  Reference r = parse_reference_csv(read_file(path), file, o);
  r.fps = fps;
  r.robot_name = robot_name;
  check_reference(r, file);
  return r;
}

}  // namespace rt
