#pragma once
/// Reading C3D files. Every malformed input becomes an rt::InputError whose location is
/// `<file>@0x<offset>` plus ` [GROUP:PARAM]` when the problem is in a known parameter, e.g.
///   walk.c3d@0x048d [POINT:LABELS]: parameter data (5790 bytes) overruns the parameter section
/// Every count read from the file is checked against the bytes that are really there before
/// anything is allocated, so a hostile file cannot make the reader allocate more than a small
/// multiple of its size.

#include <cstdint>
#include <string>
#include <string_view>

#include "formats/c3d/c3d_file.hpp"
#include "retarget/core/diagnostics.hpp"

namespace rt::c3d {

struct ReadOptions {
  /// Files larger than this are rejected before reading (protects against absurd inputs).
  std::uint64_t max_file_bytes = 1ull << 31;
};

/// Reads and decodes a C3D file. Non-fatal findings (inconsistent header copies, a garbage
/// "next" offset in the last parameter, ...) go to `diagnostics` when given.
C3dFile read_c3d(const std::string& path, Diagnostics* diagnostics = nullptr, const ReadOptions& options = {});

/// Decodes C3D bytes already in memory; `name` is used in error locations.
C3dFile parse_c3d(std::string_view bytes, const std::string& name, Diagnostics* diagnostics = nullptr);

/// `<name>@0x<offset>` with at least 4 hex digits, plus ` [GROUP:PARAM]` when `parameter` is given.
std::string c3d_location(const std::string& name, std::size_t offset, std::string_view parameter = {});

}  // namespace rt::c3d
