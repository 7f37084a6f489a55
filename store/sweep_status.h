// `causticbench status RESULTS/EXPERIMENT`: how far a (sharded) sweep is: runs stored ok, failed and
// pending, per method, and, when it was planned for a cluster (experiments/shard_plan.h), the shards
// that still have runs to do. Read only; takes no lock: a run being stored by a shard meanwhile is
// counted as pending or stored, never half.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace causticbench {

struct RunCounts {
  size_t total = 0, ok = 0, failed = 0, pending = 0;  // pending: not stored, or damaged (it is measured again)
};

struct SweepStatus {
  std::string experiment, folder;
  std::string plan;  // the shard plan read, or empty
  std::string plan_problem;  // why the shard plan there could not be read (the runs then come from experiment.json)
  int shards = 0;    // of the plan; 0 without one
  RunCounts all;
  std::map<std::string, RunCounts> methods;  // "(unknown)" for pending runs whose method is not known
  std::map<int, size_t> shard_pending;       // shard -> pending runs, only shards with some
  bool complete() const { return all.total > 0 && all.pending == 0; }
};

// The runs come from the shard plan (<folder>/slurm/shard-plan.json) when there is one, which names
// every run from the moment the sweep was planned; otherwise from experiment.json, written by the first
// `causticbench run` (a pending run's method then comes from the experiment file it names, while that
// file still expands to the same runs). A damaged plan is reported in plan_problem and experiment.json
// serves instead. InputError when the folder has neither.
// `experiment_runs(source)`: the runs (key, method) that the experiment file at `source` expands to now,
// empty when it cannot be read; the experiment layer's reader (experiments/experiment.h,
// experiment_file_runs), given by the caller so that the store needs nothing above it.
using ExperimentFileRuns = std::function<std::vector<std::pair<std::string, std::string>>(const std::string& source)>;
SweepStatus sweep_status(const std::string& folder, const ExperimentFileRuns& experiment_runs);

}  // namespace causticbench
