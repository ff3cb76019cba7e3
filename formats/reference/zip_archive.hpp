#pragma once
/// A minimal zip archive writer and reader (PKWARE APPNOTE 6.3), enough for .npz files: stored
/// and deflated entries (zlib raw deflate + crc32), no encryption, no multi-disk archives.
/// The writer produces classic (32-bit) archives and refuses contents that would need zip64;
/// the reader also understands the zip64 extended-information extra field that Python's zipfile
/// (and so numpy.savez) puts into its headers, but not zip64 end records (> 65535 entries or
/// archives > 4 GiB).
///
/// The reader trusts nothing: every offset and size is checked against the bytes present, the
/// declared uncompressed size is checked against what deflate can produce (at most 1032:1) and
/// against ReadLimits, output memory grows only as data actually inflates, and each entry's CRC-32
/// is verified. Errors are InputError with location "<file>@0x<offset> [<entry>]".

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rt::zip {

struct Entry {
  std::string name;
  std::string data;                ///< uncompressed content
  std::uint64_t header_offset = 0; ///< reader: offset of the entry's local header in the archive
};

enum class Method : std::uint16_t { Stored = 0, Deflate = 8 };

/// Builds an archive in memory. With Method::Deflate each entry is deflated (zlib level 1) unless
/// that does not make it smaller, in which case it is stored. Timestamps are fixed (1980-01-01
/// 00:00), so equal inputs give byte-identical archives. InputError when an entry or the archive
/// would exceed the 32-bit zip limits (4 GiB, 65535 entries).
std::string write_archive(const std::vector<Entry>& entries, Method method);

struct ReadLimits {
  /// Upper bound on the sum of uncompressed entry sizes [bytes]. Default 4 GiB.
  std::uint64_t max_total_bytes = std::uint64_t{1} << 32;
};

/// Reads every entry of an archive held in `bytes`, in central-directory order. `file` is used in
/// error locations. Duplicate entry names are an error.
std::vector<Entry> read_archive(std::string_view bytes, const std::string& file,
                                const ReadLimits& limits = {});

/// "<file>@0x<offset>" plus " [<entry>]" when `entry` is not empty.
std::string binary_location(const std::string& file, std::uint64_t offset, const std::string& entry = {});

}  // namespace rt::zip
