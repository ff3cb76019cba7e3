#include <cmath>
#include <cstdlib>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/load_motion.hpp"

namespace rt {

namespace {
struct UnitEntry {
  const char* name;
  double metres;
};
// CMU ASF files use ":units length 0.45", i.e. 1 unit = 1/0.45 inch.
constexpr UnitEntry kUnits[] = {{"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"inch", 0.0254}, {"cmu", 0.0254 / 0.45}};
}  // namespace

double metres_per_unit(const std::string& units) {
  const std::string u = to_lower(trim(units));
  for (const auto& e : kUnits)
    if (u == e.name) return e.metres;
  if (u == "in" || u == "inches") return 0.0254;
  if (u == "metres" || u == "meters") return 1.0;
  char* end = nullptr;
  const double v = std::strtod(u.c_str(), &end);
  if (!u.empty() && end == u.c_str() + u.size() && std::isfinite(v) && v > 0) return v;
  throw InputError("unknown source units '" + units + "' (expected m, cm, mm, inch, cmu or metres per unit)");
}

std::string units_name(double metres) {
  for (const auto& e : kUnits)
    if (std::abs(metres - e.metres) <= 1e-9 * e.metres) return e.name;
  return format("%g", metres);
}

std::pair<char, bool> parse_up_axis(const std::string& text) {
  std::string t = to_lower(trim(text));
  bool negative = false;
  if (!t.empty() && (t[0] == '-' || t[0] == '+')) {
    negative = t[0] == '-';
    t = t.substr(1);
  }
  if (t == "x" || t == "y" || t == "z") return {t[0], negative};
  throw InputError("unknown up axis '" + text + "' (expected x, y or z, optionally signed: -y)");
}

}  // namespace rt
