#include "formats/mjcf/mjcf_tree.hpp"

#include <tinyxml.h>

#include <set>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

class TreeReader {
 public:
  explicit TreeReader(MjcfTree& tree) : tree_(tree) {}

  // Children of the world body or of a body (through <frame> elements, which only move frames).
  void children(const TiXmlElement& parent, int parent_body) {
    for (const TiXmlElement* e = parent.FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->ValueStr();
      if (tag == "body") {
        body(*e, parent_body);
      } else if (tag == "frame") {
        children(*e, parent_body);
      } else if (tag == "include") {
        fail(*e, "<include> is not followed: the body order would be incomplete (inline the included file)");
      } else if ((tag == "joint" || tag == "freejoint") && parent_body < 0) {
        fail(*e, "a joint directly in <worldbody>");
      }
    }
  }

 private:
  [[noreturn]] void fail(const TiXmlElement& e, const std::string& what) const {
    throw InputError(tree_.where(e.Row()), what);
  }

  std::string name_of(const TiXmlElement& e, const char* what) const {
    const char* n = e.Attribute("name");
    if (!n || !*n) fail(e, std::string("unnamed ") + what + ": every body and joint needs a name to be matched to the robot");
    return n;
  }

  void body(const TiXmlElement& e, int parent_body) {
    MjcfBody b;
    b.name = name_of(e, "<body>");
    b.parent = parent_body;
    b.line = e.Row();
    if (!body_names_.insert(b.name).second) fail(e, "duplicate body name '" + b.name + "'");
    const int index = static_cast<int>(tree_.bodies.size());
    tree_.bodies.push_back(b);
    joints(e, index);
    children(e, index);
  }

  // The joints of a body: its own <joint>/<freejoint> children and those inside its <frame>s.
  void joints(const TiXmlElement& parent, int body_index) {
    for (const TiXmlElement* e = parent.FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->ValueStr();
      if (tag == "frame") {
        joints(*e, body_index);
        continue;
      }
      if (tag != "joint" && tag != "freejoint") continue;
      MjcfJoint j;
      j.line = e->Row();
      if (tag == "freejoint") {
        const char* n = e->Attribute("name");
        j.name = n ? n : "";
        j.type = "free";
      } else {
        j.name = name_of(*e, "<joint>");
        const char* type = e->Attribute("type");
        j.type = type ? type : "hinge";
        if (j.type != "hinge" && j.type != "slide" && j.type != "free")
          fail(*e, "joint '" + j.name + "' has type '" + j.type + "': only hinge, slide and free joints map to URDF joints");
      }
      if (!j.name.empty() && !joint_names_.insert(j.name).second) fail(*e, "duplicate joint name '" + j.name + "'");
      tree_.bodies[static_cast<std::size_t>(body_index)].joints.push_back(j);
    }
  }

  MjcfTree& tree_;
  std::set<std::string> body_names_, joint_names_;
};

}  // namespace

std::string MjcfTree::where(int line) const { return file + ":" + std::to_string(line); }

std::vector<const MjcfJoint*> MjcfTree::movable_joints() const {
  std::vector<const MjcfJoint*> out;
  for (const MjcfBody& b : bodies)
    for (const MjcfJoint& j : b.joints)
      if (j.type != "free") out.push_back(&j);
  return out;
}

MjcfTree parse_mjcf_tree(const std::string& xml_text, const std::string& file) {
  MjcfTree tree;
  tree.file = file;
  // tinyxml steps over a multi-byte sequence by its lead byte alone: reject what is not UTF-8
  // before it could read past the end.
  if (const std::size_t bad = first_invalid_utf8(xml_text); bad != std::string::npos) {
    const TextPosition at = text_position(xml_text, bad);
    throw InputError(format("%s:%d:%d", file.c_str(), at.line, at.column),
                     format("byte 0x%02X is not UTF-8; save the file as UTF-8", static_cast<unsigned char>(xml_text[bad])));
  }
  TiXmlDocument doc;
  doc.Parse(xml_text.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (doc.Error())
    throw InputError(format("%s:%d:%d", file.c_str(), doc.ErrorRow(), doc.ErrorCol()),
                     std::string("malformed XML: ") + doc.ErrorDesc());
  const TiXmlElement* root = doc.RootElement();
  if (!root || root->ValueStr() != "mujoco")
    throw InputError(file + ":" + std::to_string(root ? root->Row() : 1), "not an MJCF file: the root element is not <mujoco>");
  const TiXmlElement* world = root->FirstChildElement("worldbody");
  if (!world) throw InputError(tree.where(root->Row()), "no <worldbody>: the MJCF has no bodies");
  TreeReader reader(tree);
  for (; world; world = world->NextSiblingElement("worldbody")) reader.children(*world, -1);
  if (tree.bodies.empty()) throw InputError(tree.where(root->Row()), "no <body> in <worldbody>");
  return tree;
}

MjcfTree read_mjcf_tree(const std::string& path) {
  return parse_mjcf_tree(read_file(path, std::uint64_t{64} << 20), base_name(path));  // MJCF models are KBs
}

}  // namespace rt
