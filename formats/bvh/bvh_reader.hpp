#pragma once
/// Reading BVH text into a BvhFile (bvh_file.hpp).
///
/// Accepted: any channel order per joint, 0..6 channels on any joint (6-channel non-root joints
/// included), several ROOTs, zero-length joints, End Sites, CRLF / LF / CR line ends mixed in one
/// file, tabs, a UTF-8 byte-order mark, trailing spaces, a missing final newline, scientific
/// notation, leading '+' signs, joint names containing spaces or colons (`mixamorig:Hips`).
///
/// Rejected with rt::InputError whose location is `file:line:col` (1-based; the column counts
/// bytes) and whose message is one line: anything that is not BVH, unbalanced braces, unknown
/// keywords or channel names, a joint without OFFSET, a missing MOTION / Frames / Frame Time, a
/// motion row with fewer or more values than the hierarchy has channels, values that are not
/// numbers or not finite (NaN, inf, overflow), a negative Frame Time, a frame count that is not a
/// non-negative 32-bit integer, and fewer rows than `Frames:` declares. Motion-row errors name
/// the frame 0-based (the first row is frame 0) and the column with its joint and channel, e.g.
/// `walk.bvh:212:14: value 'nan' is not a finite number in frame 192 (column 5, Hips Xrotation)`.
///
/// More rows than `Frames:` declares is a warning (Diagnostics); by default the extra rows are
/// ignored. Memory use is bounded by the text size: nothing is reserved from a declared count
/// that the text cannot hold.

#include <cstdint>
#include <string>
#include <string_view>

#include "formats/bvh/bvh_file.hpp"
#include "retarget/core/diagnostics.hpp"

namespace rt {

struct BvhReadOptions {
  /// Rows after the `Frames:` count: false (default) ignores them (with a warning), true parses
  /// and keeps them (also with a warning). The header is the contract by default.
  bool keep_extra_rows = false;
  /// [bytes] largest file read_bvh accepts (a file this large would hold ~1e8 values).
  std::uint64_t max_file_bytes = 1ull << 30;
};

/// True when `prefix` (the start of a file, any length) begins like BVH text: optional UTF-8
/// byte-order mark and whitespace, then the keyword HIERARCHY (any case). For choosing a reader
/// by content.
bool is_bvh_text(std::string_view prefix);

/// Parses BVH text. `name` is the file name used in error locations. Warnings go to
/// `diagnostics` when it is not null.
BvhFile parse_bvh(std::string_view text, const std::string& name, Diagnostics* diagnostics = nullptr,
                  const BvhReadOptions& options = {});

/// Reads and parses a BVH file (InputError when it cannot be read).
BvhFile read_bvh(const std::string& path, Diagnostics* diagnostics = nullptr, const BvhReadOptions& options = {});

}  // namespace rt
