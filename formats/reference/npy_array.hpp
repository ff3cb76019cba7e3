#pragma once
/// One numpy array as stored in a .npy file (NEP 1 / numpy.lib.format, format versions 1.0-3.0),
/// for the subset of dtypes the project exchanges: '<f8', '<f4', '<i8', '<i4', '|u1', '|b1' and
/// unicode strings '<U<n>' (UCS-4, n code points per element, NUL padded).
///
/// Data is kept as raw little-endian element bytes in C (row-major) order; the reader converts
/// Fortran-ordered files. Shapes are numpy shapes (an empty shape is a 0-d scalar).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rt::npz {

enum class DType : std::uint8_t { Float64, Float32, Int64, Int32, UInt8, Bool, Unicode };

struct Array {
  DType dtype = DType::Float64;
  std::size_t unicode_length = 0;   ///< code points per element ('<U<n>'); Unicode only, >= 1
  std::vector<std::size_t> shape;   ///< numpy shape, C order
  std::string data;                 ///< raw little-endian element bytes, C order

  /// Number of elements (product of shape; 1 for a 0-d array).
  std::size_t size() const;
  std::size_t ndim() const { return shape.size(); }
  /// Bytes per element.
  std::size_t item_size() const;
  /// numpy dtype string: "<f8", "|b1", "<U12", ...
  std::string descr() const;
  bool is_numeric() const { return dtype != DType::Unicode; }

  /// Element `i` (flat C-order index) of a numeric array as double (bool/u1 as 0/1..255; i8
  /// beyond 2^53 rounds). Precondition: is_numeric() and i < size().
  double number(std::size_t i) const;
  /// All elements of a numeric array as doubles, C order.
  std::vector<double> to_doubles() const;
  /// All elements of a Unicode array, UTF-8, trailing NULs removed, C order.
  std::vector<std::string> to_strings() const;

  /// Builders. Values are given in C order and must number the product of `shape`
  /// (InternalError otherwise). Float32 rounds to nearest; Int*/UInt8/Bool take integral values.
  static Array from_doubles(std::vector<std::size_t> shape, const std::vector<double>& values,
                            DType dtype = DType::Float64);
  static Array from_ints(std::vector<std::size_t> shape, const std::vector<std::int64_t>& values,
                         DType dtype = DType::Int64);
  /// Unicode array; `unicode_length` = the longest string in code points (at least 1).
  /// InputError when a string is not valid UTF-8.
  static Array from_strings(std::vector<std::size_t> shape, const std::vector<std::string>& utf8);
};

/// A whole .npy file (format 1.0, header padded to a multiple of 64 bytes, as numpy writes it).
std::string encode_npy(const Array& array);

/// Parses a .npy file. `location` prefixes error messages (e.g. "walk.npz@0x1f3 [joint_pos.npy]").
/// Every length is checked against the bytes present; unsupported dtypes, malformed headers and
/// data of the wrong size are InputErrors.
Array decode_npy(std::string_view bytes, const std::string& location);

}  // namespace rt::npz
