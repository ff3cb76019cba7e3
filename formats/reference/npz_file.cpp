#include "formats/reference/npz_file.hpp"

#include <set>

#include "formats/reference/zip_archive.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt::npz {

const Array* NpzFile::find(const std::string& key) const {
  for (const NamedArray& a : arrays)
    if (a.key == key) return &a.array;
  return nullptr;
}

std::string NpzFile::location(const std::string& key) const {
  for (const NamedArray& a : arrays)
    if (a.key == key) return zip::binary_location(file, a.header_offset, key + ".npy");
  return file + " [" + key + ".npy]";
}

std::string encode_npz(const std::vector<NamedArray>& arrays, const NpzWriteOptions& options) {
  std::vector<zip::Entry> entries;
  entries.reserve(arrays.size());
  std::set<std::string> keys;
  for (const NamedArray& a : arrays) {
    RT_DEMAND(!a.key.empty() && a.key.find('/') == std::string::npos, "npz key '" + a.key + "'");
    RT_DEMAND(keys.insert(a.key).second, "duplicate npz key '" + a.key + "'");
    entries.push_back({a.key + ".npy", encode_npy(a.array), 0});
  }
  return zip::write_archive(entries, options.compress ? zip::Method::Deflate : zip::Method::Stored);
}

NpzFile decode_npz(std::string_view bytes, const std::string& file, const NpzReadOptions& options) {
  zip::ReadLimits limits;
  limits.max_total_bytes = options.max_total_bytes;
  std::vector<zip::Entry> entries = zip::read_archive(bytes, file, limits);
  NpzFile out;
  out.file = file;
  out.arrays.reserve(entries.size());
  for (zip::Entry& e : entries) {
    const std::string where = zip::binary_location(file, e.header_offset, e.name);
    if (!ends_with(e.name, ".npy") || e.name.size() == 4)
      throw InputError(where, "entry is not a '<key>.npy' array (an .npz holds only .npy files)");
    NamedArray a;
    a.key = e.name.substr(0, e.name.size() - 4);
    a.header_offset = e.header_offset;
    a.array = decode_npy(e.data, where);
    e.data = std::string();  // release the decompressed copy early
    out.arrays.push_back(std::move(a));
  }
  return out;
}

NpzFile read_npz(const std::string& path, std::uint64_t max_file_bytes, const NpzReadOptions& options) {
  const std::string bytes = read_file(path, max_file_bytes);
  return decode_npz(bytes, base_name(path), options);
}

void write_npz(const std::string& path, const std::vector<NamedArray>& arrays, const NpzWriteOptions& options) {
  write_file_atomic(path, encode_npz(arrays, options));
}

}  // namespace rt::npz
