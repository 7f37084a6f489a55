// `causticbench run`: expands an experiment into runs and executes the ones not yet stored.
// prepare() runs once per distinct set of build knobs and is reused for every render knob; each
// reference frame is computed once and cached by hash across experiments; each run is timed with
// one warm-up and N repetitions of update + render per frame. Processes may share a results folder
// (two invocations, the shards of a sweep): each run is done under its lock, by one of them
// (experiments/run_selection.h), and a run another process holds is waited for at the end.
#pragma once

#include <map>
#include <string>

#include "experiments/experiment.h"

namespace causticbench {

struct RunOptions {
  std::string results = "results";
  bool dry_run = false;
  bool force = false;
  std::string filter;
  int shard_index = 0;
  int shard_count = 1;
  // Run key -> shard (experiments/shard_plan.h): a plan file's; when empty with shard_count > 1, the
  // partition is planned from the experiment alone.
  std::map<std::string, int> shard_of;
  int threads = 0;
  // Only compute what the runs need and share: missing references and builds (experiments/prepare_builds.h).
  bool prepare_only = false;
};

struct RunSummary {
  size_t total = 0;      // runs the experiment expands to
  size_t selected = 0;   // after --filter and --shard
  size_t stored = 0;     // already stored and skipped
  size_t completed = 0;  // run now, status ok
  size_t failed = 0;     // run now, status failed
  size_t builds_computed = 0, builds_stored = 0;  // --prepare-only
};

// "i/n" -> index, count; InputError otherwise.
void parse_shard(const std::string& text, int& index, int& count);

RunSummary run_experiment(const Experiment& experiment, const RunOptions& options);

}  // namespace causticbench
