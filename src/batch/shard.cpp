#include "retarget/batch/shard.hpp"

#include <algorithm>
#include <cctype>
#include <numeric>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

constexpr int kMaxShards = 100000;

// Strict decimal integer in [1, kMaxShards]; -1 otherwise.
int parse_count(std::string_view s) {
  if (s.empty() || s.size() > 6) return -1;
  int v = 0;
  for (const char c : s) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return -1;
    v = v * 10 + (c - '0');
  }
  return v >= 1 && v <= kMaxShards ? v : -1;
}

}  // namespace

std::string ShardSpec::to_string() const { return std::to_string(index) + "/" + std::to_string(count); }

std::string ShardSpec::file_tag() const { return "shard-" + std::to_string(index) + "-of-" + std::to_string(count); }

ShardSpec parse_shard(const std::string& text) {
  const std::string_view t = trim(text);
  const auto slash = t.find('/');
  const int i = slash == std::string_view::npos ? -1 : parse_count(t.substr(0, slash));
  const int n = slash == std::string_view::npos ? -1 : parse_count(t.substr(slash + 1));
  if (i < 0 || n < 0)
    throw InputError("--shard", "expected I/N with 1 <= I <= N (e.g. 2/8), got '" + text + "'");
  if (i > n) throw InputError("--shard", format("shard %d of %d does not exist (I must be between 1 and N)", i, n));
  return {i, n};
}

std::vector<int> assign_shards(const std::vector<BatchClip>& clips, int count) {
  RT_DEMAND(count >= 1, "shard count must be >= 1");
  std::vector<std::size_t> order(clips.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (clips[a].input_bytes != clips[b].input_bytes) return clips[a].input_bytes > clips[b].input_bytes;
    return clips[a].output_name < clips[b].output_name;  // unique names: a total order
  });
  // Greedy LPT; a file of 0 bytes still costs a worker start, so it weighs 1.
  std::vector<std::uint64_t> load(static_cast<std::size_t>(count), 0);
  std::vector<int> shard(clips.size(), 0);
  for (const std::size_t k : order) {
    const auto lightest = std::min_element(load.begin(), load.end());  // first of equal loads
    shard[k] = static_cast<int>(lightest - load.begin());
    *lightest += std::max<std::uint64_t>(clips[k].input_bytes, 1);
  }
  return shard;
}

std::vector<BatchClip> select_shard(const std::vector<BatchClip>& clips, const ShardSpec& spec) {
  const std::vector<int> shard = assign_shards(clips, spec.count);
  std::vector<BatchClip> out;
  for (std::size_t k = 0; k < clips.size(); ++k)
    if (shard[k] == spec.index - 1) out.push_back(clips[k]);
  return out;
}

}  // namespace rt
