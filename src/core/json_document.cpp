#include "retarget/core/json_document.hpp"

#include <algorithm>
#include <map>
#include <vector>

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

// Byte offset of the `index`-th (0-based) object key of JSON text: a key is a string token followed
// by ':'. Only called for text that nlohmann has parsed up to past that key. npos if not found.
std::size_t key_offset(std::string_view text, std::size_t index) {
  std::size_t seen = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '"') continue;
    const std::size_t start = i;
    for (++i; i < text.size() && text[i] != '"'; ++i)
      if (text[i] == '\\') ++i;
    std::size_t j = i + 1;
    while (j < text.size() && (text[j] == ' ' || text[j] == '\t' || text[j] == '\n' || text[j] == '\r')) ++j;
    if (j < text.size() && text[j] == ':' && seen++ == index) return start;
  }
  return std::string_view::npos;
}

// A key seen twice in one object: the path ("contacts.left") and the key events' indices, located
// in the text once the parse is abandoned.
struct DuplicateKey {
  std::string path;
  std::size_t first_index, index;
};

// Rejects a key that appears twice in one object (nlohmann keeps the last one silently, so a
// second "fps" would override the first unseen). Keys are named by their path ("contacts.left").
class DuplicateKeyCheck {
 public:
  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start: scopes_.push_back({true, {}, {}}); break;
      case Json::parse_event_t::array_start: scopes_.push_back({false, {}, {}}); break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        if (!scopes_.empty()) scopes_.pop_back();
        break;
      case Json::parse_event_t::key:
        if (!scopes_.empty() && scopes_.back().is_object) {
          Scope& s = scopes_.back();
          s.last_key = parsed.is_string() ? parsed.get<std::string>() : parsed.dump();
          const auto [it, fresh] = s.keys.emplace(s.last_key, keys_seen_);
          if (!fresh) throw DuplicateKey{path(), it->second, keys_seen_};
        }
        ++keys_seen_;
        break;
      case Json::parse_event_t::value: break;
    }
    return true;
  }

 private:
  struct Scope {
    bool is_object;
    std::map<std::string, std::size_t> keys;  ///< key -> index of its key event
    std::string last_key;
  };
  std::string path() const {
    std::string p;
    for (const Scope& s : scopes_)
      if (s.is_object && !s.last_key.empty()) p += (p.empty() ? "" : ".") + s.last_key;
    return p;
  }
  std::vector<Scope> scopes_;
  std::size_t keys_seen_ = 0;
};

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
    j = Json::parse(text.begin(), text.end(), DuplicateKeyCheck());
  } catch (const DuplicateKey& d) {
    const std::size_t at = key_offset(text, d.index), first = key_offset(text, d.first_index);
    if (at == std::string_view::npos || first == std::string_view::npos) throw InputError(file, d.path + ": duplicate key");
    const std::string first_at = text_location("", text, first + 1);  // ":line:col"
    throw InputError(text_location(file, text, at + 1), d.path + ": duplicate key (first at line " +
                                                            first_at.substr(1, first_at.find(':', 1) - 1) + ")");
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
