#include <gtest/gtest.h>

#include <filesystem>

#include "batch_test_util.hpp"
#include "formats/bvh/bvh_reader.hpp"
#include "formats/c3d/c3d_reader.hpp"
#include "retarget/batch/batch_progress.hpp"
#include "retarget/batch/batch_summary.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {
namespace {

namespace fs = std::filesystem;
using test::read_text;
using test::scratch_dir;
using test::write_text;

ClipResult ok_clip(const std::string& name) {
  ClipResult c;
  c.name = name;
  c.input = "/data/" + name + ".bvh";
  c.input_bytes = 1234;
  c.status = ClipStatus::Ok;
  c.exit_code = 0;
  c.time_s = 1.25;
  c.peak_rss_mb = 88.5;
  c.frames = 90;
  c.fps = 30;
  c.duration_s = 2.966667;
  c.source_frames = 178;
  c.landmark_error_median_m = 0.031;
  c.landmark_error_p95_m = 0.052;
  c.foot_skating_p95_m = 0.0012;
  c.penetration_max_m = 0.0;
  c.check = CheckOutcome::Passed;
  c.violations = 1;
  c.main_violation = "cop-near-edge at 1.20 s: COP 0.004 m inside the edge";
  c.files.data = {name + ".csv"};
  c.files.meta = name + ".meta.json";
  c.files.log = name + ".log";
  c.files.report = name + ".report/report.json";
  c.files.report_text = name + ".report/report.txt";
  c.files.plots = {name + ".report/com_cop_y.svg"};
  c.files.view = name + ".html";
  return c;
}

ClipResult failed_clip(const std::string& name, ClipStatus status, const std::string& error) {
  ClipResult c;
  c.name = name;
  c.input = "/data/" + name + ".bvh";
  c.status = status;
  c.error = error;
  c.exit_code = status == ClipStatus::BadInput ? 2 : -1;
  c.signal = status == ClipStatus::Crashed ? 11 : 0;
  c.files.log = name + ".log";
  return c;
}

BatchSummary sample() {
  BatchSummary s;
  s.robot = "g1";
  s.robot_config = "/robots/g1/robot.yaml";
  s.input = "/data";
  s.check = true;
  s.convert_options = "--format csv --check";
  s.jobs = 2;
  s.started_utc = "2024-05-01T12:00:00Z";
  s.wall_s = 12.5;
  s.clips = {ok_clip("walk"), failed_clip("broken", ClipStatus::BadInput, "broken.bvh:3:1: expected \"HIERARCHY\", <got> & more"),
             failed_clip("sub/crash,y", ClipStatus::Crashed, "crashed: SIGSEGV (Segmentation fault)")};
  s.sort_clips();
  return s;
}

TEST(BatchSummary, StatusNames) {
  for (ClipStatus st : all_clip_statuses()) EXPECT_EQ(parse_clip_status(clip_status_name(st), "x"), st);
  EXPECT_EQ(all_clip_statuses().size(), 9u);
  EXPECT_STREQ(clip_status_name(ClipStatus::OutOfMemory), "out-of-memory");
  EXPECT_THROW(parse_clip_status("fine", "x"), InputError);
}

TEST(BatchSummary, ExitStatusPrecedence) {
  BatchSummary s;
  EXPECT_EQ(batch_exit_status(s), 0);
  s.clips = {ok_clip("a")};
  s.clips[0].status = ClipStatus::Skipped;
  EXPECT_EQ(batch_exit_status(s), 0);
  s.clips[0].check = CheckOutcome::Failed;  // skipped, but its stored check failed
  EXPECT_EQ(batch_exit_status(s), 1);
  s.clips.push_back(ok_clip("b"));
  s.clips.back().status = ClipStatus::CheckFailed;
  EXPECT_EQ(batch_exit_status(s), 1);
  for (ClipStatus hard : {ClipStatus::BadInput, ClipStatus::Crashed, ClipStatus::Timeout, ClipStatus::OutOfMemory,
                          ClipStatus::Error, ClipStatus::Cancelled}) {
    BatchSummary t = s;
    t.clips.push_back(failed_clip("c", hard, "x"));
    EXPECT_EQ(batch_exit_status(t), 2) << clip_status_name(hard);  // 2 wins over 1
  }
}

TEST(BatchSummary, JsonRoundTrip) {
  const BatchSummary s = sample();
  const std::string text = summary_json(s);
  const BatchSummary r = parse_summary(text, "summary.json");
  EXPECT_EQ(summary_json(r), text);
  ASSERT_EQ(r.clips.size(), 3u);
  EXPECT_EQ(r.clips[0].name, "broken");
  EXPECT_EQ(r.clips[0].status, ClipStatus::BadInput);
  EXPECT_EQ(r.clips[0].frames, -1);
  EXPECT_EQ(r.clips[1].signal, 11);
  const ClipResult& w = r.clips[2];
  EXPECT_EQ(w.frames, 90);
  EXPECT_DOUBLE_EQ(w.landmark_error_median_m, 0.031);
  EXPECT_EQ(w.check, CheckOutcome::Passed);
  EXPECT_EQ(w.files.plots, s.clips[2].files.plots);
  EXPECT_EQ(w.files.view, "walk.html");
  EXPECT_EQ(r.clips[0].files.view, "");  // null for a clip without a viewer page
  EXPECT_NE(text.find("\"exit_status\": 2"), std::string::npos);
  EXPECT_NE(text.find("\"bad-input\": 1"), std::string::npos);
  EXPECT_NE(text.find("\"landmark_error_median_m\": null"), std::string::npos);  // failed clips: null metrics
}

TEST(BatchSummary, ParseErrorsNameTheKey) {
  auto err = [](const std::string& text) {
    try {
      parse_summary(text, "s.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  std::string text = summary_json(sample());
  EXPECT_NE(err("{\"format\": ").find("s.json:1:"), std::string::npos);
  EXPECT_NE(err("{\"format\": \"other\"}").find("[format]"), std::string::npos);
  std::string bad = text;
  bad.replace(bad.find("\"bad-input\","), 12, "\"fine\",");
  EXPECT_NE(err(bad).find("clips[0].status"), std::string::npos) << err(bad);
  bad = text;
  bad.replace(bad.find("\"format_version\": 1"), 19, "\"format_version\": 2");
  EXPECT_NE(err(bad).find("not supported"), std::string::npos);
  bad = text;
  bad.replace(bad.find("\"frames\": 90"), 12, "\"frames\": \"x\"");
  EXPECT_NE(err(bad).find("clips[2].frames"), std::string::npos) << err(bad);
}

TEST(BatchSummary, CsvQuotesAndLeavesUnknownsEmpty) {
  const std::string csv = summary_csv(sample());
  const auto lines = split(csv, "\n");
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0].substr(0, 23), "name,status,frames,fps,");
  EXPECT_EQ(lines[1].substr(0, 18), "broken,bad-input,,");
  EXPECT_NE(lines[1].find("\"broken.bvh:3:1: expected \"\"HIERARCHY\"\", <got> & more\""), std::string::npos) << lines[1];
  EXPECT_EQ(lines[2].substr(0, 22), "\"sub/crash,y\",crashed,");
  EXPECT_EQ(lines[3].substr(0, 21), "walk,ok,90,30,2.967,1");
}

TEST(BatchSummary, HtmlEscapesAndLinks) {
  const std::string html = summary_html(sample());
  EXPECT_NE(html.find("expected &quot;HIERARCHY&quot;, &lt;got&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(html.find("<got>"), std::string::npos);
  EXPECT_NE(html.find("href=\"walk.csv\""), std::string::npos);
  EXPECT_NE(html.find("href=\"walk.report/com_cop_y.svg\""), std::string::npos);
  EXPECT_NE(html.find("href=\"walk.report/report.txt\""), std::string::npos);
  EXPECT_NE(html.find("<a href=\"walk.html\">view</a>"), std::string::npos);
  EXPECT_NE(html.find("href=\"sub/crash%2Cy.log\""), std::string::npos);
  EXPECT_NE(html.find("exit status 2"), std::string::npos);
  EXPECT_NE(html.find("class=\"st bad-input\""), std::string::npos);
}

TEST(BatchSummary, WriteUsesTaggedNames) {
  const std::string dir = scratch_dir();
  const auto files = write_summary(dir + "/out", sample(), "shard-2-of-3");
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(fs::path(files[0]).filename(), "summary-shard-2-of-3.json");
  EXPECT_EQ(fs::path(files[1]).filename(), "summary-shard-2-of-3.csv");
  EXPECT_EQ(fs::path(files[2]).filename(), "index-shard-2-of-3.html");
  EXPECT_EQ(read_summary(files[0]).clips.size(), 3u);
  EXPECT_EQ(summary_file_names("").json, "summary.json");
  for (const auto& e : fs::directory_iterator(dir + "/out"))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

TEST(BatchSummary, MergeRebasesLinksAndRecounts) {
  const std::string dir = scratch_dir();
  BatchSummary a = sample();
  a.shard = "1/2";
  a.clips.erase(a.clips.begin());  // sub/crash,y and walk
  BatchSummary b = sample();
  b.shard = "2/2";
  b.clips = {failed_clip("broken", ClipStatus::BadInput, "bad")};
  b.started_utc = "2024-05-01T11:00:00Z";
  b.wall_s = 20;
  write_summary(dir + "/m1/out", a, "shard-1-of-2");
  write_summary(dir + "/m2/out", b, "shard-2-of-2");
  const BatchSummary m = merge_summaries(
      {dir + "/m1/out/summary-shard-1-of-2.json", dir + "/m2/out/summary-shard-2-of-2.json"}, dir + "/all");
  ASSERT_EQ(m.clips.size(), 3u);
  EXPECT_EQ(m.clips[0].name, "broken");
  EXPECT_EQ(m.clips[0].files.log, "../m2/out/broken.log");
  EXPECT_EQ(m.clips[2].files.data, std::vector<std::string>{"../m1/out/walk.csv"});
  EXPECT_EQ(m.clips[2].files.plots, std::vector<std::string>{"../m1/out/walk.report/com_cop_y.svg"});
  EXPECT_EQ(m.clips[2].files.view, "../m1/out/walk.html");
  EXPECT_EQ(m.jobs, 4);
  EXPECT_DOUBLE_EQ(m.wall_s, 20);
  EXPECT_EQ(m.started_utc, "2024-05-01T11:00:00Z");
  EXPECT_TRUE(m.shard.empty());
  EXPECT_EQ(m.merged_from.size(), 2u);
  EXPECT_EQ(batch_exit_status(m), 2);
  // Merging into the shards' own folder keeps the links as they were.
  write_summary(dir + "/m1/out", b, "shard-2-of-2");
  const BatchSummary same = merge_summaries(
      {dir + "/m1/out/summary-shard-1-of-2.json", dir + "/m1/out/summary-shard-2-of-2.json"}, dir + "/m1/out");
  EXPECT_EQ(same.clips[2].files.data, std::vector<std::string>{"walk.csv"});
}

TEST(BatchSummary, MergeRejectsInconsistentSummaries) {
  const std::string dir = scratch_dir();
  BatchSummary a = sample();
  a.shard = "1/3";
  BatchSummary b = sample();
  b.shard = "2/3";
  b.clips = {ok_clip("other")};
  write_summary(dir, a, "a");
  write_summary(dir, b, "b");
  auto err = [&](const std::vector<std::string>& files) {
    try {
      merge_summaries(files, dir);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string fa = dir + "/summary-a.json", fb = dir + "/summary-b.json";
  EXPECT_NE(err({fa, fb}).find("shard 3/3 is missing"), std::string::npos) << err({fa, fb});
  EXPECT_NE(err({fa, fa}).find("is also in"), std::string::npos);
  b.robot = "h1";
  write_summary(dir, b, "b");
  EXPECT_NE(err({fa, fb}).find("robot 'h1' differs"), std::string::npos);
  b.robot = "g1";
  b.convert_options = "--fps 50";
  write_summary(dir, b, "b");
  EXPECT_NE(err({fa, fb}).find("convert options"), std::string::npos);
  EXPECT_NE(err({dir + "/none.json"}).find("cannot open"), std::string::npos);
  EXPECT_NE(err({}).find("no summaries"), std::string::npos);
}

TEST(BatchProgress, Formatting) {
  EXPECT_EQ(format_duration(45), "45s");
  EXPECT_EQ(format_duration(192), "3m12s");
  EXPECT_EQ(format_duration(3720), "1h02m");
  EXPECT_EQ(format_duration(-1), "?");
  BatchProgress p;
  p.total = 40;
  p.done = 10;
  p.skipped = 3;
  p.failed = 2;
  p.running = 2;
  p.eta_s = 192;
  const std::string bar = format_progress_bar(p, 100);
  EXPECT_LE(bar.size(), 100u);
  EXPECT_NE(bar.find("12/40"), std::string::npos) << bar;
  EXPECT_NE(bar.find("ok 10 (skipped 3)"), std::string::npos) << bar;
  EXPECT_NE(bar.find("failed 2"), std::string::npos) << bar;
  EXPECT_NE(bar.find("left 28"), std::string::npos) << bar;
  EXPECT_NE(bar.find("ETA 3m12s"), std::string::npos) << bar;
  EXPECT_EQ(bar.substr(0, 2), "[#");
  EXPECT_EQ(bar.find("clips/min"), std::string::npos) << bar;  // no rate before a clip was converted
  p.clips_per_min = 3.44;
  EXPECT_NE(format_progress_bar(p, 120).find("running 2  3.4 clips/min  ETA 3m12s"), std::string::npos)
      << format_progress_bar(p, 120);
  EXPECT_LE(format_progress_bar(p, 30).size(), 30u);
  EXPECT_EQ(format_clip_rate(12.6), "13 clips/min");
  EXPECT_EQ(format_clip_rate(-1), "? clips/min");
  const ClipResult broken = failed_clip("broken", ClipStatus::BadInput, "x.bvh:3: bad");
  const std::string line = format_clip_line(broken, 7, 40);
  EXPECT_EQ(line, "[ 7/40] bad-input     broken  0.0 s  x.bvh:3: bad");
  EXPECT_EQ(format_clip_log_line(broken, p), "[12/40] bad-input     broken  0.0 s  x.bvh:3: bad  ETA 3m12s");
  p.eta_s = -1;
  EXPECT_EQ(format_clip_log_line(broken, p), "[12/40] bad-input     broken  0.0 s  x.bvh:3: bad  ETA ?");
  p.done = 38;
  EXPECT_EQ(format_clip_log_line(ok_clip("last"), p), "[40/40] ok            last  1.2 s  check passed  ETA 0s");
}

// A C3D file: a 512-byte header (parameter block number, 0x50, words 4 and 5 = first and last
// frame) and the first bytes of the parameter section with the processor byte.
std::string c3d_header(int first, int last, unsigned char processor) {
  std::string bytes(1024, '\0');
  bytes[0] = 2;
  bytes[1] = 0x50;
  const bool big = processor == 86;
  auto put = [&](int word, int v) {
    const char hi = static_cast<char>((v >> 8) & 0xff), lo = static_cast<char>(v & 0xff);
    bytes[static_cast<std::size_t>(2 * (word - 1))] = big ? hi : lo;
    bytes[static_cast<std::size_t>(2 * (word - 1) + 1)] = big ? lo : hi;
  };
  put(4, first);
  put(5, last);
  bytes[512] = 1;
  bytes[513] = 0x50;
  bytes[514] = 1;
  bytes[515] = static_cast<char>(processor);
  return bytes;
}

TEST(BatchProgress, SourceFramesFromTheHeaderOnly) {
  EXPECT_EQ(probe_source_frames(test::source_path("examples/clips/stand.bvh")), 180);
  EXPECT_EQ(probe_source_frames(test::source_path("examples/clips/slow_steps.bvh")), 768);
  const std::string dir = scratch_dir();
  write_text(dir + "/a.BVH", "HIERARCHY\nROOT Hips\n{\n}\nMOTION\n  Frames:   42\r\nFrame Time: 0.01\n");
  EXPECT_EQ(probe_source_frames(dir + "/a.BVH"), 42);
  write_text(dir + "/b.bvh", "HIERARCHY\nROOT Hips\n{\n}\nMOTION\nFrames: 4x\n");
  EXPECT_EQ(probe_source_frames(dir + "/b.bvh"), 0);
  write_text(dir + "/c.bvh", "HIERARCHY\nROOT Hips\n");
  EXPECT_EQ(probe_source_frames(dir + "/c.bvh"), 0);
  EXPECT_EQ(probe_source_frames(dir + "/missing.bvh"), 0);
  write_text(dir + "/intel.c3d", c3d_header(1, 600, 84));
  EXPECT_EQ(probe_source_frames(dir + "/intel.c3d"), 600);
  write_text(dir + "/mips.c3d", c3d_header(11, 310, 86));
  EXPECT_EQ(probe_source_frames(dir + "/mips.c3d"), 300);
  write_text(dir + "/dec.c3d", c3d_header(1, 0x1234, 85));
  EXPECT_EQ(probe_source_frames(dir + "/dec.c3d"), 0x1234);
  write_text(dir + "/saturated.c3d", c3d_header(1, 0xffff, 84));
  EXPECT_EQ(probe_source_frames(dir + "/saturated.c3d"), 0);
  write_text(dir + "/processor.c3d", c3d_header(1, 100, 7));
  EXPECT_EQ(probe_source_frames(dir + "/processor.c3d"), 0);
  write_text(dir + "/short.c3d", c3d_header(1, 100, 84).substr(0, 300));
  EXPECT_EQ(probe_source_frames(dir + "/short.c3d"), 0);
}

// The header probe against the full readers on every real clip: the same count, or 0 (unknown)
// where the file cannot say it in its header (a saturated C3D word) or cannot be read at all.
TEST(BatchProgress, SourceFramesAgreeWithTheReadersOnRealClips) {
  RT_REQUIRE_SHARED(root, "bvh");
  int compared = 0;
  for (const char* folder : {"bvh", "c3d", "c3d/btkdata"}) {
    const std::string dir = test::shared_data_dir() + "/" + folder;
    if (!fs::is_directory(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string path = e.path().string();
      const std::string ext = to_lower(e.path().extension().string());
      if (!e.is_regular_file() || (ext != ".bvh" && ext != ".c3d")) continue;
      const std::int64_t probed = probe_source_frames(path);
      int frames = 0;
      try {
        frames = ext == ".bvh" ? read_bvh(path).declared_frames : c3d::read_c3d(path).points.num_frames;
      } catch (const InputError&) {
        continue;  // a deliberately broken file: the worker's business
      }
      if (probed == 0) continue;
      EXPECT_EQ(probed, frames) << path;
      ++compared;
    }
  }
  EXPECT_GE(compared, 15);
}

TEST(BatchProgress, UnknownFrameCountsAreEstimatedFromTheSize) {
  std::vector<BatchClip> clips(3);
  clips[0].input_bytes = 1000;
  clips[1].input_bytes = 3000;
  clips[2].input_bytes = 500;
  std::vector<double> w = source_frame_weights(clips, {100, 0, 0});
  ASSERT_EQ(w.size(), 3u);
  EXPECT_DOUBLE_EQ(w[0], 100);
  EXPECT_DOUBLE_EQ(w[1], 300);  // 0.1 frames per byte, from the probed clip
  EXPECT_DOUBLE_EQ(w[2], 50);
  w = source_frame_weights(clips, {0, 0, 0});  // none known: proportional to the size
  EXPECT_DOUBLE_EQ(w[1] / w[0], 3.0);
  clips[2].input_bytes = 0;
  EXPECT_DOUBLE_EQ(source_frame_weights(clips, {0, 0, 0})[2], 1.0);  // never 0
}

}  // namespace
}  // namespace rt
