// Which runs of an experiment `causticbench run` has to do: those of its shard and filter that are not
// stored, or stored but damaged (with a warning naming the file and what is wrong), or measured against
// another copy of their reference than the stored one, or all of them with --force. What one process
// selects another may be doing: a selected run is run only after its lock is taken and it is looked at
// again (still_to_run), so that processes sharing a results folder never run it twice.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/experiment.h"
#include "experiments/result_store.h"
#include "experiments/runner.h"

namespace causticbench {

struct PendingRun {
  const RunSpec* run = nullptr;
  // Its stored copy is to be replaced (--force, or measured against another copy of its reference);
  // `replaced_record_hash` tells whether it is still the copy this process saw.
  bool replace_stored = false;
  std::string replaced_record_hash;
};

struct RunSelection {
  std::vector<PendingRun> pending;
  size_t selected = 0, stored = 0;
  // Stored runs whose reference was not stored when they were looked at: compared with it once it is.
  std::vector<std::pair<const RunSpec*, StoredRun>> unverified;
};

// Selects the runs to do; with --dry-run also prints each selected run as stored or pending.
RunSelection select_runs(const Experiment& experiment, const RunOptions& options, const ResultPaths& paths);

// After the references of `checked_variants` are stored: the unverified runs of those variants that
// were measured against another copy, moved to `pending` with a warning.
void recheck_against_references(const Experiment& experiment, const ResultPaths& paths,
                                const std::vector<size_t>& checked_variants, RunSelection& selection);

// Looked at under the run's lock: whether it still needs running (not when another process stored it,
// or replaced the copy this process meant to replace, in the meantime).
bool still_to_run(const Experiment& experiment, const ResultPaths& paths, const PendingRun& pending);

}  // namespace causticbench
