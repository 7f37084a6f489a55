// Sweeps on a cluster without the cluster (the Slurm end-to-end test is test_slurm.cpp): the store's
// lock files and their stale-lock recovery, the cost-balanced shard plan, the reference job
// (`run --prepare-only`), a shard killed midway and resubmitted, and `causticbench status`.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/files.h"
#include "experiments/experiment.h"
#include "experiments/run_measurement.h"
#include "experiments/shard_plan.h"
#include "store/store_lock.h"
#include "store/sweep_status.h"
#include "tests/cluster_test_support.h"

using namespace causticbench;
using namespace causticbench::store_harness;
namespace fs = std::filesystem;

namespace {

// Locks of other hosts go stale after 2 s without a heartbeat here (120 s by default), for this process
// and the causticbench processes it starts; set before any lock is taken, so the heartbeat follows it.
const bool kStaleAfterTwoSeconds = (::setenv("CAUSTICBENCH_LOCK_STALE_SECONDS", "2", 1), true);

using causticbench::testing::kClusterSweep;
using causticbench::testing::stored_keys;
using causticbench::testing::SweepFolder;
using causticbench::testing::read_whole_file;
using causticbench::testing::run_command;

std::string line_of(const std::string& path) {
  std::ifstream stream(path);
  std::string line;
  std::getline(stream, line);
  return line;
}

// A pid that no process has: a child that already ended and was reaped.
pid_t ended_pid() {
  pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

}  // namespace

// A lock file is created with its holder line and removed on release; a second taker is refused while
// it is held.
TEST(StoreLockFiles, HeldByALiveProcessAndRemovedOnRelease) {
  causticbench::testing::TemporaryFolder folder("cluster_lock_live");
  const std::string path = folder.path("locks/a.lock");
  {
    std::optional<StoreLock> lock = StoreLock::try_acquire(path);
    ASSERT_TRUE(lock);
    EXPECT_EQ(line_of(path).rfind(fmt::format("pid {} on {} started ", getpid(), host_name()), 0), 0u) << line_of(path);
    EXPECT_FALSE(StoreLock::try_acquire(path)) << "a lock of a live process on this host is never stale";
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(StoreLock::try_acquire(path));
}

// A job killed on this host leaves its lock file: its pid is gone, so the lock is taken at once.
TEST(StoreLockFiles, LockOfADeadProcessOnThisHostIsRecoveredAtOnce) {
  causticbench::testing::TemporaryFolder folder("cluster_lock_dead");
  const std::string path = folder.path("a.lock");
  folder.write("a.lock", fmt::format("pid {} on {} started 1 token 00\n", ended_pid(), host_name()));
  EXPECT_TRUE(StoreLock::try_acquire(path));
}

// A job killed on another host: its pid cannot be checked from here, so its lock is stale once its
// heartbeat stopped for the stale time (2 s here), and only then.
TEST(StoreLockFiles, StaleLockOfAnotherHostIsRecoveredAfterItsHeartbeatStops) {
  causticbench::testing::TemporaryFolder folder("cluster_lock_other_host");
  const std::string path = folder.path("a.lock");
  folder.write("a.lock", "pid 4242 on node-that-died started 99 token 01\n");
  EXPECT_FALSE(StoreLock::try_acquire(path)) << "a fresh lock of another host is held";
  std::this_thread::sleep_for(std::chrono::milliseconds(2600));
  std::optional<StoreLock> lock = StoreLock::try_acquire(path);
  ASSERT_TRUE(lock);
  EXPECT_EQ(line_of(path).rfind(fmt::format("pid {} on {}", getpid(), host_name()), 0), 0u);
}

// A holder keeps its lock alive for other hosts: the heartbeat refreshes the file's modification time.
TEST(StoreLockFiles, HeldLockIsRefreshedByTheHeartbeat) {
  causticbench::testing::TemporaryFolder folder("cluster_lock_heartbeat");
  const std::string path = folder.path("a.lock");
  std::optional<StoreLock> lock = StoreLock::try_acquire(path);
  ASSERT_TRUE(lock);
  struct stat before {}, after {};
  ASSERT_EQ(::stat(path.c_str(), &before), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // heartbeat every 2/8 s
  ASSERT_EQ(::stat(path.c_str(), &after), 0);
  EXPECT_GT(after.st_mtim.tv_sec * 1000000000LL + after.st_mtim.tv_nsec,
            before.st_mtim.tv_sec * 1000000000LL + before.st_mtim.tv_nsec + 300000000LL);
}

// Runs sharing one prepare() stay in one shard; every run is in exactly one shard; groups of unequal
// cost are dealt so that no shard exceeds the least loaded one by more than the largest group.
TEST(ShardPlans, GroupsStayTogetherAndShardsAreBalanced) {
  SweepFolder folder("plan", causticbench::testing::replace_once(
                                 kClusterSweep, "repetitions: 1", "repetitions: 1\nvariants:\n  - {name: small}\n"
                                                           "  - {name: large, resolution: [72, 72]}"));
  Experiment experiment = folder.experiment();
  ASSERT_EQ(experiment.runs.size(), 12u);
  ShardPlan plan = plan_shards(experiment, 3, nullptr);
  std::map<std::string, std::set<int>> shards_of_group;
  std::vector<size_t> runs_per_shard(3, 0);
  for (const RunSpec& run : experiment.runs) {
    int shard = plan.shard_of.at(run.key);
    ASSERT_GE(shard, 0);
    ASSERT_LT(shard, 3);
    ++runs_per_shard[static_cast<size_t>(shard)];
    shards_of_group[std::to_string(run.variant) + run.build.to_json().dump()].insert(shard);
  }
  EXPECT_EQ(shards_of_group.size(), 6u);
  for (const auto& [group, shards] : shards_of_group) EXPECT_EQ(shards.size(), 1u) << "group " << group << " split";
  // The large variant's groups cost 9 times the small ones': the three large groups go to three shards.
  auto [least, most] = std::minmax_element(plan.shard_seconds.begin(), plan.shard_seconds.end());
  EXPECT_LE(*most - *least, 2.0 * 72 * 72 * 2 + 1e-6);
  EXPECT_GT(*least, 0.0);
  // The same experiment plans the same partition, whenever and wherever it is planned.
  EXPECT_EQ(plan_shards(experiment, 3, nullptr).shard_of, plan.shard_of);
}

// Planned after part of the sweep ran: the stored runs cost their shard nothing, and the estimates of the
// runs to do are seconds, scaled by the stored runs' timings, not model units.
TEST(ShardPlans, StoredRunsCostNothingAndScaleTheEstimates) {
  SweepFolder folder("plan_stored");
  Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run({"--filter", "photons=1000"}).code, 0);
  ResultPaths paths{folder.results};
  ShardPlan plan = plan_shards(experiment, 2, &paths);
  EXPECT_EQ(plan.timed_runs, 2u);
  double to_do = 0.0;
  for (const PlannedRun& run : plan.runs) {
    bool done = run.label.find("photons=1000") != std::string::npos;
    EXPECT_EQ(run.stored, done) << run.label;
    if (done) {
      EXPECT_EQ(run.estimated_seconds, 0.0) << run.label;
    } else {
      // 24 x 24 pixels, one frame, two passes: 1152 model units, a few milliseconds of photon_map.
      EXPECT_GT(run.estimated_seconds, 0.0) << run.label;
      EXPECT_LT(run.estimated_seconds, 10.0) << run.label;
    }
    to_do += run.estimated_seconds;
  }
  EXPECT_NEAR(plan.shard_seconds[0] + plan.shard_seconds[1], to_do, 1e-9 * to_do);
  // The two groups still to do go to the two shards.
  EXPECT_GT(plan.shard_seconds[0], 0.0);
  EXPECT_GT(plan.shard_seconds[1], 0.0);
}

// A plan whose runs are not the experiment's (the experiment changed since) is refused with what to do.
TEST(ShardPlans, PlanOfAnotherSweepIsRefused) {
  SweepFolder folder("plan_changed");
  Experiment experiment = folder.experiment();
  ResultPaths paths{folder.results};
  write_shard_plan(folder.path("plan.json"), plan_shards(experiment, 2, &paths));
  EXPECT_EQ(read_shard_plan(folder.path("plan.json"), experiment).shard_of.size(), 6u);
  Experiment changed = load_experiment(
      folder.write("changed.yaml", causticbench::testing::replace_once(kClusterSweep, "k: [10, 20]", "k: [10, 30]")));
  std::string message = causticbench::testing::input_error_message([&] { read_shard_plan(folder.path("plan.json"), changed); });
  EXPECT_NE(message.find("plan it again"), std::string::npos) << message;
  Finished finished = folder.run({"--shard", "0/3", "--shard-plan", folder.path("plan.json")});
  EXPECT_EQ(finished.code, 2) << finished.output;
  EXPECT_NE(finished.output.find("expected n = 2"), std::string::npos) << finished.output;
}

// The reference job computes the reference and every build and runs nothing; the shards then load the
// builds (none computes one) and, together, store exactly the experiment's runs.
TEST(ShardPlans, PrepareOnlyThenShardsByPlanStoreEveryRunOnce) {
  SweepFolder folder("prepare_then_shards");
  Experiment experiment = folder.experiment();
  Finished prepared = folder.run({"--prepare-only"});
  ASSERT_EQ(prepared.code, 0) << prepared.output;
  EXPECT_NE(prepared.output.find("3 builds computed"), std::string::npos) << prepared.output;
  EXPECT_TRUE(stored_keys(folder.results + "/sweep/runs").empty());
  ASSERT_TRUE(stored_reference_checksums(ResultPaths{folder.results}, experiment.variants[0].reference_key, experiment.frames));
  Finished slurm = folder.command({"slurm", folder.file, "--results", folder.results, "--shards", "3"});
  ASSERT_EQ(slurm.code, 0) << slurm.output;
  const std::string plan = folder.results + "/sweep/slurm/shard-plan.json";
  std::set<std::string> all;
  for (int shard = 0; shard < 3; ++shard) {
    Finished finished = folder.run({"--shard", fmt::format("{}/3", shard), "--shard-plan", plan});
    ASSERT_EQ(finished.code, 0) << finished.output;
    EXPECT_EQ(finished.output.find("computing"), std::string::npos) << "the reference is stored\n" << finished.output;
    EXPECT_EQ(finished.output.find(": computed"), std::string::npos) << "every build is stored\n" << finished.output;
    EXPECT_NE(finished.output.find("2 selected, 0 already stored, 2 run now"), std::string::npos) << finished.output;
  }
  std::set<std::string> expected;
  for (const RunSpec& run : experiment.runs) expected.insert(run.key);
  EXPECT_EQ(stored_keys(folder.results + "/sweep/runs"), expected);
  for (const char* script : {"prepare.sbatch", "shards.sbatch", "report.sbatch", "submit.sh"}) {
    EXPECT_TRUE(fs::exists(folder.results + "/sweep/slurm/" + script)) << script;
  }
}

// A shard killed midway (SIGKILL, as Slurm ends a job past its time) and resubmitted finishes its shard:
// the runs stored before the kill are kept as they were, the rest are stored once. Midway for sure: the
// store's fault injection kills it as it starts writing its third run, holding the locks of the runs it
// claimed; its fourth run is locked by a job "on another host" whose heartbeat this test beats until
// the kill. The resubmitted shard recovers both kinds of stale lock: the dead process's of this host at
// once, the other host's once it is 2 s old.
TEST(ShardPlans, KilledShardResubmittedFinishesWithNothingLostOrDuplicated) {
  SweepFolder folder("killed_shard", causticbench::testing::replace_once(kClusterSweep, "k: [10, 20]", "k: [10, 20, 30, 40]"));
  Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.command({"slurm", folder.file, "--results", folder.results, "--shards", "3"}).code, 0);
  const std::string plan_path = folder.results + "/sweep/slurm/shard-plan.json";
  ShardPlan plan = read_shard_plan(plan_path, experiment);
  std::vector<std::string> shard_keys;  // in the order the shard plays them: the experiment's
  for (const PlannedRun& run : plan.runs)
    if (run.shard == 1) shard_keys.push_back(run.key);
  ASSERT_EQ(shard_keys.size(), 4u);
  ASSERT_EQ(folder.run({"--prepare-only"}).code, 0);

  const std::string foreign_lock = ResultPaths{folder.results}.run_lock("sweep", shard_keys[3]);
  causticbench::testing::ForeignLock foreign(foreign_lock, "node-killed-elsewhere");
  const std::vector<std::string> shard = {"run", folder.file, "--results", folder.results, "--no-report",
                                          "--shard", "1/3", "--shard-plan", plan_path};
  Finished killed = run_process(shard, folder.path("killed.txt"), {"CAUSTICBENCH_FAULT_INJECT=kill@" + shard_keys[2]});
  foreign.stop();  // that job is killed too
  ASSERT_EQ(killed.code, 128 + SIGKILL) << killed.output;

  const std::string runs = folder.results + "/sweep/runs";
  ASSERT_EQ(stored_keys(runs), (std::set<std::string>{shard_keys[0], shard_keys[1]}));
  std::map<std::string, std::string> records_before;
  for (const std::string& key : {shard_keys[0], shard_keys[1]}) records_before[key] = inspect_stored_run(runs + "/" + key).record_hash;
  ASSERT_TRUE(fs::exists(ResultPaths{folder.results}.run_lock("sweep", shard_keys[2]))) << "the killed job's lock stays";

  Finished resubmitted = run_process(shard, folder.path("resubmitted.txt"));
  ASSERT_EQ(resubmitted.code, 0) << resubmitted.output;
  EXPECT_NE(resubmitted.output.find("no longer exists on this host"), std::string::npos) << resubmitted.output;
  EXPECT_NE(resubmitted.output.find("removing the stale lock " + foreign_lock), std::string::npos) << resubmitted.output;
  EXPECT_NE(resubmitted.output.find("4 selected, 2 already stored, 2 run now"), std::string::npos) << resubmitted.output;
  EXPECT_EQ(stored_keys(runs), std::set<std::string>(shard_keys.begin(), shard_keys.end())) << "exactly the shard's runs";
  for (const auto& [key, hash] : records_before) {
    EXPECT_EQ(inspect_stored_run(runs + "/" + key).record_hash, hash) << "run " << key << " stored before the kill was redone";
  }
  EXPECT_TRUE(half_written(folder.results).empty());
  for (const auto& entry : fs::directory_iterator(runs)) {
    EXPECT_NE(entry.path().filename().string().rfind(".partial-", 0), 0u) << "left behind: " << entry.path();
  }
}

// `status` of a sweep planned in two shards: incomplete (exit 3) with the shard that has work, then
// complete (exit 0), and a failed run counted as failed and not pending.
TEST(SweepStatusCommand, IncompleteCompleteAndFailed) {
  SweepFolder folder("status");
  Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.command({"slurm", folder.file, "--results", folder.results, "--shards", "2"}).code, 0);
  const std::string plan_path = folder.results + "/sweep/slurm/shard-plan.json";
  ShardPlan plan = read_shard_plan(plan_path, experiment);
  const std::string sweep = folder.results + "/sweep";

  Finished none = folder.command({"status", sweep});
  EXPECT_EQ(none.code, 3) << none.output;
  EXPECT_NE(none.output.find("6 runs: 0 stored ok, 0 failed, 6 pending"), std::string::npos) << none.output;

  ASSERT_EQ(folder.run({"--shard", "0/2", "--shard-plan", plan_path}).code, 0);
  size_t in_shard_one = 0;
  for (const PlannedRun& run : plan.runs) in_shard_one += run.shard == 1 ? 1 : 0;
  Finished incomplete = folder.command({"status", sweep});
  EXPECT_EQ(incomplete.code, 3) << incomplete.output;
  EXPECT_NE(incomplete.output.find(fmt::format("{} stored ok, 0 failed, {} pending", 6 - in_shard_one, in_shard_one)),
            std::string::npos)
      << incomplete.output;
  EXPECT_NE(incomplete.output.find(fmt::format("shard 1 has {} pending", in_shard_one)), std::string::npos) << incomplete.output;
  EXPECT_EQ(incomplete.output.find("shard 0 has"), std::string::npos) << incomplete.output;
  EXPECT_NE(incomplete.output.find("sbatch --array=1 "), std::string::npos) << incomplete.output;

  ASSERT_EQ(folder.run({"--shard", "1/2", "--shard-plan", plan_path}).code, 0);
  Finished complete = folder.command({"status", sweep});
  EXPECT_EQ(complete.code, 0) << complete.output;
  EXPECT_NE(complete.output.find("6 runs: 6 stored ok, 0 failed, 0 pending"), std::string::npos) << complete.output;
  EXPECT_NE(complete.output.find("none has runs to do"), std::string::npos) << complete.output;

  // A failed run, stored as the runner stores one: failed, not pending; the sweep is still complete.
  RunRecord failed = run_identity(experiment, experiment.runs[2]);
  failed.status = "failed";
  failed.error = "prepare() threw";
  store_run_folder(ResultPaths{folder.results}.run("sweep", experiment.runs[2].key), {}, failed.to_json());
  SweepStatus status = sweep_status(sweep, experiment_file_runs);
  EXPECT_EQ(status.all.ok, 5u);
  EXPECT_EQ(status.all.failed, 1u);
  EXPECT_EQ(status.methods.at("photon_map").failed, 1u);
  EXPECT_TRUE(status.complete());
  Finished with_failure = folder.command({"status", sweep});
  EXPECT_EQ(with_failure.code, 0) << with_failure.output;
  EXPECT_NE(with_failure.output.find("6 runs: 5 stored ok, 1 failed, 0 pending"), std::string::npos) << with_failure.output;
}

// Without a plan (a sweep run with `run` alone), `status` lists the runs of experiment.json, with the
// methods of pending runs from the experiment file it names, and no shard line.
TEST(SweepStatusCommand, WithoutAPlanFromExperimentJson) {
  SweepFolder folder("status_no_plan");
  ASSERT_EQ(folder.run({"--filter", "photons=1000"}).code, 0);
  SweepStatus status = sweep_status(folder.results + "/sweep", experiment_file_runs);
  EXPECT_EQ(status.all.total, 6u);
  EXPECT_EQ(status.all.ok, 2u);
  EXPECT_EQ(status.all.pending, 4u);
  ASSERT_EQ(status.methods.size(), 1u);
  EXPECT_EQ(status.methods.begin()->first, "photon_map");
  Finished finished = folder.command({"status", folder.results + "/sweep"});
  EXPECT_EQ(finished.code, 3) << finished.output;
  EXPECT_EQ(finished.output.find("shards ("), std::string::npos) << finished.output;
  Finished missing = folder.command({"status", folder.results + "/nothing"});
  EXPECT_EQ(missing.code, 2) << missing.output;
}

// Issue 30, defect 9: paths reach the job scripts. A newline in --results (or in the experiment's path)
// used to be written raw into `#SBATCH --output=` and a comment, so the text after it ran as a command in
// the job, and sbatch stopped reading directives there (losing --array). It is refused now, before
// anything is written. A path with spaces, quotes, '$(...)', ';', a backslash and '%' is quoted: sbatch's
// directive reads it as one word ('%' doubled, since Slurm expands %j and the like in --output), and the
// job's commands, run here by bash as Slurm would, find the experiment and results where they are and run
// nothing else.
TEST(SlurmJobs, HostilePathsAreRefusedOrQuoted) {
  SweepFolder folder("hostile_paths");
  const std::string injected = folder.path("injected");
  Finished newline = folder.command({"slurm", folder.file, "--shards", "2", "--results",
                                     folder.path("results\ntouch " + injected + "\n#")});
  EXPECT_EQ(newline.code, 2) << newline.output;
  EXPECT_NE(newline.output.find("control characters"), std::string::npos) << newline.output;
  EXPECT_FALSE(std::filesystem::exists(folder.path("results"))) << "nothing written";

  const std::string hostile = folder.path("my results 100% \"q\" 'p' $(touch " + injected + "); `touch " + injected +
                                          "` back\\slash");
  Finished quoted = folder.command({"slurm", folder.file, "--shards", "2", "--results", hostile});
  ASSERT_EQ(quoted.code, 0) << quoted.output;
  const std::filesystem::path jobs = std::filesystem::path(hostile) / "sweep" / "slurm";
  const std::string prepare = read_whole_file(jobs / "prepare.sbatch");
  // Every directive comes before the first command, and --output is one double-quoted word.
  bool commands_started = false;
  std::istringstream lines(prepare);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("#SBATCH", 0) == 0) EXPECT_FALSE(commands_started) << line;
    else if (!line.empty() && line[0] != '#') commands_started = true;
  }
  std::string logs = (jobs / "logs").string(), escaped;
  for (char c : logs) {
    if (c == '"' || c == '\\') escaped += '\\';
    if (c == '%') escaped += '%';
    escaped += c;
  }
  EXPECT_NE(prepare.find("#SBATCH \"--output=" + escaped + "/prepare-%j.out\"\n"), std::string::npos) << prepare;
  // The job as Slurm would run it: its command computes the reference into the hostile folder.
  std::ofstream(folder.path("prepare.sbatch")) << prepare;  // a path the test's own shell command can hold
  std::string output;
  int code = run_command("cd " + folder.path() + " && bash prepare.sbatch 2>&1 </dev/null", output);
  EXPECT_EQ(code, 0) << output;
  EXPECT_FALSE(std::filesystem::exists(injected)) << "no command ran from the path";
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(hostile) / "references")) << output;
}

// Issue 30, defect 13: a garbled slurm/shard-plan.json made `status` exit 2 and report nothing. It reports
// the damage and counts the runs of experiment.json instead.
TEST(SweepStatusCommand, AGarbledPlanIsReportedAndExperimentJsonCounts) {
  SweepFolder folder("status_garbled_plan");
  ASSERT_EQ(folder.run({"--filter", "photons=1000"}).code, 0);
  const std::string sweep = folder.results + "/sweep";
  std::filesystem::create_directories(sweep + "/slurm");
  std::ofstream(sweep + "/slurm/shard-plan.json") << "{\"experiment\": \"sweep\", \"shards\": [";
  Finished finished = folder.command({"status", sweep});
  EXPECT_EQ(finished.code, 3) << finished.output;
  EXPECT_NE(finished.output.find("warning: the shard plan is damaged"), std::string::npos) << finished.output;
  EXPECT_NE(finished.output.find("6 runs: 2 stored ok, 0 failed, 4 pending"), std::string::npos) << finished.output;
}
