#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>

#include "batch_test_util.hpp"
#include "retarget/batch/batch_runner.hpp"
#include "retarget/batch/clip_outputs.hpp"
#include "retarget/core/error.hpp"
#include "retarget/report/check_report.hpp"

namespace rt {
namespace {

namespace fs = std::filesystem;
using test::copy_example;
using test::find_clip;
using test::quick_batch;
using test::read_text;
using test::scratch_dir;
using test::write_text;

constexpr const char* kBrokenBvh = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition\n";

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Statuses by clip name.
std::map<std::string, ClipStatus> statuses(const BatchSummary& s) {
  std::map<std::string, ClipStatus> out;
  for (const ClipResult& c : s.clips) out[c.name] = c.status;
  return out;
}

TEST(BatchRunner, MisbehavingWorkersAreRecordedAndTheBatchGoesOn) {
  const std::string dir = scratch_dir();
  const std::string in = dir + "/in";
  write_text(in + "/crash.bvh", "FAKE-WORKER: crash\n");
  write_text(in + "/hang.bvh", "FAKE-WORKER: hang-with-child " + dir + "/child.pid\n");
  write_text(in + "/bad.bvh", "FAKE-WORKER: exit 2 bad.bvh:3:7: expected a number\n");
  write_text(in + "/internal.bvh", "FAKE-WORKER: exit 3 internal error: something broke\n");
  write_text(in + "/silent.bvh", "FAKE-WORKER: sleep 0.1\n");
#if !defined(__SANITIZE_ADDRESS__)
  write_text(in + "/oom.bvh", "FAKE-WORKER: oom\n");
#endif
  BatchOptions o = quick_batch(in, dir + "/out");
  o.jobs = 3;
  o.timeout_s = 2.0;
#if !defined(__SANITIZE_ADDRESS__)
  o.memory_limit_bytes = 128ull << 20;
#endif
  int reported = 0;
  BatchCallbacks cb;
  cb.on_clip = [&](const ClipResult&, const BatchProgress& p) {
    ++reported;
    EXPECT_EQ(p.done + p.failed, reported);
  };
  const auto t0 = std::chrono::steady_clock::now();
  const BatchSummary s = run_batch(o, cb);
  EXPECT_LT(seconds_since(t0), 20.0);
  EXPECT_EQ(reported, static_cast<int>(s.clips.size()));

  const ClipResult* crash = find_clip(s, "crash");
  ASSERT_TRUE(crash);
  EXPECT_EQ(crash->status, ClipStatus::Crashed);
  EXPECT_EQ(crash->signal, SIGSEGV);
  EXPECT_NE(crash->error.find("SIGSEGV"), std::string::npos) << crash->error;

  const ClipResult* hang = find_clip(s, "hang");
  ASSERT_TRUE(hang);
  EXPECT_EQ(hang->status, ClipStatus::Timeout);
  EXPECT_NE(hang->error.find("timeout of 2 s"), std::string::npos) << hang->error;
  EXPECT_GE(hang->time_s, 2.0);

  const ClipResult* bad = find_clip(s, "bad");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, ClipStatus::BadInput);
  EXPECT_EQ(bad->exit_code, 2);
  EXPECT_EQ(bad->error, "bad.bvh:3:7: expected a number");
  EXPECT_EQ(bad->files.log, "bad.log");

  const ClipResult* internal = find_clip(s, "internal");
  ASSERT_TRUE(internal);
  EXPECT_EQ(internal->status, ClipStatus::Error);
  EXPECT_NE(internal->error.find("status 3"), std::string::npos) << internal->error;
  EXPECT_NE(internal->error.find("something broke"), std::string::npos) << internal->error;

  const ClipResult* silent = find_clip(s, "silent");
  ASSERT_TRUE(silent);
  EXPECT_EQ(silent->status, ClipStatus::Error);
  EXPECT_NE(silent->error.find("no meta.json"), std::string::npos) << silent->error;

#if !defined(__SANITIZE_ADDRESS__)
  const ClipResult* oom = find_clip(s, "oom");
  ASSERT_TRUE(oom);
  EXPECT_EQ(oom->status, ClipStatus::OutOfMemory);
  EXPECT_NE(oom->error.find("128 MiB"), std::string::npos) << oom->error;
  EXPECT_NE(oom->error.find("bad_alloc"), std::string::npos) << oom->error;
#endif

  EXPECT_EQ(batch_exit_status(s), 2);
  for (const char* f : {"/out/summary.json", "/out/summary.csv", "/out/index.html"}) EXPECT_TRUE(fs::exists(dir + f)) << f;
  EXPECT_EQ(read_summary(dir + "/out/summary.json").clips.size(), s.clips.size());
}

TEST(BatchRunner, RealConversionsWithBrokenFiles) {
  const std::string dir = scratch_dir();
  const std::string in = dir + "/in";
  copy_example("stand", in + "/stand.bvh");
  copy_example("foot_lift", in + "/walks/foot_lift.bvh");
  write_text(in + "/broken.bvh", kBrokenBvh);
  write_text(in + "/garbage.c3d", std::string(700, '\x42'));
  BatchOptions o = quick_batch(in, dir + "/out");
  o.worker_executable = test::retarget_binary();
  o.convert.formats = {ReferenceFormat::Csv, ReferenceFormat::Npz};
  // Progress in source frames: 180 + 210 from the BVH headers, the two broken files (no frame
  // count in their header) estimated from their size at those clips' frames per byte, >= 1 each.
  std::vector<BatchProgress> after_clip;
  BatchCallbacks cb;
  cb.on_clip = [&](const ClipResult&, const BatchProgress& p) { after_clip.push_back(p); };
  const BatchSummary s = run_batch(o, cb);
  ASSERT_EQ(after_clip.size(), 4u);
  const double per_byte = 390.0 / static_cast<double>(fs::file_size(in + "/stand.bvh") + fs::file_size(in + "/walks/foot_lift.bvh"));
  const double expected_frames = 390 + std::max(1.0, per_byte * static_cast<double>(std::strlen(kBrokenBvh))) + std::max(1.0, per_byte * 700);
  for (const BatchProgress& p : after_clip) {
    EXPECT_NEAR(p.frames_total, expected_frames, 1e-6);
    EXPECT_GE(p.eta_s, 0.0);  // something was converted before each report
    EXPECT_GT(p.clips_per_min, 0.0);
  }
  EXPECT_NEAR(after_clip.back().frames_done, expected_frames, 1e-6);
  EXPECT_LT(after_clip.front().frames_done, expected_frames);
  ASSERT_EQ(s.clips.size(), 4u);
  EXPECT_EQ(s.robot, "humanoid25");
  for (const char* name : {"stand", "walks/foot_lift"}) {
    const ClipResult* c = find_clip(s, name);
    ASSERT_TRUE(c) << name;
    EXPECT_EQ(c->status, ClipStatus::Ok) << name << ": " << c->error;
    EXPECT_GT(c->frames, 50) << name;
    EXPECT_DOUBLE_EQ(c->fps, 30.0);
    EXPECT_GT(c->duration_s, 1.0);
    EXPECT_GT(c->source_frames, c->frames);
    EXPECT_GT(c->landmark_error_median_m, 0.0);
    EXPECT_LT(c->landmark_error_median_m, 0.1);
    EXPECT_GE(c->foot_skating_p95_m, 0.0);
    EXPECT_EQ(c->check, CheckOutcome::NotRun);
    EXPECT_EQ(c->files.data, (std::vector<std::string>{std::string(name) + ".csv", std::string(name) + ".npz"}));
    EXPECT_EQ(c->files.meta, std::string(name) + ".meta.json");
    EXPECT_GT(c->peak_rss_mb, 5.0);
    EXPECT_LT(c->peak_rss_mb, 300.0);
  }
  const ClipResult* broken = find_clip(s, "broken");
  ASSERT_TRUE(broken);
  EXPECT_EQ(broken->status, ClipStatus::BadInput);
  EXPECT_NE(broken->error.find("broken.bvh:"), std::string::npos) << broken->error;
  const ClipResult* garbage = find_clip(s, "garbage");
  ASSERT_TRUE(garbage);
  EXPECT_EQ(garbage->status, ClipStatus::BadInput);
  EXPECT_NE(garbage->error.find("garbage.c3d"), std::string::npos) << garbage->error;
  EXPECT_EQ(batch_exit_status(s), 2);
  EXPECT_FALSE(fs::exists(dir + "/out/broken.meta.json"));

  // A rerun skips the finished clips and retries the broken ones.
  const BatchSummary again = run_batch(o);
  const auto st = statuses(again);
  EXPECT_EQ(st.at("stand"), ClipStatus::Skipped);
  EXPECT_EQ(st.at("walks/foot_lift"), ClipStatus::Skipped);
  EXPECT_EQ(st.at("broken"), ClipStatus::BadInput);
  EXPECT_EQ(find_clip(again, "stand")->frames, find_clip(s, "stand")->frames);  // metrics of skipped clips kept
  EXPECT_EQ(batch_exit_status(again), 2);
}

TEST(BatchRunner, ResumeRules) {
  const std::string dir = scratch_dir();
  const std::string in = dir + "/in";
  copy_example("stand", in + "/a.bvh");
  copy_example("stand", in + "/b.bvh");
  // A private copy of the robot, so that its config can change.
  fs::copy(test::source_path("robots/humanoid25"), dir + "/robot", fs::copy_options::recursive);
  BatchOptions o = quick_batch(in, dir + "/out");
  o.robot = dir + "/robot/robot.yaml";
  auto run = [&](const BatchOptions& opts) { return statuses(run_batch(opts)); };
  using M = std::map<std::string, ClipStatus>;
  const ClipStatus ok = ClipStatus::Ok, skip = ClipStatus::Skipped;

  EXPECT_EQ(run(o), (M{{"a", ok}, {"b", ok}}));
  EXPECT_EQ(run(o), (M{{"a", skip}, {"b", skip}}));
  // --force redoes everything.
  BatchOptions forced = o;
  forced.force = true;
  EXPECT_EQ(run(forced), (M{{"a", ok}, {"b", ok}}));
  // Another option changes the options hash.
  BatchOptions other = o;
  other.convert.fps = 25;
  EXPECT_EQ(run(other), (M{{"a", ok}, {"b", ok}}));
  EXPECT_EQ(run(other), (M{{"a", skip}, {"b", skip}}));
  EXPECT_EQ(run(o), (M{{"a", ok}, {"b", ok}}));
  // An input touched after its meta.json was written, and one whose content changed.
  fs::last_write_time(dir + "/out/a.meta.json", fs::last_write_time(in + "/a.bvh") - std::chrono::seconds(10));
  EXPECT_EQ(run(o), (M{{"a", ok}, {"b", skip}}));
  write_text(in + "/b.bvh", read_text(in + "/b.bvh") + "\n");
  EXPECT_EQ(run(o), (M{{"a", skip}, {"b", ok}}));
  // The robot config changed.
  write_text(dir + "/robot/robot.yaml", read_text(dir + "/robot/robot.yaml") + "\n# edited\n");
  EXPECT_EQ(run(o), (M{{"a", ok}, {"b", ok}}));
  // A data file without its meta (a crash between the two writes) and a stale temporary.
  fs::remove(dir + "/out/a.meta.json");
  write_text(dir + "/out/a.csv.tmp.12345.678", "half");
  write_text(dir + "/out/a.meta.json.tmp.12345.679", "{");
  EXPECT_EQ(run(o), (M{{"a", ok}, {"b", skip}}));
  EXPECT_FALSE(fs::exists(dir + "/out/a.csv.tmp.12345.678"));
  EXPECT_FALSE(fs::exists(dir + "/out/a.meta.json.tmp.12345.679"));
  // A requested format that is missing.
  BatchOptions npz = o;
  npz.convert.formats = {ReferenceFormat::Csv, ReferenceFormat::Npz};
  const auto plan = plan_batch(npz);
  ASSERT_EQ(plan.clips.size(), 2u);
  EXPECT_FALSE(plan.clips[0].up_to_date);
  EXPECT_EQ(plan.clips[0].reason, "options changed");  // the formats are part of the options
  // A corrupt meta.json.
  write_text(dir + "/out/b.meta.json", "{\"trunc");
  EXPECT_EQ(run(o), (M{{"a", skip}, {"b", ok}}));
  // With --check, a clip converted without the check is redone (no report yet), then skipped.
  BatchOptions check = o;
  check.check = true;
  for (const auto& [name, status] : run(check))  // ok, or check-failed should the controller not hold it
    EXPECT_TRUE(status == ok || status == ClipStatus::CheckFailed) << name << ": " << clip_status_name(status);
  EXPECT_EQ(run(check), (M{{"a", skip}, {"b", skip}}));
  EXPECT_TRUE(fs::exists(dir + "/out/a.report/report.json"));
}

TEST(BatchRunner, EveryForwardedSettingKeepsAFinishedClipUpToDate) {
  // The options hash the batch computes must equal the one the worker records, for every setting
  // it forwards; otherwise a rerun would redo finished clips.
  const std::string dir = scratch_dir();
  copy_example("stand", dir + "/lib/a.bvh");
  copy_example("stand", dir + "/lib/b.bvh");
  write_text(dir + "/lib/m.yaml",
             "clips:\n  - a.bvh\n  - {path: b.bvh, source_units: \"0.01\", source_fps: 50, time_scale: 0.8, up_axis: y}\n");
  BatchOptions o = quick_batch(dir + "/lib/m.yaml", dir + "/out");
  o.worker_executable = test::retarget_binary();
  o.convert.formats = {ReferenceFormat::Npz, ReferenceFormat::Csv};
  o.convert.fps = 25;
  o.convert.time_scale = 1.25;
  o.convert.passes = "retime,scale,label-contacts,ik{max_iterations=30},ground,resample";
  o.convert.disabled_passes = {};
  o.convert.source_units = "cm";
  o.convert.up_axis = "y";
  o.convert.keep_tpose = true;
  const BatchSummary first = run_batch(o);
  for (const ClipResult& c : first.clips) EXPECT_EQ(c.status, ClipStatus::Ok) << c.name << ": " << c.error;
  EXPECT_LT(find_clip(first, "b")->frames, find_clip(first, "a")->frames);  // b plays faster
  const BatchSummary second = run_batch(o);
  for (const ClipResult& c : second.clips) EXPECT_EQ(c.status, ClipStatus::Skipped) << c.name;
}

TEST(BatchRunner, CheckOutcomesAndManifestOverrides) {
  const std::string dir = scratch_dir();
  copy_example("stand", dir + "/lib/stand.bvh");
  // The same clip at its own speed and twice slower (a per-clip override).
  write_text(dir + "/lib/m.csv", "path,output,time_scale\nstand.bvh,normal,\nstand.bvh,slow,2\n");
  // A robot too weak to stand (1 N m effort limits): its check fails whatever the controller
  // tuning, so check-failed is exercised deterministically.
  fs::copy(test::source_path("robots/humanoid25"), dir + "/weak", fs::copy_options::recursive);
  std::string urdf = read_text(dir + "/weak/humanoid25.urdf");
  for (std::size_t at = urdf.find("effort=\""); at != std::string::npos; at = urdf.find("effort=\"", at + 1))
    urdf.replace(at + 8, urdf.find('"', at + 8) - (at + 8), "1");
  write_text(dir + "/weak/humanoid25.urdf", urdf);
  BatchOptions o = quick_batch(dir + "/lib/m.csv", dir + "/out");
  o.worker_executable = test::retarget_binary();
  o.robot = dir + "/weak/robot.yaml";
  o.check = true;
  const BatchSummary s = run_batch(o);
  const ClipResult* normal = find_clip(s, "normal");
  const ClipResult* slow = find_clip(s, "slow");
  ASSERT_TRUE(normal && slow);
  EXPECT_NEAR(slow->frames, 2 * normal->frames, 2);  // the override reached the worker
  for (const ClipResult* c : {normal, slow}) {
    EXPECT_EQ(c->status, ClipStatus::CheckFailed) << c->name << ": " << c->error;
    EXPECT_EQ(c->exit_code, 1);
    EXPECT_EQ(c->check, CheckOutcome::Failed);
    EXPECT_EQ(c->main_violation.substr(0, 8), "fall at ") << c->main_violation;
    EXPECT_GE(c->violations, 1);
    EXPECT_EQ(c->files.plots.size(), 4u);
    EXPECT_EQ(c->files.report, c->name + ".report/report.json");
    EXPECT_EQ(c->files.report_text, c->name + ".report/report.txt");
    EXPECT_FALSE(read_check_report(dir + "/out/" + c->files.report).passed);
  }
  EXPECT_EQ(batch_exit_status(s), 1);
  // Skipped on a rerun, and the stored failed check still sets exit status 1.
  const BatchSummary again = run_batch(o);
  EXPECT_EQ(find_clip(again, "slow")->status, ClipStatus::Skipped);
  EXPECT_EQ(find_clip(again, "slow")->check, CheckOutcome::Failed);
  EXPECT_EQ(find_clip(again, "normal")->status, ClipStatus::Skipped);
  EXPECT_EQ(batch_exit_status(again), 1);
  // A crash of one clip outranks the failed checks: exit status 2.
  write_text(dir + "/lib/m.csv", "path,output,time_scale\nstand.bvh,normal,\nstand.bvh,slow,2\ncrash.bvh,crash,\n");
  write_text(dir + "/lib/crash.bvh", "FAKE-WORKER: crash\n");
  o.worker_executable = test::fake_worker();
  const BatchSummary third = run_batch(o);
  EXPECT_EQ(find_clip(third, "crash")->status, ClipStatus::Crashed);
  EXPECT_EQ(batch_exit_status(third), 2);
}

TEST(BatchRunner, FailFastCancelsTheRest) {
  const std::string dir = scratch_dir();
  const std::string in = dir + "/in";
  // Largest first: the failing clip (padded) runs first.
  write_text(in + "/fails.bvh", "FAKE-WORKER: exit 2 fails.bvh:1: broken\n" + std::string(1000, '#'));
  for (const char* name : {"s1", "s2", "s3"}) write_text(in + "/" + name + ".bvh", "FAKE-WORKER: hang\n");
  BatchOptions o = quick_batch(in, dir + "/out");
  o.jobs = 2;
  o.fail_fast = true;
  o.stop_grace_s = 0.2;
  const auto t0 = std::chrono::steady_clock::now();
  const BatchSummary s = run_batch(o);
  EXPECT_LT(seconds_since(t0), 10.0);
  EXPECT_EQ(find_clip(s, "fails")->status, ClipStatus::BadInput);
  int cancelled = 0;
  for (const ClipResult& c : s.clips)
    if (c.status == ClipStatus::Cancelled) {
      ++cancelled;
      EXPECT_NE(c.error.find("--fail-fast: fails failed"), std::string::npos) << c.error;
    }
  EXPECT_EQ(cancelled, 3);
  EXPECT_EQ(s.stopped, "--fail-fast: fails failed");
  EXPECT_EQ(batch_exit_status(s), 2);
}

TEST(BatchRunner, StopRequestStopsWorkersCleanly) {
  const std::string dir = scratch_dir();
  const std::string in = dir + "/in";
  for (const char* name : {"h1", "h2", "h3", "h4"}) write_text(in + "/" + name + ".bvh", "FAKE-WORKER: hang\n");
  BatchOptions o = quick_batch(in, dir + "/out");
  const auto t0 = std::chrono::steady_clock::now();
  BatchCallbacks cb;
  cb.stop_requested = [&] { return seconds_since(t0) > 0.3 ? std::string("SIGINT") : std::string(); };
  const BatchSummary s = run_batch(o, cb);
  EXPECT_LT(seconds_since(t0), 10.0);
  EXPECT_EQ(s.stopped, "SIGINT");
  ASSERT_EQ(s.clips.size(), 4u);
  int started = 0;
  for (const ClipResult& c : s.clips) {
    EXPECT_EQ(c.status, ClipStatus::Cancelled) << c.name;
    if (c.signal == SIGTERM) ++started;
  }
  EXPECT_EQ(started, 2);  // the two running workers got SIGTERM; the others never started
  const BatchSummary written = read_summary(dir + "/out/summary.json");
  EXPECT_EQ(written.stopped, "SIGINT");
}

// Issue 18 item 7: one lock per output folder whatever the shard tag. A batch running shard 1/2
// in another process holds its clip; a plain batch or a `--shard 1/1` batch into the same folder
// (which would delete its temporaries and fresh meta.json) is refused, shard 2/2 runs beside it.
TEST(BatchRunner, OneLockPerOutputFolderWhateverTheShardTag) {
  const std::string dir = scratch_dir();
  // The larger clip goes to shard 1 (size-balanced, largest first); it sleeps while we probe.
  write_text(dir + "/in/a.bvh", "FAKE-WORKER: sleep 2\n" + std::string(4000, '#') + "\n");
  write_text(dir + "/in/b.bvh", "FAKE-WORKER: sleep 0\n");
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // shard 1/2, announcing once its worker runs (the locks are taken by then)
    ::close(ready[0]);
    BatchOptions o = quick_batch(dir + "/in", dir + "/out");
    o.shard = ShardSpec{1, 2};
    BatchCallbacks cb;
    bool told = false;
    cb.on_progress = [&](const BatchProgress& p) {
      if (told || p.running == 0) return;
      told = ::write(ready[1], "x", 1) == 1;
    };
    int rc = 1;
    try {  // the fake worker writes nothing, so the clip ran (and failed) rather than being refused
      const BatchSummary s = run_batch(o, cb);
      rc = s.clips.size() == 1 && s.clips[0].name == "a" ? 0 : 1;
    } catch (...) {
      rc = 2;
    }
    ::_exit(rc);
  }
  ::close(ready[1]);
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  ::close(ready[0]);
  for (const std::optional<ShardSpec>& shard : {std::optional<ShardSpec>(), std::optional<ShardSpec>(ShardSpec{1, 1})}) {
    BatchOptions o = quick_batch(dir + "/in", dir + "/out");
    o.shard = shard;
    try {
      run_batch(o);
      ADD_FAILURE() << "expected the lock to refuse " << (shard ? "shard 1/1" : "a plain batch");
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("another retarget batch is writing clip 'a'"), std::string::npos) << e.what();
    }
  }
  BatchOptions other = quick_batch(dir + "/in", dir + "/out");
  other.shard = ShardSpec{2, 2};
  const BatchSummary beside = run_batch(other);
  ASSERT_EQ(beside.clips.size(), 1u);
  EXPECT_EQ(beside.clips[0].name, "b");
  int status = -1;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  // Once the first batch is gone, the folder is free again (the kernel dropped its locks).
  EXPECT_NO_THROW(run_batch(quick_batch(dir + "/in", dir + "/out")));
}

// A clip of `frames` frames cut from an example clip (a short check keeps the kill test fast).
std::string short_clip(const std::string& example, int frames) {
  const std::string bvh = read_text(test::source_path("examples/clips/" + example + ".bvh"));
  const auto motion = bvh.find("MOTION");
  const auto frames_at = bvh.find("Frames:", motion);
  const auto time_line = bvh.find('\n', frames_at) + 1;
  auto row = bvh.find('\n', time_line) + 1;
  for (int f = 0; f < frames; ++f) row = bvh.find('\n', row) + 1;
  return bvh.substr(0, frames_at) + "Frames: " + std::to_string(frames) + "\n" + bvh.substr(time_line, row - time_line);
}

// Issue 18 item 6: kill -9 of a worker at several points (while loading, as the CSV, meta.json,
// report.json and a plot appear), then a rerun: every clip's outputs are complete and equal to
// an uninterrupted run's. Before, a worker killed between report.json and its plots left a clip
// that every later run skipped as up to date, without its plots.
TEST(BatchRunner, KillNineOfAWorkerAtAnyPointThenRerunCompletesTheClip) {
  const std::string dir = scratch_dir();
  write_text(dir + "/in/lift.bvh", short_clip("foot_lift", 45));
  const std::string pid_file = dir + "/worker.pid";
  // The worker: a shell that records its pid and execs the real binary (same pid).
  write_text(dir + "/worker.sh", "#!/bin/sh\necho $$ > '" + pid_file + "'\nexec '" + test::retarget_binary() + "' \"$@\"\n");
  fs::permissions(dir + "/worker.sh", fs::perms::owner_all);
  auto options = [&](const std::string& out) {
    BatchOptions o = quick_batch(dir + "/in", out);
    o.worker_executable = dir + "/worker.sh";
    o.check = true;
    o.jobs = 1;
    return o;
  };
  const std::vector<std::string> outputs = {"lift.csv", "lift.meta.json", "lift.log", "lift.report/report.json",
                                            "lift.report/report.txt", "lift.report/com_cop_y.svg",
                                            "lift.report/com_cop_x.svg", "lift.report/contacts.svg",
                                            "lift.report/tracking.svg"};
  const BatchSummary reference = run_batch(options(dir + "/ref"));
  ASSERT_EQ(reference.clips.size(), 1u);
  const ClipStatus expected = reference.clips[0].status;
  ASSERT_TRUE(expected == ClipStatus::Ok || expected == ClipStatus::CheckFailed) << reference.clips[0].error;
  const std::string reference_csv = read_text(dir + "/ref/lift.csv");
  const bool reference_passed = read_check_report(dir + "/ref/lift.report/report.json").passed;

  // "" = 30 ms after the worker started (loading the robot); else when that file appears.
  const std::vector<std::string> kill_points = {"", "lift.csv", "lift.meta.json", "lift.report/report.json",
                                                "lift.report/com_cop_x.svg"};
  int landed = 0;
  for (const std::string& point : kill_points) {
    const std::string out = dir + "/out-" + std::to_string(&point - kill_points.data());
    fs::remove(pid_file);
    std::atomic<bool> done{false};
    std::thread killer([&] {
      const auto t0 = std::chrono::steady_clock::now();
      pid_t pid = 0;
      while (!done) {
        if (pid == 0) {
          std::ifstream(pid_file) >> pid;
          if (pid > 0 && point.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(30));
        }
        if (pid > 0 && (point.empty() || fs::exists(out + "/" + point))) {
          ::kill(pid, SIGKILL);
          return;
        }
        if (seconds_since(t0) > 60) return;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
    });
    const BatchSummary first = run_batch(options(out));
    done = true;
    killer.join();
    ASSERT_EQ(first.clips.size(), 1u);
    if (first.clips[0].status == ClipStatus::Crashed) ++landed;
    EXPECT_EQ(fs::exists(out + "/lift.complete"), first.clips[0].status == expected) << point;

    const BatchSummary second = run_batch(options(out));
    ASSERT_EQ(second.clips.size(), 1u);
    const ClipStatus again = second.clips[0].status;
    EXPECT_TRUE(again == expected || (again == ClipStatus::Skipped && first.clips[0].status == expected))
        << point << ": " << clip_status_name(again) << " " << second.clips[0].error;
    for (const std::string& f : outputs) EXPECT_TRUE(fs::exists(out + "/" + f)) << point << ": " << f;
    EXPECT_TRUE(fs::exists(out + "/lift.complete")) << point;
    EXPECT_EQ(read_text(out + "/lift.csv"), reference_csv) << point;
    EXPECT_EQ(read_check_report(out + "/lift.report/report.json").passed, reference_passed) << point;
    // A third run has nothing left to do.
    EXPECT_EQ(run_batch(options(out)).clips[0].status, ClipStatus::Skipped) << point;
  }
  EXPECT_GE(landed, 3) << "most kills should land while the worker runs";
}

// Issue 18 item 9: paths are checked again when the worker starts. A manifest clip that is a
// dangling symlink at planning whose target appears outside the root before its worker starts,
// and an output name through a symlink inside -o, are refused (bad input), nothing written there.
TEST(BatchRunner, PathsAreCheckedAgainWhenTheWorkerStarts) {
  const std::string dir = scratch_dir();
  write_text(dir + "/lib/first.bvh", "FAKE-WORKER: sleep 0\n" + std::string(2000, '#') + "\n");
  fs::create_symlink(dir + "/outside.bvh", dir + "/lib/late.bvh");  // dangling for now
  write_text(dir + "/lib/m.yaml", "clips:\n  - first.bvh\n  - late.bvh\n");
  BatchOptions o = quick_batch(dir + "/lib/m.yaml", dir + "/out");
  o.jobs = 1;
  BatchCallbacks cb;
  cb.on_clip = [&](const ClipResult& c, const BatchProgress&) {
    if (c.name == "first") write_text(dir + "/outside.bvh", "FAKE-WORKER: sleep 0\n");
  };
  const BatchSummary s = run_batch(o, cb);
  ASSERT_NE(find_clip(s, "late"), nullptr);
  EXPECT_EQ(find_clip(s, "late")->status, ClipStatus::BadInput) << find_clip(s, "late")->error;
  EXPECT_NE(find_clip(s, "late")->error.find("outside the input root"), std::string::npos) << find_clip(s, "late")->error;

  fs::create_directories(dir + "/elsewhere");
  fs::create_directories(dir + "/out2");
  fs::create_symlink(dir + "/elsewhere", dir + "/out2/sub");
  write_text(dir + "/lib/m.yaml", "clips:\n  - {path: first.bvh, output: sub/first}\n");
  const BatchSummary t = run_batch(quick_batch(dir + "/lib/m.yaml", dir + "/out2"));
  ASSERT_EQ(t.clips.size(), 1u);
  EXPECT_EQ(t.clips[0].status, ClipStatus::BadInput) << t.clips[0].error;
  EXPECT_NE(t.clips[0].error.find("leads outside the output folder"), std::string::npos) << t.clips[0].error;
  EXPECT_TRUE(fs::is_empty(dir + "/elsewhere"));
}

// Issue 18 item 9: a symlink planted at a clip's log name inside -o is not followed (the log was
// opened with O_TRUNC through it, truncating any file it pointed to).
TEST(BatchRunner, ALogNameThatIsASymlinkIsNotFollowed) {
  const std::string dir = scratch_dir();
  write_text(dir + "/in/walk.bvh", "FAKE-WORKER: sleep 0\n");
  write_text(dir + "/victim.txt", "keep me\n");
  fs::create_directories(dir + "/out");
  fs::create_symlink(dir + "/victim.txt", dir + "/out/walk.log");
  const BatchSummary s = run_batch(quick_batch(dir + "/in", dir + "/out"));
  ASSERT_EQ(s.clips.size(), 1u);
  EXPECT_EQ(s.clips[0].status, ClipStatus::BadInput) << s.clips[0].error;
  EXPECT_NE(s.clips[0].error.find("is a symlink"), std::string::npos) << s.clips[0].error;
  EXPECT_EQ(read_text(dir + "/victim.txt"), "keep me\n");
}

TEST(BatchRunner, BadRobotOrOptionsFailUpFront) {
  const std::string dir = scratch_dir();
  write_text(dir + "/in/x.bvh", "FAKE-WORKER: sleep 0\n");
  BatchOptions o = quick_batch(dir + "/in", dir + "/out");
  o.robot = dir + "/no-robot.yaml";
  EXPECT_THROW(run_batch(o), InputError);
  o = quick_batch(dir + "/in", dir + "/out");
  o.convert.passes = "scale,no-such-pass";
  EXPECT_THROW(run_batch(o), InputError);
  o = quick_batch(dir + "/in", "");
  EXPECT_THROW(run_batch(o), InputError);
  EXPECT_FALSE(fs::exists(dir + "/out/summary.json"));
}

TEST(BatchRunner, OnlyTheClipsOwnStaleTemporariesAreRemoved) {
  const std::string dir = scratch_dir();
  const ClipOutputPaths p = clip_output_paths(dir + "/out", "sub/walk", {ReferenceFormat::Csv, ReferenceFormat::Npz});
  EXPECT_EQ(p.stem, dir + "/out/sub/walk");
  EXPECT_EQ(p.meta, dir + "/out/sub/walk.meta.json");
  EXPECT_EQ(p.report, dir + "/out/sub/walk.report/report.json");
  const std::vector<std::string> stale = {"/out/sub/walk.csv.tmp.123.456", "/out/sub/walk.npz.tmp.1.2",
                                          "/out/sub/walk.meta.json.tmp.99.1", "/out/sub/walk.report/report.json.tmp.5.6",
                                          "/out/sub/walk.report/contacts.svg.tmp.5.7"};
  const std::vector<std::string> kept = {"/out/sub/walk.csv", "/out/sub/walker.csv.tmp.1.2", "/out/sub/walk.csv.tmp.x",
                                         "/out/walk.csv.tmp.1.2", "/out/sub/walk.report/notes.tmp.1.2",
                                         "/out/sub/walk.log.tmp.1.2"};
  for (const auto& f : stale) write_text(dir + f, "x");
  for (const auto& f : kept) write_text(dir + f, "x");
  EXPECT_EQ(remove_stale_temporaries(p), static_cast<int>(stale.size()));
  for (const auto& f : stale) EXPECT_FALSE(fs::exists(dir + f)) << f;
  for (const auto& f : kept) EXPECT_TRUE(fs::exists(dir + f)) << f;
  // A data file without meta is never up to date.
  const UpToDate u = check_up_to_date(dir + "/out/sub/walk.csv", p, ExpectedHashes{"a", "b", "c", "d"}, false);
  EXPECT_FALSE(u.up_to_date);
  EXPECT_EQ(u.reason, "no meta.json");
}

TEST(BatchRunner, DescribeConvertSettings) {
  ConvertSettings s;
  EXPECT_EQ(describe_convert_settings(s, false), "--format csv");
  s.formats = {ReferenceFormat::Csv, ReferenceFormat::Npz};
  s.fps = 50;
  s.disabled_passes = {"refine"};
  s.package_paths = {"/somewhere"};
  s.source_units = "cm";
  EXPECT_EQ(describe_convert_settings(s, true), "--format csv,npz --fps 50 --no-refine --source-units cm --check");
}

}  // namespace
}  // namespace rt
