#include "formats/asf/asf_amc.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

constexpr std::size_t kMaxBones = 1000;
constexpr std::uint64_t kMaxFileBytes = std::uint64_t{1} << 30;

struct Token {
  std::string text;
  int col = 1;
};

struct Line {
  int number = 0;
  std::vector<Token> tokens;
};

// Non-empty lines without comments ('#' to the end of the line), split at whitespace.
std::vector<Line> tokenize(const std::string& text, const std::string& file) {
  std::vector<Line> out;
  int number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++number;
    Line line;
    line.number = number;
    for (std::size_t i = pos; i < end;) {
      const char c = text[i];
      if (c == '#') break;
      if (c == ' ' || c == '\t' || c == '\r') {
        ++i;
        continue;
      }
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
        throw InputError(format("%s:%d:%zu", file.c_str(), number, i - pos + 1), "not a text file (a control or non-ASCII byte)");
      const std::size_t start = i;
      while (i < end && text[i] != ' ' && text[i] != '\t' && text[i] != '\r' && text[i] != '#') ++i;
      line.tokens.push_back({text.substr(start, i - start), static_cast<int>(start - pos + 1)});
    }
    if (!line.tokens.empty()) out.push_back(std::move(line));
    pos = end + 1;
  }
  return out;
}

class Parser {
 public:
  explicit Parser(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const Line& l, const Token& t, const std::string& what) const {
    throw InputError(format("%s:%d:%d", file_.c_str(), l.number, t.col), what);
  }
  [[noreturn]] void fail(const Line& l, const std::string& what) const {
    throw InputError(format("%s:%d:1", file_.c_str(), l.number), what);
  }
  double number(const Line& l, std::size_t i) const {
    if (i >= l.tokens.size()) fail(l, l.tokens.back(), "expected a number after '" + one_line(l.tokens.back().text) + "'");
    const Token& t = l.tokens[i];
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(t.text.c_str(), &end);
    if (end == t.text.c_str() || *end != '\0') fail(l, t, "expected a number, got '" + one_line(t.text) + "'");
    if (!std::isfinite(v) || errno == ERANGE) fail(l, t, "number '" + one_line(t.text) + "' is out of range");
    return v;
  }
  Vec3 vec3(const Line& l, std::size_t first) const { return Vec3(number(l, first), number(l, first + 1), number(l, first + 2)); }
  void expect_count(const Line& l, std::size_t n) const {
    if (l.tokens.size() != n)
      fail(l, l.tokens.size() > n ? l.tokens[n] : l.tokens.back(),
           format("'%s' takes %zu value(s), got %zu", one_line(l.tokens[0].text).c_str(), n - 1, l.tokens.size() - 1));
  }
  // "XYZ" -> {0, 1, 2}: the three axes, each once.
  std::array<int, 3> axis_order(const Line& l, const Token& t) const {
    const std::string s = to_lower(t.text);
    std::array<int, 3> out{};
    std::set<int> seen;
    if (s.size() != 3) fail(l, t, "expected an axis order such as XYZ, got '" + one_line(t.text) + "'");
    for (int i = 0; i < 3; ++i) {
      if (s[i] < 'x' || s[i] > 'z' || !seen.insert(s[i] - 'x').second)
        fail(l, t, "expected an axis order such as XYZ, got '" + one_line(t.text) + "'");
      out[i] = s[i] - 'x';
    }
    return out;
  }
  AsfDof dof(const Line& l, const Token& t) const {
    const std::string s = to_lower(t.text);
    if (s.size() == 2 && (s[0] == 'r' || s[0] == 't') && s[1] >= 'x' && s[1] <= 'z') return {s[0] == 'r', s[1] - 'x'};
    fail(l, t, "unknown dof '" + one_line(t.text) + "' (expected rx, ry, rz, tx, ty or tz)");
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

bool is_section(const Line& l) { return l.tokens[0].text[0] == ':'; }

}  // namespace

int AsfSkeleton::find_bone(const std::string& name) const {
  for (std::size_t i = 0; i < bones.size(); ++i)
    if (bones[i].name == name) return static_cast<int>(i);
  return -1;
}

AsfSkeleton parse_asf(const std::string& text, const std::string& file) {
  const std::vector<Line> lines = tokenize(text, file);
  const Parser p(file);
  AsfSkeleton s;
  s.file = file;
  std::vector<AsfBone> declared;
  std::map<std::string, std::vector<std::pair<std::string, std::pair<const Line*, const Token*>>>> children;
  bool have_root = false, have_bones = false, have_hierarchy = false;
  std::size_t i = 0;
  while (i < lines.size()) {
    const Line& l = lines[i];
    const std::string key = to_lower(l.tokens[0].text);
    if (!is_section(l)) p.fail(l, l.tokens[0], "expected a section keyword (:units, :root, :bonedata, :hierarchy, ...), got '" +
                                                   one_line(l.tokens[0].text) + "'");
    ++i;
    if (key == ":version" || key == ":name") continue;
    if (key == ":documentation") {
      while (i < lines.size() && !is_section(lines[i])) ++i;
      continue;
    }
    if (key == ":units") {
      for (; i < lines.size() && !is_section(lines[i]); ++i) {
        const Line& u = lines[i];
        const std::string k = to_lower(u.tokens[0].text);
        p.expect_count(u, 2);
        if (k == "mass") {
          p.number(u, 1);
        } else if (k == "length") {
          s.length_unit = p.number(u, 1);
          if (!(s.length_unit > 0)) p.fail(u, u.tokens[1], "the length unit must be > 0");
        } else if (k == "angle") {
          const std::string a = to_lower(u.tokens[1].text);
          if (a != "deg" && a != "rad") p.fail(u, u.tokens[1], "angle unit '" + one_line(u.tokens[1].text) + "' is not deg or rad");
          s.angles_in_degrees = a == "deg";
        } else {
          p.fail(u, u.tokens[0], "unknown unit '" + one_line(u.tokens[0].text) + "' (expected mass, length, angle)");
        }
      }
      continue;
    }
    if (key == ":root") {
      have_root = true;
      for (; i < lines.size() && !is_section(lines[i]); ++i) {
        const Line& r = lines[i];
        const std::string k = to_lower(r.tokens[0].text);
        if (k == "order") {
          s.root_order.clear();
          for (std::size_t t = 1; t < r.tokens.size(); ++t) s.root_order.push_back(p.dof(r, r.tokens[t]));
          if (s.root_order.empty() || s.root_order.size() > 6) p.fail(r, r.tokens[0], "the root order lists 1 to 6 dofs");
        } else if (k == "axis") {
          p.expect_count(r, 2);
          s.root_axis_order = p.axis_order(r, r.tokens[1]);
        } else if (k == "position") {
          p.expect_count(r, 4);
          s.root_position = p.vec3(r, 1);
        } else if (k == "orientation") {
          p.expect_count(r, 4);
          s.root_orientation = p.vec3(r, 1);
        } else {
          p.fail(r, r.tokens[0], "unknown :root entry '" + one_line(r.tokens[0].text) + "' (expected order, axis, position, orientation)");
        }
      }
      continue;
    }
    if (key == ":bonedata") {
      have_bones = true;
      while (i < lines.size() && !is_section(lines[i])) {
        const Line& b = lines[i];
        if (to_lower(b.tokens[0].text) != "begin") p.fail(b, b.tokens[0], "expected 'begin' of a bone, got '" + one_line(b.tokens[0].text) + "'");
        AsfBone bone;
        bone.line = b.number;
        bool have_direction = false, have_length = false, ended = false;
        for (++i; i < lines.size() && !is_section(lines[i]); ++i) {
          const Line& e = lines[i];
          const std::string k = to_lower(e.tokens[0].text);
          if (k == "end") {
            ended = true;
            ++i;
            break;
          }
          if (k == "begin") p.fail(e, e.tokens[0], "'begin' inside a bone (the previous bone has no 'end')");
          if (k == "id" || k == "bodymass" || k == "cofmass") continue;
          if (k == "name") {
            p.expect_count(e, 2);
            bone.name = e.tokens[1].text;
          } else if (k == "direction") {
            p.expect_count(e, 4);
            bone.direction = p.vec3(e, 1);
            const double n = bone.direction.norm();
            // Zero-length bones (CMU clavicles of some subjects) have any direction.
            bone.direction = n > 0 ? Vec3(bone.direction / n) : Vec3::UnitX();
            have_direction = true;
          } else if (k == "length") {
            p.expect_count(e, 2);
            bone.length = p.number(e, 1);
            if (bone.length < 0) p.fail(e, e.tokens[1], "negative bone length");
            have_length = true;
          } else if (k == "axis") {
            p.expect_count(e, 5);
            bone.axis_angles = p.vec3(e, 1);
            bone.axis_order = p.axis_order(e, e.tokens[4]);
          } else if (k == "dof") {
            std::set<std::string> seen;
            for (std::size_t t = 1; t < e.tokens.size(); ++t) {
              if (!seen.insert(to_lower(e.tokens[t].text)).second) p.fail(e, e.tokens[t], "dof '" + one_line(e.tokens[t].text) + "' listed twice");
              bone.dofs.push_back(p.dof(e, e.tokens[t]));
              if (!bone.dofs.back().rotation)
                p.fail(e, e.tokens[t], "translation dofs on a bone are not supported (only on the root)");
            }
          } else if (k == "limits" || k[0] == '(') {
            continue;  // joint limits: not used
          } else {
            p.fail(e, e.tokens[0], "unknown bone entry '" + one_line(e.tokens[0].text) + "'");
          }
        }
        if (!ended) p.fail(b, b.tokens[0], "bone without 'end'");
        if (bone.name.empty()) p.fail(b, b.tokens[0], "bone without a name");
        if (!have_direction || !have_length) p.fail(b, b.tokens[0], "bone '" + one_line(bone.name) + "' needs a direction and a length");
        for (const AsfBone& other : declared)
          if (other.name == bone.name) p.fail(b, b.tokens[0], "bone '" + one_line(bone.name) + "' is declared twice");
        if (to_lower(bone.name) == "root") p.fail(b, b.tokens[0], "a bone named 'root' (the name of the root)");
        declared.push_back(std::move(bone));
        if (declared.size() > kMaxBones) p.fail(b, b.tokens[0], format("more than %zu bones", kMaxBones));
      }
      continue;
    }
    if (key == ":hierarchy") {
      have_hierarchy = true;
      if (i >= lines.size() || to_lower(lines[i].tokens[0].text) != "begin")
        p.fail(l, l.tokens[0], "expected 'begin' after :hierarchy");
      bool ended = false;
      for (++i; i < lines.size() && !is_section(lines[i]); ++i) {
        const Line& h = lines[i];
        if (to_lower(h.tokens[0].text) == "end") {
          ended = true;
          ++i;
          break;
        }
        if (h.tokens.size() < 2) p.fail(h, h.tokens[0], "a hierarchy line names a parent and its children");
        for (std::size_t t = 1; t < h.tokens.size(); ++t) children[h.tokens[0].text].push_back({h.tokens[t].text, {&h, &h.tokens[t]}});
      }
      if (!ended) p.fail(l, l.tokens[0], ":hierarchy without 'end'");
      continue;
    }
    p.fail(l, l.tokens[0], "unknown section '" + one_line(l.tokens[0].text) + "'");
  }
  const int last_line = lines.empty() ? 1 : lines.back().number;
  const auto missing = [&](const char* what) { throw InputError(format("%s:%d:1", file.c_str(), last_line), what); };
  if (lines.empty()) missing("empty ASF file");
  if (!have_root) missing("no :root section");
  if (!have_bones) missing("no :bonedata section");
  if (!have_hierarchy) missing("no :hierarchy section");
  if (s.root_order.empty()) missing("the :root section has no order");

  // Bones in depth-first order from the root; every declared bone reachable exactly once.
  std::map<std::string, int> declared_index;
  for (std::size_t b = 0; b < declared.size(); ++b) declared_index[declared[b].name] = static_cast<int>(b);
  std::set<std::string> placed;
  std::vector<std::pair<std::string, int>> stack;  // (bone, parent index in s.bones)
  const auto push_children = [&](const std::string& parent, int parent_index) {
    const auto it = children.find(parent);
    if (it == children.end()) return;
    for (auto c = it->second.rbegin(); c != it->second.rend(); ++c) {
      const auto& [name, where] = *c;
      if (!declared_index.count(name)) p.fail(*where.first, *where.second, "unknown bone '" + one_line(name) + "' in :hierarchy");
      if (!placed.insert(name).second)
        p.fail(*where.first, *where.second, "bone '" + one_line(name) + "' has two parents (or is its own ancestor)");
      stack.push_back({name, parent_index});
    }
  };
  push_children("root", -1);
  while (!stack.empty()) {
    const auto [name, parent] = stack.back();
    stack.pop_back();
    AsfBone bone = declared[static_cast<std::size_t>(declared_index[name])];
    bone.parent = parent;
    s.bones.push_back(std::move(bone));
    push_children(name, static_cast<int>(s.bones.size()) - 1);
  }
  for (const auto& [parent, list] : children)
    if (parent != "root" && !declared_index.count(parent))
      p.fail(*list.front().second.first, list.front().second.first->tokens[0], "unknown bone '" + one_line(parent) + "' in :hierarchy");
  for (const AsfBone& b : declared)
    if (!placed.count(b.name))
      throw InputError(format("%s:%d:1", file.c_str(), b.line), "bone '" + one_line(b.name) + "' is not connected to the root in :hierarchy");
  return s;
}

AsfSkeleton read_asf(const std::string& path) { return parse_asf(read_file(path, kMaxFileBytes), path); }

AmcMotion parse_amc(const std::string& text, const std::string& file, const AsfSkeleton& s) {
  const std::vector<Line> lines = tokenize(text, file);
  const Parser p(file);
  AmcMotion m;
  m.file = file;
  std::map<std::string, int> bone_of;
  m.values_per_frame = static_cast<int>(s.root_order.size());
  m.bone_column.assign(s.bones.size(), -1);
  for (std::size_t b = 0; b < s.bones.size(); ++b) {
    bone_of[s.bones[b].name] = static_cast<int>(b);
    if (!s.bones[b].dofs.empty()) {
      m.bone_column[b] = m.values_per_frame;
      m.values_per_frame += static_cast<int>(s.bones[b].dofs.size());
    }
  }
  std::size_t i = 0;
  for (; i < lines.size() && is_section(lines[i]); ++i) {
    const Line& l = lines[i];
    const std::string k = to_lower(l.tokens[0].text);
    if (k == ":degrees" || k == ":radians") {
      m.has_angle_unit = true;
      m.angles_in_degrees = k == ":degrees";
    } else if (k != ":fully-specified") {
      p.fail(l, l.tokens[0], "unknown AMC keyword '" + one_line(l.tokens[0].text) + "' (expected :FULLY-SPECIFIED, :DEGREES, :RADIANS)");
    }
  }
  std::vector<char> seen(s.bones.size() + 1);
  long first_frame = 0;
  const auto finish_frame = [&](const Line& at) {
    if (m.num_frames == 0) return;
    if (!seen.back()) p.fail(at, format("frame %d has no root line", m.num_frames));
    for (std::size_t b = 0; b < s.bones.size(); ++b)
      if (m.bone_column[b] >= 0 && !seen[b]) p.fail(at, format("frame %d has no line for bone '%s'", m.num_frames, s.bones[b].name.c_str()));
  };
  for (; i < lines.size(); ++i) {
    const Line& l = lines[i];
    const Token& first = l.tokens[0];
    if (is_section(l)) p.fail(l, first, "keyword '" + one_line(first.text) + "' after the first frame");
    if (l.tokens.size() == 1 && first.text.find_first_not_of("0123456789") == std::string::npos) {
      finish_frame(l);
      const long frame = first.text.size() > 9 ? -1 : std::strtol(first.text.c_str(), nullptr, 10);
      if (m.num_frames == 0) first_frame = frame;
      if (frame < 0 || frame != first_frame + m.num_frames)
        p.fail(l, first, format("frame number %s where %ld is expected (frames are numbered consecutively)",
                                one_line(first.text).c_str(), first_frame + m.num_frames));
      m.frame_lines.push_back(l.number);
      ++m.num_frames;
      m.values.resize(static_cast<std::size_t>(m.num_frames) * static_cast<std::size_t>(m.values_per_frame), 0.0);
      std::fill(seen.begin(), seen.end(), 0);
      continue;
    }
    if (m.num_frames == 0) p.fail(l, first, "expected a frame number, got '" + one_line(first.text) + "'");
    double* row = m.values.data() + static_cast<std::size_t>(m.num_frames - 1) * static_cast<std::size_t>(m.values_per_frame);
    int column = 0;
    std::size_t count = 0;
    std::size_t slot = 0;
    if (to_lower(first.text) == "root") {
      count = s.root_order.size();
      slot = s.bones.size();
    } else {
      const auto it = bone_of.find(first.text);
      if (it == bone_of.end()) p.fail(l, first, "unknown bone '" + one_line(first.text) + "' (not in " + s.file + ")");
      slot = static_cast<std::size_t>(it->second);
      column = m.bone_column[slot];
      count = s.bones[slot].dofs.size();
      if (count == 0) p.fail(l, first, "bone '" + one_line(first.text) + "' has no dofs in " + s.file);
    }
    if (seen[slot]) p.fail(l, first, format("'%s' appears twice in frame %d", one_line(first.text).c_str(), m.num_frames));
    seen[slot] = 1;
    if (l.tokens.size() != count + 1)
      p.fail(l, l.tokens.size() > count + 1 ? l.tokens[count + 1] : l.tokens.back(),
             format("'%s' takes %zu value(s), got %zu", one_line(first.text).c_str(), count, l.tokens.size() - 1));
    for (std::size_t k = 0; k < count; ++k) row[static_cast<std::size_t>(column) + k] = p.number(l, k + 1);
  }
  if (m.num_frames == 0) throw InputError(format("%s:%d:1", file.c_str(), lines.empty() ? 1 : lines.back().number), "no frames");
  finish_frame(lines.back());
  return m;
}

AmcMotion read_amc(const std::string& path, const AsfSkeleton& skeleton) {
  return parse_amc(read_file(path, kMaxFileBytes), path, skeleton);
}

}  // namespace rt
