#include "mutator.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iterator>

namespace rt::fuzz {
namespace {

// Numbers at the edges of what readers convert: overflow, denormals, NaN, signs, int limits.
const char* const kNumbers[] = {"0",          "-0",          "1",       "-1",         "2",          "3",
                                "255",        "256",         "65535",   "65536",      "2147483647", "2147483648",
                                "-2147483649", "4294967296", "1e10",    "1e18",       "1e308",      "1e309",
                                "-1e308",     "1e-308",      "1e-400",  "nan",        "NaN",        "inf",
                                "-inf",       "0.0001",      "1e-6",    "9999999999999999999",      "0x10",
                                "1.5e",       ".",           "-",       "1e",         "00000000000001"};

// Bytes that structure text formats.
const char kStructure[] = "\n\r\t ,:;{}[]()\"'#=<>/-.\\";

std::size_t below(Rng& rng, std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); }

template <typename T>
void put(std::string& s, std::size_t at, T value, bool big_endian) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big_endian) std::reverse(std::begin(b), std::end(b));
  for (std::size_t i = 0; i < sizeof(T) && at + i < s.size(); ++i) s[at + i] = static_cast<char>(b[i]);
}

const std::string& pick_word(Rng& rng, const Target& t) {
  static const std::string empty;
  return t.dictionary.empty() ? empty : t.dictionary[below(rng, t.dictionary.size())];
}

std::string pick_token(Rng& rng, const Target& t) {
  if (rng() % 2 || t.dictionary.empty()) return kNumbers[below(rng, std::size(kNumbers))];
  return pick_word(rng, t);
}

// [begin, end) of the line holding `at`.
std::pair<std::size_t, std::size_t> line_at(const std::string& s, std::size_t at) {
  const std::size_t b = at == 0 ? 0 : (s.rfind('\n', at - 1) == std::string::npos ? 0 : s.rfind('\n', at - 1) + 1);
  const std::size_t e = std::min(s.find('\n', at), s.size());
  return {b, e};
}

void mutate_once(std::string& s, Rng& rng, const Target& t, const std::vector<Seed>& corpus) {
  if (s.empty()) {
    s = t.binary ? std::string(1, static_cast<char>(rng())) : pick_token(rng, t);
    return;
  }
  const std::size_t at = below(rng, s.size());
  const int kinds = t.binary ? 10 : 13;
  switch (below(rng, kinds)) {
    case 0: s[at] = static_cast<char>(s[at] ^ (1u << below(rng, 8))); break;  // bit flip
    case 1: s[at] = static_cast<char>(rng()); break;                         // random byte
    case 2: s.erase(at, 1 + below(rng, rng() % 4 ? 8 : 512)); break;          // deletion
    case 3: {                                                                 // duplication of a chunk
      const std::size_t from = below(rng, s.size());
      s.insert(below(rng, s.size() + 1), s.substr(from, 1 + below(rng, rng() % 4 ? 32 : 2048)));
      break;
    }
    case 4: s.resize(at); break;  // truncation
    case 5: {                     // splice: this input's head, another seed's tail
      const std::string& other = corpus[below(rng, corpus.size())].bytes;
      if (other.empty()) break;
      s = s.substr(0, at) + other.substr(below(rng, other.size()));
      break;
    }
    case 6: {  // copy a block over another place (keeps the size: moves structure around)
      const std::size_t n = 1 + below(rng, 64), from = below(rng, s.size());
      const std::string block = s.substr(from, n);
      s.replace(at, std::min(block.size(), s.size() - at), block);
      break;
    }
    // Binary: integers and floats at their limits, either byte order.
    case 7:
      if (t.binary) {
        static const std::uint16_t v16[] = {0, 1, 2, 0x7f, 0x80, 0xff, 0x100, 0x7fff, 0x8000, 0xffff};
        put(s, at, v16[below(rng, std::size(v16))], rng() % 2);
        break;
      }
      [[fallthrough]];
    case 8:
      if (t.binary) {
        static const std::uint32_t v32[] = {0, 1, 0x7fffffff, 0x80000000, 0xffffffff, 0x10000, 0x3f800000, 0x7fc00000};
        put(s, at, v32[below(rng, std::size(v32))], rng() % 2);
        break;
      }
      [[fallthrough]];
    case 9:
      if (t.binary) {
        static const float vf[] = {0.f, -1.f, 1e30f, -1e30f, 1e-30f, 65536.f, __builtin_nanf(""), __builtin_inff()};
        put(s, at, vf[below(rng, std::size(vf))], rng() % 2);
        break;
      }
      // Text: a structure character.
      s.insert(at, 1, kStructure[below(rng, sizeof kStructure - 1)]);
      break;
    case 10: s.insert(at, pick_token(rng, t)); break;  // a token or number inserted
    case 11: {                                        // a whitespace-delimited word replaced
      const std::size_t b = s.find_first_not_of(" \t\r\n", at);
      if (b == std::string::npos) break;
      const std::size_t e = std::min(s.find_first_of(" \t\r\n,:[]{}\"", b + 1), s.size());
      s.replace(b, e - b, pick_token(rng, t));
      break;
    }
    default: {  // a line duplicated (often many times) or swapped with another
      const auto [b, e] = line_at(s, at);
      const std::string line = s.substr(b, e - b) + "\n";
      if (rng() % 2) {
        const std::size_t copies = rng() % 4 ? 1 : 1 + below(rng, 64);
        std::string rep;
        for (std::size_t i = 0; i < copies; ++i) rep += line;
        s.insert(b, rep);
      } else {
        const auto [b2, e2] = line_at(s, below(rng, s.size()));
        if (b2 >= e || e2 <= b) {
          const std::string other = s.substr(b2, e2 - b2);
          if (b2 > b) {
            s.replace(b2, e2 - b2, s.substr(b, e - b));
            s.replace(b, e - b, other);
          } else {
            const std::string mine = s.substr(b, e - b);
            s.replace(b, e - b, other);
            s.replace(b2, e2 - b2, mine);
          }
        }
      }
    }
  }
}

}  // namespace

void mutate(std::string& s, Rng& rng, const Target& target, const std::vector<Seed>& corpus) {
  const int n = rng() % 2 ? 1 : 2 + static_cast<int>(rng() % 3);
  for (int i = 0; i < n; ++i) mutate_once(s, rng, target, corpus);
  if (s.size() > target.max_len) s.resize(target.max_len);
}

}  // namespace rt::fuzz
