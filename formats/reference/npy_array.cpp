#include "formats/reference/npy_array.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt::npz {

namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr std::size_t kMagicSize = 6;
// Far beyond any array the project exchanges; keeps hostile headers from asking for absurd sizes.
constexpr std::size_t kMaxUnicodeLength = std::size_t{1} << 16;
constexpr std::size_t kMaxDims = 32;  // numpy's own NPY_MAXDIMS

std::uint64_t load_le(const char* p, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = n; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}
void store_le(char* p, std::uint64_t v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<char>((v >> (8 * i)) & 0xFF);
}

// UTF-8 -> code points; false on malformed input (overlongs, surrogates, > U+10FFFF).
bool utf8_decode(const std::string& s, std::vector<std::uint32_t>& out) {
  out.clear();
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::uint32_t cp = 0;
    std::size_t n = 0;
    if (c < 0x80) { cp = c; n = 1; }
    else if ((c & 0xE0) == 0xC0) { cp = c & 0x1F; n = 2; }
    else if ((c & 0xF0) == 0xE0) { cp = c & 0x0F; n = 3; }
    else if ((c & 0xF8) == 0xF0) { cp = c & 0x07; n = 4; }
    else return false;
    if (i + n > s.size()) return false;
    for (std::size_t k = 1; k < n; ++k) {
      const auto d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (d & 0x3F);
    }
    static constexpr std::uint32_t kMinForLength[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < kMinForLength[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    out.push_back(cp);
    i += n;
  }
  return true;
}

void utf8_append(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out.push_back(static_cast<char>(cp));
  } else if (cp < 0x800) {
    out.push_back(static_cast<char>(0xC0 | (cp >> 6)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  } else if (cp < 0x10000) {
    out.push_back(static_cast<char>(0xE0 | (cp >> 12)));
    out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  } else {
    out.push_back(static_cast<char>(0xF0 | (cp >> 18)));
    out.push_back(static_cast<char>(0x80 | ((cp >> 12) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  }
}

std::size_t shape_size(const std::vector<std::size_t>& shape) {
  std::size_t n = 1;
  for (std::size_t d : shape) n *= d;
  return n;
}

// ---- header parsing: the Python dict literal numpy writes --------------------------------------

class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& location) : s_(text), loc_(location) {}

  void parse(std::string& descr, bool& fortran, std::vector<std::size_t>& shape) {
    bool have_descr = false, have_fortran = false, have_shape = false;
    skip_space();
    expect('{');
    for (;;) {
      skip_space();
      if (peek() == '}') { ++i_; break; }
      const std::string key = parse_string();
      skip_space();
      expect(':');
      skip_space();
      if (key == "descr") {
        if (have_descr) fail("duplicate key 'descr'");
        descr = parse_string();
        have_descr = true;
      } else if (key == "fortran_order") {
        if (have_fortran) fail("duplicate key 'fortran_order'");
        fortran = parse_bool();
        have_fortran = true;
      } else if (key == "shape") {
        if (have_shape) fail("duplicate key 'shape'");
        shape = parse_shape();
        have_shape = true;
      } else {
        fail("unexpected key '" + key + "'");
      }
      skip_space();
      if (peek() == ',') { ++i_; continue; }
      skip_space();
      if (peek() == '}') { ++i_; break; }
      fail("expected ',' or '}'");
    }
    skip_space();
    if (i_ != s_.size()) fail("unexpected text after the header dictionary");
    if (!have_descr || !have_fortran || !have_shape)
      fail("header lacks one of 'descr', 'fortran_order', 'shape'");
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(loc_, format("malformed .npy header at header byte %zu: %s", i_, what.c_str()));
  }
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void skip_space() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }
  void expect(char c) {
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++i_;
  }
  std::string parse_string() {
    const char quote = peek();
    if (quote != '\'' && quote != '"') fail("expected a quoted string");
    ++i_;
    const std::size_t start = i_;
    while (i_ < s_.size() && s_[i_] != quote) {
      if (s_[i_] == '\\' || static_cast<unsigned char>(s_[i_]) < 0x20) fail("unsupported character in string");
      ++i_;
    }
    if (i_ >= s_.size()) fail("unterminated string");
    std::string out(s_.substr(start, i_ - start));
    ++i_;
    return out;
  }
  bool parse_bool() {
    if (s_.substr(i_, 4) == "True") { i_ += 4; return true; }
    if (s_.substr(i_, 5) == "False") { i_ += 5; return false; }
    fail("expected True or False");
  }
  std::vector<std::size_t> parse_shape() {
    std::vector<std::size_t> shape;
    expect('(');
    for (;;) {
      skip_space();
      if (peek() == ')') { ++i_; break; }
      if (peek() < '0' || peek() > '9') fail("expected a dimension");
      std::uint64_t v = 0;
      while (peek() >= '0' && peek() <= '9') {
        if (v > (std::numeric_limits<std::uint64_t>::max() >> 4)) fail("dimension too large");
        v = v * 10 + static_cast<std::uint64_t>(peek() - '0');
        ++i_;
      }
      if (peek() == 'L') ++i_;  // Python 2 long suffix
      if (shape.size() >= kMaxDims) fail("too many dimensions");
      shape.push_back(static_cast<std::size_t>(v));
      skip_space();
      if (peek() == ',') { ++i_; continue; }
      skip_space();
      if (peek() == ')') { ++i_; break; }
      fail("expected ',' or ')' in shape");
    }
    return shape;
  }

  std::string_view s_;
  const std::string& loc_;
  std::size_t i_ = 0;
};

bool parse_descr(const std::string& d, DType& dtype, std::size_t& unicode_length) {
  static const struct { const char* name; DType type; } kFixed[] = {
      {"<f8", DType::Float64}, {"<f4", DType::Float32}, {"<i8", DType::Int64}, {"<i4", DType::Int32},
      {"|u1", DType::UInt8},   {"|b1", DType::Bool},    {"<u1", DType::UInt8}, {"<b1", DType::Bool},
  };
  for (const auto& f : kFixed) {
    if (d == f.name) {
      dtype = f.type;
      return true;
    }
  }
  if (d.size() >= 3 && d[0] == '<' && d[1] == 'U' && d.size() <= 9) {
    std::size_t n = 0;
    for (std::size_t i = 2; i < d.size(); ++i) {
      if (d[i] < '0' || d[i] > '9') return false;
      n = n * 10 + static_cast<std::size_t>(d[i] - '0');
    }
    if (n < 1 || n > kMaxUnicodeLength) return false;
    dtype = DType::Unicode;
    unicode_length = n;
    return true;
  }
  return false;
}

}  // namespace

// ---- Array --------------------------------------------------------------------------------------

std::size_t Array::size() const { return shape_size(shape); }

std::size_t Array::item_size() const {
  switch (dtype) {
    case DType::Float64: case DType::Int64: return 8;
    case DType::Float32: case DType::Int32: return 4;
    case DType::UInt8: case DType::Bool: return 1;
    case DType::Unicode: return 4 * unicode_length;
  }
  return 0;
}

std::string Array::descr() const {
  switch (dtype) {
    case DType::Float64: return "<f8";
    case DType::Float32: return "<f4";
    case DType::Int64: return "<i8";
    case DType::Int32: return "<i4";
    case DType::UInt8: return "|u1";
    case DType::Bool: return "|b1";
    case DType::Unicode: return "<U" + std::to_string(unicode_length);
  }
  return "?";
}

double Array::number(std::size_t i) const {
  const char* p = data.data() + i * item_size();
  switch (dtype) {
    case DType::Float64: {
      const std::uint64_t bits = load_le(p, 8);
      double v;
      std::memcpy(&v, &bits, 8);
      return v;
    }
    case DType::Float32: {
      const auto bits = static_cast<std::uint32_t>(load_le(p, 4));
      float v;
      std::memcpy(&v, &bits, 4);
      return v;
    }
    case DType::Int64: return static_cast<double>(static_cast<std::int64_t>(load_le(p, 8)));
    case DType::Int32: return static_cast<double>(static_cast<std::int32_t>(static_cast<std::uint32_t>(load_le(p, 4))));
    case DType::UInt8: return static_cast<unsigned char>(*p);
    case DType::Bool: return *p != 0 ? 1.0 : 0.0;
    case DType::Unicode: break;
  }
  throw InternalError("npz::Array::number on a unicode array");
}

std::vector<double> Array::to_doubles() const {
  RT_DEMAND(is_numeric(), "to_doubles on a unicode array");
  std::vector<double> out(size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = number(i);
  return out;
}

std::vector<std::string> Array::to_strings() const {
  RT_DEMAND(dtype == DType::Unicode, "to_strings on a numeric array");
  std::vector<std::string> out(size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const char* p = data.data() + i * item_size();
    std::size_t len = unicode_length;
    while (len > 0 && load_le(p + 4 * (len - 1), 4) == 0) --len;  // numpy strips trailing NULs
    for (std::size_t k = 0; k < len; ++k) utf8_append(out[i], static_cast<std::uint32_t>(load_le(p + 4 * k, 4)));
  }
  return out;
}

Array Array::from_doubles(std::vector<std::size_t> shape, const std::vector<double>& values, DType dtype) {
  RT_DEMAND(dtype != DType::Unicode, "from_doubles with a unicode dtype");
  Array a;
  a.dtype = dtype;
  a.shape = std::move(shape);
  RT_DEMAND(a.size() == values.size(), "npz::Array value count does not match its shape");
  const std::size_t w = a.item_size();
  a.data.resize(values.size() * w);
  for (std::size_t i = 0; i < values.size(); ++i) {
    char* p = a.data.data() + i * w;
    const double v = values[i];
    switch (dtype) {
      case DType::Float64: {
        std::uint64_t bits;
        std::memcpy(&bits, &v, 8);
        store_le(p, bits, 8);
        break;
      }
      case DType::Float32: {
        const float f = static_cast<float>(v);
        std::uint32_t bits;
        std::memcpy(&bits, &f, 4);
        store_le(p, bits, 4);
        break;
      }
      case DType::Int64: case DType::Int32: case DType::UInt8: case DType::Bool:
        RT_DEMAND(std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9.2e18, "non-integral value for an integer dtype");
        store_le(p, static_cast<std::uint64_t>(static_cast<std::int64_t>(v)), w);
        break;
      case DType::Unicode: break;
    }
  }
  return a;
}

Array Array::from_ints(std::vector<std::size_t> shape, const std::vector<std::int64_t>& values, DType dtype) {
  RT_DEMAND(dtype == DType::Int64 || dtype == DType::Int32 || dtype == DType::UInt8 || dtype == DType::Bool,
            "from_ints needs an integer dtype");
  Array a;
  a.dtype = dtype;
  a.shape = std::move(shape);
  RT_DEMAND(a.size() == values.size(), "npz::Array value count does not match its shape");
  const std::size_t w = a.item_size();
  a.data.resize(values.size() * w);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::int64_t v = dtype == DType::Bool ? (values[i] != 0) : values[i];
    store_le(a.data.data() + i * w, static_cast<std::uint64_t>(v), w);
  }
  return a;
}

Array Array::from_strings(std::vector<std::size_t> shape, const std::vector<std::string>& utf8) {
  Array a;
  a.dtype = DType::Unicode;
  a.shape = std::move(shape);
  RT_DEMAND(a.size() == utf8.size(), "npz::Array string count does not match its shape");
  std::vector<std::vector<std::uint32_t>> decoded(utf8.size());
  std::size_t longest = 1;
  for (std::size_t i = 0; i < utf8.size(); ++i) {
    if (!utf8_decode(utf8[i], decoded[i])) throw InputError("string '" + utf8[i] + "'", "not valid UTF-8");
    longest = std::max(longest, decoded[i].size());
  }
  if (longest > kMaxUnicodeLength) throw InputError("npz", "string longer than 65536 code points");
  a.unicode_length = longest;
  const std::size_t w = a.item_size();
  a.data.assign(utf8.size() * w, '\0');
  for (std::size_t i = 0; i < decoded.size(); ++i)
    for (std::size_t k = 0; k < decoded[i].size(); ++k) store_le(a.data.data() + i * w + 4 * k, decoded[i][k], 4);
  return a;
}

// ---- .npy encode / decode -----------------------------------------------------------------------

std::string encode_npy(const Array& array) {
  RT_DEMAND(array.data.size() == array.size() * array.item_size(), "npz::Array data size does not match its shape");
  std::string dict = "{'descr': '" + array.descr() + "', 'fortran_order': False, 'shape': (";
  for (std::size_t i = 0; i < array.shape.size(); ++i) {
    if (i > 0) dict += ", ";
    dict += std::to_string(array.shape[i]);
  }
  if (array.shape.size() == 1) dict += ",";
  dict += "), }";
  // Pad with spaces and end with '\n' so that magic + version + length + header is a multiple of
  // 64 bytes (numpy >= 1.14 does so, which keeps the data aligned for memory mapping).
  const std::size_t prefix = kMagicSize + 2 + 2;
  const std::size_t total = (prefix + dict.size() + 1 + 63) / 64 * 64;
  dict.append(total - prefix - dict.size() - 1, ' ');
  dict.push_back('\n');
  if (dict.size() > 0xFFFF) throw InputError("npy", "array header too long for format 1.0");
  std::string out(kMagic, kMagicSize);
  out.push_back('\x01');
  out.push_back('\x00');
  out.push_back(static_cast<char>(dict.size() & 0xFF));
  out.push_back(static_cast<char>(dict.size() >> 8));
  out += dict;
  out += array.data;
  return out;
}

Array decode_npy(std::string_view bytes, const std::string& location) {
  if (bytes.size() < kMagicSize + 4 || bytes.substr(0, kMagicSize) != std::string_view(kMagic, kMagicSize))
    throw InputError(location, "not a .npy array (missing \\x93NUMPY magic)");
  const auto major = static_cast<unsigned char>(bytes[6]);
  const auto minor = static_cast<unsigned char>(bytes[7]);
  if (major < 1 || major > 3 || minor != 0)
    throw InputError(location, format(".npy format version %u.%u is not supported (1.0-3.0)", major, minor));
  const std::size_t len_size = major == 1 ? 2 : 4;
  if (bytes.size() < kMagicSize + 2 + len_size) throw InputError(location, "truncated .npy header");
  const std::uint64_t header_len = load_le(bytes.data() + 8, len_size);
  const std::size_t header_at = kMagicSize + 2 + len_size;
  if (header_len > bytes.size() - header_at)
    throw InputError(location, format(".npy header length %llu runs past the %zu-byte array",
                                      static_cast<unsigned long long>(header_len), bytes.size()));
  const std::string_view header = bytes.substr(header_at, header_len);
  std::string descr;
  bool fortran = false;
  Array a;
  HeaderParser(header, location).parse(descr, fortran, a.shape);
  if (!parse_descr(descr, a.dtype, a.unicode_length))
    throw InputError(location, "unsupported dtype '" + descr.substr(0, 40) +
                                   "' (supported: <f8 <f4 <i8 <i4 |u1 |b1 <U<n>)");

  const std::string_view payload = bytes.substr(header_at + header_len);
  // Element count with overflow checks; the payload must hold exactly count * item size bytes,
  // which bounds every later allocation by the input size.
  std::uint64_t count = 1;
  for (std::size_t d : a.shape) count = d == 0 ? 0 : count;
  for (std::size_t d : a.shape) {
    if (count == 0) break;
    if (count > payload.size() / d) {
      count = std::numeric_limits<std::uint64_t>::max();
      break;
    }
    count *= d;
  }
  const std::uint64_t item = a.item_size();
  if (count == std::numeric_limits<std::uint64_t>::max() || count > payload.size() / item ||
      count * item != payload.size())
    throw InputError(location, format("array data has %zu bytes, shape and dtype %s need %s",
                                      payload.size(), descr.c_str(),
                                      count == std::numeric_limits<std::uint64_t>::max()
                                          ? "more than the file holds"
                                          : (std::to_string(count * item) + " bytes").c_str()));
  if (a.dtype == DType::Unicode) {
    for (std::size_t i = 0; i < payload.size(); i += 4) {
      const std::uint64_t cp = load_le(payload.data() + i, 4);
      if (cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
        throw InputError(location, format("invalid unicode code point 0x%llx in string data",
                                          static_cast<unsigned long long>(cp)));
    }
  }
  if (!fortran || a.shape.size() < 2) {
    a.data.assign(payload.data(), payload.size());
    return a;
  }
  // Fortran order: element (i0, i1, ..., in) is at flat index i0 + d0*(i1 + d1*(...)). Walk the
  // C-order index odometer and gather.
  a.data.resize(payload.size());
  const std::size_t n = a.shape.size();
  std::vector<std::size_t> index(n, 0), f_stride(n, 1);
  for (std::size_t k = 1; k < n; ++k) f_stride[k] = f_stride[k - 1] * a.shape[k - 1];
  for (std::size_t c = 0; c < count; ++c) {
    std::size_t f = 0;
    for (std::size_t k = 0; k < n; ++k) f += index[k] * f_stride[k];
    std::memcpy(a.data.data() + c * item, payload.data() + f * item, item);
    for (std::size_t k = n; k-- > 0;) {
      if (++index[k] < a.shape[k]) break;
      index[k] = 0;
    }
  }
  return a;
}

}  // namespace rt::npz
