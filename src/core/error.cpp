#include "retarget/core/error.hpp"

#include <algorithm>

namespace rt {

namespace {
// Messages echo user text (names, values, paths) that may hold line breaks or other control
// bytes; they are written as escapes (\n, \r, \t, \xNN) so that what() stays one line and shows
// what is in the file.
std::string escape_controls(std::string s) {
  if (std::none_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; })) return s;
  std::string out;
  out.reserve(s.size() + 8);
  static const char* hex = "0123456789abcdef";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) out += c;
    else if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else out += std::string("\\x") + hex[u >> 4] + hex[u & 15];
  }
  return out;
}

std::string compose(const std::string& location, const std::string& message) {
  return location.empty() ? message : location + ": " + message;
}
}  // namespace

InputError::InputError(std::string location, std::string message)
    : std::runtime_error(compose(escape_controls(location), escape_controls(message))),
      location_(escape_controls(std::move(location))),
      message_(escape_controls(std::move(message))) {}

}  // namespace rt
