#pragma once
// The per-pass flags shared by `convert` and `batch`: --no-<pass> skips a pass of the default
// pipeline, --<pass> adds one that is not in it.

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace rt::cli {

/// Adds the flags to `app` (group "Passes"), filling `enabled` and `disabled` with pass names. A
/// default pass also takes --<pass> (hidden, no effect), so that scripts written while it was
/// opt-in (`--com-plan`) keep working. The vectors must outlive the parse.
void add_pass_flags(CLI::App* app, std::vector<std::string>* enabled, std::vector<std::string>* disabled);

}  // namespace rt::cli
