// The results store's guarantees (docs/results-format.md, "Guarantees"), each tried as a hostile but
// realistic user would: two `causticbench run` processes (or two shards) on one results folder, with
// their interleavings forced through the store's locks; a kill at every write step of a run and of a
// --force rerun (the fault-injection hook of core/files.h); a full file system (a small tmpfs, where the
// test may mount one). Damaged records and references, and references that do or do not depend on the
// machine: tests/test_reliability_references.cpp. The helpers that start processes and inspect a results
// folder: tests/reliability/store_harness.h; the experiments they run: tests/reliability/store_experiments.h.
#include <sys/mount.h>

#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "core/files.h"
#include "core/parallel.h"
#include "core/staging_folder.h"
#include "tests/reliability/store_experiments.h"

using namespace causticbench;
using namespace causticbench::store_harness;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------------
// The atomic write helper.

// Every failure names the file and the OS error; nothing of the attempt is left; the old content stays.
TEST(AtomicWrite, NamesTheOsErrorAndLeavesNothingBehind) {
  StoreFolder folder("write_helper");
  const std::string target = folder.path("record.json");
  write_text_atomically(target, "old");
  try {
    write_text_atomically(folder.path("no/such/folder/record.json"), "x");
    ADD_FAILURE() << "no error";
  } catch (const WriteError& error) {
    EXPECT_NE(std::string(error.what()).find("no/such/folder/record.json: No such file or directory (ENOENT)"),
              std::string::npos) << error.what();
  }
  setenv("CAUSTICBENCH_FAULT_INJECT", "fail@store_write_helper/record.json", 1);
  auto expect_full_disk = [&](const std::function<void()>& write) {
    try {
      write();
      ADD_FAILURE() << "no error";
    } catch (const WriteError& error) {
      EXPECT_NE(std::string(error.what()).find(target + ": No space left on device (ENOSPC)"), std::string::npos)
          << error.what();
    }
  };
  expect_full_disk([&] { write_file_atomically(target, std::string(10000, 'n')); });
  expect_full_disk([&] {
    write_file_atomically_with(target, [](const std::string& temporary) { std::ofstream(temporary) << "new"; });
  });
  unsetenv("CAUSTICBENCH_FAULT_INJECT");
  // A path writer that fails after leaving its own temporary file beside ours (as OpenImageIO does).
  EXPECT_THROW(write_file_atomically_with(target,
                                          [](const std::string& temporary) {
                                            std::ofstream(temporary) << "half";
                                            std::ofstream(temporary + ".partial.exr") << "half";
                                            throw std::runtime_error("image writer failed");
                                          }),
               WriteError);
  EXPECT_EQ(read_all(target), "old");
  EXPECT_EQ(leftovers(folder.path()), std::vector<std::string>());
  write_file_atomically_with(target, [](const std::string& temporary) { std::ofstream(temporary) << "new"; });
  EXPECT_EQ(read_all(target), "new");
}

// Temporary files of dead processes go; a live process's stay; files with no owner go only from a
// folder whose lock the caller holds.
TEST(AtomicWrite, StaleTemporaryFilesOfDeadProcessesAreRemoved) {
  StoreFolder folder("stale_files");
  pid_t dead = fork();
  if (dead == 0) _exit(0);
  waitpid(dead, nullptr, 0);
  const std::string host = host_name();
  const std::vector<std::string> of_dead = {"environment.json.partial." + std::to_string(dead),
                                            "record.json.partial." + host + "-" + std::to_string(dead) + ".3.json"};
  const std::string live = "record.json.partial." + host + "-" + std::to_string(getpid()) + ".1.json";
  const std::string unowned = "frame_0000.exr.partial.exr";
  for (const std::string& name : of_dead) folder.write(name, "x");
  folder.write(live, "x");
  folder.write(unowned, "x");
  EXPECT_EQ(remove_stale_partial_files(folder.path()), 2u);
  EXPECT_TRUE(fs::exists(folder.path(live)));
  EXPECT_TRUE(fs::exists(folder.path(unowned)));
  EXPECT_EQ(remove_stale_partial_files(folder.path(), /*folder_is_locked=*/true), 1u);
  EXPECT_FALSE(fs::exists(folder.path(unowned)));
  EXPECT_TRUE(fs::exists(folder.path(live)));
}

// A replacement that a kill interrupted between its two renames (the fallback where the file system
// cannot exchange two names) is finished from the complete new copy, or undone from the old one.
TEST(StagingFolder, AnInterruptedReplacementIsFinishedOrUndone) {
  StoreFolder folder("staging_recovery");
  pid_t dead = fork();
  if (dead == 0) _exit(0);
  waitpid(dead, nullptr, 0);
  const std::string staging = ".partial-run-" + host_name() + "-" + std::to_string(dead) + ".0";
  fs::create_directories(folder.path(staging));
  folder.write(staging + "/content", "new");
  fs::create_directories(folder.path(staging + ".old"));
  folder.write(staging + ".old/content", "old");
  remove_stale_staging(folder.path());
  EXPECT_EQ(read_all(folder.path("run/content")), "new");
  EXPECT_FALSE(fs::exists(folder.path(staging + ".old")));

  fs::remove_all(folder.path("run"));
  fs::create_directories(folder.path(staging + ".old"));
  folder.write(staging + ".old/content", "old");
  remove_stale_staging(folder.path());
  EXPECT_EQ(read_all(folder.path("run/content")), "old") << "no new copy: the old one is put back";
}

// ---------------------------------------------------------------------------------------------------
// Concurrent processes on one results folder.

// Two `run` processes started together, made to overlap for certain: the test holds the reference's
// lock until both wait for it (so both have selected every run as pending), then lets them race.
void run_together(const StoreFolder& folder, const std::vector<std::string>& first, const std::vector<std::string>& second,
                  std::string& output_a, std::string& output_b) {
  const std::string lock = ResultPaths{folder.results}.reference_lock(folder.experiment().variants[0].reference_key);
  HeldLock held(lock);
  Process a(first, folder.path("a.txt")), b(second, folder.path("b.txt"));
  EXPECT_TRUE(a.wait_for_output("waiting for reference")) << a.output();
  EXPECT_TRUE(b.wait_for_output("waiting for reference")) << b.output();
  held.release();
  EXPECT_EQ(a.wait(), 0) << a.output();
  EXPECT_EQ(b.wait(), 0) << b.output();
  output_a = a.output();
  output_b = b.output();
}

// Two shards started together, against a reference that stops on its time cap (so that two computations
// of it differ): it is computed once, and every run of both shards is measured against the stored one.
TEST(Concurrency, TwoShardsStartedTogetherComputeTheReferenceOnce) {
  StoreFolder folder("shards", causticbench::testing::replace_once(
                                   kFourRuns, "reference: {photons_per_pass: 20000, max_passes: 2, target_error: 0, max_seconds: 0}",
                                   kTimeCapped));
  std::vector<std::string> first = folder.run_arguments(), second = folder.run_arguments();
  first.insert(first.end(), {"--shard", "0/2"});
  second.insert(second.end(), {"--shard", "1/2"});
  std::string a, b;
  run_together(folder, first, second, a, b);
  EXPECT_EQ(count_of(a + b, "frame 0: computing"), 1u) << a << b;
  EXPECT_EQ(runs_now(a) + runs_now(b), 4) << a << b;
  expect_complete(folder.experiment(), folder.results);
}

// Two processes of one experiment started together: the reference is computed once and every run once.
TEST(Concurrency, TwoProcessesOfOneExperimentDoEveryRunOnce) {
  StoreFolder folder("same_experiment", kFourRuns);
  std::string a, b;
  run_together(folder, folder.run_arguments(), folder.run_arguments(), a, b);
  EXPECT_EQ(count_of(a + b, "frame 0: computing"), 1u) << a << b;
  EXPECT_EQ(runs_now(a) + runs_now(b), 4) << "no run done twice:\n" << a << b;
  expect_complete(folder.experiment(), folder.results);
}

// Forced interleaving: while another process holds the reference's lock, `run` waits, says so once,
// computes nothing; when the lock is released without the reference stored, it computes it.
TEST(Concurrency, AWaitingProcessSaysOnceWhatItWaitsFor) {
  StoreFolder folder("wait_reference");
  Experiment experiment = folder.experiment();
  HeldLock held(ResultPaths{folder.results}.reference_lock(experiment.variants[0].reference_key));
  Process process(folder.run_arguments(), folder.path("out.txt"));
  ASSERT_TRUE(process.wait_for_output("waiting for reference " + experiment.variants[0].reference_key)) << process.output();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_TRUE(process.running());
  EXPECT_EQ(process.output().find("computing"), std::string::npos) << "nothing is computed while it waits";
  held.release();
  ASSERT_EQ(process.wait(), 0) << process.output();
  EXPECT_EQ(count_of(process.output(), "waiting for"), 1u) << process.output();
  EXPECT_NE(process.output().find("(lock "), std::string::npos) << process.output();
  expect_complete(experiment, folder.results);
}

// Forced interleaving: a run whose lock another process holds is left for last and waited for; its
// holder ending without storing it (a kill), it is run here after all, and every other run once.
TEST(Concurrency, ARunHeldByAnotherProcessIsWaitedForThenRun) {
  StoreFolder folder("wait_run", kFourRuns);
  Experiment experiment = folder.experiment();
  const RunSpec& held_run = experiment.runs[1];
  HeldLock held(ResultPaths{folder.results}.run_lock(experiment.name, held_run.key));
  Process process(folder.run_arguments(), folder.path("out.txt"));
  ASSERT_TRUE(process.wait_for_output("waiting for run " + held_run.label + " (" + held_run.key + ")")) << process.output();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_FALSE(fs::exists(ResultPaths{folder.results}.run(experiment.name, held_run.key)));
  size_t others = 0;
  for (const RunSpec& run : experiment.runs) others += run_is_stored(ResultPaths{folder.results}.run(experiment.name, run.key));
  EXPECT_EQ(others, 3u) << "the other runs are done while it waits";
  held.release();
  ASSERT_EQ(process.wait(), 0) << process.output();
  EXPECT_EQ(runs_now(process.output()), 4) << process.output();
  expect_complete(experiment, folder.results);
}

// ---------------------------------------------------------------------------------------------------
// Kills and failures at every write step.

// A kill at each write step of a first run (reference, environment, build cache, run): what a reader
// finds is never half written, and the next run completes the store and cleans up every leftover.
TEST(Kills, AtEveryWriteStepOfARunTheStoreIsNeverHalfWritten) {
  StoreFolder folder("kill_steps");
  const Experiment experiment = folder.experiment();
  Finished traced = folder.run({}, {"CAUSTICBENCH_FAULT_INJECT=trace"}, folder.path("traced"));
  ASSERT_EQ(traced.code, 0) << traced.output;
  std::vector<std::pair<int, std::string>> steps = traced_steps(traced.output);
  ASSERT_GE(steps.size(), 17u) << traced.output;
  std::vector<std::string> failures(steps.size());
  for_each_in_parallel(steps.size(), [&](size_t index) {
    const auto& [step, description] = steps[index];
    const std::string results = folder.path("kill_" + std::to_string(step));
    std::string& failure = failures[index];
    std::vector<std::string> arguments = folder.run_arguments(results);
    Finished killed = run_process(arguments, results + ".killed.txt", {"CAUSTICBENCH_FAULT_INJECT=kill@" + std::to_string(step)});
    if (killed.code != 128 + SIGKILL) failure += "not killed (exit " + std::to_string(killed.code) + "): " + killed.output;
    for (const std::string& problem : half_written(results)) failure += "after the kill: " + problem + "\n";
    Finished rerun = run_process(arguments, results + ".rerun.txt");
    if (rerun.code != 0) failure += "the rerun failed: " + rerun.output;
    if (!failure.empty()) failure = "kill at step " + std::to_string(step) + " (" + description + "):\n" + failure;
  });
  for (size_t index = 0; index < steps.size(); ++index) {
    EXPECT_EQ(failures[index], "");
    SCOPED_TRACE("kill at step " + std::to_string(steps[index].first) + " (" + steps[index].second + ")");
    expect_complete(experiment, folder.path("kill_" + std::to_string(steps[index].first)));
  }
}

// --force under a kill at each of its write steps, with the atomic exchange and with the two-rename
// fallback: the run is always stored (the old copy or the complete new one), never pending.
TEST(Kills, ForceReplacesARunAtomicallyUnderAKillAtEveryStep) {
  StoreFolder folder("kill_force");
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run().code, 0);
  const std::string old_record = record_text(experiment, folder.results, experiment.runs[0]);
  std::vector<std::pair<std::string, std::pair<int, std::string>>> cases;  // (mode, step)
  for (std::string mode : {"", ",no_rename_exchange"}) {
    fs::remove_all(folder.path("traced"));
    fs::copy(folder.results, folder.path("traced"), fs::copy_options::recursive);
    Finished traced = folder.run({"--force"}, {"CAUSTICBENCH_FAULT_INJECT=trace" + mode}, folder.path("traced"));
    ASSERT_EQ(traced.code, 0) << traced.output;
    for (const auto& step : traced_steps(traced.output))
      if (step.second.find("/runs/") != std::string::npos) cases.push_back({mode, step});
  }
  EXPECT_EQ(cases.size(), 6u + 7u) << "write, rename (images, record), commit, [replace,] discard";
  std::vector<std::string> failures(cases.size());
  for_each_in_parallel(cases.size(), [&](size_t index) {
    const auto& [mode, step] = cases[index];
    const std::string results = folder.path("force_" + std::to_string(index));
    fs::copy(folder.results, results, fs::copy_options::recursive);
    std::vector<std::string> arguments = folder.run_arguments(results);
    arguments.push_back("--force");
    Finished killed = run_process(arguments, results + ".killed.txt",
                                  {"CAUSTICBENCH_FAULT_INJECT=kill@" + std::to_string(step.first) + mode});
    std::string& failure = failures[index];
    if (killed.code != 128 + SIGKILL) failure += "not killed: " + killed.output;
    // What the next invocation sees: it first finishes or undoes interrupted replacements, as here; where
    // that matters (between the fallback's two renames) through the command line itself.
    if (step.second.rfind("replace ", 0) == 0) {
      Finished listed = run_process({"run", folder.experiment_file, "--results", results, "--dry-run"}, results + ".listed.txt");
      if (listed.output.find(experiment.runs[0].key + "  stored") == std::string::npos)
        failure += "the run is not listed as stored: " + listed.output;
    }
    remove_stale_staging(ResultPaths{results}.experiment(experiment.name) + "/runs");
    StoredRun stored = inspect_stored_run(ResultPaths{results}.run(experiment.name, experiment.runs[0].key));
    if (stored.state != StoredRun::State::stored) failure += "not stored: " + stored.problem;
    for (const std::string& left : leftovers(fs::path(results) / experiment.name)) failure += "left over: " + left + "\n";
    if (!failure.empty()) failure = "kill at " + step.second + (mode.empty() ? "" : " (no exchange)") + ":\n" + failure;
  });
  for (const std::string& failure : failures) EXPECT_EQ(failure, "");
  EXPECT_EQ(record_text(experiment, folder.results, experiment.runs[0]), old_record);
}

// A write of --force that fails as on a full disk: the error names the file and ENOSPC, the old copy
// stays, nothing is left behind.
TEST(Kills, AFailedWriteKeepsTheOldCopyAndNamesTheError) {
  StoreFolder folder("fail_force");
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run().code, 0);
  const std::string old_record = record_text(experiment, folder.results, experiment.runs[0]);
  Finished failed = folder.run({"--force"}, {"CAUSTICBENCH_FAULT_INJECT=fail@/runs/"});
  EXPECT_EQ(failed.code, 1) << failed.output;
  EXPECT_NE(failed.output.find("/frame_0000.exr: No space left on device (ENOSPC)"), std::string::npos) << failed.output;
  EXPECT_EQ(record_text(experiment, folder.results, experiment.runs[0]), old_record);
  EXPECT_EQ(leftovers(folder.results), std::vector<std::string>());
}

// A real full file system (a 1 MiB tmpfs filled up): the first write fails naming ENOSPC and the file,
// nothing is left half written; once there is space again the run completes; a --force on a full disk
// keeps every old copy.
TEST(FullDisk, AFullFileSystemIsNamedAndNothingIsHalfWritten) {
  StoreFolder folder("full_disk");
  const std::string disk = folder.path("disk");
  fs::create_directories(disk);
  if (mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=1m") != 0) {
    GTEST_SKIP() << "cannot mount a tmpfs here (" << os_error_text(errno) << "); the full-disk case is covered by "
                 << "Kills.AFailedWriteKeepsTheOldCopyAndNamesTheError through the fault-injection hook";
  }
  struct Unmount {
    std::string path;
    ~Unmount() { umount2(path.c_str(), MNT_DETACH); }
  } unmount{disk};
  const std::string results = disk + "/results", filler = disk + "/filler";
  auto fill = [&] {
    std::ofstream stream(filler, std::ios::binary | std::ios::app);
    std::string block(4096, 'f');
    while (stream.write(block.data(), block.size()) && stream.flush()) {
    }
  };
  const Experiment experiment = folder.experiment();
  fill();
  Finished full = folder.run({}, {}, results);
  EXPECT_EQ(full.code, 1) << full.output;
  EXPECT_NE(full.output.find("cannot write " + results), std::string::npos) << full.output;
  EXPECT_NE(full.output.find("No space left on device (ENOSPC)"), std::string::npos) << full.output;
  EXPECT_EQ(half_written(results), std::vector<std::string>());
  EXPECT_EQ(leftovers(results), std::vector<std::string>());

  fs::remove(filler);
  ASSERT_EQ(folder.run({}, {}, results).code, 0);
  expect_complete(experiment, results);
  const std::string old_record = record_text(experiment, results, experiment.runs[0]);
  fill();
  Finished forced = folder.run({"--force"}, {}, results);
  EXPECT_EQ(forced.code, 1) << forced.output;
  EXPECT_NE(forced.output.find("No space left on device (ENOSPC)"), std::string::npos) << forced.output;
  EXPECT_EQ(record_text(experiment, results, experiment.runs[0]), old_record);
  EXPECT_EQ(leftovers(results), std::vector<std::string>());
  fs::remove(filler);
  Finished again = folder.run({}, {}, results);
  EXPECT_NE(again.output.find("1 already stored"), std::string::npos) << again.output;
}

// Issue 30, defect 7: once the reference settings change, every stored run was measured against another
// reference. `run` measures it again against the new one (it used to say "1 already stored, 0 run now"),
// and `status` counts it pending while experiment.json names the new reference (it used to say complete).
TEST(StaleRuns, AreMeasuredAgainAfterTheReferenceChanges) {
  StoreFolder folder("stale_runs");
  ASSERT_EQ(folder.run().code, 0);
  const Experiment before = folder.experiment();
  folder.write("store.yaml", causticbench::testing::replace_once(kOneRun, "max_passes: 2", "max_passes: 3"));
  const Experiment after = folder.experiment();
  ASSERT_NE(before.variants[0].reference_key, after.variants[0].reference_key);
  ASSERT_EQ(before.runs[0].key, after.runs[0].key) << "the run's own key hashes its knobs, not the reference's";

  // status, with experiment.json naming the new reference (as `run` writes it before it measures).
  const std::string sweep = folder.results + "/store";
  std::string json_text = read_all(fs::path(sweep) / "experiment.json");
  // Every occurrence: the experiment's and its variant's.
  std::string changed = json_text;
  for (size_t at; (at = changed.find(before.variants[0].reference_key)) != std::string::npos;)
    changed.replace(at, before.variants[0].reference_key.size(), after.variants[0].reference_key);
  std::ofstream(fs::path(sweep) / "experiment.json") << changed;
  Finished status = run_process({"status", sweep}, folder.path("status.txt"));
  EXPECT_EQ(status.code, 3) << status.output;
  std::ofstream(fs::path(sweep) / "experiment.json") << json_text;

  Finished again = folder.run();
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_EQ(runs_now(again.output), 1) << again.output;
  EXPECT_NE(again.output.find("measuring the run again"), std::string::npos) << again.output;
  expect_complete(after, folder.results);
  Finished third = folder.run();
  EXPECT_EQ(runs_now(third.output), 0) << "measured once against the new reference, it is stored";
}

// Issue 30, defect 13: a hand-edited record with a negative time or an infinite metric used to count as a
// stored, ok run (and could win a front). It is damaged: not counted, named, and measured again.
TEST(StoredRecords, ImpossibleMeasurementsAreDamaged) {
  StoreFolder folder("impossible_values");
  ASSERT_EQ(folder.run().code, 0);
  const Experiment experiment = folder.experiment();
  const std::string run_folder = ResultPaths{folder.results}.run(experiment.name, experiment.runs[0].key);
  const std::string original = read_all(fs::path(run_folder) / "record.json");
  nlohmann::json record = nlohmann::json::parse(original);
  ASSERT_TRUE(record["frames"][0]["render_ms"].is_array());
  struct Edit {
    std::string what;
    std::function<void(nlohmann::json&)> apply;
    std::string expected;
  };
  const std::vector<Edit> edits = {
      {"negative render time", [](nlohmann::json& r) { r["frames"][0]["render_ms"][0] = -5.0; },
       "holds a time of -5 ms: expected a finite time >= 0"},
      {"negative prepare time", [](nlohmann::json& r) { r["prepare"]["prepare_seconds"] = -1.0; },
       "a prepare time of -1 s"},
      // Beyond the largest double: no JSON reader takes it as a number, so the record is damaged whole.
      {"overflowing metric", [](nlohmann::json& r) { r["metrics"]["relmse"] = std::numeric_limits<double>::infinity(); },
       "record.json"},
      // Issue 50, item 9: finite, but more than float images can give (relMSE at most about 1.5e187).
      {"relmse beyond what images give", [](nlohmann::json& r) { r["metrics"]["relmse"] = 1.79e308; },
       "metric relmse is 1.79e+308: expected a finite value in [0, 1.529"},
      {"flip above 1", [](nlohmann::json& r) { r["frames"][0]["metrics"]["flip"] = 3.0; },
       "frame 0: metric flip is 3: expected a finite value in [0, 1]"}};
  for (const Edit& edit : edits) {
    nlohmann::json edited = record;
    edit.apply(edited);
    std::string text = edited.dump(2);
    // nlohmann writes infinity as null; the hand edit the issue found wrote 1.8e308, which parses as infinity.
    for (size_t at; (at = text.find("\"relmse\": null")) != std::string::npos;) text.replace(at, 14, "\"relmse\": 1.8e308");
    std::ofstream(fs::path(run_folder) / "record.json") << text;
    StoredRun stored = inspect_stored_run(run_folder);
    EXPECT_EQ(stored.state, StoredRun::State::damaged) << edit.what;
    EXPECT_NE(stored.problem.find(edit.expected), std::string::npos) << edit.what << ": " << stored.problem;
    Finished again = folder.run();
    EXPECT_EQ(runs_now(again.output), 1) << edit.what << ": " << again.output;
    expect_complete(experiment, folder.results);
  }
}

// Issue 30, defect 6: a method's build files were written with a plain stream, so a full disk while
// photon_map wrote photons.bin was stored as a failed run ("write failed", no errno name), `status` called
// the sweep complete and nothing was retried once space was freed. They go through the store's atomic
// writes now: the write names the file and ENOSPC, `run` exits 1, the run stays pending, and the next run
// after the space is back measures it.
TEST(FullDisk, ABuildFileThatCannotBeWrittenLeavesTheRunPending) {
  StoreFolder folder("build_full");
  const Experiment experiment = folder.experiment();
  Finished failed = folder.run({}, {"CAUSTICBENCH_FAULT_INJECT=fail@photons.bin"});
  EXPECT_EQ(failed.code, 1) << failed.output;
  EXPECT_NE(failed.output.find("photons.bin: No space left on device (ENOSPC)"), std::string::npos) << failed.output;
  StoredRun stored = inspect_stored_run(ResultPaths{folder.results}.run(experiment.name, experiment.runs[0].key));
  EXPECT_EQ(stored.state, StoredRun::State::absent) << "the run is not stored, as failed or otherwise";
  Finished status = run_process({"status", folder.results + "/store"}, folder.path("status.txt"));
  EXPECT_EQ(status.code, 3) << status.output;
  EXPECT_EQ(leftovers(folder.results), std::vector<std::string>());
  Finished again = folder.run();
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_EQ(runs_now(again.output), 1) << again.output;
  expect_complete(experiment, folder.results);
}

// Runs that differ only in render knobs share one prepared instance; each record holds its own method
// record, counters and memory, taken right after its own render (it used to hold the group's last run's:
// every reference_convergence.yaml run reported the error estimate of the last one).
TEST(StoredRecords, EachRunOfASharedInstanceKeepsItsOwnMethodRecord) {
  StoreFolder folder("own_method_record", R"(name: store
scene: scene.yaml
reference: {photons_per_pass: 20000, max_passes: 2, target_error: 0, max_seconds: 0}
repetitions: 1
methods:
  - method: reference
    render: {photons_per_pass: 2000, min_passes: 1, target_error: 0, max_seconds: 0}
    sweep:
      max_passes: [1, 2, 3]
)");
  ASSERT_EQ(folder.run().code, 0);
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(experiment.runs.size(), 3u);
  for (const RunSpec& run : experiment.runs) {
    nlohmann::json record = nlohmann::json::parse(record_text(experiment, folder.results, run));
    EXPECT_EQ(record["method_record"]["passes"].get<int64_t>(), run.params.integer("max_passes")) << run.label;
    EXPECT_EQ(record["counters"]["passes"].get<double>(), static_cast<double>(run.params.integer("max_passes"))) << run.label;
  }
}
