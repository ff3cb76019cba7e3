#pragma once
/// The built-in passes, in default pipeline order (README "Passes" lists them with their options).

#include "retarget/pipeline/pipeline.hpp"

namespace rt {

const PassRegistry& builtin_passes();

}  // namespace rt
