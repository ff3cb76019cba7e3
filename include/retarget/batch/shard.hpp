#pragma once
/// Splitting a batch across machines (`--shard I/N`, design.md §1): shard I of N gets a
/// deterministic subset of the clips, balanced by input file size.
///
/// Assignment (the same on every machine and every run for the same clip list and sizes):
/// the clips are sorted by size, largest first (ties by output name), and each goes to the shard
/// with the smallest total size so far (ties to the lowest shard number) — greedy
/// longest-processing-time scheduling: the heaviest shard exceeds the lightest by at most the
/// largest clip's size, and is within 4/3 of the best possible split. Empty files weigh 1 byte. Adding or removing clips may move others between
/// shards; run every shard of one split against the same input.

#include <cstdint>
#include <string>
#include <vector>

#include "retarget/batch/batch_clip.hpp"

namespace rt {

struct ShardSpec {
  int index = 1;  ///< 1-based shard number I, 1 <= I <= count
  int count = 1;  ///< N >= 1

  /// "I/N".
  std::string to_string() const;
  /// "shard-I-of-N": the suffix of a shard's summary files.
  std::string file_tag() const;
};

/// Parses "I/N" (1 <= I <= N <= 100000). InputError naming `--shard` otherwise.
ShardSpec parse_shard(const std::string& text);

/// 0-based shard of every clip (same order as `clips`) for `count` shards (rule above).
std::vector<int> assign_shards(const std::vector<BatchClip>& clips, int count);

/// The clips of one shard, in their original order.
std::vector<BatchClip> select_shard(const std::vector<BatchClip>& clips, const ShardSpec& shard);

}  // namespace rt
