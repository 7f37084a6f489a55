#include "store/sweep_status.h"

#include "store/result_paths.h"

#include <filesystem>
#include <map>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "store/result_paths.h"
#include "store/run_folders.h"
#include "store/run_record.h"
#include "store/shard_plan_file.h"
#include "store/store_files.h"

namespace causticbench {

namespace fs = std::filesystem;

namespace {

struct ListedRun {
  std::string key, method;
  int shard = -1;
};

// Each variant's current reference key, from experiment.json (empty when it has none).
std::map<std::string, std::string> current_reference_keys(const std::string& folder) {
  std::map<std::string, std::string> keys;
  std::optional<std::string> text = read_file_bytes((fs::path(folder) / "experiment.json").string());
  if (!text) return keys;
  nlohmann::json json = nlohmann::json::parse(*text, nullptr, false);
  if (json.is_discarded() || !json.contains("variants") || !json["variants"].is_array()) return keys;
  for (const nlohmann::json& variant : json["variants"]) {
    if (variant.is_object() && variant.value("name", nlohmann::json()).is_string() &&
        variant.value("reference_key", nlohmann::json()).is_string())
      keys[variant["name"].get<std::string>()] = variant["reference_key"].get<std::string>();
  }
  return keys;
}

// The seeds experiment.json asks for (1 when it says nothing).
int asked_seed_count(const std::string& folder) {
  std::optional<std::string> text = read_file_bytes((fs::path(folder) / "experiment.json").string());
  if (!text) return 1;
  const nlohmann::json json = nlohmann::json::parse(*text, nullptr, false);
  return json.is_object() && json.value("seeds", nlohmann::json()).is_number_integer() ? json["seeds"].get<int>() : 1;
}

// From experiment.json: the run keys; their methods from the experiment file when it still expands to them.
std::vector<ListedRun> runs_of_experiment_json(const std::string& folder, std::string& name,
                                               const ExperimentFileRuns& experiment_runs) {
  const std::string path = (fs::path(folder) / "experiment.json").string();
  std::optional<std::string> text = read_file_bytes(path);
  if (!text) {
    throw InputError(fmt::format("{}: expected an experiment's results folder (with experiment.json, written by "
                                 "`causticbench run`, or slurm/shard-plan.json, written by `causticbench slurm`){}",
                                 folder, experiment_folders_hint(folder)));
  }
  nlohmann::json json = nlohmann::json::parse(*text, nullptr, false);
  if (json.is_discarded() || !json.contains("runs") || !json["runs"].is_array()) {
    throw InputError(fmt::format("{}: key 'runs': expected a list of run keys, found a damaged file", path));
  }
  name = json.value("name", fs::path(folder).filename().string());
  std::vector<ListedRun> runs;
  for (const nlohmann::json& key : json["runs"]) runs.push_back({key.get<std::string>(), "", -1});
  // When the experiment file moved or changed, stored runs still name their method in their records.
  const std::vector<std::pair<std::string, std::string>> file_runs =
      experiment_runs ? experiment_runs(json.value("source", "")) : std::vector<std::pair<std::string, std::string>>{};
  bool same = file_runs.size() == runs.size();
  for (size_t i = 0; same && i < runs.size(); ++i) same = file_runs[i].first == runs[i].key;
  if (same)
    for (size_t i = 0; i < runs.size(); ++i) runs[i].method = file_runs[i].second;
  return runs;
}

}  // namespace

SweepStatus sweep_status(const std::string& folder, const ExperimentFileRuns& experiment_runs) {
  SweepStatus status;
  status.folder = folder;
  std::vector<ListedRun> runs;
  const std::string plan_path = (fs::path(folder) / "slurm" / "shard-plan.json").string();
  std::optional<ShardPlan> plan;
  if (fs::exists(plan_path)) {
    try {
      plan = read_shard_plan_file(plan_path);
    } catch (const InputError& error) {
      // A garbled plan is something to report, not a reason to report nothing: experiment.json still
      // names every run (issue 30, defect 13).
      status.plan_problem = error.what();
    }
  }
  if (plan) {
    status.plan = plan_path;
    status.shards = plan->shards;
    status.experiment = plan->experiment;
    for (const PlannedRun& run : plan->runs) runs.push_back({run.key, run.method, run.shard});
  } else {
    try {
      runs = runs_of_experiment_json(folder, status.experiment, experiment_runs);
    } catch (const InputError& error) {
      if (status.plan_problem.empty()) throw;
      throw InputError(status.plan_problem + "; and " + error.what());
    }
  }
  const std::map<std::string, std::string> reference_keys = current_reference_keys(folder);
  const int asked_seeds = asked_seed_count(folder);
  for (const ListedRun& run : runs) {
    StoredRun stored = inspect_stored_run((fs::path(folder) / "runs" / run.key).string());
    if (stored.state == StoredRun::State::stored) {
      // A stale run (measured against another reference than its variant's now) is still to be run.
      auto current = reference_keys.find(stored.record.value("variant", std::string("default")));
      if (current != reference_keys.end() && measured_against_other_reference(stored.record, current->second))
        stored.state = StoredRun::State::absent;
      // So is one measured with fewer seeds than the experiment asks for now.
      if (stored_with_fewer_seeds(stored.record, asked_seeds)) stored.state = StoredRun::State::absent;
    }
    std::string method = run.method;
    if (stored.state == StoredRun::State::stored) method = stored.record.value("method", method);
    if (method.empty()) method = "(unknown)";
    RunCounts& counts = status.methods[method];
    ++counts.total;
    ++status.all.total;
    if (stored.state != StoredRun::State::stored) {
      ++counts.pending;
      ++status.all.pending;
      if (run.shard >= 0) ++status.shard_pending[run.shard];
    } else if (stored.record.value("status", "") == "ok") {
      ++counts.ok;
      ++status.all.ok;
    } else {
      ++counts.failed;
      ++status.all.failed;
    }
  }
  return status;
}

}  // namespace causticbench
