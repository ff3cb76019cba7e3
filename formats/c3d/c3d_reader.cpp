#include "formats/c3d/c3d_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt::c3d {

namespace {

constexpr std::size_t kBlock = 512;
constexpr int kMaxHeaderEvents = 18;
constexpr int kEventKey = 12345;

std::uint32_t bits_le(const unsigned char* b) {
  return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
}
std::uint32_t bits_be(const unsigned char* b) {
  return std::uint32_t(b[3]) | std::uint32_t(b[2]) << 8 | std::uint32_t(b[1]) << 16 | std::uint32_t(b[0]) << 24;
}
float float_from_bits(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

// VAX F-float (DEC processor type): the 16-bit words are swapped relative to a little-endian IEEE
// float and the exponent bias is 2 higher, so after the word swap the IEEE reading is 4x too big.
// Exponent 0 is zero (or, with the sign bit, a "reserved operand": reported as NaN); exponent 255
// is an ordinary finite number in VAX but Inf/NaN in IEEE, so it is rebuilt explicitly.
float vax_to_float(const unsigned char* b) {
  const std::uint32_t u = std::uint32_t(b[2]) | std::uint32_t(b[3]) << 8 | std::uint32_t(b[0]) << 16 |
                          std::uint32_t(b[1]) << 24;
  const std::uint32_t exponent = (u >> 23) & 0xffu;
  const bool negative = (u >> 31) != 0;
  if (exponent == 0) return negative ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
  if (exponent == 255) {
    const double mantissa = 1.0 + double(u & 0x7fffffu) / double(1u << 23);
    const double v = std::ldexp(mantissa, 126);
    return static_cast<float>(negative ? -v : v);
  }
  return float_from_bits(u) * 0.25f;
}

// Processor-aware element decoding. Callers check bounds first.
struct Decoder {
  Processor processor = Processor::Intel;

  std::int16_t i16(const unsigned char* b) const {
    const std::uint16_t u = processor == Processor::Mips ? std::uint16_t(b[0] << 8 | b[1]) : std::uint16_t(b[1] << 8 | b[0]);
    return static_cast<std::int16_t>(u);
  }
  std::uint16_t u16(const unsigned char* b) const { return static_cast<std::uint16_t>(i16(b)); }
  float f32(const unsigned char* b) const {
    switch (processor) {
      case Processor::Intel: return float_from_bits(bits_le(b));
      case Processor::Mips: return float_from_bits(bits_be(b));
      case Processor::Dec: return vax_to_float(b);
    }
    return 0.0f;
  }
};

std::string trim_copy(std::string_view s) {
  // C3D pads strings with blanks; some writers pad with NULs.
  std::size_t e = s.size();
  while (e > 0 && (s[e - 1] == ' ' || s[e - 1] == '\0' || s[e - 1] == '\t' || s[e - 1] == '\r' || s[e - 1] == '\n')) --e;
  std::size_t b = 0;
  while (b < e && (s[b] == ' ' || s[b] == '\0')) ++b;
  return std::string(s.substr(b, e - b));
}

class Parser {
 public:
  Parser(std::string_view bytes, std::string name, Diagnostics* diagnostics)
      : data_(reinterpret_cast<const unsigned char*>(bytes.data())),
        size_(bytes.size()),
        name_(std::move(name)),
        diagnostics_(diagnostics) {}

  C3dFile parse() {
    file_.name = name_;
    file_.file_size = size_;
    parse_header();
    parse_parameters();
    interpret_points();
    interpret_analog();
    locate_data();
    // One label per point (sized only now that the data section has been checked to hold the
    // points; the label vectors themselves are bounded by the parameter section).
    file_.point_labels.resize(static_cast<std::size_t>(file_.points.num_points));
    file_.point_descriptions.resize(static_cast<std::size_t>(file_.points.num_points));
    interpret_point_kinds();
    read_events();
    choose_integer_scale();
    decode_points();
    return std::move(file_);
  }

 private:
  [[noreturn]] void fail(std::size_t offset, std::string_view parameter, const std::string& message) const {
    throw InputError(c3d_location(name_, offset, parameter), message);
  }
  void warn(std::size_t offset, std::string_view parameter, const std::string& message) const {
    if (diagnostics_) diagnostics_->warn(c3d_location(name_, offset, parameter), message);
  }
  void note(std::size_t offset, std::string_view parameter, const std::string& message) const {
    if (diagnostics_) diagnostics_->note(c3d_location(name_, offset, parameter), message);
  }

  // ---- header -------------------------------------------------------------------------------
  std::uint16_t word(int n) const { return dec_.u16(data_ + 2 * (n - 1)); }  // 1-based word number

  void parse_header() {
    if (size_ == 0) fail(0, {}, "empty file (a C3D file starts with a 512-byte header)");
    if (size_ < 2 || data_[1] != 0x50)
      fail(size_ < 2 ? 0 : 1, {},
           size_ < 2 ? std::string("file too short for a C3D header")
                     : format("not a C3D file: header byte 2 is 0x%02x, expected 0x50", data_[1]));
    if (size_ < kBlock) fail(size_, {}, format("file truncated inside the 512-byte header (%zu bytes)", size_));
    Header& h = file_.header;
    h.parameter_block = data_[0];
    if (h.parameter_block < 2)
      fail(0, {}, format("parameter section pointer is block %d; the parameters start at block 2 or later", h.parameter_block));
    param_begin_ = (static_cast<std::size_t>(h.parameter_block) - 1) * kBlock;
    if (param_begin_ + 4 > size_)
      fail(0, {}, format("parameter section pointer (block %d, offset 0x%zx) is past the end of the file (%zu bytes)",
                         h.parameter_block, param_begin_, size_));
    const int processor = data_[param_begin_ + 3];
    if (processor < 84 || processor > 86)
      fail(param_begin_ + 3, {},
           format("unknown processor type %d (expected 84 Intel, 85 DEC or 86 MIPS)", processor));
    file_.processor = static_cast<Processor>(processor);
    dec_.processor = file_.processor;

    h.point_count = word(2);
    h.analog_per_frame = word(3);
    h.first_frame = word(4);
    h.last_frame = word(5);
    h.max_interpolation_gap = word(6);
    h.scale = dec_.f32(data_ + 12);
    h.data_start_block = word(9);
    h.analog_samples_per_frame = word(10);
    h.frame_rate = dec_.f32(data_ + 20);
    h.has_label_range = word(148) == kEventKey;
    h.four_char_event_labels = word(150) == kEventKey;
    h.event_count = word(151);
  }

  // ---- parameter section ----------------------------------------------------------------------
  void parse_parameters() {
    const std::size_t blocks = data_[param_begin_ + 2];
    param_end_ = param_begin_ + blocks * kBlock;
    if (blocks == 0) {
      note(param_begin_ + 2, {}, "the parameter section is empty (no groups, no parameters)");
      return;
    }
    if (param_end_ > size_)
      fail(param_begin_ + 2, {},
           format("parameter section (%zu blocks from 0x%zx) extends past the end of the file (%zu bytes)", blocks,
                  param_begin_, size_));
    // Real files declare too few blocks and run on to the data section (c3d.org golfswing, FP1):
    // the data start (header word 9) bounds the section when it lies beyond the declared end and
    // inside the file; a record that crosses the declared end says so once.
    declared_param_end_ = param_end_;
    const std::size_t data_start =
        file_.header.data_start_block > 0 ? (static_cast<std::size_t>(file_.header.data_start_block) - 1) * kBlock : 0;
    if (data_start > param_end_ && data_start <= size_) param_end_ = data_start;

    std::size_t pos = param_begin_ + 4;
    while (pos + 2 <= param_end_) {
      const int name_length = static_cast<std::int8_t>(data_[pos]);
      const int group_id = static_cast<std::int8_t>(data_[pos + 1]);
      if (name_length == 0) break;  // end of the parameter list
      const std::size_t n = static_cast<std::size_t>(std::abs(name_length));
      if (group_id == 0) fail(pos + 1, {}, "record has group id 0 (neither a group nor a parameter)");
      if (pos + 2 + n + 2 > param_end_)
        fail(pos, {}, "record name runs past the end of the parameter section" + after_parameter(pos));
      std::string name(reinterpret_cast<const char*>(data_ + pos + 2), n);
      for (std::size_t i = 0; i < n; ++i) {
        const unsigned char c = data_[pos + 2 + i];
        if (c < 0x20 || c > 0x7e)
          fail(pos + 2 + i, {},
               format("record name contains byte 0x%02x (names are printable ASCII)", c) + after_parameter(pos));
      }
      name = trim_copy(name);
      const std::size_t link = pos + 2 + n;  // the "next record" offset is relative to this word
      const int next = dec_.i16(data_ + link);
      std::string qualified = group_id < 0 ? name : group_name_for(group_id) + ":" + name;
      if (next < 0)
        fail(link, qualified, format("next-record offset %d points backwards (a cycle in the parameter list)", next));

      bool last = next == 0;
      bool out_of_range = false;
      std::size_t record_end = param_end_;
      if (!last) {
        record_end = link + static_cast<std::size_t>(next);
        if (record_end > param_end_) {
          out_of_range = true;
          record_end = param_end_;
        } else if (record_end <= link + 1) {
          fail(link, qualified, format("next-record offset %d points into the record itself", next));
        }
      }
      std::size_t natural_end;
      if (group_id < 0)
        natural_end = parse_group(pos, -group_id, name, name_length < 0, link + 2, record_end);
      else
        natural_end = parse_parameter(pos, group_id, name, name_length < 0, link + 2, record_end);

      if (out_of_range) {
        // Some writers leave a garbage "next" offset in the last record. Accept that only when
        // nothing but the end-of-list marker (or the end of the section) follows the record.
        const bool at_end = natural_end + 2 > param_end_ || data_[natural_end] == 0;
        if (!at_end)
          fail(link, qualified,
               format("next-record offset %d points past the end of the parameter section (0x%zx)", next, param_end_));
        note(link, qualified, format("next-record offset %d points past the parameter section; taken as the last record", next));
        break;
      }
      if (natural_end > declared_param_end_ && !warned_overflow_) {
        warned_overflow_ = true;
        warn(param_begin_ + 2, {},
             format("the parameter header declares %zu blocks, but the parameters run on past 0x%zx to the data "
                    "section at 0x%zx; reading up to the data section", blocks, declared_param_end_, param_end_));
      }
      if (last) break;
      pos = record_end;
    }
    resolve_group_names();
  }

  // Parameters the reader interprets: their data must be sound. Others may be kept empty.
  static bool interpreted(const std::string& group, const std::string& name) {
    const std::string g = to_lower(group), n = to_lower(name);
    return g == "point" || g == "trial" || g == "event" || g == "events" || (g == "analog" && (n == "used" || n == "rate"));
  }

  // " (after parameter GROUP:NAME)" for an error in the record at `pos`: names what came before it,
  // or that the walk has reached the data section.
  std::string after_parameter(std::size_t pos) const {
    std::string s;
    const std::size_t data_start =
        file_.header.data_start_block > 0 ? (static_cast<std::size_t>(file_.header.data_start_block) - 1) * kBlock : 0;
    if (data_start > 0 && pos >= data_start) s = " (inside the data section";
    if (!file_.parameters.empty()) s += (s.empty() ? " (" : ", ") + std::string("after parameter ") + file_.parameters.back().qualified_name();
    return s.empty() ? s : s + ")";
  }

  std::string group_name_for(int id) const {
    for (const Group& g : file_.groups)
      if (g.id == id) return g.name;
    return format("group%d", id);
  }

  // Returns the end of the record as laid out by the C3D guide.
  std::size_t parse_group(std::size_t pos, int id, const std::string& name, bool locked, std::size_t p,
                          std::size_t record_end) {
    Group g;
    g.id = id;
    g.name = name;
    g.locked = locked;
    g.offset = pos;
    std::size_t end = p;
    if (p < record_end) {
      const std::size_t len = data_[p];
      const std::size_t avail = std::min(len, record_end - p - 1);
      g.description = trim_copy(std::string_view(reinterpret_cast<const char*>(data_ + p + 1), avail));
      end = p + 1 + len;
    }
    file_.groups.push_back(std::move(g));
    return end;
  }

  std::size_t parse_parameter(std::size_t pos, int group_id, const std::string& name, bool locked, std::size_t p,
                              std::size_t record_end) {
    Parameter prm;
    prm.group_id = group_id;
    prm.group = group_name_for(group_id);
    prm.name = name;
    prm.locked = locked;
    prm.offset = pos;
    const std::string qualified = prm.qualified_name();
    if (p + 2 > record_end) fail(p, qualified, "parameter record truncated before its type and dimensions");
    const int type = static_cast<std::int8_t>(data_[p]);
    if (type != -1 && type != 1 && type != 2 && type != 4)
      fail(p, qualified, format("unknown parameter type %d (expected -1, 1, 2 or 4)", type));
    prm.type = static_cast<DataType>(type);
    const std::size_t ndims = data_[p + 1];
    if (ndims > 7) fail(p + 1, qualified, format("%zu dimensions (C3D allows at most 7)", ndims));
    if (p + 2 + ndims > record_end) fail(p + 1, qualified, "parameter dimensions run past the end of the record");
    std::size_t count = 1;
    for (std::size_t i = 0; i < ndims; ++i) {
      const int d = data_[p + 2 + i];
      prm.dims.push_back(d);
      count *= static_cast<std::size_t>(d);  // at most 255^7 < 2^56: no overflow in 64 bits
    }
    const std::size_t element = static_cast<std::size_t>(std::abs(type));
    const std::size_t q = p + 2 + ndims;
    const std::size_t available = record_end - q;
    if (count > available / element) {
      const std::string what = format("parameter data (%zu elements of %zu bytes)", count, element);
      if (record_end >= param_end_)  // bounded by the section, not by a next-record offset
        fail(q, qualified, format("%s overruns the parameter section (%zu bytes left)", what.c_str(), available));
      if (interpreted(prm.group, prm.name))
        fail(q, qualified, format("%s overruns its record (%zu bytes to the next record)", what.c_str(), available));
      // A parameter the reader does not use, whose next-record offset is good but whose own data
      // are not (ANALOG:UNITS with 2 dimensions and one dimension byte in BTK's
      // badParameterOffset.c3d): kept empty, as BTK does.
      warn(q, qualified, format("%s overruns its record (%zu bytes to the next record); kept empty", what.c_str(), available));
      prm.dims.clear();
      file_.parameters.push_back(std::move(prm));
      return record_end;
    }
    const std::size_t bytes = count * element;
    if (prm.type == DataType::Char) {
      const char* s = reinterpret_cast<const char*>(data_ + q);
      if (ndims <= 1) {
        prm.strings.push_back(trim_copy(std::string_view(s, bytes)));
      } else {
        const std::size_t width = static_cast<std::size_t>(prm.dims[0]);
        const std::size_t rows = width == 0 ? 0 : count / width;
        prm.strings.reserve(rows);
        for (std::size_t r = 0; r < rows; ++r) prm.strings.push_back(trim_copy(std::string_view(s + r * width, width)));
      }
    } else {
      prm.numbers.resize(count);
      for (std::size_t i = 0; i < count; ++i) {
        const unsigned char* e = data_ + q + i * element;
        double v = 0;
        if (prm.type == DataType::Byte) v = e[0];
        else if (prm.type == DataType::Int16) v = dec_.i16(e);
        else v = dec_.f32(e);
        prm.numbers[i] = v;
      }
    }
    std::size_t end = q + bytes;
    // The description length byte is missing in some writers' records (OptiTrack POINT:LABELS):
    // read it only when the record, as bounded by its "next" offset, still has room for it.
    if (end < record_end) {
      const std::size_t len = data_[end];
      const std::size_t avail = std::min(len, record_end - end - 1);
      prm.description = trim_copy(std::string_view(reinterpret_cast<const char*>(data_ + end + 1), avail));
      end += 1 + len;
    }
    file_.parameters.push_back(std::move(prm));
    return end;
  }

  void resolve_group_names() {
    std::map<int, std::string> names;
    for (const Group& g : file_.groups) names.emplace(g.id, g.name);  // first definition wins
    int orphans = 0;
    for (Parameter& p : file_.parameters) {
      auto it = names.find(p.group_id);
      if (it != names.end()) {
        p.group = it->second;
      } else {
        p.group.clear();
        ++orphans;
      }
    }
    if (orphans > 0)
      warn(param_begin_, {}, format("%d parameters belong to no group record; they are ignored", orphans));
  }

  // ---- interpretation ----------------------------------------------------------------------------
  const Parameter* numeric(std::string_view group, std::string_view name) const {
    const Parameter* p = file_.find(group, name);
    if (!p) return nullptr;
    if (p->type == DataType::Char) {
      warn(p->offset, p->qualified_name(), "expected a number, found text; ignored");
      return nullptr;
    }
    if (p->numbers.empty()) return nullptr;  // an empty array (e.g. EVENT:TIMES with no events)
    return p;
  }

  // A count stored in a parameter (POINT:USED, ANALOG:USED, ...). C3D stores counts as unsigned
  // 16-bit integers; some writers store floats. Anything but a whole number from 0 to 65535 (NaN,
  // -1, 1e10) is an error at the parameter, not an undefined float-to-int conversion.
  int count_value(const Parameter& p, std::size_t i = 0) const {
    const double v = p.count_at(i);
    if (!(v >= 0 && v <= 65535 && v == std::floor(v)))
      fail(p.offset, p.qualified_name(), format("%g is not a count (a whole number from 0 to 65535)", v));
    return static_cast<int>(v);
  }

  std::vector<std::string> concatenated_strings(std::string_view group, std::string_view base) const {
    std::vector<std::string> out;
    for (int k = 1; k < 100; ++k) {
      const std::string name = k == 1 ? std::string(base) : std::string(base) + std::to_string(k);
      const Parameter* p = file_.find(group, name);
      if (!p) break;
      if (p->type != DataType::Char) {
        warn(p->offset, p->qualified_name(), "expected text; ignored");
        break;
      }
      out.insert(out.end(), p->strings.begin(), p->strings.end());
    }
    return out;
  }

  void interpret_points() {
    const Header& h = file_.header;
    int points = h.point_count;
    if (const Parameter* used = numeric("POINT", "USED")) {
      const int v = count_value(*used);
      if (v != points)
        warn(used->offset, "POINT:USED", format("%d points, but header word 2 says %d; using POINT:USED", v, points));
      points = v;
    }
    file_.points.num_points = points;

    double scale = h.scale;
    if (const Parameter* s = numeric("POINT", "SCALE")) {
      if (std::isfinite(s->numbers[0]) && std::isfinite(scale) && s->numbers[0] != scale &&
          std::abs(s->numbers[0] - scale) > 1e-6 * std::abs(scale))
        note(s->offset, "POINT:SCALE", format("%g differs from the header copy %g; using POINT:SCALE", s->numbers[0], scale));
      scale = s->numbers[0];
      scale_offset_ = s->offset;
      scale_param_ = "POINT:SCALE";
    }
    if (!std::isfinite(scale)) fail(scale_offset_, scale_param_, "point scale is not a finite number");
    file_.point_scale = scale;
    file_.float_storage = scale < 0;

    double rate = h.frame_rate;
    std::size_t rate_offset = 20;
    std::string_view rate_param;
    if (const Parameter* r = numeric("POINT", "RATE")) {
      rate = r->numbers[0];
      rate_offset = r->offset;
      rate_param = "POINT:RATE";
    }
    if (!std::isfinite(rate) || rate < 0 || rate > 1e6)
      fail(rate_offset, rate_param, format("frame rate %g Hz is not a plausible rate", rate));
    file_.point_rate = rate;

    if (const Parameter* u = file_.find("POINT", "UNITS"); u && u->type == DataType::Char && !u->strings.empty())
      file_.point_units = u->strings[0];

    // Frame range: TRIAL:ACTUAL_*_FIELD hold 32-bit frame numbers (two 16-bit words) and win over
    // the 16-bit header words, which overflow for long trials.
    long long first = h.first_frame, last = h.last_frame;
    std::size_t range_offset = 6;
    std::string range_param;
    const Parameter* start_field = numeric("TRIAL", "ACTUAL_START_FIELD");
    const Parameter* end_field = numeric("TRIAL", "ACTUAL_END_FIELD");
    if (start_field && end_field && start_field->numbers.size() >= 2 && end_field->numbers.size() >= 2) {
      first = count_value(*start_field, 0) + 65536LL * count_value(*start_field, 1);
      last = count_value(*end_field, 0) + 65536LL * count_value(*end_field, 1);
      range_offset = end_field->offset;
      range_param = "TRIAL:ACTUAL_END_FIELD";
    }
    if (last < first) {
      if (first == last + 1) {
        last = first - 1;  // an empty trial
      } else {
        fail(range_offset, range_param, format("last frame %lld is before first frame %lld", last, first));
      }
    }
    const long long frames = last - first + 1;
    if (frames > std::numeric_limits<int>::max())
      fail(range_offset, range_param, format("%lld frames is not a plausible frame count", frames));
    file_.first_frame = static_cast<int>(std::min<long long>(first, std::numeric_limits<int>::max()));
    file_.points.num_frames = static_cast<int>(frames);
    if (const Parameter* f = numeric("POINT", "FRAMES")) {
      const double v = f->count_at(0);
      if (v != static_cast<double>(frames) && frames <= 65535)
        note(f->offset, "POINT:FRAMES", format("says %g frames, the frame range says %lld; using the frame range", v, frames));
    }

    file_.point_labels = concatenated_strings("POINT", "LABELS");
    file_.point_descriptions = concatenated_strings("POINT", "DESCRIPTIONS");
    const std::size_t n = static_cast<std::size_t>(points);
    if (!file_.point_labels.empty() && file_.point_labels.size() < n) {
      const Parameter* l = file_.find("POINT", "LABELS");
      warn(l ? l->offset : param_begin_, "POINT:LABELS",
           format("%zu labels for %zu points; the rest are unlabeled", file_.point_labels.size(), n));
    }
  }

  void interpret_analog() {
    const Header& h = file_.header;
    // Candidate from the header: word 3 counts all analog samples of one 3-D frame.
    const long long header_words = h.analog_per_frame;
    long long words = header_words;
    int channels = h.analog_samples_per_frame > 0 ? h.analog_per_frame / h.analog_samples_per_frame : 0;
    int samples = h.analog_samples_per_frame;
    double rate = file_.point_rate * samples;

    const Parameter* used = numeric("ANALOG", "USED");
    if (used) {
      const Parameter* r = numeric("ANALOG", "RATE");
      const int param_channels = count_value(*used);
      double param_rate = r ? r->numbers[0] : rate;
      int param_samples = 0;
      if (param_channels > 0) {
        if (!std::isfinite(param_rate) || param_rate <= 0 || file_.point_rate <= 0) {
          param_samples = samples;
        } else {
          const double ratio = param_rate / file_.point_rate;
          if (!(ratio < 1e6)) fail(r ? r->offset : used->offset, "ANALOG:RATE", format("analog rate %g Hz is not plausible", param_rate));
          param_samples = static_cast<int>(std::lround(ratio));
          if (std::abs(ratio - param_samples) > 1e-3)
            warn(r ? r->offset : used->offset, "ANALOG:RATE",
                 format("analog rate %g Hz is not a multiple of the point rate %g Hz", param_rate, file_.point_rate));
        }
      }
      const long long param_words = static_cast<long long>(param_channels) * param_samples;
      if (param_words != header_words) {
        // The 16-bit header word overflows for large channel counts; otherwise pick the layout
        // that matches the file size and say so.
        const std::size_t ws = file_.float_storage ? 4 : 2;
        auto fits = [&](long long analog) {  // in double: the product may exceed 64 bits
          const double frame = (4.0 * file_.points.num_points + static_cast<double>(analog)) * static_cast<double>(ws);
          const double need = frame * file_.points.num_frames;
          const double start = (static_cast<double>(data_start_block_guess()) - 1) * static_cast<double>(kBlock);
          return start >= 0 && start + need <= static_cast<double>(size_);
        };
        const bool param_fits = fits(param_words), header_fits = fits(header_words);
        const bool use_header = header_fits && !param_fits;
        warn(used->offset, "ANALOG:USED",
             format("ANALOG:USED x samples per frame = %lld analog words per frame, header word 3 says %lld; using %s",
                    param_words, header_words, use_header ? "the header" : "the parameters"));
        if (!use_header) {
          words = param_words;
          channels = param_channels;
          samples = param_samples;
          rate = param_rate;
        }
      } else {
        channels = param_channels;
        samples = param_samples;
        rate = param_rate;
      }
    }
    analog_words_ = words;
    file_.analog_channels = words > 0 ? channels : 0;
    file_.analog_samples_per_frame = words > 0 ? samples : 0;
    file_.analog_rate = words > 0 && std::isfinite(rate) ? rate : 0;
  }

  int data_start_block_guess() const {
    if (const Parameter* d = file_.find("POINT", "DATA_START"); d && d->type != DataType::Char && !d->numbers.empty()) {
      const int v = count_value(*d);
      if (v > 0) return v;
    }
    return file_.header.data_start_block;
  }

  // The sign of the scale says float (< 0) or int16 (> 0) storage. When the header word and
  // POINT:SCALE disagree in sign, the data section's size decides: float data needs twice the
  // bytes, so a section that holds the frames as floats is float, one that holds only int16 is not.
  void resolve_storage(int block, std::size_t frame_words) {
    const double header = file_.header.scale;
    if (scale_param_.empty() || !std::isfinite(header) || header == 0 || (header < 0) == (file_.point_scale < 0)) return;
    const std::size_t frames = static_cast<std::size_t>(file_.points.num_frames);
    if (frames == 0 || frame_words == 0 || block < 2) return;
    const std::size_t offset = (static_cast<std::size_t>(block) - 1) * kBlock;
    const std::size_t available = offset < size_ ? size_ - offset : 0;
    const bool fits_float = frames <= available / (frame_words * 4);
    file_.float_storage = fits_float;
    warn(scale_offset_, scale_param_,
         format("%g and the header's %g disagree on the storage; the data section (%zu bytes for %zu frames) holds %s",
                file_.point_scale, header, available, frames, fits_float ? "floats" : "int16 values only"));
    // The scale's sign follows the storage chosen (its magnitude scales int16 coordinates and residuals).
    if (!fits_float && file_.point_scale < 0) file_.point_scale = -file_.point_scale;
    if (fits_float && file_.point_scale > 0) file_.point_scale = -file_.point_scale;
  }

  void locate_data() {
    int block = file_.header.data_start_block;
    std::size_t where = 16;
    std::string where_param;
    if (const Parameter* d = numeric("POINT", "DATA_START")) {
      const int v = count_value(*d);
      if (v > 0) {
        if (block != 0 && v != block)
          warn(d->offset, "POINT:DATA_START", format("block %d, header word 9 says %d; using POINT:DATA_START", v, block));
        block = v;
        where = d->offset;
        where_param = "POINT:DATA_START";
      } else {
        note(d->offset, "POINT:DATA_START", format("is %d; using header word 9 (block %d)", v, block));
      }
    }
    const std::size_t frame_words = 4 * static_cast<std::size_t>(file_.points.num_points) + static_cast<std::size_t>(analog_words_);
    resolve_storage(block, frame_words);
    const std::size_t ws = file_.float_storage ? 4 : 2;
    file_.frame_bytes = frame_words * ws;
    const std::size_t frames = static_cast<std::size_t>(file_.points.num_frames);
    if (frames == 0 || frame_words == 0) {
      file_.data_offset = block > 0 ? (static_cast<std::size_t>(block) - 1) * kBlock : 0;
      return;
    }
    if (block < 2) fail(where, where_param, format("data section starts at block %d (must be 2 or later)", block));
    file_.data_offset = (static_cast<std::size_t>(block) - 1) * kBlock;
    if (file_.data_offset < param_end_ && param_end_ > param_begin_)
      warn(where, where_param, format("data section (block %d) overlaps the parameter section", block));
    if (file_.data_offset > size_)
      fail(where, where_param, format("data section (block %d, offset 0x%zx) starts past the end of the file (%zu bytes)",
                                      block, file_.data_offset, size_));
    const std::size_t available = size_ - file_.data_offset;
    // Compared by division: frames x frame_bytes may exceed 64 bits for absurd counts.
    if (frames > available / file_.frame_bytes) {
      std::size_t complete = available / file_.frame_bytes;
      // The zero bytes that pad the last 512-byte block are no frames (every point at the origin).
      auto all_zero = [&](std::size_t f) {
        const unsigned char* p = data_ + file_.data_offset + f * file_.frame_bytes;
        return std::all_of(p, p + file_.frame_bytes, [](unsigned char c) { return c == 0; });
      };
      while (complete > 0 && all_zero(complete - 1)) --complete;
      if (complete > 0) {  // a cut file: its complete frames are read, as ezc3d does
        warn(file_.data_offset + complete * file_.frame_bytes, {},
             format("data section truncated: it holds %zu complete frames of the %zu the header declares; reading "
                    "those (frame %zu is incomplete)", complete, frames, complete + 1));
        file_.points.num_frames = static_cast<int>(complete);
        return;
      }
      fail(file_.data_offset + complete * file_.frame_bytes, {},
           format("data section truncated: %zu frames of %zu bytes (%d points, %lld analog words per frame, %s) need "
                  "%.0f bytes from 0x%zx, the file has %zu (frame %zu is incomplete)",
                  frames, file_.frame_bytes, file_.points.num_points, analog_words_,
                  file_.float_storage ? "float" : "int16", static_cast<double>(frames) * static_cast<double>(file_.frame_bytes),
                  file_.data_offset, available, complete + 1));
    }
  }

  void interpret_point_kinds() {
    const std::size_t n = static_cast<std::size_t>(file_.points.num_points);
    file_.point_kinds.assign(n, PointKind::Marker);
    std::vector<std::pair<std::string, PointKind>> groups = {
        {"ANGLES", PointKind::Angle}, {"FORCES", PointKind::Force}, {"MOMENTS", PointKind::Moment}, {"POWERS", PointKind::Power}};
    if (const Parameter* t = file_.find("POINT", "TYPE_GROUPS"); t && t->type == DataType::Char) {
      for (std::size_t i = 0; i + 1 < t->strings.size(); i += 2) {
        const std::string& param = t->strings[i];
        if (param.empty()) continue;
        bool known = false;
        for (auto& g : groups) known = known || g.first == param;
        if (!known) groups.emplace_back(param, PointKind::Other);
      }
    }
    for (const auto& [param, kind] : groups) {
      const Parameter* p = file_.find("POINT", param);
      if (!p || p->type != DataType::Char) continue;
      for (const std::string& label : p->strings) {
        if (label.empty()) continue;
        for (std::size_t i = 0; i < n; ++i)
          if (file_.point_labels[i] == label) file_.point_kinds[i] = kind;
      }
    }
  }

  void read_events() {
    // The C3D guide's group is EVENT; some writers (BKIN) name it EVENTS.
    const char* group = file_.find("EVENT", "USED") || !file_.find("EVENTS", "USED") ? "EVENT" : "EVENTS";
    const Parameter* used = numeric(group, "USED");
    if (used) {
      const Parameter* labels = file_.find(group, "LABELS");
      const Parameter* contexts = file_.find(group, "CONTEXTS");
      const Parameter* times = numeric(group, "TIMES");
      std::size_t count = static_cast<std::size_t>(count_value(*used));
      const std::size_t time_count = times ? times->numbers.size() / 2 : 0;
      if (count > time_count) {
        if (count > 0)
          warn(used->offset, used->qualified_name(),
               format("%zu events but %s:TIMES holds %zu; reading %zu", count, group, time_count, time_count));
        count = time_count;
      }
      for (std::size_t k = 0; k < count; ++k) {
        Event e;
        const double minutes = times->numbers[2 * k], seconds = times->numbers[2 * k + 1];
        e.time_s = 60.0 * minutes + seconds;
        if (!std::isfinite(e.time_s)) {
          warn(times->offset, times->qualified_name(), format("event %zu has a non-finite time; skipped", k + 1));
          continue;
        }
        if (labels && labels->type == DataType::Char && k < labels->strings.size()) e.label = labels->strings[k];
        if (contexts && contexts->type == DataType::Char && k < contexts->strings.size()) e.context = contexts->strings[k];
        file_.events.push_back(std::move(e));
      }
      return;
    }
    const Header& h = file_.header;
    if (!h.four_char_event_labels || h.event_count == 0) return;
    int count = h.event_count;
    if (count > kMaxHeaderEvents) {
      warn(300, {}, format("header says %d events; the header event block holds at most 18", count));
      count = kMaxHeaderEvents;
    }
    for (int k = 0; k < count; ++k) {
      Event e;
      e.from_header = true;
      e.time_s = dec_.f32(data_ + 304 + 4 * k);
      e.label = trim_copy(std::string_view(reinterpret_cast<const char*>(data_ + 396 + 4 * k), 4));
      if (!std::isfinite(e.time_s)) {
        warn(static_cast<std::size_t>(304 + 4 * k), {}, format("header event %d has a non-finite time; skipped", k + 1));
        continue;
      }
      file_.events.push_back(std::move(e));
    }
  }

  [[noreturn]] void bad_sample(std::size_t offset, int frame, int point, const char* what) const {
    const std::string& label = file_.point_labels[static_cast<std::size_t>(point)];
    fail(offset, {},
         format("frame %d (file frame %lld), point %d%s%s%s: %s in a sample marked valid", frame,
                static_cast<long long>(file_.first_frame) + frame, point + 1, label.empty() ? "" : " '",
                label.c_str(), label.empty() ? "" : "'", what));
  }

  // Integer data whose header scale and POINT:SCALE disagree in magnitude (c3d.org MACsample:
  // with POINT:SCALE the shoulder lands at 0.57 m). The one that gives the markers a body's
  // extent (0.9-3 m across, median over frames) wins, with a warning; if both or neither do, a
  // located error: a silent conversion at the wrong scale is worse than none.
  void choose_integer_scale() {
    const double header = file_.header.scale, param = file_.point_scale;
    if (file_.float_storage || scale_param_.empty() || !(header > 0) || !(param > 0) ||
        std::abs(header - param) <= 1e-6 * std::abs(header))
      return;
    const std::size_t n = static_cast<std::size_t>(file_.points.num_points);
    const std::size_t frames = static_cast<std::size_t>(file_.points.num_frames);
    if (n == 0 || frames == 0) return;
    std::vector<double> extents;  // per sampled frame, in stored integer counts
    const std::size_t step = std::max<std::size_t>(1, frames / 200);
    for (std::size_t f = 0; f < frames; f += step) {
      const unsigned char* frame = data_ + file_.data_offset + f * file_.frame_bytes;
      double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
      int valid = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const unsigned char* q = frame + i * 8;
        if (dec_.i16(q + 6) < 0) continue;
        ++valid;
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], static_cast<double>(dec_.i16(q + 2 * a)));
          hi[a] = std::max(hi[a], static_cast<double>(dec_.i16(q + 2 * a)));
        }
      }
      if (valid >= 3) extents.push_back(std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}));
    }
    if (extents.empty()) return;
    std::nth_element(extents.begin(), extents.begin() + static_cast<long>(extents.size() / 2), extents.end());
    const std::string u = to_lower(file_.point_units);
    const double metres = u == "m" ? 1 : u == "cm" ? 0.01 : 0.001;  // mm, or unknown: as the motion layer assumes
    const double counts = extents[extents.size() / 2];
    auto plausible = [&](double scale) { return counts * scale * metres >= 0.9 && counts * scale * metres <= 3; };
    const std::string says = format("POINT:SCALE %g gives markers %.2f m across, the header's %g gives %.2f m", param,
                                    counts * param * metres, header, counts * header * metres);
    if (plausible(header) == plausible(param))
      fail(scale_offset_, scale_param_, "the point scale is ambiguous: " + says + "; cannot tell which is right");
    file_.point_scale = plausible(header) ? header : param;
    warn(scale_offset_, scale_param_, says + format("; using %g", file_.point_scale));
  }

  void decode_points() {
    PointSamples& ps = file_.points;
    const std::size_t n = static_cast<std::size_t>(ps.num_points);
    const std::size_t frames = static_cast<std::size_t>(ps.num_frames);
    if (n == 0 || frames == 0) return;
    if (!file_.float_storage && file_.point_scale == 0)
      fail(scale_offset_, scale_param_, "point scale is 0: integer coordinates cannot be scaled");
    // Bounded by the data section size checked in locate_data (>= 8 bytes per sample).
    ps.xyz.assign(n * frames * 3, 0.0f);
    ps.residual.assign(n * frames, -1.0f);
    const float scale = static_cast<float>(file_.point_scale);
    const float residual_scale = static_cast<float>(std::abs(file_.point_scale));
    for (std::size_t f = 0; f < frames; ++f) {
      const unsigned char* frame = data_ + file_.data_offset + f * file_.frame_bytes;
      float* xyz = ps.xyz.data() + f * n * 3;
      float* res = ps.residual.data() + f * n;
      if (file_.float_storage) {
        for (std::size_t i = 0; i < n; ++i) {
          const unsigned char* s = frame + i * 16;
          const float r = dec_.f32(s + 12);
          if (r < 0) continue;  // invalid sample: coordinates are meaningless (often 0 or NaN)
          const float x = dec_.f32(s), y = dec_.f32(s + 4), z = dec_.f32(s + 8);
          if (!std::isfinite(r)) bad_sample(static_cast<std::size_t>(s + 12 - data_), static_cast<int>(f), static_cast<int>(i), "non-finite residual");
          if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            bad_sample(static_cast<std::size_t>(s - data_), static_cast<int>(f), static_cast<int>(i), "non-finite coordinate");
          xyz[3 * i] = x;
          xyz[3 * i + 1] = y;
          xyz[3 * i + 2] = z;
          // The 4th word packs the camera mask (high byte) and the residual in scale units (low byte).
          const int w = static_cast<int>(std::min(r, 65535.0f));
          res[i] = static_cast<float>(w & 0xff) * residual_scale;
        }
      } else {
        for (std::size_t i = 0; i < n; ++i) {
          const unsigned char* s = frame + i * 8;
          const int w = dec_.i16(s + 6);
          if (w < 0) continue;
          xyz[3 * i] = static_cast<float>(dec_.i16(s)) * scale;
          xyz[3 * i + 1] = static_cast<float>(dec_.i16(s + 2)) * scale;
          xyz[3 * i + 2] = static_cast<float>(dec_.i16(s + 4)) * scale;
          res[i] = static_cast<float>(w & 0xff) * residual_scale;
        }
      }
    }
  }

  const unsigned char* data_;
  std::size_t size_;
  std::string name_;
  Diagnostics* diagnostics_;
  Decoder dec_;
  C3dFile file_;
  std::size_t param_begin_ = 0;
  std::size_t param_end_ = 0;           // the section as read (up to the data start, see parse_parameters)
  std::size_t declared_param_end_ = 0;  // as the parameter header's block count says
  bool warned_overflow_ = false;
  long long analog_words_ = 0;
  std::size_t scale_offset_ = 12;
  std::string scale_param_;
};

}  // namespace

std::string c3d_location(const std::string& name, std::size_t offset, std::string_view parameter) {
  std::string s = name + format("@0x%04zx", offset);
  if (!parameter.empty()) {
    s += " [";
    s += parameter;
    s += "]";
  }
  return s;
}

C3dFile parse_c3d(std::string_view bytes, const std::string& name, Diagnostics* diagnostics) {
  return Parser(bytes, name, diagnostics).parse();
}

C3dFile read_c3d(const std::string& path, Diagnostics* diagnostics, const ReadOptions& options) {
  const std::string bytes = read_file(path, options.max_file_bytes);
  return parse_c3d(bytes, path, diagnostics);
}

}  // namespace rt::c3d
