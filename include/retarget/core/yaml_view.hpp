#pragma once
/// Schema-checked access to YAML configuration (robot.yaml, skeleton profiles, manifests).
/// Every error names the file, the line and the key path, e.g.
///   `robots/g1/robot.yaml:12: feet.left.link: expected a string`
/// and unknown keys are rejected with the list of allowed ones, so typos never pass silently.

#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "retarget/core/error.hpp"

namespace rt {

class YamlView {
 public:
  /// Parses a YAML file; syntax errors become InputError with file:line.
  static YamlView load_file(const std::string& path);
  /// Parses YAML text; `name` is used as the file name in errors.
  static YamlView load_string(const std::string& text, const std::string& name);

  YamlView(YAML::Node node, std::string file, std::string path);

  bool has(const std::string& key) const;
  /// Child of a map (InputError if missing).
  YamlView at(const std::string& key) const;
  /// Child of a map, or nullopt if missing.
  std::optional<YamlView> find(const std::string& key) const;
  /// Element of a sequence.
  YamlView at(std::size_t index) const;

  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }
  std::size_t size() const { return node_.size(); }
  /// Keys of a map in document order (InputError if not a map).
  std::vector<std::string> keys() const;

  /// Rejects keys not in `allowed` (InputError naming the first unknown key and the allowed set).
  void check_keys(std::initializer_list<const char*> allowed) const;
  void expect_map() const;
  void expect_sequence() const;

  double as_double() const;
  int as_int() const;
  bool as_bool() const;
  std::string as_string() const;
  std::vector<double> as_doubles() const;
  std::vector<std::string> as_strings() const;

  /// Value of `key` converted, or `fallback` when absent.
  double get(const std::string& key, double fallback) const;
  int get(const std::string& key, int fallback) const;
  bool get(const std::string& key, bool fallback) const;
  std::string get(const std::string& key, const std::string& fallback) const;
  std::string get(const std::string& key, const char* fallback) const {
    return get(key, std::string(fallback));
  }

  /// "file:line" of this node (1-based line).
  std::string location() const;
  /// Dotted key path of this node ("feet.left.link", "landmarks[3].weight").
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  const YAML::Node& node() const { return node_; }

  /// Throws InputError at this node: "<file>:<line>: <path>: <message>".
  [[noreturn]] void fail(const std::string& message) const;

 private:
  YAML::Node node_;
  std::string file_;
  std::string path_;
};

}  // namespace rt
