#include "retarget/pipeline/statistics.hpp"

namespace rt {

void Statistics::set(std::string name, double value, std::string unit, std::string note) {
  for (Statistic& s : items_)
    if (s.name == name) {
      s.value = value;
      s.unit = std::move(unit);
      s.note = std::move(note);
      return;
    }
  items_.push_back({std::move(name), value, std::move(unit), std::move(note)});
}

double Statistics::get(const std::string& name, double fallback) const {
  for (const Statistic& s : items_)
    if (s.name == name) return s.value;
  return fallback;
}

bool Statistics::has(const std::string& name) const {
  for (const Statistic& s : items_)
    if (s.name == name) return true;
  return false;
}

}  // namespace rt
