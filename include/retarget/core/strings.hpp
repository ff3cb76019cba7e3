#pragma once
/// Small string utilities (ASCII only).

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
/// printf-style formatting into a std::string.
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace rt
