#include "retarget/core/json_document.hpp"

#include <gtest/gtest.h>

#include <string>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {
namespace {

// what() of the InputError parse_json_object throws, or "" when it accepts the text.
std::string error_of(const std::string& text, int max_depth = 8) {
  try {
    parse_json_object(text, "d.json", "a document", max_depth);
    return "";
  } catch (const InputError& e) {
    return e.what();
  }
}

TEST(JsonDocument, ParsesAnObjectKeepingKeyOrder) {
  const auto j = parse_json_object("{\"b\": 1, \"a\": [true, null]}", "d.json", "a document", 8);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j.begin().key(), "b");
  EXPECT_EQ(json_type_phrase(j["a"]), "an array");
  EXPECT_EQ(json_type_phrase(j["a"][1]), "null");
  EXPECT_EQ(json_type_phrase(j["b"]), "a number");
}

TEST(JsonDocument, SyntaxErrorsCarryLineAndColumn) {
  // The offending '}' is line 3, column 8.
  const std::string e = error_of("{\n  \"a\": 1,\n  \"b\": }");
  EXPECT_EQ(e.rfind("d.json:3:8: invalid JSON: ", 0), 0u) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_EQ(error_of("").rfind("d.json:1:1: invalid JSON", 0), 0u) << error_of("");
}

TEST(JsonDocument, RejectsNonObjectsUnrepresentableNumbersAndDeepNesting) {
  EXPECT_EQ(error_of("[1, 2]"), "d.json:1:1: a document must be a JSON object");
  EXPECT_EQ(error_of("{\"x\": 1e999}").rfind("d.json", 0), 0u) << error_of("{\"x\": 1e999}");
  EXPECT_NE(error_of("{\"x\": 1e999}").find("invalid JSON"), std::string::npos);
  // Depth 3 is accepted at a limit of 3, depth 4 is not.
  EXPECT_EQ(error_of("{\"a\": [[1]]}", 3), "");
  EXPECT_EQ(error_of("{\"a\": [[[1]]]}", 3), "d.json: JSON nests deeper than 3 levels");
}

// Issue 18: nlohmann keeps the last of two equal keys silently; a second "fps" must not override
// the first unseen. The error is located at the second key (line:column) and names the key's path
// and the first one's line.
TEST(JsonDocument, RejectsDuplicateKeysByPath) {
  EXPECT_EQ(error_of("{\"fps\": 30, \"fps\": 0.001}"), "d.json:1:13: fps: duplicate key (first at line 1)");
  EXPECT_EQ(error_of("{\"a\": {\"b\": 1, \"c\": {\"d\": 1, \"d\": 2}}}"),
            "d.json:1:30: a.c.d: duplicate key (first at line 1)");
  // Across lines, with keys inside strings, escaped quotes and values that look like keys.
  EXPECT_EQ(error_of("{\n  \"note\": \"\\\"fps\\\": 1\",\n  \"fps\": 30,\n  \"x\": [\"fps\", {\"fps\": 1}],\n  \"fps\": 2\n}"),
            "d.json:5:3: fps: duplicate key (first at line 3)");
  // The same key in sibling objects, in array elements and at other levels is fine.
  EXPECT_EQ(error_of("{\"a\": {\"x\": 1}, \"b\": {\"x\": 1}, \"x\": [{\"x\": 1}, {\"x\": 2}]}"), "");
  EXPECT_EQ(error_of("{\"l\": [{\"k\": 1},\n {\"k\": 1, \"k\": 2}]}"), "d.json:2:11: l.k: duplicate key (first at line 2)");
}

TEST(JsonDocument, DepthCountsContainersAndStopsAtTheLimit) {
  const auto j = nlohmann::ordered_json::parse("{\"a\": [1, {\"b\": []}]}");
  EXPECT_EQ(json_depth(j, 10), 4);
  EXPECT_EQ(json_depth(j, 2), 2);
  EXPECT_EQ(json_depth(nlohmann::ordered_json(3), 10), 0);
}

TEST(Strings, OneLineReplacesControlCharacters) {
  EXPECT_EQ(one_line("a\nb\tc\r"), "a b c ");
  EXPECT_EQ(one_line("plain"), "plain");
}

}  // namespace
}  // namespace rt
