#pragma once
/// SHA-256 (FIPS 180-4) for content hashes recorded in meta.json (source clip, URDF, options).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace rt {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(std::string_view s) { update(s.data(), s.size()); }
  /// Lower-case hex digest; the object must not be updated afterwards.
  std::string hex_digest();

 private:
  void compress(const std::uint8_t* block);
  std::uint32_t state_[8];
  std::uint8_t buffer_[64];
  std::size_t buffer_size_ = 0;
  std::uint64_t total_bytes_ = 0;
};

/// Hex SHA-256 of a byte string.
std::string sha256_hex(std::string_view data);
/// Hex SHA-256 of a file's contents (InputError if unreadable).
std::string sha256_file(const std::string& path);

}  // namespace rt
