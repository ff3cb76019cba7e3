#pragma once
/// Exit statuses of the `retarget` tool (README "Exit codes").

namespace rt::cli {

inline constexpr int kExitOk = 0;           ///< success (and, for checks, the check passed)
inline constexpr int kExitCheckFailed = 1;  ///< a dynamics check failed (fall, unmet contact, ...)
inline constexpr int kExitBadInput = 2;     ///< bad input file, configuration or usage
inline constexpr int kExitInternal = 3;     ///< internal error (a bug: please report it)

}  // namespace rt::cli
