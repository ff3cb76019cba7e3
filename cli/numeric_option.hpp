#pragma once
/// Range checks for numeric command-line options that state the valid range in words
/// ("--fps: 1e+300 is not between 1 and 1000 Hz"), so a huge or non-finite value is a one-line
/// usage error (exit 2) before anything is sized from it.

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

#include "retarget/core/limits.hpp"

namespace rt::cli {

/// A CLI11 validator accepting a finite number in [lo, hi]; `unit` ("Hz", "s", "") is used in the
/// message and in --help.
inline CLI::Validator bounded(double lo, double hi, const std::string& unit) {
  const std::string range = range_in_words(lo, hi, unit);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        const char* begin = text.c_str();
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(begin, &end);
        if (end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(v))
          return "'" + text.substr(0, 40) + "' is not a number " + range;
        if (v < lo || v > hi) return "'" + text.substr(0, 40) + "' is not " + range;
        return std::string();
      },
      range, "BOUNDED");
}

}  // namespace rt::cli
