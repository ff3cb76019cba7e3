#pragma once
/// Errors raised by library code. The library never prints or exits: it throws, and the CLI maps
/// exception types to exit codes (README, "Exit codes").
///
/// Locations follow the format's nature:
///   text files      `clip.bvh:212:14`           (file:line[:column], 1-based)
///   binary files    `walk.c3d@0x0200 [POINT:LABELS]`
///   numerics        `walk.bvh frame 812 joint l_knee`
///   config files    `robots/g1/robot.yaml:12: feet.left.link`

#include <stdexcept>
#include <string>

namespace rt {

/// A user-supplied input (file, argument, configuration) is malformed or inconsistent.
/// what() is a single line: "<location>: <message>" (or just the message when there is no
/// location). CLI exit status 2.
class InputError : public std::runtime_error {
 public:
  InputError(std::string location, std::string message);
  explicit InputError(std::string message) : InputError(std::string(), std::move(message)) {}

  const std::string& location() const noexcept { return location_; }
  const std::string& message() const noexcept { return message_; }

 private:
  std::string location_;
  std::string message_;
};

/// An invariant inside the library was broken (a bug, not bad input). CLI exit status 3.
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// Throws InputError(location, message) unless `condition` holds.
inline void require_input(bool condition, const std::string& location, const std::string& message) {
  if (!condition) throw InputError(location, message);
}

/// Throws InternalError unless `condition` holds. Always on (not compiled out in Release).
#define RT_DEMAND(condition, message)                                                        \
  do {                                                                                       \
    if (!(condition))                                                                        \
      throw ::rt::InternalError(std::string(__FILE__) + ":" + std::to_string(__LINE__) +     \
                                ": internal error: " + (message) + " (" #condition ")");     \
  } while (0)

}  // namespace rt
