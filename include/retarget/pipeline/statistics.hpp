#pragma once
/// Per-pass statistics (MLIR-style "(S)" counters): a name, a value and a unit, in the order the
/// pass reported them. The pipeline keeps one list per pass; the CLI prints them with -v and
/// meta.json records them.

#include <string>
#include <vector>

namespace rt {

struct Statistic {
  std::string name;   ///< e.g. "landmark-error-median"
  double value = 0;
  std::string unit;   ///< e.g. "m", "frames", "" for counts
  std::string note;   ///< optional free text (e.g. the worst landmark)
};

class Statistics {
 public:
  void set(std::string name, double value, std::string unit = "", std::string note = "");
  const std::vector<Statistic>& items() const { return items_; }
  /// Value of a statistic by name, or `fallback`.
  double get(const std::string& name, double fallback = 0) const;
  bool has(const std::string& name) const;

 private:
  std::vector<Statistic> items_;
};

}  // namespace rt
