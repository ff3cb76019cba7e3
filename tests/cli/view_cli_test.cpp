// `retarget view`, `convert --view` and `inspect --view` end to end, and the page in a headless
// Chromium (Debian `chromium`): no script error and a non-blank picture of the robot. Skips
// cleanly when libjs-three or Chromium is absent.

#include <gtest/gtest.h>
#include <zlib.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "retarget/core/file_io.hpp"
#include "retarget/report/motion_viewer.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int status = -1;
  std::string out, err;
};

CliRun run(const std::string& dir, const std::string& args) {
  const std::string cmd = "cd '" + dir + "' && '" RT_RETARGET_BIN "' " + args + " > out.txt 2> err.txt";
  const int raw = std::system(cmd.c_str());
  CliRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = read_file(dir + "/out.txt");
  r.err = read_file(dir + "/err.txt");
  return r;
}

bool three_js_installed() { return fs::exists(std::string(kThreeJsDefaultDir) + "/three.min.js"); }

#define RT_REQUIRE_THREE_JS() \
  if (!three_js_installed()) GTEST_SKIP() << "libjs-three is not installed (apt-get install libjs-three)"

std::string robot() { return "--robot '" + test::source_path("robots/humanoid25") + "'"; }

// The first Chromium on PATH, or "".
std::string chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    const std::string cmd = std::string("command -v ") + name + " > /dev/null 2>&1";
    if (std::system(cmd.c_str()) == 0) return name;
  }
  return "";
}

// A PNG's pixels (8-bit RGB or RGBA, not interlaced: what Chromium's screenshots are), decoded
// with zlib. Empty on anything else.
struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<unsigned char> pixels;
};

std::uint32_t be32(const std::string& s, std::size_t at) {
  return (std::uint32_t(static_cast<unsigned char>(s[at])) << 24) | (std::uint32_t(static_cast<unsigned char>(s[at + 1])) << 16) |
         (std::uint32_t(static_cast<unsigned char>(s[at + 2])) << 8) | std::uint32_t(static_cast<unsigned char>(s[at + 3]));
}

Image read_png(const std::string& path) {
  const std::string f = read_file(path);
  Image img;
  if (f.size() < 33 || f.compare(1, 3, "PNG") != 0) return img;
  std::string idat;
  int depth = 0, color = 0, interlace = 0;
  for (std::size_t at = 8; at + 12 <= f.size();) {
    const std::uint32_t n = be32(f, at);
    const std::string type = f.substr(at + 4, 4);
    if (at + 12 + n > f.size()) return {};
    if (type == "IHDR") {
      img.width = static_cast<int>(be32(f, at + 8));
      img.height = static_cast<int>(be32(f, at + 12));
      depth = static_cast<unsigned char>(f[at + 16]);
      color = static_cast<unsigned char>(f[at + 17]);
      interlace = static_cast<unsigned char>(f[at + 20]);
    } else if (type == "IDAT") {
      idat += f.substr(at + 8, n);
    }
    at += 12 + n;
  }
  if (depth != 8 || interlace != 0 || (color != 2 && color != 6)) return {};
  img.channels = color == 2 ? 3 : 4;
  const std::size_t stride = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.channels);
  std::vector<unsigned char> raw((stride + 1) * static_cast<std::size_t>(img.height));
  uLongf raw_size = static_cast<uLongf>(raw.size());
  if (uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(idat.data()), static_cast<uLong>(idat.size())) != Z_OK ||
      raw_size != raw.size())
    return {};
  img.pixels.assign(stride * static_cast<std::size_t>(img.height), 0);
  const std::size_t bpp = static_cast<std::size_t>(img.channels);
  for (int y = 0; y < img.height; ++y) {
    const unsigned char filter = raw[static_cast<std::size_t>(y) * (stride + 1)];
    const unsigned char* in = &raw[static_cast<std::size_t>(y) * (stride + 1) + 1];
    unsigned char* out = &img.pixels[static_cast<std::size_t>(y) * stride];
    const unsigned char* up = y > 0 ? out - stride : nullptr;
    for (std::size_t x = 0; x < stride; ++x) {
      const int a = x >= bpp ? out[x - bpp] : 0, b = up ? up[x] : 0, c = (up && x >= bpp) ? up[x - bpp] : 0;
      int pred = 0;
      switch (filter) {
        case 0: pred = 0; break;
        case 1: pred = a; break;
        case 2: pred = b; break;
        case 3: pred = (a + b) / 2; break;
        case 4: {
          const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
          pred = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
          break;
        }
        default: return {};
      }
      out[x] = static_cast<unsigned char>(in[x] + pred);
    }
  }
  return img;
}

TEST(ViewCli, ViewWritesAPageOfTheReference) {
  RT_REQUIRE_THREE_JS();
  const std::string dir = test::scratch_dir();
  CliRun r = run(dir, "convert '" + test::source_path("examples/clips/foot_lift.bvh") + "' " + robot() +
                          " -o ref/lift.csv --no-com-plan");
  ASSERT_EQ(r.status, 0) << r.err;
  r = run(dir, "view ref/lift.csv " + robot());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("view        ref/lift.html"), std::string::npos) << r.out;
  const ViewerScene s = parse_viewer_page(read_file(dir + "/ref/lift.html"), "lift.html");
  EXPECT_GT(s.num_frames, 30);
  EXPECT_EQ(s.robot, "humanoid25");
  EXPECT_FALSE(s.contact[0].empty());  // the meta's contact schedule
  EXPECT_TRUE(s.skeleton.empty());     // a reference alone has no source skeleton
  r = run(dir, "view ref/lift.csv " + robot() + " -o page.html --collision-meshes --max-triangles 500");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(parse_viewer_page(read_file(dir + "/page.html"), "page.html").mesh_source, "collision");
  EXPECT_TRUE(s.com_planned_W.empty());  // without com-plan no COM is planned
  // An NPZ with the COM plan (com_pos_w, cop_ref_w; the default pipeline's): the planned COM and
  // ZMP are on the page.
  r = run(dir, "convert '" + test::source_path("examples/clips/foot_lift.bvh") + "' " + robot() +
                   " -o plan/lift --format csv,npz");
  ASSERT_EQ(r.status, 0) << r.err;
  r = run(dir, "view plan/lift.npz " + robot() + " -o npz.html");
  ASSERT_EQ(r.status, 0) << r.err;
  const ViewerScene p = parse_viewer_page(read_file(dir + "/npz.html"), "npz.html");
  EXPECT_EQ(p.com_planned_W.size(), static_cast<std::size_t>(3 * p.num_frames));
  EXPECT_EQ(p.cop_planned_W.size(), static_cast<std::size_t>(2 * p.num_frames));
  EXPECT_FALSE(p.contact[1].empty());
  // A plain CSV (no meta.json, no schedule): contacts labelled from the kinematics, as validate does.
  fs::create_directories(dir + "/plain");
  fs::copy_file(dir + "/ref/lift.csv", dir + "/plain/lift.csv");
  r = run(dir, "view plain/lift.csv --fps 30 " + robot());
  ASSERT_EQ(r.status, 0) << r.err;
  const ViewerScene plain = parse_viewer_page(read_file(dir + "/plain/lift.html"), "lift.html");
  ASSERT_EQ(plain.contact[0].size(), static_cast<std::size_t>(plain.num_frames));
  EXPECT_EQ(std::count(plain.contact[0].begin(), plain.contact[0].end(), 1), plain.num_frames);  // left foot stands
  EXPECT_LT(std::count(plain.contact[1].begin(), plain.contact[1].end(), 1), plain.num_frames);  // right foot lifts
  ASSERT_FALSE(plain.notes.empty());
  EXPECT_NE(plain.notes.back().find("contacts labelled"), std::string::npos);
}

TEST(ViewCli, BadInputIsOneLineExitTwo) {
  const std::string dir = test::scratch_dir();
  CliRun r = run(dir, "view missing.csv " + robot());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("missing.csv"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  std::ofstream(dir + "/bad.csv") << "0,0,0.8,0,0,0,1\n";  // 7 columns: no joints
  r = run(dir, "view bad.csv --fps 30 " + robot());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.csv:1"), std::string::npos) << r.err;
  r = run(dir, "inspect '" + test::source_path("examples/clips/foot_lift.bvh") + "' --view");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--view"), std::string::npos) << r.err;
  r = run(dir, "inspect '" + test::source_path("robots/humanoid25") + "' -o robot.html");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "error: -o: names the --view page; add --view\n");
  // three.js missing: one line naming the package, before any work.
  const std::string env = "RETARGET_THREE_JS_DIR=/nonexistent/three ";
  const std::string cmd = "cd '" + dir + "' && " + env + "'" RT_RETARGET_BIN "' convert '" +
                          test::source_path("examples/clips/foot_lift.bvh") + "' " + robot() + " -o x --view 2> err.txt";
  const int raw = std::system(cmd.c_str());
  EXPECT_EQ(WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, 2);
  EXPECT_EQ(read_file(dir + "/err.txt"),
            "error: /nonexistent/three/three.min.js: not found; the viewer inlines three.js from the Debian package "
            "libjs-three (apt-get install libjs-three)\n");
  EXPECT_FALSE(fs::exists(dir + "/x.csv"));  // refused before converting
}

TEST(ViewCli, ConvertViewAndInspectView) {
  RT_REQUIRE_THREE_JS();
  const std::string dir = test::scratch_dir();
  CliRun r = run(dir, "convert '" + test::source_path("examples/clips/foot_lift.bvh") + "' " + robot() + " -o out/lift --view");
  ASSERT_EQ(r.status, 0) << r.err;
  const ViewerScene s = parse_viewer_page(read_file(dir + "/out/lift.html"), "lift.html");
  ASSERT_FALSE(s.skeleton.empty());  // the source human, scaled to the robot
  EXPECT_GE(s.skeleton.names.size(), 15u);
  EXPECT_EQ(s.skeleton.p_W.size(), static_cast<std::size_t>(s.num_frames) * s.skeleton.names.size() * 3);
  EXPECT_EQ(s.title, "humanoid25: foot_lift.bvh");
  r = run(dir, "inspect '" + test::source_path("robots/humanoid25") + "' --view -o robot.html");
  ASSERT_EQ(r.status, 0) << r.err;
  const ViewerScene robot_page = parse_viewer_page(read_file(dir + "/robot.html"), "robot.html");
  EXPECT_EQ(robot_page.mode, "robot");
  EXPECT_FALSE(robot_page.landmarks.empty());
}

TEST(ViewCli, BatchViewLinksEachClipsPageFromTheIndex) {
  RT_REQUIRE_THREE_JS();
  const std::string dir = test::scratch_dir();
  fs::create_directories(dir + "/in");
  fs::copy_file(test::source_path("examples/clips/foot_lift.bvh"), dir + "/in/lift.bvh");
  CliRun r = run(dir, "batch in " + robot() + " -o out -j 1 --view");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_TRUE(fs::exists(dir + "/out/lift.html"));
  EXPECT_NE(read_file(dir + "/out/index.html").find("href=\"lift.html\">view</a>"), std::string::npos);
  EXPECT_NE(read_file(dir + "/out/summary.json").find("\"view\": \"lift.html\""), std::string::npos);
  // Up to date needs the page too when --view is asked for.
  fs::remove(dir + "/out/lift.html");
  r = run(dir, "batch in " + robot() + " -o out -j 1 --view --dry-run");
  EXPECT_NE(r.out.find("no viewer page (--view)"), std::string::npos) << r.out;
  r = run(dir, "batch in " + robot() + " -o out -j 1");
  EXPECT_NE(r.out.find("skipped"), std::string::npos) << r.out;  // without --view the clip is done
  EXPECT_EQ(read_file(dir + "/out/index.html").find(">view</a>"), std::string::npos);
}

std::string chromium_flags(const std::string& dir) {
  // Software WebGL (SwiftShader); no sandbox (it refuses root and needs user namespaces, often
  // absent in containers); /tmp instead of a possibly small /dev/shm; a profile of its own.
  return " --headless --disable-gpu --no-sandbox --enable-unsafe-swiftshader --hide-scrollbars --disable-dev-shm-usage "
         "--no-first-run --user-data-dir='" + dir + "/chromium-profile' --window-size=800,600 ";
}

// Whether this Chromium starts headless at all (a container may lack what it needs); the tests
// below are about our page, so a browser that cannot start skips them with its log.
std::string chromium_problem(const std::string& dir) {
  const std::string probe = "timeout 60 " + chromium() + chromium_flags(dir) +
                            "--dump-dom 'data:text/html,<p id=probe>ok</p>' > '" + dir + "/probe.html' 2> '" + dir +
                            "/probe.log'";
  if (std::system(probe.c_str()) == 0 && read_file(dir + "/probe.html").find("id=\"probe\"") != std::string::npos) return "";
  const std::string log = read_file(dir + "/probe.log");
  return "Chromium does not start headless here: " + log.substr(log.size() > 600 ? log.size() - 600 : 0);
}

// Loads a page in headless Chromium: the error hook's marker must say "ok", and the screenshot
// must show the robot (many pixels unlike the page background).
void expect_page_renders(const std::string& dir, const std::string& page, int frames) {
  const std::string browser = chromium();
  const std::string flags = chromium_flags(dir);
  const std::string url = "'file://" + dir + "/" + page + "'";
  const std::string dump = "timeout 120 " + browser + flags + "--virtual-time-budget=1000 --dump-dom " + url +
                           " > '" + dir + "/dom.html' 2> '" + dir + "/chromium.log'";
  ASSERT_EQ(std::system(dump.c_str()), 0) << read_file(dir + "/chromium.log");
  const std::string dom = read_file(dir + "/dom.html");
  const std::size_t at = dom.find("id=\"rt-status\"");
  ASSERT_NE(at, std::string::npos) << dom.substr(0, 2000);
  const std::string status = dom.substr(at, dom.find('>', at) - at);
  EXPECT_NE(status.find("data-status=\"ok\""), std::string::npos) << dom.substr(at, 800);
  EXPECT_NE(status.find("data-frames=\"" + std::to_string(frames) + "\""), std::string::npos) << status;

  const std::string shot = "timeout 120 " + browser + flags + "--virtual-time-budget=500 --screenshot='" + dir +
                           "/shot.png' " + url + " 2>> '" + dir + "/chromium.log'";
  ASSERT_EQ(std::system(shot.c_str()), 0) << read_file(dir + "/chromium.log");
  const Image img = read_png(dir + "/shot.png");
  ASSERT_EQ(img.width, 800);
  ASSERT_EQ(img.height, 600);
  // The floor, the grid and the page are neutral greys; the robot's left links are tinted blue and
  // its right links warm (motion_viewer.hpp). Both tints must cover a good part of the 3-D view
  // (above the 92 px control bar), and much of the view must differ from the background.
  int left = 0, right = 0, drawn = 0, total = 0;
  for (int y = 0; y < 600 - 92; ++y)
    for (int x = 0; x < 800; ++x) {
      const unsigned char* p = &img.pixels[(static_cast<std::size_t>(y) * 800 + static_cast<std::size_t>(x)) *
                                           static_cast<std::size_t>(img.channels)];
      const int r = p[0], g = p[1], b = p[2];
      left += b - r > 30;
      right += r - b > 30;
      drawn += std::min({r, g, b}) < 200 || std::max({r, g, b}) - std::min({r, g, b}) > 40;
      ++total;
    }
  EXPECT_GT(left, 2000) << "robot's left side (blue tint) barely drawn";
  EXPECT_GT(right, 2000) << "robot's right side (warm tint) barely drawn";
  EXPECT_GT(drawn, total / 50) << "the screenshot is nearly blank: " << drawn << " of " << total << " pixels drawn";
}

TEST(ViewCli, PagesRenderInHeadlessChromium) {
  RT_REQUIRE_THREE_JS();
  if (chromium().empty()) GTEST_SKIP() << "Chromium is not installed (apt-get install chromium)";
  const std::string dir = test::scratch_dir();
  if (const std::string problem = chromium_problem(dir); !problem.empty()) GTEST_SKIP() << problem;
  // With the COM plan, so that the planned COM and ZMP are drawn too (the default; --com-plan, the
  // flag from when it was opt-in, is still accepted).
  CliRun r = run(dir, "convert '" + test::source_path("examples/clips/foot_lift.bvh") + "' " + robot() +
                          " -o lift --view --com-plan");
  ASSERT_EQ(r.status, 0) << r.err;
  const int frames = parse_viewer_page(read_file(dir + "/lift.html"), "lift.html").num_frames;
  expect_page_renders(dir, "lift.html", frames);
  r = run(dir, "inspect '" + test::source_path("robots/humanoid25") + "' --view -o robot.html");
  ASSERT_EQ(r.status, 0) << r.err;
  expect_page_renders(dir, "robot.html", 1);
}

TEST(ViewCli, G1PageRendersInHeadlessChromium) {
  RT_REQUIRE_THREE_JS();
  RT_REQUIRE_SHARED(g1, "robots/unitree_g1/g1_29dof_rev_1_0.urdf");
  // A third-party G1 reference (a plain 60 Hz Unitree-layout CSV, 442 frames): the visual meshes,
  // decimated, and contacts labelled from its kinematics.
  RT_REQUIRE_SHARED(hands_up, "retargeted/g1_moves/B_HandsUp.csv");
  if (chromium().empty()) GTEST_SKIP() << "Chromium is not installed (apt-get install chromium)";
  const std::string dir = test::scratch_dir();
  if (const std::string problem = chromium_problem(dir); !problem.empty()) GTEST_SKIP() << problem;
  CliRun r = run(dir, "view '" + hands_up + "' --fps 60 --robot '" + test::source_path("robots/g1") + "' -o hands_up.html");
  ASSERT_EQ(r.status, 0) << r.err;
  const ViewerScene s = parse_viewer_page(read_file(dir + "/hands_up.html"), "hands_up.html");
  EXPECT_EQ(s.mesh_source, "visual");
  EXPECT_EQ(s.num_frames, 442);
  EXPECT_FALSE(s.contact[0].empty());
  expect_page_renders(dir, "hands_up.html", s.num_frames);
}

}  // namespace
}  // namespace rt
