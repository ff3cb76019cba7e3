// BVH reader.
//
// Why our own reader instead of assimp's BVH importer (design.md §3.1 prefers assimp "unless it
// fails a real clip"). assimp 5.2.4 (Debian libassimp5 5.2.5~ds0) does load all ten clips in
// ../shared/data/bvh and honours per-joint channel orders (tests/unit/bvh uses it as an independent
// FK oracle), but a probe program on small edited copies of a valid file showed that it fails the
// project's input requirements (design.md §8, issue 3):
//   * a motion row with too few values is accepted silently: assimp reads the motion section as
//     one token stream, so the next row's values slide into the short frame (rows of 8, 9 and 10
//     values for 9 channels load as 3 frames of shifted data, no error);
//   * rows beyond `Frames:` are dropped without a warning;
//   * `nan`, `inf` and `1e999` values load without error;
//   * `Frames: 2000000000` (and `Frames: -5`) make it reserve memory from the declared count and
//     fail with a bare `std::bad_alloc` that has no location: allocation is not bounded by the
//     file size;
//   * `Frame Time: 0` loads, with an infinite tick rate;
//   * errors carry no column, and too few rows only say "Unexpected end of file while trying to
//     read a float";
//   * channel values come back as single-precision (ai_real = float) quaternions per node, so
//     the declared channels and exact values are not available to the rest of the pipeline;
//   * 89 ms for the 1901-frame Bandai clip before any forward kinematics, i.e. ~21,000 frames/s
//     for parsing alone against a target of >= 20,000 frames/s for load + landmark extraction.
//     This reader parses the same clip in ~4 ms (~500 MB/s; tests/benchmarks/bvh).

#include "formats/bvh/bvh_reader.hpp"

#include <locale.h>

#include <charconv>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <unordered_map>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

constexpr std::string_view kChannelNames[6] = {"Xposition", "Yposition", "Zposition",
                                               "Xrotation", "Yrotation", "Zrotation"};

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

// A token for messages: printable ASCII kept, other bytes as \xNN, at most ~40 characters.
std::string show(std::string_view s) {
  std::string out;
  for (std::size_t i = 0; i < s.size() && out.size() < 40; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) out += static_cast<char>(c);
    else out += format("\\x%02X", c);
  }
  if (out.size() >= 40 && s.size() > 40) out += "...";
  return out;
}

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }
inline bool is_newline(char c) { return c == '\n' || c == '\r'; }
inline bool is_separator(char c) { return is_blank(c) || is_newline(c); }

// Decimal number at [s, e), stopping at the first character that cannot continue it. Returns the
// end pointer, or nullptr when no number starts at s. Out-of-range magnitudes come back as
// +-inf (overflow, rejected by callers as non-finite) or a tiny / zero value (underflow).
const char* scan_double(const char* s, const char* e, double* v) {
  const char* q = s;
  if (q < e && *q == '+') {
    ++q;  // std::from_chars rejects a leading '+', some writers emit one
    if (q < e && (*q == '+' || *q == '-')) return nullptr;
  }
  const auto r = std::from_chars(q, e, *v);
  if (r.ec == std::errc()) return r.ptr;
  if (r.ec != std::errc::result_out_of_range) return nullptr;
  // Rare path: let strtod (in the "C" locale, whatever the process locale is) say whether it
  // overflowed (HUGE_VAL) or underflowed (0 or a subnormal).
  const std::string token(q, r.ptr);
  locale_t c_locale = newlocale(LC_ALL_MASK, "C", static_cast<locale_t>(nullptr));
  if (c_locale == static_cast<locale_t>(nullptr)) {
    *v = INFINITY;
    return r.ptr;
  }
  *v = strtod_l(token.c_str(), nullptr, c_locale);
  freelocale(c_locale);
  return r.ptr;
}

struct Token {
  std::string_view text;  // empty at end of input
  int line = 0;
  int col = 0;
};

class Parser {
 public:
  Parser(std::string_view text, const std::string& name, Diagnostics* diagnostics, const BvhReadOptions& options)
      : p_(text.data()), end_(text.data() + text.size()), line_start_(text.data()),
        name_(name), diagnostics_(diagnostics), options_(options) {}

  BvhFile run() {
    file_.name = name_;
    if (end_ - p_ >= 3 && static_cast<unsigned char>(p_[0]) == 0xEF && static_cast<unsigned char>(p_[1]) == 0xBB &&
        static_cast<unsigned char>(p_[2]) == 0xBF)
      p_ += 3, line_start_ = p_;  // UTF-8 byte-order mark
    parse_hierarchy();
    parse_motion();
    return std::move(file_);
  }

 private:
  // ---- scanning ---------------------------------------------------------------------------
  void skip_blanks() {
    while (p_ < end_ && is_blank(*p_)) ++p_;
  }
  void eat_newline() {  // p_ is at '\n' or '\r': consume "\r\n", "\n" or a lone "\r"
    if (*p_ == '\r' && p_ + 1 < end_ && p_[1] == '\n') ++p_;
    ++p_;
    ++line_;
    line_start_ = p_;
  }
  void skip_space() {
    for (;;) {
      skip_blanks();
      if (p_ < end_ && is_newline(*p_)) eat_newline();
      else return;
    }
  }
  int col() const { return static_cast<int>(p_ - line_start_) + 1; }

  // Next token across lines: '{' and '}' are tokens on their own, other tokens end at blanks,
  // line ends or braces.
  Token next_token() {
    skip_space();
    Token t{{}, line_, col()};
    const char* b = p_;
    if (p_ < end_ && (*p_ == '{' || *p_ == '}')) {
      ++p_;
    } else {
      while (p_ < end_ && !is_separator(*p_) && *p_ != '{' && *p_ != '}') ++p_;
    }
    t.text = std::string_view(b, static_cast<std::size_t>(p_ - b));
    return t;
  }

  std::string where(int line, int column) const {
    return name_ + ":" + std::to_string(line) + ":" + std::to_string(column);
  }
  [[noreturn]] void fail(const Token& t, const std::string& message) const {
    throw InputError(where(t.line, t.col), message);
  }
  [[noreturn]] void fail_here(const std::string& message) const { throw InputError(where(line_, col()), message); }
  static std::string found(const Token& t) {
    return t.text.empty() ? std::string("end of file") : "'" + show(t.text) + "'";
  }

  // ---- hierarchy ----------------------------------------------------------------------------
  struct Open {
    int joint;
    bool has_offset = false;
    bool has_channels = false;
  };

  void parse_hierarchy() {
    Token t = next_token();
    if (t.text.empty()) fail(t, "empty file: expected a BVH file starting with 'HIERARCHY'");
    if (!iequals(t.text, "HIERARCHY"))
      fail(t, "not a BVH file: expected 'HIERARCHY' at the start, found " + found(t));
    std::vector<Open> stack;
    for (;;) {
      t = next_token();
      if (stack.empty()) {
        if (iequals(t.text, "ROOT")) {
          open_joint(t, -1, stack);
          continue;
        }
        if (iequals(t.text, "MOTION")) {
          if (file_.joints.empty()) fail(t, "MOTION before any ROOT: the hierarchy is empty");
          motion_token_ = t;
          return;
        }
        if (t.text.empty())
          fail(t, file_.joints.empty() ? "unexpected end of file: expected ROOT" : "unexpected end of file: expected MOTION");
        if (t.text == "}") fail(t, "unbalanced braces: '}' without a matching '{'");
        fail(t, std::string("expected ") + (file_.joints.empty() ? "ROOT" : "ROOT or MOTION") + ", found " + found(t));
      }
      Open& top = stack.back();
      BvhJoint& joint = file_.joints[static_cast<std::size_t>(top.joint)];
      if (iequals(t.text, "OFFSET")) {
        if (top.has_offset) fail(t, "second OFFSET in joint '" + show(joint.name) + "'");
        joint.offset = read_vec3("OFFSET");
        top.has_offset = true;
      } else if (iequals(t.text, "CHANNELS")) {
        if (top.has_channels) fail(t, "second CHANNELS in joint '" + show(joint.name) + "'");
        read_channels(t, top.joint);
        top.has_channels = true;
      } else if (iequals(t.text, "JOINT")) {
        open_joint(t, top.joint, stack);
      } else if (iequals(t.text, "End")) {
        read_end_site(t, top.joint);
      } else if (t.text == "}") {
        if (!top.has_offset)
          throw InputError(where(joint.line, 1), "joint '" + show(joint.name) + "' has no OFFSET");
        stack.pop_back();
      } else if (t.text.empty()) {
        fail(t, "unexpected end of file inside joint '" + show(joint.name) + "' (line " + std::to_string(joint.line) +
                    "): missing '}'");
      } else if (iequals(t.text, "MOTION") || iequals(t.text, "ROOT")) {
        fail(t, "unbalanced braces: joint '" + show(joint.name) + "' opened at line " + std::to_string(joint.line) +
                    " is not closed before " + std::string(t.text));
      } else {
        fail(t, "unknown keyword " + found(t) + " in joint '" + show(joint.name) +
                    "' (expected OFFSET, CHANNELS, JOINT, End Site or '}')");
      }
    }
  }

  // After ROOT / JOINT: the name is the rest of the line up to an optional '{' (names may contain
  // spaces), then '{' on this or a later line.
  void open_joint(const Token& keyword, int parent, std::vector<Open>& stack) {
    skip_blanks();
    const char* b = p_;
    while (p_ < end_ && !is_newline(*p_) && *p_ != '{' && *p_ != '}') ++p_;
    const std::string_view name = trim(std::string_view(b, static_cast<std::size_t>(p_ - b)));
    if (name.empty()) fail(keyword, std::string(keyword.text) + " without a name");
    const Token brace = next_token();
    if (brace.text != "{")
      fail(brace, "expected '{' after " + std::string(keyword.text) + " '" + show(name) + "', found " + found(brace));
    BvhJoint joint;
    joint.name = std::string(name);
    joint.parent = parent;
    joint.line = keyword.line;
    joint.first_column = file_.num_channels;
    const int index = static_cast<int>(file_.joints.size());
    const auto [it, inserted] = joint_lines_.emplace(joint.name, joint.line);
    if (!inserted && diagnostics_)
      diagnostics_->warn(where(keyword.line, keyword.col), "joint name '" + show(name) + "' repeats the joint at line " +
                                                               std::to_string(it->second) + "; lookups by name find the first");
    file_.joints.push_back(std::move(joint));
    stack.push_back(Open{index});
  }

  double read_number(const char* what) {
    const Token t = next_token();
    double v = 0;
    const char* e = t.text.empty() ? nullptr : scan_double(t.text.data(), t.text.data() + t.text.size(), &v);
    if (e != t.text.data() + t.text.size() || t.text.empty())
      fail(t, std::string("expected a number for ") + what + ", found " + found(t));
    if (!std::isfinite(v)) fail(t, std::string(what) + " value '" + show(t.text) + "' is not a finite number");
    return v;
  }

  Vec3 read_vec3(const char* what) {
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = read_number(what);
    return v;
  }

  void read_channels(const Token& keyword, int joint_index) {
    const Token count_token = next_token();
    int count = -1;
    if (count_token.text.size() == 1 && count_token.text[0] >= '0' && count_token.text[0] <= '6')
      count = count_token.text[0] - '0';
    if (count < 0)
      fail(count_token, "CHANNELS count must be an integer from 0 to 6, found " + found(count_token));
    BvhJoint& joint = file_.joints[static_cast<std::size_t>(joint_index)];
    joint.first_column = file_.num_channels;
    unsigned seen = 0;
    for (int i = 0; i < count; ++i) {
      const Token t = next_token();
      if (t.text.empty())
        fail(t, "unexpected end of file: CHANNELS at line " + std::to_string(keyword.line) + " declares " +
                    std::to_string(count) + " channels, found " + std::to_string(i));
      int channel = -1;
      for (int k = 0; k < 6; ++k)
        if (iequals(t.text, kChannelNames[k])) channel = k;
      if (channel < 0)
        fail(t, "unknown channel " + found(t) + " (CHANNELS at line " + std::to_string(keyword.line) + " declares " +
                    std::to_string(count) + "; expected Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)");
      if (seen & (1u << channel))
        fail(t, "channel " + std::string(kChannelNames[channel]) + " listed twice in joint '" + show(joint.name) + "'");
      seen |= 1u << channel;
      joint.channels.push_back(static_cast<BvhChannel>(channel));
    }
    file_.num_channels += count;
  }

  void read_end_site(const Token& keyword, int parent) {
    const Token site = next_token();
    if (!iequals(site.text, "Site")) fail(site, "expected 'Site' after 'End', found " + found(site));
    Token t = next_token();
    if (t.text != "{") fail(t, "expected '{' after End Site, found " + found(t));
    t = next_token();
    if (!iequals(t.text, "OFFSET")) fail(t, "expected OFFSET in End Site, found " + found(t));
    BvhEndSite end_site;
    end_site.parent = parent;
    end_site.line = keyword.line;
    end_site.offset = read_vec3("OFFSET");
    t = next_token();
    if (t.text != "}") fail(t, "expected '}' to close the End Site opened at line " + std::to_string(keyword.line) +
                                   ", found " + found(t));
    file_.end_sites.push_back(end_site);
  }

  // ---- motion -------------------------------------------------------------------------------

  // Reads a label such as "Frames:" or "Frame Time:" (words separated by blanks, case-insensitive,
  // the ':' may be preceded by blanks). Fails with `what_is_expected` otherwise.
  void expect_label(std::initializer_list<std::string_view> words, const char* what_is_expected) {
    skip_space();
    const Token start{{}, line_, col()};
    bool first = true;
    for (std::string_view w : words) {
      if (!first) skip_blanks();
      first = false;
      const char* b = p_;
      while (p_ < end_ && ((*p_ >= 'A' && *p_ <= 'Z') || (*p_ >= 'a' && *p_ <= 'z'))) ++p_;
      if (!iequals(std::string_view(b, static_cast<std::size_t>(p_ - b)), w)) {
        p_ = b;
        fail(start, std::string("expected '") + what_is_expected + "', found " + found(peek_token_text(start)));
      }
    }
    skip_blanks();
    if (p_ >= end_ || *p_ != ':') fail_here(std::string("expected ':' after '") + what_is_expected + "'");
    ++p_;
    skip_blanks();
  }

  // The rest of the word at the start token's position (for messages only).
  Token peek_token_text(const Token& start) const {
    const char* b = line_start_ + (start.col - 1);
    const char* e = b;
    while (e < end_ && !is_separator(*e)) ++e;
    return Token{std::string_view(b, static_cast<std::size_t>(e - b)), start.line, start.col};
  }

  // Word on the current line (no line crossing).
  Token word_on_line() {
    Token t{{}, line_, col()};
    const char* b = p_;
    while (p_ < end_ && !is_separator(*p_)) ++p_;
    t.text = std::string_view(b, static_cast<std::size_t>(p_ - b));
    return t;
  }

  void expect_line_end(const char* after) {
    skip_blanks();
    if (p_ < end_ && !is_newline(*p_)) fail_here(std::string("unexpected text after ") + after);
  }

  void parse_motion() {
    // Frames:
    expect_label({"Frames"}, "Frames:");
    file_.frames_line = line_;
    const Token count = word_on_line();
    long long declared = -1;
    {
      const char* b = count.text.data();
      const char* e = b + count.text.size();
      if (b < e && *b == '+') ++b;
      long long v = 0;
      const auto r = std::from_chars(b, e, v);
      if (!count.text.empty() && r.ec == std::errc() && r.ptr == e && v >= 0) declared = v;
      else if (r.ec == std::errc::result_out_of_range && r.ptr == e && *b != '-') declared = LLONG_MAX;
    }
    if (count.text.empty()) fail(count, "expected the frame count after 'Frames:'");
    if (declared < 0) fail(count, "frame count " + found(count) + " is not a non-negative integer");
    if (declared > INT_MAX) fail(count, "frame count " + found(count) + " is absurd (more than 2^31 - 1)");
    file_.declared_frames = static_cast<int>(declared);
    expect_line_end("the frame count");

    // Frame Time:
    expect_label({"Frame", "Time"}, "Frame Time:");
    file_.frame_time_line = line_;
    const Token ft = word_on_line();
    double frame_time = 0;
    const char* e = ft.text.empty() ? nullptr : scan_double(ft.text.data(), ft.text.data() + ft.text.size(), &frame_time);
    if (ft.text.empty() || e != ft.text.data() + ft.text.size())
      fail(ft, "expected the frame time in seconds after 'Frame Time:', found " + found(ft));
    if (!std::isfinite(frame_time) || frame_time < 0)
      fail(ft, "frame time " + found(ft) + " must be a finite, non-negative number of seconds");
    file_.frame_time_s = frame_time;
    if (ft.text.find_first_of("eE") == std::string_view::npos) {
      const std::size_t dot = ft.text.find('.');
      file_.frame_time_decimals = dot == std::string_view::npos ? 0 : static_cast<int>(ft.text.size() - dot - 1);
    }
    expect_line_end("the frame time");

    const std::size_t channels = static_cast<std::size_t>(file_.num_channels);
    if (channels == 0) {
      if (diagnostics_)
        diagnostics_->warn(where(motion_token_.line, motion_token_.col), "the hierarchy declares no channels");
      skip_space();
      if (p_ < end_) fail_here("motion data found but the hierarchy declares no channels");
      if (file_.declared_frames > 0)
        fail_here("the hierarchy declares no channels, so the " + std::to_string(file_.declared_frames) +
                  " declared frames cannot be read");
      return;
    }
    // Bounded reservation: every value takes at least two bytes (a digit and a separator) except
    // the last one in the file, so the remaining text caps the number of complete rows.
    const std::size_t remaining = static_cast<std::size_t>(end_ - p_);
    const std::size_t max_rows = (remaining + 1) / (2 * channels);
    const std::size_t reserve_rows = std::min<std::size_t>(static_cast<std::size_t>(file_.declared_frames), max_rows);
    file_.values.reserve(reserve_rows * channels);

    int rows = 0;
    int first_extra_line = 0;
    int extra_rows = 0;
    for (;;) {
      // Skip blank lines.
      for (;;) {
        skip_blanks();
        if (p_ < end_ && is_newline(*p_)) eat_newline();
        else break;
      }
      if (p_ >= end_) break;
      if (rows >= file_.declared_frames) {
        if (first_extra_line == 0) first_extra_line = line_;
        if (!options_.keep_extra_rows) {
          extra_rows = count_nonblank_lines();
          break;
        }
        ++extra_rows;
      }
      if (rows == INT_MAX) fail_here("too many motion rows");
      if (rows == 0) file_.first_row_line = line_;
      parse_row(rows, channels);
      ++rows;
    }
    file_.num_frames = rows;
    if (rows < file_.declared_frames) {
      std::string message = "the file ends after " + std::to_string(rows) + " frame" + (rows == 1 ? "" : "s") +
                            " but 'Frames:' at line " + std::to_string(file_.frames_line) + " declares " +
                            std::to_string(file_.declared_frames);
      // Point out counts that are absurd rather than merely unmet (truncated files).
      if (static_cast<std::size_t>(file_.declared_frames) > 2 * max_rows + 1)
        message += " (more than a file of this size can hold)";
      fail_here(message);
    }
    if (extra_rows > 0 && diagnostics_) {
      diagnostics_->warn(name_ + ":" + std::to_string(first_extra_line),
                         std::to_string(extra_rows) + " motion row" + (extra_rows == 1 ? "" : "s") + " after the " +
                             std::to_string(file_.declared_frames) + " frames declared by 'Frames:' at line " +
                             std::to_string(file_.frames_line) + (options_.keep_extra_rows ? " kept" : " ignored"));
    }
  }

  int count_nonblank_lines() {
    int n = 0;
    bool content = false;
    for (; p_ < end_; ++p_) {
      if (is_newline(*p_)) {
        n += content;
        content = false;
        if (*p_ == '\r' && p_ + 1 < end_ && p_[1] == '\n') ++p_;
      } else if (!is_blank(*p_)) {
        content = true;
      }
    }
    return n + content;
  }

  std::string column_name(std::size_t column) const {
    const int j = file_.joint_of_column(static_cast<int>(column));
    if (j < 0) return "column " + std::to_string(column + 1);
    const BvhJoint& joint = file_.joints[static_cast<std::size_t>(j)];
    const auto k = column - static_cast<std::size_t>(joint.first_column);
    return "column " + std::to_string(column + 1) + ", " + show(joint.name) + " " +
           std::string(kChannelNames[static_cast<int>(joint.channels[k])]);
  }

  void parse_row(int row, std::size_t channels) {
    const std::size_t base = file_.values.size();
    file_.values.resize(base + channels);
    double* out = file_.values.data() + base;
    for (std::size_t c = 0; c < channels; ++c) {
      skip_blanks();
      if (p_ >= end_ || is_newline(*p_))
        fail_here("frame " + std::to_string(row) + " has " + std::to_string(c) + " values, expected " +
                  std::to_string(channels) + " (one per channel)");
      const char* s = p_;
      double v;
      const char* e = scan_double(s, end_, &v);
      if (e == nullptr || (e < end_ && !is_separator(*e))) {
        const Token bad = word_on_line();
        fail(Token{bad.text, line_, static_cast<int>(s - line_start_) + 1},
             "invalid number " + found(bad) + " in frame " + std::to_string(row) + " (" + column_name(c) + ")");
      }
      if (!std::isfinite(v))
        throw InputError(where(line_, static_cast<int>(s - line_start_) + 1),
                         "value '" + show(std::string_view(s, static_cast<std::size_t>(e - s))) +
                             "' is not a finite number in frame " + std::to_string(row) + " (" + column_name(c) + ")");
      out[c] = v;
      p_ = e;
    }
    skip_blanks();
    if (p_ < end_ && !is_newline(*p_))
      fail_here("frame " + std::to_string(row) + " has more than " + std::to_string(channels) +
                " values (one per channel)");
    if (p_ < end_) eat_newline();
  }

  const char* p_;
  const char* end_;
  const char* line_start_;
  int line_ = 1;
  std::string name_;
  Diagnostics* diagnostics_;
  const BvhReadOptions& options_;
  BvhFile file_;
  Token motion_token_;
  std::unordered_map<std::string, int> joint_lines_;
};

}  // namespace

bool is_bvh_text(std::string_view prefix) {
  if (prefix.size() >= 3 && prefix.compare(0, 3, "\xEF\xBB\xBF") == 0) prefix.remove_prefix(3);
  std::size_t i = 0;
  while (i < prefix.size() && is_separator(prefix[i])) ++i;
  constexpr std::string_view kKeyword = "HIERARCHY";
  if (prefix.size() - i < kKeyword.size() || !iequals(prefix.substr(i, kKeyword.size()), kKeyword)) return false;
  return prefix.size() - i == kKeyword.size() || is_separator(prefix[i + kKeyword.size()]);
}

BvhFile parse_bvh(std::string_view text, const std::string& name, Diagnostics* diagnostics,
                  const BvhReadOptions& options) {
  if (text.size() > options.max_file_bytes || text.size() > static_cast<std::size_t>(INT_MAX))
    throw InputError(name + ":1:1", "file is too large (" + std::to_string(text.size()) + " bytes, limit " +
                                        std::to_string(options.max_file_bytes) + ")");
  return Parser(text, name, diagnostics, options).run();
}

BvhFile read_bvh(const std::string& path, Diagnostics* diagnostics, const BvhReadOptions& options) {
  const std::string text = read_file(path, options.max_file_bytes);
  return parse_bvh(text, path, diagnostics, options);
}

}  // namespace rt
