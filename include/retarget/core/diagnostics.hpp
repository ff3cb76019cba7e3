#pragma once
/// Non-fatal findings (warnings and notes) collected while processing an input. Errors are
/// exceptions (error.hpp); everything the user should still hear about goes here, and the CLI
/// decides how to print it.

#include <string>
#include <vector>

namespace rt {

struct Diagnostic {
  enum class Severity { Note, Warning };
  Severity severity = Severity::Warning;
  std::string location;  ///< same conventions as InputError locations; may be empty
  std::string message;

  /// "<location>: warning: <message>" (or "note"); one line.
  std::string to_string() const;
};

class Diagnostics {
 public:
  void warn(std::string location, std::string message);
  void note(std::string location, std::string message);
  void append(const Diagnostics& other);

  const std::vector<Diagnostic>& items() const noexcept { return items_; }
  bool empty() const noexcept { return items_.empty(); }
  std::size_t warning_count() const noexcept;

 private:
  std::vector<Diagnostic> items_;
};

}  // namespace rt
