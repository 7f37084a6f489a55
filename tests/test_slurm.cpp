// A sweep on a real single-node Slurm cluster (slurmctld and slurmd of Debian's slurm-wlm, started here
// with a configuration in a temporary folder by tests/slurm/single_node_cluster.sh, and stopped here):
// `causticbench slurm --submit` runs a reference job, an array of 3 shards after it and a report job
// after the array; the stored runs equal those of a local `run` of the same experiment (same keys, same
// records apart from timings) and the report is written. Skipped, saying why, only where the daemons
// cannot start (no slurm-wlm, no auth/none plugin, a node that does not come up).
#include <fcntl.h>
#include <unistd.h>
#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "experiments/experiment.h"
#include "store/result_paths.h"
#include "store/run_folders.h"
#include "experiments/shard_plan.h"
#include "tests/cluster_test_support.h"

using namespace causticbench;
using namespace causticbench::store_harness;
using causticbench::testing::run_command;
namespace fs = std::filesystem;

namespace {

// The cluster of one test: started in the constructor, stopped in the destructor, so that its daemons
// end even when an assertion fails.
class SingleNodeCluster {
 public:
  explicit SingleNodeCluster(const std::string& folder) : folder_(folder) {
    code_ = run_command(fmt::format("bash {} start {} {}", CAUSTICBENCH_SLURM_CLUSTER, folder_, ::getpid()), output_);
    if (code_ == 0) ::setenv("SLURM_CONF", (folder_ + "/slurm.conf").c_str(), 1);
  }
  ~SingleNodeCluster() {
    std::string output;
    run_command(fmt::format("bash {} stop {}", CAUSTICBENCH_SLURM_CLUSTER, folder_), output);
    ::unsetenv("SLURM_CONF");
  }
  int code() const { return code_; }
  const std::string& output() const { return output_; }
  std::string logs() const {
    std::string text;
    run_command(fmt::format("tail -n 30 {}/log/*", folder_), text);
    return text;
  }

 private:
  std::string folder_, output_;
  int code_ = 0;
};

// The record without what differs between two measurements of one run: timings, memory peaks, and how
// its build came to be (loaded from the reference job's build here, computed by the local run).
nlohmann::json without_timings(nlohmann::json record) {
  if (record.is_object()) {
    for (const char* key : {"update_ms", "render_ms", "gpu_render_ms", "timings", "prepare", "prepare_seconds",
                            "load_seconds", "save_seconds", "peak_rss_bytes"}) {
      record.erase(key);
    }
  }
  if (record.is_structured()) {
    for (auto& value : record) value = without_timings(value);
  }
  return record;
}

std::map<std::string, nlohmann::json> stored_records(const std::string& runs_folder) {
  std::map<std::string, nlohmann::json> records;
  if (!fs::is_directory(runs_folder)) return records;
  for (const auto& entry : fs::directory_iterator(runs_folder)) {
    StoredRun stored = inspect_stored_run(entry.path().string());
    if (stored.state == StoredRun::State::stored) records[entry.path().filename().string()] = without_timings(stored.record);
  }
  return records;
}

// Waits (at most `seconds`) until no job is queued or running; "" then, else what squeue still lists.
std::string wait_for_empty_queue(double seconds) {
  std::string queue;
  auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    if (run_command("squeue -h -o '%i %T %r'", queue) != 0) return "squeue failed: " + queue;
  } while (!queue.empty() && std::chrono::steady_clock::now() < deadline);
  return queue;
}

}  // namespace

TEST(SlurmCluster, ReferenceJobShardArrayAndReportEqualALocalRun) {
  auto start = std::chrono::steady_clock::now();
  causticbench::testing::SweepFolder folder("slurm");
  const std::string experiment_file = folder.file;
  SingleNodeCluster cluster(folder.path("cluster"));
  if (cluster.code() == 77) GTEST_SKIP() << "the Slurm daemons cannot start here: " << cluster.output();
  ASSERT_EQ(cluster.code(), 0) << cluster.output();

  const std::string results = folder.path("cluster_results");
  Finished submitted = run_process({"slurm", experiment_file, "--shards", "3", "--results", results, "--cpus-per-task", "1",
                                    "--time", "10:00", "--submit"},
                                   folder.path("submit.txt"));
  ASSERT_EQ(submitted.code, 0) << submitted.output;
  ASSERT_NE(submitted.output.find("shard array"), std::string::npos) << submitted.output;

  // Every job ends within 3 minutes (a few seconds on an idle machine).
  std::string queue = wait_for_empty_queue(180);
  ASSERT_TRUE(queue.empty()) << "jobs still queued:\n" << queue << cluster.logs();

  // Each job completed: the prepare job, the 3 array tasks, the report job.
  std::ifstream jobs_file(results + "/sweep/slurm/jobs");
  std::string prepare_job, shard_job, report_job;
  jobs_file >> prepare_job >> shard_job >> report_job;
  for (const std::string& job : {prepare_job, shard_job, report_job}) {
    std::string state;
    run_command("scontrol show job " + job + " | grep -o 'JobState=[A-Z_]*'", state);
    size_t tasks = job == shard_job ? 3 : 1;
    size_t completed = 0;
    for (size_t at = state.find("JobState=COMPLETED"); at != std::string::npos; at = state.find("JobState=COMPLETED", at + 1))
      ++completed;
    EXPECT_EQ(completed, tasks) << "job " << job << ": " << state;
  }
  // The reference job computed the reference and the builds; no shard computed either.
  std::string logs, shard_logs;
  run_command("cat " + results + "/sweep/slurm/logs/*", logs);
  run_command("cat " + results + "/sweep/slurm/logs/shard-*", shard_logs);
  EXPECT_NE(logs.find("computing"), std::string::npos) << logs;
  EXPECT_EQ(shard_logs.find("computing"), std::string::npos) << shard_logs;
  EXPECT_EQ(shard_logs.find(": computed"), std::string::npos) << shard_logs;
  EXPECT_TRUE(fs::exists(results + "/sweep/report.html")) << logs;
  EXPECT_NE(logs.find("\ncomplete\n"), std::string::npos) << "the report job's status line\n" << logs;

  // Locally, the builds are also computed first and loaded by the runs: a loaded photon_map build
  // reports fewer memory_bytes than one computed in the run (its vectors' spare capacity).
  const std::string local_results = folder.path("local_results");
  ASSERT_EQ(run_process({"run", experiment_file, "--results", local_results, "--prepare-only"}, folder.path("prepare.txt")).code, 0);
  Finished local = run_process({"run", experiment_file, "--results", local_results, "--no-report"}, folder.path("local.txt"));
  ASSERT_EQ(local.code, 0) << local.output;
  std::map<std::string, nlohmann::json> on_cluster = stored_records(results + "/sweep/runs");
  std::map<std::string, nlohmann::json> here = stored_records(local_results + "/sweep/runs");
  ASSERT_EQ(here.size(), load_experiment(experiment_file).runs.size());
  ASSERT_EQ(on_cluster.size(), here.size()) << logs;
  for (const auto& [key, record] : here) {
    ASSERT_TRUE(on_cluster.count(key)) << "run " << key << " missing on the cluster";
    EXPECT_EQ(on_cluster.at(key), record) << "run " << key;
  }
  std::cout << "Slurm end to end: "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
}

// A shard job cancelled midway (scancel, as Slurm ends a job at its time limit) and resubmitted with
// `sbatch --array=1 shards.sbatch` finishes its shard: what it stored before is kept as it was, the
// rest is stored once. Midway for sure: one of its runs is locked by a job "on another host" whose
// heartbeat this test keeps beating, so the shard stores its other run and waits; the cancel comes
// then, and the other host's job dies too (its heartbeat stops), so the resubmitted shard recovers
// that stale lock once it is 2 s old.
TEST(SlurmCluster, ShardCancelledMidwayAndResubmittedFinishesItsShard) {
  causticbench::testing::SweepFolder folder("slurm_cancel");
  SingleNodeCluster cluster(folder.path("cluster"));
  if (cluster.code() == 77) GTEST_SKIP() << "the Slurm daemons cannot start here: " << cluster.output();
  ASSERT_EQ(cluster.code(), 0) << cluster.output();
  ::setenv("CAUSTICBENCH_LOCK_STALE_SECONDS", "2", 1);  // sbatch passes this environment on to the jobs
  const std::string results = folder.path("results"), slurm = results + "/sweep/slurm";
  ASSERT_EQ(run_process({"slurm", folder.file, "--shards", "3", "--results", results}, folder.path("write.txt")).code, 0);
  Experiment experiment = folder.experiment();
  ShardPlan plan = read_shard_plan(slurm + "/shard-plan.json", experiment);
  std::vector<std::string> shard_runs;
  for (const PlannedRun& run : plan.runs)
    if (run.shard == 1) shard_runs.push_back(run.key);
  ASSERT_EQ(shard_runs.size(), 2u);
  const std::string foreign = ResultPaths{results}.run_lock("sweep", shard_runs[1]);
  causticbench::testing::ForeignLock foreign_job(foreign, "node-b");

  std::string submitted;
  ASSERT_EQ(run_command("bash " + slurm + "/submit.sh", submitted), 0) << submitted;
  std::ifstream jobs_file(slurm + "/jobs");
  std::string prepare_job, shard_job, report_job;
  jobs_file >> prepare_job >> shard_job >> report_job;
  // Shard 1 stores its free run, then waits for the locked one.
  std::string log;
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(90);
  while (log.find("waiting for run") == std::string::npos && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    run_command("cat " + slurm + "/logs/shard-1-*.out", log);
  }
  ASSERT_NE(log.find("waiting for run"), std::string::npos) << log << cluster.logs();
  std::string cancelled;
  ASSERT_EQ(run_command("scancel " + shard_job + "_1", cancelled), 0) << cancelled;
  std::string queue = wait_for_empty_queue(120);
  ASSERT_TRUE(queue.empty()) << queue << cluster.logs();
  const std::string runs = results + "/sweep/runs";
  EXPECT_TRUE(run_is_stored(runs + "/" + shard_runs[0]));
  EXPECT_FALSE(run_is_stored(runs + "/" + shard_runs[1]));
  const std::string hash_before = inspect_stored_run(runs + "/" + shard_runs[0]).record_hash;
  std::string status;
  EXPECT_EQ(run_command(fmt::format("{} status {}", CAUSTICBENCH_BINARY, results + "/sweep"), status), 3) << status;
  EXPECT_NE(status.find("shard 1 has 1 pending"), std::string::npos) << status;

  foreign_job.stop();  // the other host's job is gone too
  std::string resubmitted;
  ASSERT_EQ(run_command("cd " + slurm + " && sbatch --parsable --array=1 shards.sbatch", resubmitted), 0) << resubmitted;
  queue = wait_for_empty_queue(120);
  ASSERT_TRUE(queue.empty()) << queue << cluster.logs();
  std::string again;
  run_command(fmt::format("cat {}/logs/shard-1-{}.out", slurm, resubmitted.substr(0, resubmitted.find_first_of(";\n"))), again);
  EXPECT_NE(again.find("removing the stale lock " + foreign), std::string::npos) << again;
  EXPECT_NE(again.find("2 selected, 1 already stored, 1 run now"), std::string::npos) << again;
  EXPECT_EQ(inspect_stored_run(runs + "/" + shard_runs[0]).record_hash, hash_before) << "a run stored before the cancel was redone";
  std::set<std::string> expected;
  for (const RunSpec& run : experiment.runs) expected.insert(run.key);
  EXPECT_EQ(causticbench::testing::stored_keys(runs), expected);
  EXPECT_EQ(run_command(fmt::format("{} status {}", CAUSTICBENCH_BINARY, results + "/sweep"), status), 0) << status;
  EXPECT_TRUE(half_written(results).empty());
  ::unsetenv("CAUSTICBENCH_LOCK_STALE_SECONDS");
}
