#pragma once
/// One fuzz target: a parser (plus what the tool does next with its result) run on one input.
/// Targets register themselves (RT_FUZZ_TARGET) with the seeded mutation driver (fuzz_main.cpp);
/// the driver mutates their seeds for a bounded time and fails on anything but a normal return
/// or a one-line rt::InputError: another exception, a crash or sanitizer report, a per-input
/// timeout, or an allocation far beyond what a small input can need.

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace rt::fuzz {

using Rng = std::mt19937_64;

struct Seed {
  std::string name;   ///< where it came from (a path or "generated:...")
  std::string bytes;
};

/// Where seed files are looked for.
struct SeedDirs {
  std::string source;  ///< the repository root (tests/data, examples, robots)
  std::string shared;  ///< ../shared/data, or "" when absent
};

struct Target {
  std::string name;
  /// Small generated inputs plus files from the repository and the shared data.
  std::function<std::vector<Seed>(const SeedDirs&)> seeds;
  /// Called once before the first input (scratch files a target needs); may be empty.
  std::function<void(const std::string& scratch_dir)> setup;
  /// Parses one input. May throw rt::InputError; anything else is a failure.
  std::function<void(std::string_view input)> run;
  /// Tokens of the format, inserted or swapped in by the text mutations.
  std::vector<std::string> dictionary;
  /// Binary formats get integer-overwrite mutations instead of token and line mutations.
  bool binary = false;
  /// Optional structure-aware mutation (e.g. re-zipping a mutated NPZ entry with valid CRCs);
  /// returns false when it does not apply to this input. Used for about half of the mutants.
  std::function<bool(std::string& input, Rng& rng)> mutate;
  /// Mutants are cut to this size.
  std::size_t max_len = 1 << 20;
};

/// Registers a target (called from static initialisers, see RT_FUZZ_TARGET).
bool register_target(Target target);

/// All registered targets, by name.
const std::vector<Target>& targets();

/// Reports a failed check on the current input (saved as an artifact) and aborts.
[[noreturn]] void fail(const std::string& what);

/// fail() unless `condition`.
inline void check(bool condition, const std::string& what) {
  if (!condition) fail(what);
}

/// Seed helpers: every regular file under `dir` whose name ends in one of `extensions` (any
/// extension when empty), sorted, each cut to `max_bytes`; nothing when `dir` does not exist.
std::vector<Seed> seed_files(const std::string& dir, const std::vector<std::string>& extensions,
                             std::size_t max_bytes = 256 * 1024, bool recursive = false);

/// The file's bytes, or "" when it cannot be read.
std::string read_or_empty(const std::string& path);

}  // namespace rt::fuzz

#define RT_FUZZ_CONCAT2(a, b) a##b
#define RT_FUZZ_CONCAT(a, b) RT_FUZZ_CONCAT2(a, b)
/// RT_FUZZ_TARGET(make_target) where `make_target` returns a Target.
#define RT_FUZZ_TARGET(make) \
  [[maybe_unused]] static const bool RT_FUZZ_CONCAT(rt_fuzz_registered_, __LINE__) = ::rt::fuzz::register_target(make())
