#include "formats/urdf/package_uri.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "retarget/core/strings.hpp"

namespace fs = std::filesystem;

namespace rt {

namespace {

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

bool is_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

std::string normalised(const fs::path& p) {
  std::error_code ec;
  fs::path abs = fs::absolute(p, ec);
  if (ec) abs = p;
  return abs.lexically_normal().string();
}

ResolvedResource found(const fs::path& p) { return {normalised(p), ""}; }
ResolvedResource missing(std::string why) { return {"", std::move(why)}; }

// Folders that may hold package `pkg` under `root`: root/pkg and root/*/pkg (one level down), in a
// deterministic (sorted) order.
std::vector<fs::path> package_candidates(const fs::path& root, const std::string& pkg) {
  std::vector<fs::path> out;
  if (is_dir(root / pkg)) out.push_back(root / pkg);
  std::error_code ec;
  std::vector<fs::path> subdirs;
  for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    if (is_dir(it->path()) && is_dir(it->path() / pkg)) subdirs.push_back(it->path() / pkg);
  }
  std::sort(subdirs.begin(), subdirs.end());
  out.insert(out.end(), subdirs.begin(), subdirs.end());
  return out;
}

}  // namespace

std::vector<std::string> split_path_list(const std::string& list) { return split(list, ":"); }

ResolvedResource resolve_package_uri(const std::string& uri, const std::string& base_dir,
                                     const std::vector<std::string>& package_paths) {
  if (uri.empty()) return missing("empty file name");
  if (starts_with(uri, "package://")) {
    std::string rest = uri.substr(10);
    // package:///pkg/rel (an empty authority, as example-robot-data and some exporters write it)
    // names the same file as package://pkg/rel; an existing absolute path is taken as such.
    const bool triple_slash = starts_with(rest, "/");
    if (triple_slash) {
      if (is_file(rest)) return found(rest);
      rest = rest.substr(rest.find_first_not_of('/') == std::string::npos ? rest.size() : rest.find_first_not_of('/'));
    }
    const auto slash = rest.find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 >= rest.size())
      return missing("malformed package URI '" + uri + "' (expected package://<package>/<path>)");
    const std::string pkg = rest.substr(0, slash);
    const std::string rel = rest.substr(slash + 1);
    if (package_paths.empty())
      return missing("cannot resolve '" + uri + "': the package search path is empty (set package_paths in robot.yaml, --package-path or ROS_PACKAGE_PATH)");
    bool package_seen = false;
    for (const auto& root : package_paths) {
      for (const auto& dir : package_candidates(root, pkg)) {
        package_seen = true;
        if (is_file(dir / rel)) return found(dir / rel);
      }
    }
    if (package_seen)
      return missing("file not found: '" + uri + "' (package '" + pkg + "' exists but has no '" + rel +
                     "'; searched: " + join(package_paths, ":") + ")");
    return missing("cannot resolve '" + uri + "': package '" + pkg + "' not found in the package search path " +
                   join(package_paths, ":"));
  }
  if (starts_with(uri, "file://")) {
    const std::string p = uri.substr(7);
    if (is_file(p)) return found(p);
    return missing("file not found: " + p + " (from '" + uri + "')");
  }
  if (uri.find("://") != std::string::npos) return missing("unsupported URI scheme in '" + uri + "'");
  fs::path p(uri);
  if (p.is_relative()) p = fs::path(base_dir.empty() ? "." : base_dir) / p;
  if (is_file(p)) return found(p);
  return missing("file not found: " + normalised(p));
}

}  // namespace rt
