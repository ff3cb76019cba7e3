// End-to-end tests of `retarget batch` and `retarget merge-summaries` as a user runs them: the
// real binary, real clips, signals (kill -9, Ctrl-C) and shards.

#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "batch_test_util.hpp"
#include "retarget/batch/batch_summary.hpp"
#include "retarget/batch/worker_process.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/reference/reference_io.hpp"

namespace rt {
namespace {

namespace fs = std::filesystem;
using test::copy_example;
using test::read_text;
using test::scratch_dir;
using test::write_text;

struct CliRun {
  int exit_code = -1;
  std::string output;
};

CliRun retarget(const std::vector<std::string>& args, const std::string& log) {
  WorkerLaunch l;
  l.argv = {test::retarget_binary()};
  l.argv.insert(l.argv.end(), args.begin(), args.end());
  l.log_path = log;
  l.timeout_s = 300;
  const WorkerExit x = run_worker(l);
  return {x.exited ? x.exit_code : 128 + x.signal, read_text(log)};
}

std::vector<std::string> files_with(const std::string& folder, const std::string& needle) {
  std::vector<std::string> out;
  if (!fs::exists(folder)) return out;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    if (e.path().filename().string().find(needle) != std::string::npos) out.push_back(e.path().string());
  return out;
}

// Live (non-zombie) processes whose command line mentions `needle`.
int processes_mentioning(const std::string& needle) {
  int n = 0;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string pid = e.path().filename().string();
    if (pid.empty() || !std::isdigit(static_cast<unsigned char>(pid[0]))) continue;
    const std::string cmd = read_text(e.path().string() + "/cmdline");
    const std::string stat = read_text(e.path().string() + "/stat");
    const auto paren = stat.rfind(')');
    const bool zombie = paren == std::string::npos || paren + 2 >= stat.size() || stat[paren + 2] == 'Z';
    if (!zombie && cmd.find(needle) != std::string::npos) ++n;
  }
  return n;
}

bool wait_for(const std::function<bool()>& condition, double timeout_s) {
  const auto t0 = std::chrono::steady_clock::now();
  while (!condition()) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

// Everything in a summary that does not depend on timing or on how the batch was split.
std::string comparable(BatchSummary s) {
  s.jobs = 0;
  s.wall_s = 0;
  s.started_utc.clear();
  s.shard.clear();
  s.merged_from.clear();
  for (ClipResult& c : s.clips) {
    c.time_s = 0;
    c.peak_rss_mb = 0;
  }
  return summary_json(s);
}

TEST(BatchCli, KillNineMidRunThenRerunFinishesOnlyWhatIsMissing) {
  const std::string dir = scratch_dir();
  const std::string in = dir + "/in", out = dir + "/out";
  for (int i = 0; i < 3; ++i) {
    copy_example("slow_steps", in + format("/steps%d.bvh", i));
    copy_example("stand", in + format("/stand%d.bvh", i));
  }
  WorkerLaunch l;
  l.argv = {test::retarget_binary(), "batch", in, "-o", out, "-j", "1", "--no-refine", "--format", "csv,npz"};
  l.log_path = dir + "/first.log";
  auto batch = std::make_unique<WorkerProcess>(l);
  ASSERT_TRUE(wait_for([&] { return !files_with(out, ".meta.json").empty(); }, 120)) << read_text(dir + "/first.log");
  ::kill(batch->pid(), SIGKILL);  // the batch only, as `kill -9 <pid>` does
  batch->wait();
  batch.reset();
  // Its worker died with it (PR_SET_PDEATHSIG): nothing goes on writing into the folder.
  EXPECT_TRUE(wait_for([&] { return processes_mentioning(in) == 0; }, 5.0));
  EXPECT_FALSE(fs::exists(out + "/summary.json"));
  // Done: the clips the batch recorded complete (a worker that wrote its meta.json but was not
  // reaped yet is redone).
  std::vector<std::string> done;  // markers, not a marker's temporary left by the kill
  for (const std::string& f : files_with(out, ".complete"))
    if (f.size() > 9 && f.compare(f.size() - 9, 9, ".complete") == 0) done.push_back(f);
  ASSERT_LT(done.size(), 6u) << "the batch finished before it was killed";
  // What a crash at the worst moment leaves: a data file without meta and stale temporaries.
  std::string victim;
  for (const char* name : {"stand0", "stand1", "stand2", "steps0", "steps1", "steps2"})
    if (!fs::exists(out + "/" + name + ".complete")) victim = name;
  ASSERT_FALSE(victim.empty());
  write_text(out + "/" + victim + ".csv", "0,0,0\n");
  write_text(out + "/" + victim + ".csv.tmp.4242.1", "half-written");
  write_text(out + "/" + victim + ".meta.json.tmp.4242.2", "{\"fps\": 3");

  const CliRun second = retarget({"batch", in, "-o", out, "-j", "2", "--no-refine", "--format", "csv,npz"}, dir + "/second.log");
  EXPECT_EQ(second.exit_code, 0) << second.output;
  const BatchSummary s = read_summary(out + "/summary.json");
  ASSERT_EQ(s.clips.size(), 6u);
  EXPECT_EQ(s.count(ClipStatus::Skipped), static_cast<int>(done.size())) << second.output;
  EXPECT_EQ(s.count(ClipStatus::Ok), 6 - static_cast<int>(done.size())) << second.output;
  for (const std::string& marker : done) {
    const std::string name = fs::path(marker).stem().string();
    EXPECT_EQ(test::find_clip(s, name)->status, ClipStatus::Skipped) << name;
  }
  EXPECT_EQ(test::find_clip(s, victim)->status, ClipStatus::Ok);
  EXPECT_TRUE(files_with(out, ".tmp.").empty());
  for (const ClipResult& c : s.clips) {
    const Reference ref = read_reference(out + "/" + c.name + ".csv");
    EXPECT_EQ(ref.num_frames(), c.frames) << c.name;
    const Reference npz = read_reference(out + "/" + c.name + ".npz");
    EXPECT_EQ(npz.num_frames(), c.frames) << c.name;
  }
  // And a third run has nothing left to do.
  const CliRun third = retarget({"batch", in, "-o", out, "-j", "2", "--no-refine", "--format", "csv,npz"}, dir + "/third.log");
  EXPECT_EQ(third.exit_code, 0);
  EXPECT_EQ(read_summary(out + "/summary.json").count(ClipStatus::Skipped), 6);
}

TEST(BatchCli, ThreeShardsMergedEqualASingleRun) {
  const std::string dir = scratch_dir();
  const std::string in = dir + "/in";
  copy_example("stand", in + "/a/stand.bvh");
  copy_example("stand", in + "/b/stand.bvh");
  copy_example("foot_lift", in + "/foot_lift.bvh");
  copy_example("stand", in + "/stand_copy.bvh");
  write_text(in + "/broken.bvh", "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 x\n");
  const std::vector<std::string> common = {"--no-refine", "--check"};
  auto args = [&](std::vector<std::string> a) {
    a.insert(a.end(), common.begin(), common.end());
    return a;
  };
  const CliRun single = retarget(args({"batch", in, "-o", dir + "/single", "-j", "2"}), dir + "/single.log");
  EXPECT_EQ(single.exit_code, 2) << single.output;  // the broken clip

  // The three shards at once, into one folder (their clips are disjoint, so are their locks).
  std::vector<std::unique_ptr<WorkerProcess>> shards;
  for (int i = 1; i <= 3; ++i) {
    WorkerLaunch l;
    l.argv = args({test::retarget_binary(), "batch", in, "-o", dir + "/sharded", "--shard", format("%d/3", i), "-j", "1"});
    l.log_path = dir + format("/shard%d.log", i);
    shards.push_back(std::make_unique<WorkerProcess>(l));
  }
  int shard_clips = 0;
  for (int i = 1; i <= 3; ++i) {
    const WorkerExit& x = shards[static_cast<std::size_t>(i - 1)]->wait();
    EXPECT_TRUE(x.exited) << i;
    const BatchSummary s = read_summary(dir + format("/sharded/summary-shard-%d-of-3.json", i));
    EXPECT_EQ(s.shard, format("%d/3", i));
    EXPECT_GE(s.clips.size(), 1u);
    shard_clips += static_cast<int>(s.clips.size());
    EXPECT_TRUE(fs::exists(dir + format("/sharded/index-shard-%d-of-3.html", i)));
  }
  EXPECT_EQ(shard_clips, 5);
  const CliRun merge = retarget({"merge-summaries", dir + "/sharded", dir + "/sharded"}, dir + "/merge.log");
  EXPECT_EQ(merge.exit_code, 2) << merge.output;
  EXPECT_NE(merge.output.find("merged 3 summaries"), std::string::npos) << merge.output;
  const BatchSummary one = read_summary(dir + "/single/summary.json");
  const BatchSummary merged = read_summary(dir + "/sharded/summary.json");
  EXPECT_EQ(merged.merged_from.size(), 3u);
  EXPECT_EQ(comparable(merged), comparable(one));
  EXPECT_EQ(read_text(dir + "/sharded/summary.csv").size() > 0, true);
  // The merged index links the shards' outputs.
  EXPECT_NE(read_text(dir + "/sharded/index.html").find("href=\"a/stand.report/contacts.svg\""), std::string::npos);
}

TEST(BatchCli, InterruptStopsWorkersAndWritesTheSummary) {
  const std::string dir = scratch_dir();
  const std::string in = dir + "/in", out = dir + "/out";
  for (int i = 0; i < 4; ++i) copy_example("slow_steps", in + format("/steps%d.bvh", i));
  WorkerLaunch l;
  l.argv = {test::retarget_binary(), "batch", in, "-o", out, "-j", "2", "--check", "--no-refine"};
  l.log_path = dir + "/batch.log";
  WorkerProcess batch(l);
  ASSERT_TRUE(wait_for([&] { return files_with(out, ".log").size() >= 2; }, 60)) << read_text(dir + "/batch.log");
  ::kill(batch.pid(), SIGINT);
  const auto t0 = std::chrono::steady_clock::now();
  const WorkerExit& x = batch.wait();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0);
  EXPECT_TRUE(x.exited);
  EXPECT_EQ(x.exit_code, 130) << read_text(dir + "/batch.log");
  EXPECT_TRUE(wait_for([&] { return processes_mentioning(in) == 0; }, 5.0));
  const BatchSummary s = read_summary(out + "/summary.json");
  EXPECT_EQ(s.stopped, "SIGINT");
  EXPECT_EQ(s.clips.size(), 4u);
  EXPECT_GE(s.count(ClipStatus::Cancelled), 2);
  EXPECT_NE(read_text(dir + "/batch.log").find("stopped early: SIGINT"), std::string::npos);
}

TEST(BatchCli, ExitCodesOutputAndDryRun) {
  const std::string dir = scratch_dir();
  copy_example("stand", dir + "/good/stand.bvh");
  copy_example("stand", dir + "/mixed/stand.bvh");
  write_text(dir + "/mixed/broken.bvh", "HIERARCHY\n");

  CliRun r = retarget({"batch", dir + "/good", "-o", dir + "/out1", "--no-refine"}, dir + "/1.log");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("[1/1] ok            stand"), std::string::npos) << r.output;  // plain lines: not a TTY
  EXPECT_NE(r.output.find(" s  ETA 0s\n"), std::string::npos) << r.output;           // with the running ETA
  EXPECT_NE(r.output.find("summary: " + dir + "/out1/summary.json"), std::string::npos) << r.output;

  r = retarget({"batch", dir + "/mixed", "-o", dir + "/out2", "--no-refine"}, dir + "/2.log");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad-input"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("broken.bvh:"), std::string::npos) << r.output;

  r = retarget({"batch", dir + "/mixed", "-o", dir + "/out2", "--no-refine", "--dry-run"}, dir + "/3.log");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 clip(s) for robot humanoid25: 1 to convert, 1 up to date"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("skip stand"), std::string::npos) << r.output;

  r = retarget({"batch", dir + "/good", "-o", dir + "/out3", "--robot", dir + "/none.yaml"}, dir + "/4.log");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("error: "), std::string::npos) << r.output;
  r = retarget({"batch", dir + "/good", "-o", dir + "/out3", "--shard", "4/3"}, dir + "/5.log");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--shard"), std::string::npos) << r.output;
  r = retarget({"batch", dir + "/good"}, dir + "/6.log");
  EXPECT_EQ(r.exit_code, 2);  // -o is required
  r = retarget({"merge-summaries", dir + "/m", dir + "/out1/nothing.json"}, dir + "/7.log");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("nothing.json"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace rt
