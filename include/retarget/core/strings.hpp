#pragma once
/// Small string utilities (ASCII, plus UTF-8 validation).

#include <string>
#include <string_view>
#include <vector>

namespace rt {

std::string to_lower(std::string_view s);
std::string_view trim(std::string_view s);
bool starts_with(std::string_view s, std::string_view prefix);
bool ends_with(std::string_view s, std::string_view suffix);
/// Splits on any character of `separators`, dropping empty pieces.
std::vector<std::string> split(std::string_view s, std::string_view separators);
/// Joins with a separator.
std::string join(const std::vector<std::string>& parts, std::string_view separator);
/// Control characters (newline, tab, ...) replaced by spaces, so that a value quoted in a one-line
/// error message keeps it one line.
std::string one_line(std::string s);
/// Length of the well-formed, shortest-form UTF-8 sequence that starts at s[i] (1 for ASCII), or 0
/// where the bytes there are not one: a stray continuation byte, a sequence cut short, an overlong
/// form, a surrogate or a code point above U+10FFFF.
std::size_t utf8_sequence_length(std::string_view s, std::size_t i);
/// Offset of the first byte that does not start a well-formed UTF-8 sequence, or npos when the
/// whole text is UTF-8.
std::size_t first_invalid_utf8(std::string_view s);
/// 1-based line and column (in bytes) of byte offset `at` of a text.
struct TextPosition {
  int line = 1;
  int column = 1;
};
TextPosition text_position(std::string_view s, std::size_t at);
/// printf-style formatting into a std::string.
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace rt
