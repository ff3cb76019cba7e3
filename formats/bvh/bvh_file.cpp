#include "formats/bvh/bvh_file.hpp"

namespace rt {

std::string_view bvh_channel_name(BvhChannel channel) {
  static constexpr std::string_view kNames[6] = {"Xposition", "Yposition", "Zposition",
                                                 "Xrotation", "Yrotation", "Zrotation"};
  const auto i = static_cast<std::size_t>(channel);
  return i < 6 ? kNames[i] : std::string_view("invalid");
}

int BvhFile::find_joint(std::string_view joint_name) const {
  for (std::size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == joint_name) return static_cast<int>(i);
  return -1;
}

int BvhFile::joint_of_column(int column) const {
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const BvhJoint& j = joints[i];
    if (column >= j.first_column && column < j.first_column + static_cast<int>(j.channels.size()))
      return static_cast<int>(i);
  }
  return -1;
}

}  // namespace rt
