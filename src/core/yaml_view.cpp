#include "retarget/core/yaml_view.hpp"

#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

// yaml-cpp keeps both of two equal keys and lookups see the first: a second `feet:` would be
// ignored unseen. Refused at the second key's line, with its path. Iterative (no recursion on a
// hostile nesting depth); aliases are followed once per node.
void reject_duplicate_keys(const YAML::Node& root, const std::string& name) {
  std::vector<std::pair<YAML::Node, std::string>> stack{{root, ""}};
  std::size_t visited = 0;
  while (!stack.empty()) {
    const auto [node, path] = stack.back();
    stack.pop_back();
    if (++visited > (1u << 22)) throw InputError(name, "YAML document too large (more than 4M nodes, aliases counted)");
    if (node.IsMap()) {
      std::set<std::string> keys;
      for (const auto& kv : node) {
        const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("<complex key>");
        const std::string child = path.empty() ? key : path + "." + key;
        if (!keys.insert(key).second) {
          const YAML::Mark m = kv.first.Mark();
          throw InputError(m.line < 0 ? name : name + ":" + std::to_string(m.line + 1), child + ": duplicate key");
        }
        stack.emplace_back(kv.second, child);
      }
    } else if (node.IsSequence()) {
      std::size_t i = 0;
      for (const auto& item : node) stack.emplace_back(item, path + "[" + std::to_string(i++) + "]");
    }
  }
}

YamlView parse(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(name + ":" + std::to_string(e.mark.line + 1), "YAML syntax error: " + e.msg);
  }
  reject_duplicate_keys(root, name);
  return YamlView(root, name, "");
}

}  // namespace

YamlView YamlView::load_file(const std::string& path) {
  return parse(read_file(path, 64ull << 20), path);
}

YamlView YamlView::load_string(const std::string& text, const std::string& name) {
  return parse(text, name);
}

YamlView::YamlView(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

std::string YamlView::location() const {
  const YAML::Mark mark = node_.Mark();
  if (mark.line < 0) return file_;
  return file_ + ":" + std::to_string(mark.line + 1);
}

void YamlView::fail(const std::string& message) const {
  throw InputError(location(), path_.empty() ? message : path_ + ": " + message);
}

void YamlView::expect_map() const {
  if (!node_.IsMap()) fail("expected a map of keys");
}

void YamlView::expect_sequence() const {
  if (!node_.IsSequence()) fail("expected a list");
}

bool YamlView::has(const std::string& key) const { return node_.IsMap() && node_[key].IsDefined(); }

std::optional<YamlView> YamlView::find(const std::string& key) const {
  expect_map();
  YAML::Node child = node_[key];
  if (!child.IsDefined() || child.IsNull()) return std::nullopt;
  return YamlView(child, file_, path_.empty() ? key : path_ + "." + key);
}

YamlView YamlView::at(const std::string& key) const {
  auto child = find(key);
  if (!child) fail("missing required key '" + key + "'");
  return *child;
}

YamlView YamlView::at(std::size_t index) const {
  expect_sequence();
  if (index >= node_.size()) fail("index " + std::to_string(index) + " out of range");
  return YamlView(node_[index], file_, path_ + "[" + std::to_string(index) + "]");
}

// A sequence or map as a key ("[a]: 1", "? {a: 1}") has no name: as<std::string>() threw
// yaml-cpp's own exception (an internal error, exit 3). It is an error at the key's line.
const char* const kComplexKey = "expected a plain key, got a sequence or map as key";

std::vector<std::string> YamlView::keys() const {
  expect_map();
  std::vector<std::string> out;
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) YamlView(kv.first, file_, path_).fail(kComplexKey);
    out.push_back(kv.first.Scalar());
  }
  return out;
}

void YamlView::check_keys(std::initializer_list<const char*> allowed) const {
  expect_map();
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) YamlView(kv.first, file_, path_).fail(kComplexKey);
    const std::string key = kv.first.Scalar();
    bool ok = false;
    for (const char* a : allowed) ok = ok || key == a;
    if (!ok) {
      std::vector<std::string> names(allowed.begin(), allowed.end());
      YamlView(kv.first, file_, path_.empty() ? key : path_ + "." + key)
          .fail("unknown key (allowed: " + join(names, ", ") + ")");
    }
  }
}

double YamlView::as_double() const {
  if (!node_.IsScalar()) fail("expected a number");
  try {
    const double v = node_.as<double>();
    if (!std::isfinite(v)) fail("expected a finite number, got '" + node_.Scalar() + "'");
    return v;
  } catch (const YAML::Exception&) {
    fail("expected a number, got '" + node_.Scalar() + "'");
  }
}

int YamlView::as_int() const {
  if (!node_.IsScalar()) fail("expected an integer");
  try {
    return node_.as<int>();
  } catch (const YAML::Exception&) {
    fail("expected an integer, got '" + node_.Scalar() + "'");
  }
}

bool YamlView::as_bool() const {
  if (!node_.IsScalar()) fail("expected true or false");
  try {
    return node_.as<bool>();
  } catch (const YAML::Exception&) {
    fail("expected true or false, got '" + node_.Scalar() + "'");
  }
}

std::string YamlView::as_string() const {
  if (!node_.IsScalar()) fail("expected a string");
  return node_.Scalar();
}

std::vector<double> YamlView::as_doubles() const {
  expect_sequence();
  std::vector<double> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(at(i).as_double());
  return out;
}

std::vector<std::string> YamlView::as_strings() const {
  expect_sequence();
  std::vector<std::string> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(at(i).as_string());
  return out;
}

double YamlView::get(const std::string& key, double fallback) const {
  auto c = find(key);
  return c ? c->as_double() : fallback;
}
int YamlView::get(const std::string& key, int fallback) const {
  auto c = find(key);
  return c ? c->as_int() : fallback;
}
bool YamlView::get(const std::string& key, bool fallback) const {
  auto c = find(key);
  return c ? c->as_bool() : fallback;
}
std::string YamlView::get(const std::string& key, const std::string& fallback) const {
  auto c = find(key);
  return c ? c->as_string() : fallback;
}

}  // namespace rt
