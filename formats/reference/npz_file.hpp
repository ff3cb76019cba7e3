#pragma once
/// A generic .npz (numpy.savez / savez_compressed) writer and reader: a zip archive whose entries
/// are `<key>.npy` files (npy_array.hpp, zip_archive.hpp). numpy.load reads what write_npz
/// writes; read_npz reads what numpy writes (stored or deflated, with Python's zip64 extras).

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "formats/reference/npy_array.hpp"

namespace rt::npz {

/// One array of an .npz file.
struct NamedArray {
  std::string key;                 ///< entry name without ".npy"
  Array array;
  std::uint64_t header_offset = 0; ///< reader: offset of the entry in the archive (for locations)
};

struct NpzFile {
  std::string file;                ///< file name used in locations
  std::vector<NamedArray> arrays;  ///< in archive order

  /// The array named `key`, or nullptr.
  const Array* find(const std::string& key) const;
  /// "<file>@0x<offset> [<key>.npy]" for an entry of this file ("<file> [<key>.npy]" when absent).
  std::string location(const std::string& key) const;
};

struct NpzWriteOptions {
  bool compress = true;  ///< deflate entries (numpy.savez_compressed); false = stored (savez)
};

/// The bytes of an .npz holding `arrays` in the given order. Keys must be unique, non-empty and
/// free of '/' (InternalError otherwise).
std::string encode_npz(const std::vector<NamedArray>& arrays, const NpzWriteOptions& options = {});

struct NpzReadOptions {
  /// Upper bound on the total uncompressed size [bytes]. Default 4 GiB.
  std::uint64_t max_total_bytes = std::uint64_t{1} << 32;
};

/// Parses .npz bytes. Every entry must be a `<key>.npy` file; `file` names it in errors
/// ("walk.npz@0x1f3 [joint_pos.npy]: CRC mismatch ...").
NpzFile decode_npz(std::string_view bytes, const std::string& file, const NpzReadOptions& options = {});

/// Reads an .npz file from disk (InputError when unreadable or larger than `max_file_bytes`).
NpzFile read_npz(const std::string& path, std::uint64_t max_file_bytes = std::uint64_t{1} << 31,
                 const NpzReadOptions& options = {});

/// Writes an .npz file atomically (rt::write_file_atomic).
void write_npz(const std::string& path, const std::vector<NamedArray>& arrays,
               const NpzWriteOptions& options = {});

}  // namespace rt::npz
