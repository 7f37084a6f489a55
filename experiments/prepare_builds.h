// `causticbench run --prepare-only`: what the runs of a sweep share, computed once before the shards
// start (the reference job of `causticbench slurm`): every missing reference frame (the runner's
// reference check does that) and every missing build of the build cache (store/build_cache.h). Shards
// that started together would otherwise wait on each other's reference lock and each compute the same
// build, the cache letting the first rename win.
#pragma once

#include <vector>

#include "experiments/experiment.h"
#include "store/result_paths.h"

namespace causticbench {

struct BuildSummary {
  size_t computed = 0;   // computed now and stored
  size_t stored = 0;     // already stored and usable
  size_t uncached = 0;   // groups whose method stores no build for these knobs (prepared by each shard)
  size_t failed = 0;     // prepare() threw: the shard's runs record the failure
};

// For each group of `runs` sharing one prepare() (variant, method, build knobs) whose method declares
// build dependencies: computes and stores the build unless a usable one is stored.
BuildSummary prepare_missing_builds(const Experiment& experiment, const std::vector<const RunSpec*>& runs,
                                    const ResultPaths& paths);

}  // namespace causticbench
