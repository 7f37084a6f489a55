// A sweep's shard plan as stored, <results>/<experiment>/slurm/shard-plan.json: which shard does which
// run (experiments/shard_plan.h makes the plan; `causticbench slurm` writes it; every shard and
// `causticbench status` read it).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/result_paths.h"

namespace causticbench {

struct PlannedRun {
  std::string key, method, label;
  size_t group = 0;  // index of its prepare() group
  int shard = 0;
  double estimated_seconds = 0.0;  // 0 for a stored run
  bool stored = false;             // stored when planned: the shard skips it
};

struct ShardPlan {
  std::string experiment;
  int shards = 1;
  std::vector<PlannedRun> runs;          // in the experiment's order
  std::vector<double> shard_seconds;     // estimated cost per shard of the runs still to do
  size_t timed_runs = 0;                 // stored runs whose timings scaled the estimates
  std::map<std::string, int> shard_of;   // run key -> shard

  nlohmann::json to_json() const;
};

// <results>/<experiment>/slurm/shard-plan.json: where `causticbench slurm` writes the plan.
std::string shard_plan_path(const ResultPaths& paths, const std::string& experiment_name);
void write_shard_plan(const std::string& path, const ShardPlan& plan);
// InputError (file, key) when it cannot be read or is no shard plan.
ShardPlan read_shard_plan_file(const std::string& path);

}  // namespace causticbench
