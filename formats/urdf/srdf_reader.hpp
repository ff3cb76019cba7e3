#pragma once
/// The part of an SRDF (MoveIt's semantic robot description) that onboarding uses: the named
/// joint configurations (<group_state name=... group=...><joint name=... value=.../>).

#include <map>
#include <string>
#include <vector>

namespace rt {

struct SrdfGroupState {
  std::string name;
  std::string group;
  std::map<std::string, double> joints;  ///< [rad] or [m]
  int line = 0;
};

/// Reads the group states of an SRDF file, in document order. Throws InputError "<file>:<line>:"
/// for a file that is not XML, has no <robot>, or a joint without a numeric value.
std::vector<SrdfGroupState> read_srdf_group_states(const std::string& path);

}  // namespace rt
