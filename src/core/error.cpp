#include "retarget/core/error.hpp"

namespace rt {

namespace {
std::string compose(const std::string& location, const std::string& message) {
  return location.empty() ? message : location + ": " + message;
}
}  // namespace

InputError::InputError(std::string location, std::string message)
    : std::runtime_error(compose(location, message)),
      location_(std::move(location)),
      message_(std::move(message)) {}

}  // namespace rt
