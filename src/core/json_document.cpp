#include "retarget/core/json_document.hpp"

#include <algorithm>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

using Json = nlohmann::ordered_json;

// 1-based line and column of byte offset `byte`; nlohmann counts from 1 and points at the last
// character read.
std::string text_location(const std::string& file, std::string_view text, std::size_t byte) {
  const std::size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size());
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return format("%s:%zu:%zu", file.c_str(), line, col);
}

}  // namespace

int json_depth(const Json& j, int limit) {
  if (!j.is_structured() || limit <= 0) return 0;
  int deepest = 0;
  for (const auto& v : j) deepest = std::max(deepest, json_depth(v, limit - 1));
  return deepest + 1;
}

std::string json_type_phrase(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return "a boolean";
    case Json::value_t::string: return "a string";
    case Json::value_t::array: return "an array";
    case Json::value_t::object: return "an object";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "a number";
    default: return "an unsupported value";
  }
}

Json parse_json_object(std::string_view text, const std::string& file, const std::string& what, int max_depth) {
  Json j;
  try {
    j = Json::parse(text.begin(), text.end());
  } catch (const Json::parse_error& e) {
    // what() is "[json.exception.parse_error.101] parse error at line 3, column 5: <detail>";
    // keep the detail, use our own location format.
    std::string detail = one_line(e.what());
    const auto colon = detail.find(": ", detail.find("parse error"));
    if (colon != std::string::npos) detail = detail.substr(colon + 2);
    throw InputError(text_location(file, text, e.byte), "invalid JSON: " + detail.substr(0, 300));
  } catch (const Json::exception& e) {
    // Valid syntax the library cannot represent, e.g. a number beyond double range.
    std::string detail = one_line(e.what());
    const auto bracket = detail.find("] ");
    if (bracket != std::string::npos) detail = detail.substr(bracket + 2);
    throw InputError(file, "invalid JSON: " + detail.substr(0, 300));
  }
  if (!j.is_object()) throw InputError(file + ":1:1", what + " must be a JSON object");
  if (json_depth(j, max_depth + 1) > max_depth) throw InputError(file, format("JSON nests deeper than %d levels", max_depth));
  return j;
}

}  // namespace rt
