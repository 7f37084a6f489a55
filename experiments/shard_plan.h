// Which shard of a sweep does which run: `causticbench run --shard i/n` and the Slurm array jobs of
// `causticbench slurm` (apps/slurm_command.cpp). Runs that share one prepare() (same variant, method and
// build knobs: the runner's group) stay in one shard, so no build is computed twice; groups are dealt
// out largest first, each to the shard with the least estimated cost so far (longest processing time
// first), so that shards end at about the same time rather than whoever drew the costly knobs last.
//
// A shard must agree with every other shard on the partition, even when they start at different times
// while others are storing results. So the partition depends only on what is fixed when it is made:
//  - without a plan file, on the experiment alone (the cost model below, never the store);
//  - with a plan file (written once by `causticbench slurm`, read by every shard), on the stored
//    timings of earlier runs as they were when it was written.
// Only what is still to do is dealt out: a run already stored (ok or failed) costs its shard nothing.
// Cost of a run to do: the model pixels x frames x (repetitions + 1), in seconds per model unit as the
// stored timings of earlier runs measured it (update and render of every timed pass and the warm-up):
// those of its own group where some of the group is stored, else of its method, else of any method;
// plus, once per group, the prepare() time a stored run of the group measured when its build is not
// cached (each shard then prepares again; a cached build is computed by the prepare job). No method
// declares its own estimate yet: the model is the fallback the issue allows.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/experiment.h"
#include "experiments/result_store.h"

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

// `paths` == nullptr: from the experiment alone (what `run --shard i/n` without a plan uses).
ShardPlan plan_shards(const Experiment& experiment, int shards, const ResultPaths* paths);

// <results>/<experiment>/slurm/shard-plan.json: where `causticbench slurm` writes the plan.
std::string shard_plan_path(const ResultPaths& paths, const std::string& experiment_name);
void write_shard_plan(const std::string& path, const ShardPlan& plan);
// InputError (file, key) when it cannot be read, is for another experiment, or does not name every run
// of the experiment exactly once (the experiment changed since it was planned: plan it again).
ShardPlan read_shard_plan(const std::string& path, const Experiment* experiment = nullptr);

}  // namespace causticbench
