#include "retarget/core/diagnostics.hpp"

#include <algorithm>

namespace rt {

std::string Diagnostic::to_string() const {
  const char* kind = severity == Severity::Warning ? "warning: " : "note: ";
  return location.empty() ? kind + message : location + ": " + kind + message;
}

void Diagnostics::warn(std::string location, std::string message) {
  items_.push_back({Diagnostic::Severity::Warning, std::move(location), std::move(message)});
}

void Diagnostics::note(std::string location, std::string message) {
  items_.push_back({Diagnostic::Severity::Note, std::move(location), std::move(message)});
}

void Diagnostics::append(const Diagnostics& other) {
  items_.insert(items_.end(), other.items_.begin(), other.items_.end());
}

std::size_t Diagnostics::warning_count() const noexcept {
  return static_cast<std::size_t>(std::count_if(items_.begin(), items_.end(), [](const Diagnostic& d) {
    return d.severity == Diagnostic::Severity::Warning;
  }));
}

}  // namespace rt
