#pragma once
/// A tiny XML well-formedness checker for the report tests: one root element after an optional
/// declaration, balanced and properly nested tags, quoted attributes without duplicates, only the
/// five predefined entities and numeric character references, no '<' or bare '&' in text or
/// attribute values. Also counts elements by name and collects attribute values, so tests can
/// look at what was drawn.

#include <cctype>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace rt::test {

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;  ///< values as written (entities not decoded)
  std::string text;                               ///< direct character data, as written
};

struct XmlCheck {
  bool ok = false;
  std::string error;                 ///< first problem, with its byte offset
  std::vector<XmlElement> elements;  ///< in document order
  std::size_t count(const std::string& name) const {
    std::size_t n = 0;
    for (const XmlElement& e : elements) n += e.name == name;
    return n;
  }
};

inline XmlCheck check_xml(const std::string& s) {
  XmlCheck r;
  std::size_t i = 0;
  std::vector<std::size_t> open;  // indices into r.elements
  bool root_seen = false;
  auto fail = [&](const std::string& what) {
    r.ok = false;
    r.error = what + " at byte " + std::to_string(i);
    return r;
  };
  auto name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == ':' || c == '.'; };
  auto skip_space = [&] {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  };
  // Character data or attribute value up to `stop`; checks entities.
  auto chars = [&](char stop, std::string& out) -> bool {
    while (i < s.size() && s[i] != stop) {
      if (s[i] == '<') return false;
      if (s[i] == '&') {
        const std::size_t semi = s.find(';', i);
        if (semi == std::string::npos || semi - i > 10) return false;
        const std::string ent = s.substr(i + 1, semi - i - 1);
        static const std::set<std::string> known = {"amp", "lt", "gt", "quot", "apos"};
        const bool numeric = ent.size() > 1 && ent[0] == '#';
        if (!known.count(ent) && !numeric) return false;
        out += s.substr(i, semi - i + 1);
        i = semi + 1;
        continue;
      }
      out.push_back(s[i++]);
    }
    return true;
  };
  if (s.compare(0, 5, "<?xml") == 0) {
    const std::size_t end = s.find("?>");
    if (end == std::string::npos) return fail("unterminated XML declaration");
    i = end + 2;
  }
  while (i < s.size()) {
    if (s[i] != '<') {
      std::string text;
      if (!chars('<', text)) return fail("bad character data");
      if (open.empty() && text.find_first_not_of(" \t\r\n") != std::string::npos) return fail("text outside the root");
      if (!open.empty()) r.elements[open.back()].text += text;
      continue;
    }
    ++i;
    if (i < s.size() && s[i] == '/') {  // end tag
      ++i;
      const std::size_t b = i;
      while (i < s.size() && name_char(s[i])) ++i;
      const std::string name = s.substr(b, i - b);
      skip_space();
      if (i >= s.size() || s[i] != '>') return fail("bad end tag");
      ++i;
      if (open.empty() || r.elements[open.back()].name != name) return fail("mismatched end tag </" + name + ">");
      open.pop_back();
      continue;
    }
    if (open.empty() && root_seen) return fail("second root element");
    const std::size_t b = i;
    while (i < s.size() && name_char(s[i])) ++i;
    XmlElement e;
    e.name = s.substr(b, i - b);
    if (e.name.empty()) return fail("empty element name");
    bool self_closing = false;
    for (;;) {
      skip_space();
      if (i >= s.size()) return fail("unterminated start tag");
      if (s[i] == '>') {
        ++i;
        break;
      }
      if (s[i] == '/') {
        if (i + 1 >= s.size() || s[i + 1] != '>') return fail("bad '/' in tag");
        i += 2;
        self_closing = true;
        break;
      }
      const std::size_t a = i;
      while (i < s.size() && name_char(s[i])) ++i;
      const std::string attr = s.substr(a, i - a);
      if (attr.empty()) return fail("bad attribute name");
      skip_space();
      if (i >= s.size() || s[i] != '=') return fail("attribute without '='");
      ++i;
      skip_space();
      if (i >= s.size() || (s[i] != '"' && s[i] != '\'')) return fail("unquoted attribute");
      const char quote = s[i++];
      std::string value;
      if (!chars(quote, value) || i >= s.size()) return fail("bad attribute value");
      ++i;
      if (e.attributes.count(attr)) return fail("duplicate attribute " + attr);
      e.attributes[attr] = value;
    }
    root_seen = true;
    r.elements.push_back(std::move(e));
    if (!self_closing) open.push_back(r.elements.size() - 1);
  }
  if (!open.empty()) return fail("unclosed element <" + r.elements[open.back()].name + ">");
  if (!root_seen) return fail("no root element");
  r.ok = true;
  return r;
}

}  // namespace rt::test
