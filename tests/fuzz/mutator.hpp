#pragma once
/// Byte-, token- and line-level mutations for the fuzz driver. Deterministic for a given Rng
/// state; `corpus` is used for splices (crossover with another seed).

#include <string>
#include <vector>

#include "fuzz_target.hpp"

namespace rt::fuzz {

/// Applies 1-4 mutations to `s` (mostly 1-2). Text targets get token, number and line mutations
/// with `dictionary` words; binary targets get integer and float overwrites.
void mutate(std::string& s, Rng& rng, const Target& target, const std::vector<Seed>& corpus);

}  // namespace rt::fuzz
