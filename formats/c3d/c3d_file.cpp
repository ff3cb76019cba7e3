#include "formats/c3d/c3d_file.hpp"

#include <algorithm>

namespace rt::c3d {

namespace {
bool iequal(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'a' && x <= 'z') x = static_cast<char>(x - 'a' + 'A');
    if (y >= 'a' && y <= 'z') y = static_cast<char>(y - 'a' + 'A');
    if (x != y) return false;
  }
  return true;
}
}  // namespace

const char* processor_name(Processor p) {
  switch (p) {
    case Processor::Intel: return "Intel";
    case Processor::Dec: return "DEC";
    case Processor::Mips: return "MIPS";
  }
  return "unknown";
}

std::size_t Parameter::element_count() const {
  std::size_t n = 1;
  for (int d : dims) n *= static_cast<std::size_t>(d);
  return n;
}

double Parameter::count_at(std::size_t i) const {
  if (i >= numbers.size()) return 0;
  const double v = numbers[i];
  return (type == DataType::Int16 && v < 0) ? v + 65536.0 : v;
}

const Parameter* C3dFile::find(std::string_view group, std::string_view name) const {
  for (const Parameter& p : parameters)
    if (iequal(p.name, name) && iequal(p.group, group)) return &p;
  return nullptr;
}

const Group* C3dFile::find_group(std::string_view name) const {
  for (const Group& g : groups)
    if (iequal(g.name, name)) return &g;
  return nullptr;
}

int C3dFile::marker_count() const {
  return static_cast<int>(std::count(point_kinds.begin(), point_kinds.end(), PointKind::Marker));
}

}  // namespace rt::c3d
