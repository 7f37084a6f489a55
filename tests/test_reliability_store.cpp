// The results store's guarantees (docs/results-format.md, "Guarantees"), each tried as a hostile but
// realistic user would: two `causticbench run` processes (or two shards) on one results folder, with
// their interleavings forced through the store's locks; a kill at every write step of a run and of a
// --force rerun (the fault-injection hook of core/files.h); a full file system (a small tmpfs, where the
// test may mount one); damaged records and references; references that do or do not depend on the
// machine's speed. The helpers that start processes and inspect a results folder: tests/reliability/store_harness.h.
#include <sys/mount.h>

#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/files.h"
#include "core/parallel.h"
#include "core/staging_folder.h"
#include "experiments/experiment.h"
#include "experiments/reference_frames.h"
#include "tests/reliability/store_harness.h"
#include "tests/test_support.h"

using namespace causticbench;
using namespace causticbench::store_harness;
namespace fs = std::filesystem;

namespace {

// One photon_map run of a 16 x 16 glass sphere against a two-pass reference: every kind of write step
// of the store (reference, environment, build cache, run) in about 20 steps.
const char* const kOneRun = R"(name: store
scene: scene.yaml
reference: {photons_per_pass: 20000, max_passes: 2, target_noise_floor: 0, max_seconds: 0}
repetitions: 1
methods:
  - method: photon_map
    build: {photons: 1000}
    render: {k: 10, max_radius: 0.3}
)";

// Four runs in two build groups.
const char* const kFourRuns = R"(name: store
scene: scene.yaml
reference: {photons_per_pass: 20000, max_passes: 2, target_noise_floor: 0, max_seconds: 0}
repetitions: 1
methods:
  - method: photon_map
    render: {max_radius: 0.3}
    sweep:
      photons: [1000, 2000]
      k: [10, 20]
)";

// A reference that stops on its time cap after its first pass: two computations of it differ.
const std::string kTimeCapped = "reference: {photons_per_pass: 20000, max_passes: 100000, target_noise_floor: 0, max_seconds: 0.000001}";

class StoreFolder : public causticbench::testing::TemporaryFolder {
 public:
  explicit StoreFolder(const std::string& name, const std::string& experiment = kOneRun)
      : TemporaryFolder("store_" + name) {
    write("scene.yaml", causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                            "resolution: [40, 40]", "resolution: [16, 16]"));
    experiment_file = write("store.yaml", experiment);
    results = path("results");
  }
  Experiment experiment() const { return load_experiment(experiment_file); }
  std::vector<std::string> run_arguments(const std::string& results_folder = "") const {
    return {"run", experiment_file, "--results", results_folder.empty() ? results : results_folder, "--no-report"};
  }
  Finished run(const std::vector<std::string>& extra = {}, const std::vector<std::string>& environment = {},
               const std::string& results_folder = "") const {
    std::vector<std::string> arguments = run_arguments(results_folder);
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return run_process(arguments, path("output_" + std::to_string(outputs_++) + ".txt"), environment);
  }

  std::string experiment_file, results;

 private:
  mutable int outputs_ = 0;
};

// Every run of the experiment is stored under `results`, passes the store's checks and was measured
// against the reference that is stored; nothing is half written and nothing left over.
void expect_complete(const Experiment& experiment, const std::string& results) {
  ResultPaths paths{results};
  std::optional<nlohmann::json> reference =
      stored_reference_checksums(paths, experiment.variants[0].reference_key, experiment.frames);
  ASSERT_TRUE(reference) << "the reference is stored";
  for (const RunSpec& run : experiment.runs) {
    StoredRun stored = inspect_stored_run(paths.run(experiment.name, run.key));
    ASSERT_EQ(stored.state, StoredRun::State::stored) << run.label << ": " << stored.problem;
    EXPECT_EQ(stored.record["status"], "ok") << stored.record["error"];
    EXPECT_EQ(stored.record["reference_images"], *reference) << run.label << " was measured against another reference";
  }
  EXPECT_EQ(half_written(results), std::vector<std::string>());
  EXPECT_EQ(leftovers(results), std::vector<std::string>());
}

std::string record_text(const Experiment& experiment, const std::string& results, const RunSpec& run) {
  return read_all(fs::path(ResultPaths{results}.run(experiment.name, run.key)) / "record.json");
}

// "N run now" of the summary line.
int runs_now(const std::string& output) {
  std::smatch match;
  return std::regex_search(output, match, std::regex("([0-9]+) run now")) ? std::stoi(match[1].str()) : -1;
}

}  // namespace

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
                                   kFourRuns, "reference: {photons_per_pass: 20000, max_passes: 2, target_noise_floor: 0, max_seconds: 0}",
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

// ---------------------------------------------------------------------------------------------------
// Damaged records and references.

// Truncated, `{}` and wrong-checksum run records are not stored: the report shows them as failed (never
// ok), and the next run measures them again, naming each file and what was wrong.
TEST(Corruption, DamagedRunRecordsAreReportedAsFailedAndMeasuredAgain) {
  StoreFolder folder("damaged_runs", kFourRuns);
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run().code, 0);
  ResultPaths paths{folder.results};
  auto run_folder = [&](size_t index) { return fs::path(paths.run(experiment.name, experiment.runs[index].key)); };
  const std::string record = read_all(run_folder(0) / "record.json");
  std::ofstream(run_folder(0) / "record.json", std::ios::trunc) << record.substr(0, record.size() / 2);
  std::ofstream(run_folder(1) / "record.json", std::ios::trunc) << "{}";
  std::string image = read_all(run_folder(2) / "frame_0000.exr");
  image[image.size() / 2] ^= 0x5a;  // same size, other content
  std::ofstream(run_folder(2) / "frame_0000.exr", std::ios::binary | std::ios::trunc) << image;

  Finished report = run_process({"report", paths.experiment(experiment.name)}, folder.path("report.txt"));
  ASSERT_EQ(report.code, 0) << report.output;
  nlohmann::json results = nlohmann::json::parse(read_all(fs::path(paths.experiment(experiment.name)) / "results.json"));
  std::map<std::string, std::string> status;
  for (const nlohmann::json& run : results["runs"]) status[run.value("key", "")] = run.value("status", "");
  for (size_t index : {0, 1, 2}) EXPECT_EQ(status[experiment.runs[index].key], "failed") << index;
  EXPECT_EQ(status[experiment.runs[3].key], "ok");

  Finished rerun = folder.run();
  ASSERT_EQ(rerun.code, 0) << rerun.output;
  EXPECT_EQ(runs_now(rerun.output), 3) << rerun.output;
  for (const std::string& expected : std::vector<std::string>{
           (run_folder(0) / "record.json").string() + ": not valid JSON",
           (run_folder(1) / "record.json").string() + ": field 'key' is missing",
           "its image frame_0000.exr: its content does not match the checksum"})
    EXPECT_NE(rerun.output.find(expected), std::string::npos) << expected << " in:\n" << rerun.output;
  expect_complete(experiment, folder.results);
}

// A truncated reference EXR, a `{}` frame record and a truncated summary are found when the reference
// is next needed and computed again; the reference being deterministic, the new copy is the same bytes,
// so the runs measured against the old one stay stored.
TEST(Corruption, DamagedReferencesAreComputedAgain) {
  StoreFolder folder("damaged_reference");
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run().code, 0);
  const fs::path reference = ResultPaths{folder.results}.reference(experiment.variants[0].reference_key);
  const std::string image = read_all(reference / "frame_0000.exr");
  // A second experiment of the same reference has a run to do, so it needs the reference.
  const std::string second = folder.write("second.yaml", causticbench::testing::replace_once(
                                                             causticbench::testing::replace_once(kOneRun, "name: store", "name: second"),
                                                             "k: 10", "k: 11"));
  auto run_second = [&](const std::string& name) {
    return run_process({"run", second, "--results", folder.results, "--no-report"}, folder.path(name));
  };
  std::ofstream(reference / "frame_0000.exr", std::ios::trunc) << image.substr(0, image.size() / 2);
  Finished truncated = run_second("truncated.txt");
  ASSERT_EQ(truncated.code, 0) << truncated.output;
  EXPECT_NE(truncated.output.find("frame_0000.exr: " + std::to_string(image.size() / 2) + " bytes where its record says"),
            std::string::npos) << truncated.output;
  EXPECT_NE(truncated.output.find("computing"), std::string::npos) << truncated.output;
  EXPECT_EQ(read_all(reference / "frame_0000.exr"), image) << "same settings, same seed: the same bytes";

  std::ofstream(reference / "record_0000.json", std::ios::trunc) << "{}";
  std::ofstream(reference / "record.json", std::ios::trunc) << "{\"key\": ";
  Finished empty = run_process({"run", second, "--results", folder.results, "--no-report", "--force"}, folder.path("empty.txt"));
  ASSERT_EQ(empty.code, 0) << empty.output;
  EXPECT_NE(empty.output.find("record_0000.json: field 'frame' is missing; computing it again"), std::string::npos)
      << empty.output;
  Finished first = folder.run();
  EXPECT_NE(first.output.find("1 already stored, 0 run now"), std::string::npos) << first.output;
  expect_complete(experiment, folder.results);
}

// A stored run measured against another copy of its reference than the stored one (a time-capped
// reference computed again) is measured again, with a warning.
TEST(Corruption, ARunMeasuredAgainstAnotherCopyOfItsReferenceIsMeasuredAgain) {
  StoreFolder folder("other_copy");
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run().code, 0);
  const fs::path record_path = fs::path(ResultPaths{folder.results}.run(experiment.name, experiment.runs[0].key)) / "record.json";
  nlohmann::json record = nlohmann::json::parse(read_all(record_path));
  record["reference_images"]["frame_0000.exr"]["xxhash"] = "0123456789abcdef";
  std::ofstream(record_path, std::ios::trunc) << record.dump(2);
  Finished rerun = folder.run();
  ASSERT_EQ(rerun.code, 0) << rerun.output;
  EXPECT_NE(rerun.output.find("was measured against another copy of reference"), std::string::npos) << rerun.output;
  EXPECT_EQ(runs_now(rerun.output), 1) << rerun.output;
  expect_complete(experiment, folder.results);
}

// A mesh the scene names, edited in place, leaves the scene file's text and so every key as they were:
// the reference stored with the old mesh is computed again (its record holds the scene's content hash),
// and the run measured against the old copy is measured again.
TEST(Corruption, AnEditedMeshComputesItsReferenceAndRunsAgain) {
  // A glass octahedron of half-diagonal `size` at the sphere's place.
  auto octahedron = [](double size) {
    std::string text;
    for (const char* corner : {"1 0 0", "-1 0 0", "0 1 0", "0 -1 0", "0 0 1", "0 0 -1"}) {
      std::istringstream in(corner);
      double x, y, z;
      in >> x >> y >> z;
      text += fmt::format("v {} {} {}\n", x * size, y * size + 0.6, z * size);
    }
    return text + "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
  };
  StoreFolder folder("edited_mesh");
  folder.write("gem.obj", octahedron(0.4));
  folder.write("scene.yaml", causticbench::testing::replace_once(
                                 causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                                     "resolution: [40, 40]", "resolution: [16, 16]"),
                                 "shape: {type: sphere, radius: 0.4}", "shape: {type: mesh, asset: gem.obj, smooth_normals: false}"));
  const Experiment before = folder.experiment();
  Finished first = folder.run();
  ASSERT_EQ(first.code, 0) << first.output;
  EXPECT_EQ(runs_now(first.output), 1) << first.output;
  const fs::path reference = ResultPaths{folder.results}.reference(before.variants[0].reference_key);
  EXPECT_EQ(nlohmann::json::parse(read_all(reference / "record_0000.json"))["scene_content"], before.variants[0].content_hash);
  Finished unchanged = folder.run();
  EXPECT_EQ(runs_now(unchanged.output), 0) << unchanged.output;

  folder.write("gem.obj", octahedron(0.3));
  const Experiment after = folder.experiment();
  ASSERT_EQ(after.variants[0].reference_key, before.variants[0].reference_key) << "the keys hash the scene file's text";
  ASSERT_EQ(after.runs[0].key, before.runs[0].key);
  ASSERT_NE(after.variants[0].content_hash, before.variants[0].content_hash);
  Finished edited = folder.run();
  ASSERT_EQ(edited.code, 0) << edited.output;
  EXPECT_NE(edited.output.find("computed for other scene content"), std::string::npos) << edited.output;
  EXPECT_EQ(runs_now(edited.output), 1) << edited.output;
  EXPECT_EQ(nlohmann::json::parse(read_all(reference / "record_0000.json"))["scene_content"], after.variants[0].content_hash);
  expect_complete(after, folder.results);
}

// ---------------------------------------------------------------------------------------------------
// References that do and do not depend on the machine.

// Stopped on its pass count or its noise floor, the reference is the same image on 1 and 2 threads.
TEST(Reference, SameSeedGivesTheSameImageOnAnyThreadCount) {
  Scene scene = causticbench::testing::scene_from_yaml(causticbench::testing::replace_once(
      causticbench::testing::kSmallGlassSphere, "resolution: [40, 40]", "resolution: [24, 24]"));
  const std::vector<std::vector<std::string>> stops = {
      {"photons_per_pass=20000", "max_passes=3", "target_noise_floor=0", "max_seconds=0"},
      {"photons_per_pass=20000", "max_passes=1000", "target_noise_floor=0.015", "min_passes=2", "max_seconds=0"}};
  for (const std::vector<std::string>& knobs : stops) {
    auto render_on = [&](int threads) {
      ThreadLimit limit(threads);
      return causticbench::testing::render(scene, "reference", knobs);
    };
    FrameResult one = render_on(1), two = render_on(2);
    EXPECT_EQ(one.method_record["passes"], two.method_record["passes"]);
    EXPECT_EQ(one.method_record["stop_reason"], knobs[2] == "target_noise_floor=0" ? "max_passes" : "target_noise_floor");
    EXPECT_TRUE(one.caustic.values() == two.caustic.values()) << knobs[2];
    EXPECT_EQ(encode_exr(one.caustic), encode_exr(two.caustic)) << "the stored bytes too";
  }
}

// Stopped on its time cap, the reference is stored as not converged with the reason; the runs measured
// against it and the report say so.
TEST(Reference, ATimeCappedReferenceIsMarkedAndItsRunsSaySo) {
  StoreFolder folder("time_cap", causticbench::testing::replace_once(
                                     kOneRun, "reference: {photons_per_pass: 20000, max_passes: 2, target_noise_floor: 0, max_seconds: 0}",
                                     kTimeCapped));
  const Experiment experiment = folder.experiment();
  Finished run = run_process({"run", folder.experiment_file, "--results", folder.results}, folder.path("out.txt"));
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("is not converged"), std::string::npos) << run.output;
  const fs::path reference = ResultPaths{folder.results}.reference(experiment.variants[0].reference_key);
  nlohmann::json frame = nlohmann::json::parse(read_all(reference / "record_0000.json"));
  EXPECT_EQ(frame["stop_reason"], "max_seconds");
  EXPECT_EQ(frame["converged"], false);
  EXPECT_NE(frame.value("unconverged_reason", std::string()).find("time cap (max_seconds"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(read_all(reference / "record.json"))["converged"], false);
  StoredRun stored = inspect_stored_run(ResultPaths{folder.results}.run(experiment.name, experiment.runs[0].key));
  EXPECT_EQ(stored.record["reference_converged"], false);
  EXPECT_EQ(stored.record["reference_unconverged"], frame["unconverged_reason"]);
  const std::string markdown = read_all(fs::path(folder.results) / experiment.name / "report.md");
  EXPECT_NE(markdown.find("NOT converged"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("1 run(s) were measured against a reference that stopped on its time cap"), std::string::npos)
      << markdown;
}
