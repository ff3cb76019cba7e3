#pragma once
/// Reading a JSON document we did not necessarily write (meta.json, report.json, summary.json):
/// parse errors and hostile nesting become one-line InputErrors with `file:line:column`.
///
/// This header exposes nlohmann::json; only modules that already link nlohmann_json (privately)
/// include it, so public headers stay free of it.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace rt {

/// Parses `text` (the content of `file`, used only in messages) as one JSON value whose top level
/// must be an object; `what` names the document in that message ("meta.json", "a check report").
/// Throws InputError on a syntax error (at `file:line:column`), on a value the library cannot
/// represent (e.g. a number beyond double range), on a non-object top level and on nesting deeper
/// than `max_depth` levels.
nlohmann::ordered_json parse_json_object(std::string_view text, const std::string& file, const std::string& what,
                                         int max_depth);

/// Nesting depth of `j` (a scalar is 0), counting at most `limit` levels.
int json_depth(const nlohmann::ordered_json& j, int limit);

/// "a number", "an object", ... for "expected X, got Y" messages.
std::string json_type_phrase(const nlohmann::ordered_json& j);

}  // namespace rt
