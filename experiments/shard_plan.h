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

#include "experiments/experiment.h"
#include "store/result_paths.h"
#include "store/shard_plan_file.h"

namespace causticbench {

// `paths` == nullptr: from the experiment alone (what `run --shard i/n` without a plan uses).
ShardPlan plan_shards(const Experiment& experiment, int shards, const ResultPaths* paths);

// The plan file (store/shard_plan_file.h) checked against the experiment: InputError (file, key) when it
// cannot be read, is for another experiment, or does not name every run of the experiment exactly once
// (the experiment changed since it was planned: plan it again).
ShardPlan read_shard_plan(const std::string& path, const Experiment& experiment);

}  // namespace causticbench
