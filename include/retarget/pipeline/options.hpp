#pragma once
/// Self-documenting option tables for passes: every option has a name, a default (the value of the
/// field when the table is built), a unit-bearing one-line doc, and a parser. They back the pass
/// pipeline syntax `ik{max_iterations=80,regularization=1e-3}`, `retarget convert --list-passes`
/// and the option record written to meta.json.

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace rt {

/// The values a numeric option accepts, [lo, hi] (in the option's unit, named in messages). The
/// options that size work — rates, periods, iteration counts, window lengths — carry one, so
/// `com-replan{period=1e-9}` is a usage error instead of a huge allocation.
struct OptionRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  std::string unit;  ///< "Hz", "s", "" ...
};

class OptionTable {
 public:
  struct Entry {
    std::string name;
    std::string doc;
    std::function<void(const std::string&)> set;  ///< throws InputError for a bad value
    std::function<std::string()> get;
  };

  void add(const std::string& name, double& field, const std::string& doc, const OptionRange& range = {});
  void add(const std::string& name, int& field, const std::string& doc, const OptionRange& range = {});
  void add(const std::string& name, bool& field, const std::string& doc);
  void add(const std::string& name, std::string& field, const std::string& doc);

  /// Sets one option from text; `context` names the pass in errors. Unknown names are InputError
  /// listing the known ones.
  void set(const std::string& name, const std::string& value, const std::string& context);
  const std::vector<Entry>& entries() const { return entries_; }
  /// "name=value,name=value" in declaration order.
  std::string to_string() const;

 private:
  std::vector<Entry> entries_;
};

}  // namespace rt
