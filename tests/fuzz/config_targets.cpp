// Fuzz targets for the configuration inputs: URDF, robot.yaml, MJCF (for --npz-layout mjcf:) and
// batch manifests (YAML and CSV, against clip files in a scratch folder).

#include <filesystem>
#include <fstream>

#include "formats/mjcf/mjcf_tree.hpp"
#include "formats/urdf/urdf_description.hpp"
#include "fuzz_target.hpp"
#include "retarget/batch/clip_discovery.hpp"
#include "retarget/core/error.hpp"
#include "retarget/model/robot_config.hpp"

namespace rt::fuzz {
namespace {

const std::vector<std::string> kXmlWords = {
    "<robot name=\"r\">", "</robot>", "<link name=\"a\"/>", "<joint name=\"j\" type=\"revolute\">", "</joint>",
    "<parent link=\"a\"/>", "<child link=\"b\"/>", "<origin xyz=\"0 0 1\" rpy=\"0 0 0\"/>", "<axis xyz=\"0 0 1\"/>",
    "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>", "<inertial>", "<mass value=\"1\"/>",
    "<inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/>", "<mesh filename=\"package://p/m.stl\"/>",
    "<body name=\"b\">", "</body>", "<worldbody>", "<include file=\"x\"/>", "<!--", "-->", "<![CDATA[", "]]>", "&amp;",
    "&#0;", "<?xml version=\"1.0\" encoding=\"UTF-16\"?>", "=\"", "\"", "<", ">", "/>", "continuous", "floating", "fixed",
    "prismatic", "planar"};

std::string g_source, g_scratch;

Target urdf_target() {
  Target t;
  t.name = "urdf";
  t.dictionary = kXmlWords;
  t.seeds = [](const SeedDirs& d) {
    g_source = d.source;
    std::vector<Seed> s = seed_files(d.source + "/tests/data/urdf", {".urdf"}, 256 * 1024, true);
    for (Seed& f : seed_files(d.source + "/robots/humanoid25", {".urdf"})) s.push_back(std::move(f));
    if (!d.shared.empty())
      for (Seed& f : seed_files(d.shared + "/robots", {".urdf"}, 256 * 1024, true)) s.push_back(std::move(f));
    return s;
  };
  t.run = [](std::string_view in) {
    UrdfReadOptions o;
    o.require_mesh_files = false;  // meshes are assimp's to parse; the fuzz target is the URDF text
    read_urdf_string(std::string(in), "fuzz.urdf", g_source + "/tests/data/urdf/mini_biped", o);
  };
  return t;
}
RT_FUZZ_TARGET(urdf_target);

Target mjcf_target() {
  Target t;
  t.name = "mjcf";
  t.dictionary = kXmlWords;
  t.seeds = [](const SeedDirs& d) {
    std::vector<Seed> s = {{"generated", "<mujoco model=\"m\"><worldbody><body name=\"pelvis\"><freejoint/>"
                                         "<body name=\"thigh\"><joint name=\"hip\" type=\"hinge\"/><body name=\"shin\">"
                                         "<joint name=\"knee\"/></body></body></body></worldbody></mujoco>\n"}};
    if (!d.shared.empty())
      for (Seed& f : seed_files(d.shared + "/robots", {".xml"}, 128 * 1024, true)) s.push_back(std::move(f));
    return s;
  };
  t.run = [](std::string_view in) { parse_mjcf_tree(std::string(in), "fuzz.xml"); };
  return t;
}
RT_FUZZ_TARGET(mjcf_target);

// robot.yaml, parsed as if it were tests/data/urdf/mini_biped/robot.yaml (so that its URDF is
// found); the repository's other configs are seeds with their URDF line pointed there too.
Target robot_yaml_target() {
  Target t;
  t.name = "robot_yaml";
  t.dictionary = {"name:", "urdf:", "landmarks:", "link:", "offset:", "weight:", "feet:", "left:", "right:", "sole:",
                  "standing_pose:", "joints:", "controller:", "kp:", "kd:", "package_paths:", "base_orientation:",
                  "joint_limits:", "export_joints:", "npz_layout:", "[", "]", "{", "}", "- ", ": ", "&a", "*a", "<<: *a",
                  "!!binary", "1e300", "pelvis", "left_foot", "~", "'", "\""};
  t.seeds = [](const SeedDirs& d) {
    g_source = d.source;
    std::vector<Seed> s;
    for (const std::string& dir : {d.source + "/tests/data/urdf/mini_biped", d.source + "/tests/data/urdf/odd_biped",
                                   d.source + "/robots/humanoid25", d.source + "/robots/g1", d.source + "/robots/h1",
                                   d.source + "/robots/jvrc1"}) {
      std::string text = read_or_empty(dir + "/robot.yaml");
      const std::size_t u = text.find("\nurdf:");
      if (u != std::string::npos) text.replace(u + 1, text.find('\n', u + 1) - u - 1, "urdf: mini_biped.urdf");
      if (!text.empty()) s.push_back({dir + "/robot.yaml", text});
    }
    return s;
  };
  t.run = [](std::string_view in) {
    parse_robot_config(std::string(in), g_source + "/tests/data/urdf/mini_biped/robot.yaml");
  };
  return t;
}
RT_FUZZ_TARGET(robot_yaml_target);

// ---- batch manifests -----------------------------------------------------------------------------

void make_clip_folder(const std::string& scratch) {
  g_scratch = scratch;
  namespace fs = std::filesystem;
  fs::create_directories(scratch + "/walks");
  for (const char* f : {"a.bvh", "b.c3d", "walks/c.bvh", "p.yaml"}) std::ofstream(scratch + "/" + f) << "x\n";
  std::error_code ec;
  fs::create_symlink("/etc/passwd", scratch + "/outside.bvh", ec);
  fs::create_symlink("a.bvh", scratch + "/inside.bvh", ec);
}

const std::vector<std::string> kManifestWords = {
    "clips:", "path:", "output:", "time_scale:", "source_units:", "source_fps:", "up_axis:", "profile:", "- ", ": ",
    "a.bvh", "b.c3d", "walks/c.bvh", "p.yaml", "outside.bvh", "inside.bvh", "../", "/etc/passwd", "..", "walks/",
    "cm", "mm", "inch", "cmu", "-y", "z", "0.05", "20", "1e-9", "[", "]", "{", "}", "&a", "*a", "\"", "'", ",", "\\"};

Target manifest_target(bool csv) {
  Target t;
  t.name = csv ? "manifest_csv" : "manifest_yaml";
  t.dictionary = kManifestWords;
  t.setup = make_clip_folder;
  t.seeds = [csv](const SeedDirs& d) {
    std::vector<Seed> s;
    if (csv) {
      s.push_back({"generated", "path,output,time_scale,source_units,source_fps,up_axis,profile\n"
                                "a.bvh,a,1,cm,120,y,p.yaml\nb.c3d,,,,,,\nwalks/c.bvh,walks/c,0.5,mm,30,-z,\n"});
    } else {
      s.push_back({"generated", "clips:\n  - a.bvh\n  - path: b.c3d\n    output: walks/b\n    time_scale: 1.5\n"
                                "    source_fps: 60\n    up_axis: y\n    profile: p.yaml\n  - walks/c.bvh\n"});
    }
    // The example manifests, pointed at the scratch folder's clips.
    std::string text = read_or_empty(d.source + (csv ? "/examples/manifests/example.csv" : "/examples/manifests/example.yaml"));
    for (std::size_t p; (p = text.find("../clips/")) != std::string::npos;) text.erase(p, 9);
    for (const char* c : {"stand.bvh", "foot_lift.bvh", "slow_steps.bvh"})
      for (std::size_t p; (p = text.find(c)) != std::string::npos;) text.replace(p, std::string(c).size(), "a.bvh");
    s.push_back({"example", text});
    return s;
  };
  t.run = [csv](std::string_view in) {
    check_unique_output_names(parse_manifest(std::string(in), g_scratch + (csv ? "/m.csv" : "/m.yaml"), csv));
  };
  return t;
}
RT_FUZZ_TARGET([] { return manifest_target(false); });
RT_FUZZ_TARGET([] { return manifest_target(true); });

}  // namespace
}  // namespace rt::fuzz
