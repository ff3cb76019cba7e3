#pragma once
/// The kinematic tree of a MuJoCo MJCF file as a simulator numbers it: bodies in document order
/// (depth-first, as MuJoCo assigns body ids; the world body is not listed) and the joints in
/// each body, also in document order (MuJoCo's joint ids and qpos order).
///
/// Read: <worldbody> and the <body>, <frame> (transparent), <joint> and <freejoint> elements
/// below it; everything else (geoms, sites, assets, defaults) is ignored. Not followed:
/// <include> (an error naming the element, since the order would be incomplete).
/// Errors: InputError "<file>:<line>: ..." (unnamed body or joint, duplicate names, a joint type
/// other than hinge/slide/free, no <worldbody> or no body in it).

#include <string>
#include <vector>

namespace rt {

struct MjcfJoint {
  std::string name;
  std::string type;   ///< "hinge", "slide" or "free" (a <freejoint> or type="free")
  int line = 0;
};

struct MjcfBody {
  std::string name;
  int parent = -1;    ///< index into MjcfTree::bodies; -1 = child of the world body
  int line = 0;
  std::vector<MjcfJoint> joints;  ///< in document order
};

struct MjcfTree {
  std::string file;              ///< base name, for messages
  std::vector<MjcfBody> bodies;  ///< document order = MuJoCo body id - 1

  /// "g1.xml:61" for messages.
  std::string where(int line) const;
  /// Every joint of the tree except free joints, in document order (MuJoCo's actuated order).
  std::vector<const MjcfJoint*> movable_joints() const;
};

/// Parses MJCF text; `file` names it in messages.
MjcfTree parse_mjcf_tree(const std::string& xml_text, const std::string& file);
/// Reads and parses an MJCF file.
MjcfTree read_mjcf_tree(const std::string& path);

}  // namespace rt
