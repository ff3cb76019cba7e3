#pragma once
/// Seeded byte-level mutation of a text input for fuzz-style tests of the text readers (robot.yaml,
/// manifests): every mutant must parse or raise one one-line InputError, within a time budget.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <random>
#include <string>

#include "retarget/core/error.hpp"

namespace rt::test {

/// 1-4 mutations (bit flip, overwrite, insert, delete, truncate, duplicate a chunk); inserted
/// bytes are drawn from `alphabet` half of the time.
inline std::string mutate_text(std::string s, std::mt19937& rng, const std::string& alphabet) {
  const int count = 1 + static_cast<int>(rng() % 4);
  for (int m = 0; m < count; ++m) {
    auto pick_char = [&] { return rng() % 2 && !alphabet.empty() ? alphabet[rng() % alphabet.size()] : static_cast<char>(rng() & 0xFF); };
    if (s.empty()) {
      s.push_back(pick_char());
      continue;
    }
    const std::size_t p = rng() % s.size();
    switch (rng() % 6) {
      case 0: s[p] = static_cast<char>(s[p] ^ (1 << (rng() % 8))); break;
      case 1: s[p] = pick_char(); break;
      case 2: s.insert(s.begin() + static_cast<std::ptrdiff_t>(p), pick_char()); break;
      case 3: s.erase(p, std::min<std::size_t>(1 + rng() % 8, s.size() - p)); break;
      case 4: s.resize(p); break;
      default: {
        const std::size_t n = std::min<std::size_t>(1 + rng() % 32, s.size() - p);
        s.insert(rng() % (s.size() + 1), s.substr(p, n));
      }
    }
  }
  return s;
}

/// Runs `parse` on `iterations` mutants of `seed_text` (or until `budget`); any exception but a
/// one-line InputError fails the test. Returns how many mutants were rejected.
template <typename Parse>
int fuzz_text(const std::string& seed_text, const std::string& alphabet, unsigned seed, int iterations,
              std::chrono::milliseconds budget, Parse parse) {
  std::mt19937 rng(seed);
  const auto t0 = std::chrono::steady_clock::now();
  int rejected = 0;
  for (int i = 0; i < iterations && std::chrono::steady_clock::now() - t0 < budget; ++i) {
    const std::string input = mutate_text(seed_text, rng, alphabet);
    try {
      parse(input);
    } catch (const InputError& e) {
      ++rejected;
      const std::string what = e.what();
      if (what.find('\n') != std::string::npos) ADD_FAILURE() << "multi-line error: " << what << "\ninput:\n" << input;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what() << "\ninput:\n" << input;
      return rejected;
    }
  }
  return rejected;
}

}  // namespace rt::test
