#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "retarget/batch/shard.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {
namespace {

std::vector<BatchClip> random_clips(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::lognormal_distribution<double> size(13.0, 1.0);  // ~0.4 MB median, a long tail like mocap files
  std::vector<BatchClip> clips;
  for (int i = 0; i < n; ++i) {
    BatchClip c;
    c.output_name = format("clip%04d", i);
    c.input = "/data/" + c.output_name + ".bvh";
    c.input_bytes = static_cast<std::uint64_t>(size(rng));
    clips.push_back(c);
  }
  return clips;
}

TEST(Shard, Parse) {
  const ShardSpec s = parse_shard(" 2/8 ");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 8);
  EXPECT_EQ(s.to_string(), "2/8");
  EXPECT_EQ(s.file_tag(), "shard-2-of-8");
  EXPECT_EQ(parse_shard("1/1").count, 1);
  for (const char* bad : {"", "3", "0/2", "3/2", "1/0", "-1/2", "a/b", "1/2/3", "1 /2", "1/100001", "1.0/2"})
    EXPECT_THROW(parse_shard(bad), InputError) << bad;
}

TEST(Shard, EveryClipInExactlyOneShard) {
  const auto clips = random_clips(101, 1);
  for (int n : {1, 2, 3, 7, 101, 150}) {
    std::multiset<std::string> seen;
    for (int i = 1; i <= n; ++i)
      for (const BatchClip& c : select_shard(clips, {i, n})) seen.insert(c.output_name);
    EXPECT_EQ(seen.size(), clips.size()) << n;
    for (const BatchClip& c : clips) EXPECT_EQ(seen.count(c.output_name), 1u) << n;
  }
}

TEST(Shard, DeterministicAndIndependentOfListingOrder) {
  const auto clips = random_clips(200, 2);
  const std::vector<int> a = assign_shards(clips, 5);
  EXPECT_EQ(a, assign_shards(clips, 5));  // stable across runs
  auto shuffled = clips;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
  const std::vector<int> b = assign_shards(shuffled, 5);
  for (std::size_t i = 0; i < shuffled.size(); ++i) {
    const auto k = static_cast<std::size_t>(std::find_if(clips.begin(), clips.end(), [&](const BatchClip& c) {
                                              return c.output_name == shuffled[i].output_name;
                                            }) -
                                            clips.begin());
    EXPECT_EQ(b[i], a[k]) << shuffled[i].output_name;
  }
  // select_shard keeps the original order.
  const auto s = select_shard(clips, {2, 5});
  EXPECT_TRUE(std::is_sorted(s.begin(), s.end(), [](const BatchClip& x, const BatchClip& y) { return x.output_name < y.output_name; }));
}

TEST(Shard, BalancedBySize) {
  for (unsigned seed : {4u, 5u, 6u}) {
    const auto clips = random_clips(300, seed);
    for (int n : {2, 3, 8}) {
      const std::vector<int> shard = assign_shards(clips, n);
      std::vector<std::uint64_t> load(static_cast<std::size_t>(n), 0);
      std::vector<int> count(static_cast<std::size_t>(n), 0);
      std::uint64_t largest = 0, total = 0;
      for (std::size_t i = 0; i < clips.size(); ++i) {
        load[static_cast<std::size_t>(shard[i])] += clips[i].input_bytes;
        ++count[static_cast<std::size_t>(shard[i])];
        largest = std::max(largest, clips[i].input_bytes);
        total += clips[i].input_bytes;
      }
      const auto [lo, hi] = std::minmax_element(load.begin(), load.end());
      EXPECT_LE(*hi - *lo, largest) << "seed " << seed << " n " << n;  // the LPT bound
      // With hundreds of clips the shards are within a few percent of the mean.
      EXPECT_LT(static_cast<double>(*hi), 1.05 * static_cast<double>(total) / n) << "seed " << seed << " n " << n;
      for (int c : count) EXPECT_GT(c, 0);
    }
  }
}

TEST(Shard, OneHugeClipGetsAShardOfItsOwn) {
  auto clips = random_clips(20, 7);
  clips[5].input_bytes = 1ull << 40;
  const std::vector<int> shard = assign_shards(clips, 3);
  for (std::size_t i = 0; i < clips.size(); ++i)
    if (i != 5) {
      EXPECT_NE(shard[i], shard[5]) << i;
    }
}

TEST(Shard, EmptyFilesAreSpreadToo) {
  std::vector<BatchClip> clips(9);
  for (std::size_t i = 0; i < clips.size(); ++i) clips[i].output_name = format("e%zu", i);
  const std::vector<int> shard = assign_shards(clips, 3);
  for (int s = 0; s < 3; ++s) EXPECT_EQ(std::count(shard.begin(), shard.end(), s), 3) << s;
}

}  // namespace
}  // namespace rt
