#include "retarget/motion/c3d/marker_map.hpp"

#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/c3d/marker_trajectories.hpp"

namespace rt {

MarkerMap parse_marker_map(const YamlView& root) {
  root.expect_map();
  root.check_keys({"name", "base", "landmarks"});
  MarkerMap map;
  map.path = root.file();
  map.name = root.get("name", "");
  if (const auto base = root.find("base")) {
    const std::string b = to_lower(base->as_string());
    if (b == "auto") map.start_from_builtin = true;
    else if (b != "none") base->fail("expected 'none' or 'auto', got '" + base->as_string() + "'");
  }
  const YamlView landmarks = root.at("landmarks");
  landmarks.expect_map();
  for (const std::string& key : landmarks.keys()) {
    const YamlView entry = landmarks.at(key);
    const auto l = landmark_from_name(key);
    if (!l) {
      std::vector<std::string> names;
      for (Landmark x : all_landmarks()) names.emplace_back(landmark_name(x));
      entry.fail("unknown landmark (known: " + join(names, ", ") + ")");
    }
    MarkerMapEntry e;
    e.landmark = *l;
    e.location = entry.location() + ": " + entry.path();
    std::vector<std::string> raw;
    if (entry.is_sequence()) raw = entry.as_strings();
    else raw.push_back(entry.as_string());
    if (raw.empty()) entry.fail("expected a marker name or a non-empty list of marker names");
    for (const std::string& r : raw) {
      const std::string n = normalise_marker_name(r);
      if (n.empty()) entry.fail("empty marker name");
      e.markers.push_back(n);
    }
    for (const MarkerMapEntry& other : map.entries)
      if (other.landmark == e.landmark) entry.fail("landmark given twice");
    map.entries.push_back(std::move(e));
  }
  if (map.entries.empty()) landmarks.fail("no landmarks given");
  if (map.name.empty()) map.name = base_name(map.path);
  return map;
}

MarkerMap load_marker_map(const std::string& path) { return parse_marker_map(YamlView::load_file(path)); }

}  // namespace rt
