#include "retarget/pipeline/options.hpp"

#include <cmath>
#include <cstdlib>

#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

double parse_double(const std::string& name, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    throw InputError("option " + name + ": expected a number, got '" + text + "'");
  return v;
}

void check_range(const std::string& name, double v, const OptionRange& r) {
  if (v >= r.lo && v <= r.hi) return;
  throw InputError(format("option %s: %g is not %s", name.c_str(), v, range_in_words(r.lo, r.hi, r.unit).c_str()));
}

}  // namespace

void OptionTable::add(const std::string& name, double& field, const std::string& doc, const OptionRange& range) {
  entries_.push_back({name, doc,
                      [&field, name, range](const std::string& v) {
                        const double d = parse_double(name, v);
                        check_range(name, d, range);
                        field = d;
                      },
                      [&field] { return format("%g", field); }});
}

void OptionTable::add(const std::string& name, int& field, const std::string& doc, const OptionRange& range) {
  entries_.push_back({name, doc,
                      [&field, name, range](const std::string& v) {
                        const double d = parse_double(name, v);
                        if (d != std::floor(d) || std::abs(d) > 1e9)
                          throw InputError("option " + name + ": expected an integer, got '" + v + "'");
                        check_range(name, d, range);
                        field = static_cast<int>(d);
                      },
                      [&field] { return std::to_string(field); }});
}

void OptionTable::add(const std::string& name, bool& field, const std::string& doc) {
  entries_.push_back({name, doc,
                      [&field, name](const std::string& v) {
                        const std::string l = to_lower(v);
                        if (l == "true" || l == "1" || l == "yes" || l == "on") field = true;
                        else if (l == "false" || l == "0" || l == "no" || l == "off") field = false;
                        else throw InputError("option " + name + ": expected true or false, got '" + v + "'");
                      },
                      [&field] { return std::string(field ? "true" : "false"); }});
}

void OptionTable::add(const std::string& name, std::string& field, const std::string& doc) {
  entries_.push_back({name, doc, [&field](const std::string& v) { field = v; }, [&field] { return field; }});
}

void OptionTable::set(const std::string& name, const std::string& value, const std::string& context) {
  for (Entry& e : entries_)
    if (e.name == name) {
      try {
        e.set(value);
      } catch (const InputError& err) {
        throw InputError(context, err.message());
      }
      return;
    }
  std::vector<std::string> names;
  for (const Entry& e : entries_) names.push_back(e.name);
  throw InputError(context, "unknown option '" + name + "'" +
                                (names.empty() ? std::string(" (this pass has no options)")
                                               : " (options: " + join(names, ", ") + ")"));
}

std::string OptionTable::to_string() const {
  std::vector<std::string> parts;
  for (const Entry& e : entries_) parts.push_back(e.name + "=" + e.get());
  return join(parts, ",");
}

}  // namespace rt
