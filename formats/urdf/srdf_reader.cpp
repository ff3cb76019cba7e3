#include "formats/urdf/srdf_reader.hpp"

#include <tinyxml.h>

#include <cmath>
#include <cstdlib>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

std::vector<SrdfGroupState> read_srdf_group_states(const std::string& path) {
  const std::string text = read_file(path, 16u << 20);
  if (const std::size_t bad = first_invalid_utf8(text); bad != std::string::npos) {
    const TextPosition at = text_position(text, bad);
    throw InputError(path + ":" + std::to_string(at.line) + ":" + std::to_string(at.column),
                     format("byte 0x%02X is not UTF-8; save the file as UTF-8", static_cast<unsigned char>(text[bad])));
  }
  TiXmlDocument doc;
  doc.Parse(text.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (doc.Error()) throw InputError(path + ":" + std::to_string(doc.ErrorRow()), std::string("not XML: ") + doc.ErrorDesc());
  const TiXmlElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Value()) != "robot") throw InputError(path, "no <robot> element");
  std::vector<SrdfGroupState> out;
  for (const TiXmlElement* gs = robot->FirstChildElement("group_state"); gs; gs = gs->NextSiblingElement("group_state")) {
    SrdfGroupState s;
    s.line = gs->Row();
    if (const char* n = gs->Attribute("name")) s.name = n;
    if (const char* g = gs->Attribute("group")) s.group = g;
    for (const TiXmlElement* j = gs->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
      const char* name = j->Attribute("name");
      const char* value = j->Attribute("value");
      const std::string where = path + ":" + std::to_string(j->Row());
      if (!name || !value) throw InputError(where, "<joint> of a group_state needs name and value");
      char* end = nullptr;
      const double v = std::strtod(value, &end);
      if (end == value || *end != '\0' || !std::isfinite(v))
        throw InputError(where, std::string("joint '") + name + "': value '" + value + "' is not a number");
      s.joints[name] = v;
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace rt
