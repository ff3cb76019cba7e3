#include "retarget/core/strings.hpp"

#include <gtest/gtest.h>

#include <string>

namespace rt {
namespace {

TEST(Utf8, WellFormedSequencesHaveTheirLength) {
  EXPECT_EQ(utf8_sequence_length("a", 0), 1u);
  EXPECT_EQ(utf8_sequence_length("\xC3\xA9", 0), 2u);          // é
  EXPECT_EQ(utf8_sequence_length("\xE2\x86\x90", 0), 3u);      // ←
  EXPECT_EQ(utf8_sequence_length("\xF0\x9F\x98\x80", 0), 4u);  // U+1F600
  EXPECT_EQ(first_invalid_utf8("plain \xC3\xA9 text \xE2\x86\x90"), std::string::npos);
  EXPECT_EQ(first_invalid_utf8(""), std::string::npos);
}

TEST(Utf8, MalformedBytesAreFoundWhereTheyStart) {
  EXPECT_EQ(utf8_sequence_length("\x80", 0), 0u);              // stray continuation byte
  EXPECT_EQ(utf8_sequence_length("\xC0\xAF", 0), 0u);          // overlong '/'
  EXPECT_EQ(utf8_sequence_length("\xE0\x80\xAF", 0), 0u);      // overlong, three bytes
  EXPECT_EQ(utf8_sequence_length("\xED\xA0\x80", 0), 0u);      // surrogate
  EXPECT_EQ(utf8_sequence_length("\xF4\x90\x80\x80", 0), 0u);  // above U+10FFFF
  EXPECT_EQ(utf8_sequence_length("\xFF", 0), 0u);
  // A lead byte cut short by the end of the text or by an ASCII byte: what made tinyxml read past
  // the end of a fuzzed URDF.
  const std::string cut = "<a/>\n  \xEF<";
  EXPECT_EQ(first_invalid_utf8(cut), 7u);
  EXPECT_EQ(first_invalid_utf8(std::string("ok\xE2\x86")), 2u);
  const TextPosition at = text_position(cut, 7);
  EXPECT_EQ(at.line, 2);
  EXPECT_EQ(at.column, 3);
}

}  // namespace
}  // namespace rt
